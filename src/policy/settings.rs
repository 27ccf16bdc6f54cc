//! The settings of a policy: every stage's own, the loop's limits, and what all stages share, from
//! which the policy builds its [`Problem`].

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::{Pricing, Riders};
use crate::cluster::{FlushPairs, Hierarchical, HierarchicalSettings, Milp, MilpSettings, RowTest};
use crate::error::Result;
use crate::grasp::{GraspModel, MultiObjectSettings, SingleObjectSettings};
use crate::problem::Problem;
use crate::push::{ForkSettings, SocpSettings, TowardCentralSettings};
use crate::time_model::TimeModel;

/// Settings of every stage of a policy and of the loop. What every stage must agree on (the grasp
/// model, the fork-push geometry, the shortest push, the time model) is set once here and built
/// into one [`Problem`] ([`PolicySettings::problem`]) that the policy hands to each stage; the MILP
/// is seeded by `clustering` and proposes the rows the push planner can make
/// ([`PolicySettings::row_test`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PolicySettings {
    /// Hierarchical clustering (`mog`, `push-mog`, `push-mog-socp`).
    pub clustering: HierarchicalSettings,
    /// Optimal clustering (`push-mog-milp`, `push-mog-opt`).
    pub milp: MilpSettings,
    /// Pushes toward the central object (`push-mog`, `push-mog-milp`).
    pub pushing: TowardCentralSettings,
    /// SOCP push targets (`push-mog-socp`, `push-mog-opt`).
    pub socp: SocpSettings,
    /// Single-object grasps (`sog`, and the fallback of the others).
    pub single: SingleObjectSettings,
    /// Multi-object grasps (`mog`, `push-mog`).
    pub multi: MultiObjectSettings,
    /// Limits of the loop.
    pub run: LoopSettings,
    /// What a closing does, for every stage that asks: the multi- and single-object planners, the
    /// SOCP's judgement of rows, and the ideal executor.
    pub grasp_model: GraspModel,
    /// Fork-push geometry, for both push planners.
    pub fork: ForkSettings,
    /// Pushes shorter than this are not made, metres, by the push planners and in the MILP's
    /// estimates. Default 0.003.
    pub min_push: f64,
    /// Judge multi-object candidates by rolling each sample out in the rapier simulator (default
    /// settings) instead of with the grasp model: slower by two orders of magnitude, for comparison.
    /// Default false.
    pub rollout: bool,
    /// Seconds per trip and per push: the time each run reports, and the time the MILP clustering
    /// minimises.
    pub time_model: TimeModel,
    /// Whether pushes are made whenever a multi-object grasp follows them (objects per trip, the
    /// default) or only when they are expected to save robot time ([`Pricing`]).
    pub pricing: Pricing,
    /// Riders: single objects put down on a row's top before its grasp (off by default; written
    /// only when set).
    #[serde(skip_serializing_if = "Riders::is_default")]
    pub riders: Riders,
}

impl Default for PolicySettings {
    fn default() -> Self {
        Self {
            clustering: HierarchicalSettings::default(),
            milp: MilpSettings::default(),
            pushing: TowardCentralSettings::default(),
            socp: SocpSettings::default(),
            single: SingleObjectSettings::default(),
            multi: MultiObjectSettings::default(),
            run: LoopSettings::default(),
            grasp_model: GraspModel::default(),
            fork: ForkSettings::default(),
            min_push: 0.003,
            rollout: false,
            time_model: TimeModel::default(),
            pricing: Pricing::default(),
            riders: Riders::default(),
        }
    }
}

