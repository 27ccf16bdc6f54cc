//! Policies and the closed loop that runs them (the Push-MOG paper's Algorithm 1).
//!
//! Each trip: observe the table, plan, execute, count the trip, until the table is clear:
//! - `sog`: pick a graspable object at random (seeded), grasp it alone ([`SingleObject`]).
//! - `mog`: cluster ([`Hierarchical`]), pick a cluster at random, grasp with [`MultiObject`] on the
//!   table as it is: multi-object grasps without pushes.
//! - `push-mog`: cluster, pick a cluster at random, plan fork pushes toward its central object
//!   ([`TowardCentral`]), predict the table after them, plan the multi-object grasp on the
//!   prediction, then execute pushes and grasp (the paper's method).
//! - `push-mog-opt`: the same loop with optimal clustering ([`Milp`]) and SOCP push targets
//!   ([`Socp`]); `push-mog-milp` (MILP clustering, the paper's pushes) and `push-mog-socp` (the
//!   paper's clustering, SOCP pushes) separate the two effects. The push planner's intended grasp is
//!   offered to the grasp planner as a candidate.
//!
//! After a trip's pushes the loop looks at the table again (`run.observe_after_pushes`, default on)
//! and plans the rest of the trip on what it sees ([`Policy::correct_trip`]): the grasp where the
//! objects are, not where the pushes were meant to leave them, and, when the row did not form,
//! corrective pushes (at most `run.max_corrections` rounds, each followed by another look). Pushes
//! cost robot time, not trips; every look costs an observation. With the option off the grasp is
//! made on the predicted table, as the Push-MOG paper does to save that observation.
//!
//! When the push planner finds no row for a whole cluster of three or more, its largest sub-clusters
//! are tried and the object left out waits for a later trip. When the multi-object planner finds
//! nothing for a cluster, a single-object grasp of one of its objects is tried; when no object of it
//! can be taken by itself, a push that parts it from the neighbour in its plates' way, and failing
//! that a grasp of it together with that neighbour as they lie, even within the edge margin
//! (`separate.rs`). An attempt that yields no grasp is recorded with its reason and costs no trip; a
//! grasp that carries nothing is a trip (a failed grasp). Its jaws are not proposed again, and after
//! [`GIVE_UP_AFTER`] multi-object grasps of the same objects carried nothing, those objects are no
//! longer grasped together ([`TripContext`]). A rider left standing on its row by such a grasp
//! ([`Perched`]) goes with the row, grasped again as it lies before anything else when the jaws can
//! stay clear of it (`perched.rs`). The run stops when the table is clear, when
//! every object left is wider than the jaw gap, after `max_failed_attempts` fruitless attempts in a
//! row, or at the trip limit; it never loops forever.
//!
//! [`SingleObject`]: crate::grasp::SingleObject
//! [`Hierarchical`]: crate::cluster::Hierarchical
//! [`TowardCentral`]: crate::push::TowardCentral
//! [`Milp`]: crate::cluster::Milp
//! [`Socp`]: crate::push::Socp

use std::str::FromStr;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::cluster::Clusterer;
use crate::error::{Error, Result};
use crate::exec::{Executor, Ideal};
use crate::grasp::{Grasp, GraspPlanner, MultiObject};
use crate::outcome::Abilities;
use crate::plan::Plan;
use crate::problem::Problem;
use crate::push::PushPlanner;
use crate::scene::{ObjectId, Scene};
use crate::time_model::TimeModel;

/// Which policy.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub enum PolicyKind {
    /// Single-object grasps in random order.
    #[serde(rename = "sog")]
    Sog,
    /// Multi-object grasps of clusters, no pushes.
    #[serde(rename = "mog")]
    Mog,
    /// Fork pushes toward each cluster's central object, then a multi-object grasp (the paper).
    #[serde(rename = "push-mog")]
    PushMog,
    /// Optimal (MILP) clustering, the paper's pushes toward the central object.
    #[serde(rename = "push-mog-milp")]
    PushMogMilp,
    /// The paper's hierarchical clustering, push targets from the SOCP.
    #[serde(rename = "push-mog-socp")]
    PushMogSocp,
    /// Optimal clustering and SOCP push targets.
    #[serde(rename = "push-mog-opt")]
    PushMogOpt,
}

impl PolicyKind {
    /// Every policy, in table order.
    pub const ALL: [PolicyKind; 6] = [
        PolicyKind::Sog,
        PolicyKind::Mog,
        PolicyKind::PushMog,
        PolicyKind::PushMogMilp,
        PolicyKind::PushMogSocp,
        PolicyKind::PushMogOpt,
    ];

