//! Push targets from a second-order cone program: the least total push distance that lines a cluster
//! up between the jaws (`formulations/pushing.md`).
//!
//! For a fixed closing axis and order the problem is convex ([`row`](super::row)). The planner's
//! axes are `axes` even directions over `[0, π)`, every member's edge normals (along them objects meet
//! the plates and each other flat), the directions joining the members' centroids and their principal
//! axis; axes along which the members' widths cannot fit the jaws are dropped, and the rest carry a
//! lower bound on the push distance ([`lower_bound`]). A solved row becomes pushes as follows:
//! 1. members that would move less than `min_push` are held where they are and the program is solved
//!    again with them fixed ("objects already in place are not pushed"); when every member is that
//!    close, only the one nearest its target is held, since their small offsets add up across the row;
//! 2. the pushes are sequenced: every order of the pushes is tried until one has every object's straight
//!    sweep and the fingers' footprint clear of every other object as it stands at that moment
//!    (exact separating-axis sweeps, `geometry::cast_distance`, and [`plan_fork`]); a member whose
//!    straight push is refused may take two legs, across the closing axis and along it;
//! 3. the row is judged at its intended grasp: with `robust_rows` (default) as the policy's
//!    multi-object planner judges grasps, on the predicted table and on noisy copies of it
//!    ([`MultiObject::carries`]); otherwise by the grasp model alone (held, or a member slips out).
//!
//! The search, with `prefer_held_rows` (default), looks for the cheapest held row: every axis is
//! visited, first those along which a perfect row of the members is held by the grasp model (a cheap
//! test before any program), each group in order of its bound, skipping axes whose bound cannot beat
//! the cheapest held row found. Without a held row (or without the preference), the cheapest row that
//! can be pushed into place is taken, visiting axes by bound until none can beat it. For three or more
//! members, the other orders along the chosen axis are tried too (up to `max_orders`). The answer is
//! the cheapest held row if there is one, else the cheapest row; `PushPlan::row_held` says
//! which, with status [`Status::BestFound`]. No row on any axis: [`Status::Infeasible`]; rows but no
//! push sequence: a failed status. With `time_limit`, a search still running at the limit stops
//! before its next solve: the cheapest row so far with [`Status::TimeLimit`], or a failed status
//! naming the limit (never `infeasible`, since the rows not solved prove nothing).
//!
//! With `flush` (flush pushes, [`super::flush`]) every push must meet a face of its object flat:
//! each moving member's target is kept within a cone about one face's inward normal (two linear
//! rows of the program, [`row`](super::row)). A pair is tried for every face of either member that
//! faces the other, along the axis [`pair_axis`] finds (the line through both centroids once the
//! pushed one stops), with the other held and the row no longer than the two and `flush_gap`, so
//! the pushed one ends nearly touching; larger clusters are solved freely on each axis first and
//! again with each moving member's push turned to its nearest face normal. Pushes are made with
//! the jaws closed to one block facing the face.
//!
//! Objects outside the cluster are kept clear by fixed half-planes: the line of largest separation
//! between the outside object and the hull of the cluster (or, if the object reaches into that hull,
//! between it and each member), with the current gap (at most `clearance`) kept. A member's whole
//! straight sweep then stays on its side.

mod rows;
mod search;
mod sequence;
mod settings;

use std::sync::Arc;

pub use settings::SocpSettings;

use super::{PushPlan, PushPlanner};
use crate::error::Result;
use crate::grasp::{Memory, MultiObject};
use crate::outcome::{Abilities, Outcome};
use crate::problem::Problem;
use crate::scene::{ObjectId, Scene};

/// Push targets from the row SOCP.
#[derive(Clone, Debug)]
pub struct Socp {
    settings: SocpSettings,
    /// What every stage agrees on: the grasp model, the fork, `min_push` and the time model.
    problem: Arc<Problem>,
    /// Closings of perfect rows already judged (`grasp/memory.rs`): the same cluster is planned
    /// again on later trips.
    memory: Memory,
    /// The policy's multi-object planner, judging rows under noise when `robust_rows` is set.
    judge: Option<MultiObject>,
}

impl Default for Socp {
    fn default() -> Self {
        Self {
            settings: SocpSettings::default(),
            problem: Problem::shared_default(),
            memory: Memory::default(),
            judge: None,
        }
    }
}

impl Socp {
    /// A planner with these settings, judging rows with the problem's grasp model, making fork pushes
    /// of its geometry, none shorter than its `min_push`, and choosing which members move by its
    /// time model.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: SocpSettings, problem: Arc<Problem>) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            settings,
            problem,
            memory: Memory::default(),
            judge: None,
        })
    }

    /// The same planner judging rows as `judge` judges its grasps ([`MultiObject::carries`]) when
    /// `robust_rows` is set (the policies give it their multi-object planner).
    pub fn with_judge(mut self, judge: MultiObject) -> Self {
        self.judge = Some(judge);
        self
    }

    /// The effective settings.
    pub fn settings(&self) -> &SocpSettings {
        &self.settings
    }
}

impl PushPlanner for Socp {
    fn name(&self) -> &'static str {
        "socp"
    }

    /// The best of the axes and orders sampled, never proven; stops at `time_limit` if set.
    fn abilities(&self) -> Abilities {
        Abilities {
            time_limit: self.settings.time_limit,
            ..Abilities::heuristic(self.name())
        }
    }

    fn plan(&self, scene: &Scene, cluster: &[ObjectId]) -> Result<Outcome<PushPlan>> {
        search::plan(self, scene, cluster)
    }
}