/// Limits that keep the closed loop finite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct LoopSettings {
    /// Attempts in a row that find no grasp or carry nothing before the run stops. Default 10.
    pub max_failed_attempts: usize,
    /// Trips allowed per object on the table at the start (at least one trip). Default 3.
    pub max_trips_per_object: f64,
    /// Look at the table again after a trip's pushes and plan its grasp on what is seen
    /// ([`Policy::replan_grasp`]), at the cost of one more observation; `false` grasps the table
    /// predicted after the pushes, as the Push-MOG paper does to save that observation. Default true.
    pub observe_after_pushes: bool,
    /// Rounds of corrective pushes a trip may make after its first pushes, each planned on a new
    /// observation (needs `observe_after_pushes`). Default 2.
    pub max_corrections: usize,
    /// Plan on the mean of the poses seen since an object was last touched, instead of the newest
    /// look alone (`policy/fuse.rs`; `formulations/perception.md`, "Looks fused"): the camera's
    /// error, `multi.noise.perception_position` and `perception_yaw`, shrinks as 1/√looks for
    /// objects that stand still. Default false (written only when set).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub fuse_looks: bool,
    /// How far past the workspace's edge the arm may take an object by itself, metres, once
    /// nothing is left in the workspace but objects that lie past its edge (`policy/past_edge.rs`;
    /// `formulations/grasping.md`, "Objects past the workspace's edge"). The cell must allow it:
    /// the table goes on that far, the camera sees that far and the arm reaches it. Only an
    /// executor that reports such objects ([`crate::exec::Executor::past_edge`]; the simulator,
    /// with or without its depth camera) is taken up on it. Default 0, off (written only when set).
    #[serde(skip_serializing_if = "is_zero")]
    pub reach_past_edge: f64,
}

fn is_zero(value: &f64) -> bool {
    *value == 0.0
}

impl Default for LoopSettings {
    fn default() -> Self {
        Self {
            max_failed_attempts: 10,
            max_trips_per_object: 3.0,
            observe_after_pushes: true,
            max_corrections: 2,
            fuse_looks: false,
            reach_past_edge: 0.0,
        }
    }
}

impl PolicySettings {
    /// Checks every stage's settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.problem()?;
        self.validate_stages()
    }

    /// The problem every stage of the policy shares, built and checked once: the grasp model, the
    /// fork, `min_push` and the time model.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn problem(&self) -> Result<Arc<Problem>> {
        Problem::new(
            self.grasp_model.clone(),
            self.fork.clone(),
            self.min_push,
            self.time_model.clone(),
        )
    }

    /// The MILP's candidate test that follows this policy's push planner: rows leave the SOCP's
    /// margin, and with flush pushes only pairs a flush push lines up.
    pub fn row_test(&self) -> RowTest {
        RowTest {
            margin: self.socp.margin,
            flush_pairs: self.socp.flush.then_some(FlushPairs {
                straddle: self.socp.straddle,
                margin: self.socp.flush_margin,
                cone: self.socp.flush_cone,
                tight: self.socp.flush_gap,
            }),
        }
    }

    /// The MILP clusterer of these settings: `milp` with the shared `problem`, proposing the
    /// clusters that pass `rows` (in a policy whose pushes are the SOCP's, [`Self::row_test`]),
    /// seeded by the `clustering` heuristic; choosing riders for its rows when `riders.enabled`
    /// and `riders.in_clustering`.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn milp_clusterer(&self, problem: Arc<Problem>, rows: RowTest) -> Result<Milp> {
        let milp = Milp::new(self.milp.clone(), problem)?
            .with_rows(rows)?
            .seeded_by(Hierarchical::new(self.clustering.clone())?);
        let riders = &self.riders;
        if riders.enabled && riders.in_clustering {
            return milp.with_rides(crate::cluster::RideOptions {
                checks: riders.checks.clone(),
                carried: riders.carried,
                reach: riders.reach,
            });
        }
        Ok(milp)
    }

    pub(super) fn validate_stages(&self) -> Result<()> {
        self.clustering.validate()?;
        self.milp.validate()?;
        self.pushing.validate()?;
        self.socp.validate()?;
        self.single.validate()?;
        self.multi.validate()?;
        self.pricing.validate()?;
        self.riders.validate()?;
        crate::error::count_in_range(
            "run",
            "max_failed_attempts",
            self.run.max_failed_attempts,
            (1, 1000),
            "each attempt is a planning call",
        )?;
        crate::error::count_in_range(
            "run",
            "max_corrections",
            self.run.max_corrections,
            (0, 10),
            "each round is an observation and more pushes within one trip",
        )?;
        crate::error::in_range(
            "run",
            "max_trips_per_object",
            self.run.max_trips_per_object,
            (0.01, 100.0),
            "trips per object; every object needs at most one trip when grasps hold",
        )?;
        crate::error::in_range(
            "run",
            "reach_past_edge",
            self.run.reach_past_edge,
            (0.0, 0.2),
            "metres past the workspace's edge; 0 turns it off",
        )?;
        Ok(())
    }
}