    /// The policy's name (`sog`, `mog`, `push-mog`, `push-mog-milp`, `push-mog-socp`,
    /// `push-mog-opt`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Sog => "sog",
            Self::Mog => "mog",
            Self::PushMog => "push-mog",
            Self::PushMogMilp => "push-mog-milp",
            Self::PushMogSocp => "push-mog-socp",
            Self::PushMogOpt => "push-mog-opt",
        }
    }

    /// Whether the policy clusters with the MILP (rather than the paper's hierarchical clustering).
    pub fn optimal_clustering(self) -> bool {
        matches!(self, Self::PushMogMilp | Self::PushMogOpt)
    }

    /// Whether the policy places push targets with the SOCP (rather than toward the central object).
    pub fn optimal_pushing(self) -> bool {
        matches!(self, Self::PushMogSocp | Self::PushMogOpt)
    }

    /// Whether the policy pushes at all.
    pub fn pushes(self) -> bool {
        !matches!(self, Self::Sog | Self::Mog)
    }
}

impl std::fmt::Display for PolicyKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PolicyKind {
    type Err = Error;
    fn from_str(text: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|kind| kind.name() == text)
            .ok_or_else(|| {
                Error::field(
                    "policy",
                    "name",
                    format!(
                        "unknown policy `{text}`; choose one of {}",
                        Self::ALL.map(|k| k.name()).join(", ")
                    ),
                )
            })
    }
}

/// Which clusterer a policy uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ClustererKind {
    /// The paper's hierarchical clustering with separating-line splits.
    Hierarchical,
    /// The optimal set-partitioning MILP.
    Milp,
}

/// Which push planner a policy uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum PusherKind {
    /// No pushes.
    None,
    /// The paper's pushes toward each cluster's central object.
    TowardCentral,
    /// Push targets from the second-order cone program.
    Socp,
}

impl PolicyKind {
    /// The clusterer of this preset (`None` for single-object grasping, which does not cluster).
    pub fn clusterer(self) -> Option<ClustererKind> {
        match self {
            Self::Sog => None,
            Self::Mog | Self::PushMog | Self::PushMogSocp => Some(ClustererKind::Hierarchical),
            Self::PushMogMilp | Self::PushMogOpt => Some(ClustererKind::Milp),
        }
    }

    /// The push planner of this preset.
    pub fn pusher(self) -> PusherKind {
        match self {
            Self::Sog | Self::Mog => PusherKind::None,
            Self::PushMog | Self::PushMogMilp => PusherKind::TowardCentral,
            Self::PushMogSocp | Self::PushMogOpt => PusherKind::Socp,
        }
    }
}

/// A clusterer a policy can hold.
pub trait PolicyClusterer: Clusterer + Send + Sync + std::fmt::Debug {}
impl<T: Clusterer + Send + Sync + std::fmt::Debug> PolicyClusterer for T {}

/// A push planner a policy can hold.
pub trait PolicyPusher: PushPlanner + Send + Sync + std::fmt::Debug {}
impl<T: PushPlanner + Send + Sync + std::fmt::Debug> PolicyPusher for T {}

/// A grasp planner a policy can hold.
pub trait PolicyGraspPlanner: GraspPlanner + Send + Sync + std::fmt::Debug {}
impl<T: GraspPlanner + Send + Sync + std::fmt::Debug> PolicyGraspPlanner for T {}

/// A policy ready to run: a clusterer, a push planner and the grasp planners, each a trait object, so
/// a researcher can put their own in with [`PolicyBuilder`].
#[derive(Clone, Debug)]
pub struct Policy {
    kind: PolicyKind,
    settings: PolicySettings,
    /// `None`: single-object grasps of objects picked at random, no clustering.
    clusterer: Option<Arc<dyn PolicyClusterer>>,
    pusher: Option<Arc<dyn PolicyPusher>>,
    /// Grasps of one object.
    single: Arc<dyn PolicyGraspPlanner>,
    /// Grasps of several objects.
    multi: Arc<dyn PolicyGraspPlanner>,
    /// The built-in multi-object planner, whatever `multi` is: it judges the SOCP's rows and lists
    /// the candidates it refuses ([`Policy::refused_candidates`]).
    judge: MultiObject,
    /// The built-in multi-object planner without the edge margin, when the policy's has one and
    /// `multi` was not replaced: the last way out of a dead end near the workspace's edge
    /// ([`Policy::take_with_neighbours`]).
    at_edges: Option<Arc<dyn PolicyGraspPlanner>>,
    /// What every stage shares, built once from `settings`.
    problem: Arc<Problem>,
}

