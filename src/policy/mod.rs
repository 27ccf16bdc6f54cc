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
//! When the push planner finds no row for a whole cluster of three or more, its largest sub-clusters
//! are tried and the object left out waits for a later trip. When the multi-object planner finds nothing
//! for a cluster, a single-object grasp of one of its
//! objects is tried. An attempt that yields no grasp is recorded with its reason and costs no trip; a
//! grasp that carries nothing is a trip (a failed grasp). The run stops when the table is clear, when
//! every object left is wider than the jaw gap, after `max_failed_attempts` fruitless attempts in a
//! row, or at the trip limit; it never loops forever.

use std::str::FromStr;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::cluster::{Clusterer, Hierarchical, HierarchicalSettings, Milp, MilpSettings};
use crate::error::{Error, Result};
use crate::exec::{Executor, Ideal, Rollout, SimSettings};
use crate::grasp::{
    Grasp, GraspModel, MultiObject, MultiObjectSettings, SingleObject, SingleObjectSettings,
};
use crate::plan::Plan;
use crate::push::{
    ForkSettings, PushPlanner, Socp, SocpSettings, TowardCentral, TowardCentralSettings,
};
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

/// Settings of every stage of a policy and of the loop. Each physical setting is set once here and
/// shared by every stage that needs it (the grasp model, the fork-push geometry, the shortest push,
/// the time model, the heuristic clustering that seeds the MILP); the stages' own copies are filled
/// from these when the policy is built and are not read from settings files.
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
}

impl Default for LoopSettings {
    fn default() -> Self {
        Self {
            max_failed_attempts: 10,
            max_trips_per_object: 3.0,
        }
    }
}

impl PolicySettings {
    /// Checks every stage's settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.effective().validate_stages()
    }

    /// The settings with every stage's copy of a shared setting filled from its single source.
    pub fn effective(&self) -> Self {
        let mut s = self.clone();
        s.milp.time_model = s.time_model.clone();
        s.milp.heuristic = s.clustering.clone();
        s.milp.min_push = s.min_push;
        s.milp.row_margin = s.socp.margin;
        s.pushing.fork = s.fork.clone();
        s.pushing.min_push = s.min_push;
        s.socp.model = s.grasp_model.clone();
        s.socp.fork = s.fork.clone();
        s.socp.min_push = s.min_push;
        s.single.model = s.grasp_model.clone();
        s.multi.model = s.grasp_model.clone();
        s
    }

    fn validate_stages(&self) -> Result<()> {
        if !(self.min_push.is_finite() && (0.0..=0.1).contains(&self.min_push)) {
            return Err(Error::field(
                "policy",
                "min_push",
                format!("must be between 0 and 0.1 m, got {}", self.min_push),
            ));
        }
        self.grasp_model.validate()?;
        self.fork.validate()?;
        self.clustering.validate()?;
        self.milp.validate()?;
        self.pushing.validate()?;
        self.socp.validate()?;
        self.single.validate()?;
        self.multi.validate()?;
        self.time_model.validate()?;
        if self.run.max_failed_attempts == 0 {
            return Err(Error::field(
                "run",
                "max_failed_attempts",
                "must be at least 1",
            ));
        }
        if !(self.run.max_trips_per_object.is_finite() && self.run.max_trips_per_object > 0.0) {
            return Err(Error::field(
                "run",
                "max_trips_per_object",
                format!("must be positive, got {}", self.run.max_trips_per_object),
            ));
        }
        Ok(())
    }
}

/// A policy ready to run.
#[derive(Clone, Debug)]
pub struct Policy {
    kind: PolicyKind,
    settings: PolicySettings,
    clusterer: AnyClusterer,
    pusher: AnyPusher,
    single: SingleObject,
    multi: MultiObject,
}

/// One of the clusterers, chosen by the settings.
#[derive(Clone, Debug)]
enum AnyClusterer {
    Hierarchical(Hierarchical),
    Milp(Milp),
}

impl AnyClusterer {
    fn get(&self) -> &dyn Clusterer {
        match self {
            Self::Hierarchical(c) => c,
            Self::Milp(c) => c,
        }
    }
}

/// One of the push planners, chosen by the policy.
#[derive(Clone, Debug)]
enum AnyPusher {
    TowardCentral(TowardCentral),
    Socp(Socp),
}

impl AnyPusher {
    fn get(&self) -> &dyn PushPlanner {
        match self {
            Self::TowardCentral(p) => p,
            Self::Socp(p) => p,
        }
    }
}

mod run;
mod trip;

pub use run::{Run, RunTiming, run_seconds};
pub use trip::{TripContext, TripPlan};

impl Policy {
    /// A policy with these settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(kind: PolicyKind, settings: PolicySettings) -> Result<Self> {
        settings.validate()?;
        let settings = settings.effective();
        Ok(Self {
            kind,
            clusterer: if kind.optimal_clustering() {
                AnyClusterer::Milp(Milp::new(settings.milp.clone())?)
            } else {
                AnyClusterer::Hierarchical(Hierarchical::new(settings.clustering.clone())?)
            },
            pusher: if kind.optimal_pushing() {
                AnyPusher::Socp(Socp::new(settings.socp.clone())?)
            } else {
                AnyPusher::TowardCentral(TowardCentral::new(settings.pushing.clone())?)
            },
            single: SingleObject::new(settings.single.clone())?,
            multi: if settings.rollout {
                MultiObject::with_outcome(
                    settings.multi.clone(),
                    Arc::new(Rollout {
                        settings: SimSettings::default(),
                        samples: settings.multi.samples,
                        noise: settings.multi.noise.clone(),
                    }),
                )?
            } else {
                MultiObject::new(settings.multi.clone())?
            },
            settings,
        })
    }

    /// Which policy this is.
    pub fn kind(&self) -> PolicyKind {
        self.kind
    }

    /// The effective settings.
    pub fn settings(&self) -> &PolicySettings {
        &self.settings
    }

    /// An executor that applies this policy's plans exactly, judging grasps with its grasp model.
    pub fn ideal(&self) -> Ideal {
        Ideal::new(self.settings.grasp_model.clone())
    }

    /// Grasps of `targets` the multi-object planner refuses although they catch two or more objects
    /// and land on nothing, evenly spread over its candidates (see [`MultiObject::refused`]).
    ///
    /// # Errors
    /// An id that is not in the scene.
    pub fn refused_candidates(&self, scene: &Scene, targets: &[ObjectId]) -> Result<Vec<Grasp>> {
        let all = self.multi.refused(scene, targets)?;
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