/// What the planners of a policy can claim of their answers ([`Policy::abilities`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PolicyAbilities {
    /// The clusterer's, if the policy clusters.
    pub clusterer: Option<Abilities>,
    /// The push planner's, if the policy pushes.
    pub pusher: Option<Abilities>,
    /// The single-object grasp planner's.
    pub single_object: Abilities,
    /// The multi-object grasp planner's, if the policy grasps several objects at once.
    pub multi_object: Option<Abilities>,
}

mod ahead;
mod builder;
mod context;
mod correct;
mod fuse;
mod no_trip;
mod past_edge;
mod perched;
pub mod preset;
mod price;
mod riders;
mod run;
mod separate;
mod settings;
mod trip;

pub use crate::plan::TripPlan;
pub use ahead::AHEAD_TRIES;
pub use builder::PolicyBuilder;
pub use context::{GIVE_UP_AFTER, Landing, Perched, TripContext};
pub use fuse::{LookFusion, TOUCH_REACH};
pub use no_trip::{NoTrip, TripAnswer};
pub use price::{Pricing, SuccessBand, TripObjective, grasp_path, push_paths, rider_paths};
pub use riders::Riders;
pub use run::{Run, RunTiming, run_seconds};
pub use settings::{LoopSettings, PolicySettings};

impl Policy {
    /// The preset `kind` with these settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(kind: PolicyKind, settings: PolicySettings) -> Result<Self> {
        Self::builder(kind).settings(settings).build()
    }

    /// A builder starting from the preset `kind` with default settings.
    pub fn builder(kind: PolicyKind) -> PolicyBuilder {
        PolicyBuilder {
            kind,
            settings: PolicySettings::default(),
            clusterer: None,
            pusher: None,
            single: None,
            multi: None,
            parts: (None, None),
        }
    }

    /// Which policy this is.
    pub fn kind(&self) -> PolicyKind {
        self.kind
    }

    /// The settings the policy was built with.
    pub fn settings(&self) -> &PolicySettings {
        &self.settings
    }

    /// The problem every stage of the policy shares.
    pub fn problem(&self) -> &Arc<Problem> {
        &self.problem
    }

    /// What each of its planners can claim of its answers, for logs: the clusterer and push planner
    /// where the policy has them, and the grasp planners it asks (sog asks only the single-object
    /// one).
    pub fn abilities(&self) -> PolicyAbilities {
        PolicyAbilities {
            clusterer: self.clusterer.as_ref().map(|c| c.abilities()),
            pusher: self.pusher.as_ref().map(|p| p.abilities()),
            single_object: self.single.abilities(),
            multi_object: (self.kind != PolicyKind::Sog).then(|| self.multi.abilities()),
        }
    }

    /// An executor that applies this policy's plans exactly, judging grasps with its grasp model.
    pub fn ideal(&self) -> Ideal {
        Ideal::new(self.problem.grasp_model().clone())
    }

    /// Grasps of `targets` the multi-object planner refuses although they catch two or more objects
    /// and land on nothing, evenly spread over its candidates (see [`MultiObject::refused`]).
    ///
    /// # Errors
    /// An id that is not in the scene.
    pub fn refused_candidates(&self, scene: &Scene, targets: &[ObjectId]) -> Result<Vec<Grasp>> {
        let all = self.judge.refused(scene, targets)?;
        // Every k-th, so a few replays sample the whole list.
        let stride = (all.len() / 8).max(1);
        Ok(all.into_iter().step_by(stride).collect())
    }

    /// Clears `scene` with `executor`, planning after every observation; `seed` drives the random
    /// choices (which object or cluster next). A loop over [`Run::step`].
    ///
    /// # Errors
    /// Misuse or an executor fault (drive a [`Run`] yourself to keep the record of a run that
    /// failed); a run that cannot clear the table ends with [`crate::plan::RunStatus::Stopped`] inside `Ok`.
    pub fn run(&self, scene: &Scene, executor: &mut dyn Executor, seed: u64) -> Result<Plan> {
        self.run_timed(scene, executor, seed).map(|(plan, _)| plan)
    }

    /// As [`Policy::run`], also returning how long planning took (wall-clock, so not reproducible;
    /// kept apart from the plan).
    ///
    /// # Errors
    /// As [`Policy::run`].
    pub fn run_timed(
        &self,
        scene: &Scene,
        executor: &mut dyn Executor,
        seed: u64,
    ) -> Result<(Plan, RunTiming)> {
        let mut run = Run::start(self, scene, executor, seed)?;
        while run.step(executor)?.is_none() {}
        Ok(run.finish())
    }
}
