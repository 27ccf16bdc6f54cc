//! What planners return and what a whole run records.
//!
//! - [`Outcome`]: a planner's answer with its [`Status`] and [`Stats`]. `Err` is kept for misuse; a
//!   stage that finds nothing good says so in its status.
//! - [`Plan`]: the record of a closed-loop run (the paper's Algorithm 1): for every trip, the scene it
//!   was planned on, the clustering, the chosen cluster, the pushes, the grasp and what was carried.
//!   [`verify`] checks a plan independently of the planners.

mod file;
mod shared;
mod verify;

pub use crate::outcome::{Outcome, Stats, Status};
pub use file::{LookRecord, Moved, ObjectChange, TripRecord};
pub use shared::SharedScene;
pub use verify::{Violation, verify, verify_clustering, verify_record, verify_trip};

use serde::{Deserialize, Serialize};

use crate::cluster::Clustering;
use crate::grasp::{Grasp, JawPose};
use crate::push::{Push, SkippedPush};
use crate::scene::{ObjectId, Pose, SceneSpec};

/// One trip of a run: plan on an observation, push, grasp, carry to the bin.
#[derive(Clone, Debug, PartialEq)]
pub struct Trip {
    /// The observation this trip was planned on (objects unchanged since the trip before are
    /// shared with it).
    pub scene: SharedScene,
    /// What the trip did, as planned on `scene` and amended at each look: its clustering and
    /// cluster, its pushes in execution order (corrective pushes planned on a later look
    /// included), the pushes not made, and the grasp, planned on the table predicted after the
    /// pushes (`scene` after all of them, or, when the trip looked again, the last look's scene
    /// after the pushes that follow it). `judged`, `ahead` and `ahead_rows` are the first plan's;
    /// `push_statuses` holds the first plan's, then one per look whose corrective pushes were made
    /// (empty in plans written before statuses were recorded); `riders` are the last plan's, put
    /// down before the grasp.
    pub plan: TripPlan,
    /// New observations made during the trip, in order, each after some of its pushes: what follows
    /// a look (corrective pushes, the grasp) was planned on it. Empty when the whole trip was
    /// planned on `scene`.
    pub looks: Vec<Look>,
    /// The objects the executor reports carried to the bin (empty for a failed grasp).
    pub carried: Vec<ObjectId>,
    /// Set when an action was stopped because the gripper came down on an object; the rest of the
    /// trip was not carried out.
    pub fault: Option<Fault>,
    /// Objects the executor first reported lost (outside the workspace, toppled, lying on another
    /// object) at an observation after this trip's actions began: at one of its looks, or at the
    /// observation that followed it. Empty with the ideal executor.
    pub lost: Vec<LostObject>,
}

/// A trip as a policy plans it: what to push, then where to grasp (`policy::Policy::plan_trip`).
/// A run's [`Trip`] holds one as it was carried out, amended by the looks during the trip, with
/// what the executor reported.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TripPlan {
    /// The clustering of the scene (empty for policies that do not cluster).
    pub clustering: Clustering,
    /// Position in `clustering.clusters` of the cluster this trip works on (`None` when not clustered).
    pub cluster: Option<usize>,
    /// The fork pushes, in execution order.
    pub pushes: Vec<Push>,
    /// Pushes that were not planned or not made, with their reasons.
    pub skipped_pushes: Vec<SkippedPush>,
    /// The grasp, planned on the scene predicted after the pushes.
    pub grasp: Grasp,
    /// With pushes, the grasp planner's estimate of the probability that the grasp they prepare
    /// carries every object it is planned for, on the table predicted after them (the `p` of the
    /// expected-time price): this trip's grasp, or, for pushes ahead (`pricing.push_ahead`), the
    /// grasp of the pushed row a later trip is to make. `None` without pushes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub judged: Option<f64>,
    /// When pushing ahead (`pricing.push_ahead`): the objects this trip's pushes arrange into rows
    /// for later trips' grasps, none of them taken by this trip's grasp. Empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ahead: Vec<ObjectId>,
    /// Those objects row by row, in the order the rows are pushed, each with the grasp judge's
    /// probability for the grasp a later trip is to make of it (the first row's is `judged`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ahead_rows: Vec<AheadRow>,
    /// The status of each push planner answer whose pushes the trip makes, in order (one per row
    /// pushed ahead): [`Status::BestFound`] for the SOCP's search, [`Status::TimeLimit`] when its
    /// `time_limit` cut it short, [`Status::Heuristic`] for the paper's pushes and for a push that
    /// only separates two objects. Empty without pushes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub push_statuses: Vec<Status>,
    /// Objects picked by themselves after the pushes and put down on the top of the row the grasp
    /// takes, in order, to ride with it (`formulations/stacking.md`). Empty without riders.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub riders: Vec<Rider>,
}

impl TripPlan {
    /// A trip that makes `grasp` of `cluster` in `clustering` and nothing else: no pushes, no
    /// riders.
    pub fn grasping(clustering: Clustering, cluster: Option<usize>, grasp: Grasp) -> Self {
        Self {
            clustering,
            cluster,
            pushes: Vec::new(),
            skipped_pushes: Vec::new(),
            grasp,
            judged: None,
            ahead: Vec::new(),
            ahead_rows: Vec::new(),
            push_statuses: Vec::new(),
            riders: Vec::new(),
        }
    }
}

/// An object picked by itself and put down on the top of a row just before the row's grasp, so
/// that it travels to the bin on the row (`formulations/stacking.md`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Rider {
    /// The object.
    pub object: ObjectId,
    /// Its single-object grasp where it lies, planned on the table predicted after the pushes.
    pub pick: Grasp,
    /// Where it is put down: its pose seen from above.
    pub place: Pose,
    /// The jaws when it stands at `place` (the pick's jaws moved with it), where they open to let
    /// it go.
    pub release: JawPose,
    /// The height of its base above the table once put down (the row's top), metres.
    pub base: f64,
    /// The objects of the row it rests on.
    pub on: Vec<ObjectId>,
}

/// A row a trip pushed ahead for a later trip's grasp.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AheadRow {
    /// The objects a later grasp is planned to take together.
    pub objects: Vec<ObjectId>,
    /// The grasp planner's estimate that such a grasp carries them all, on the table predicted
    /// after the trip's pushes.
    pub judged: f64,
}

/// An object that is still somewhere but can no longer be planned for, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LostObject {
    /// The object.
    pub object: ObjectId,
    /// The executor's reason, such as "outside the workspace" or "toppled".
    pub reason: String,
}

/// A new observation during a trip, after its first `after_pushes` pushes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Look {
    /// How many of the trip's pushes had been made.
    pub after_pushes: usize,
    /// The table as observed then (same workspace and gripper as the trip's scene).
    #[schemars(with = "SceneSpec")]
    pub scene: SharedScene,
}

impl Trip {
    /// The scene on which the trip's pushes from `start` on were planned, and that start: the last
    /// look's, or the trip's own scene from push 0.
    pub fn last_plan_scene(&self) -> (&SharedScene, usize) {
        self.looks
            .last()
            .map_or((&self.scene, 0), |look| (&look.scene, look.after_pushes))
    }
}

/// The gripper came down on top of an object while descending, which stopped the trip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "during", rename_all = "snake_case")]
pub enum Fault {
    /// During the descent of a fork push; later pushes and the grasp were not made.
    Push {
        /// The push, counted from 0 within the trip (over all its pushes, corrective ones included).
        push: usize,
        /// The object landed on.
        object: ObjectId,
    },
    /// During the grasp's descent; nothing was carried.
    Grasp {
        /// The object landed on.
        object: ObjectId,
    },
    /// During the descent to a rider's pick; later riders and the grasp were not made.
    Place {
        /// The rider, counted from 0 within the trip.
        rider: usize,
        /// The object landed on.
        object: ObjectId,
    },
}

impl std::fmt::Display for Fault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Push { push, object } => write!(
                f,
                "push {} stopped: a finger came down on object {object}",
                push + 1
            ),
            Self::Grasp { object } => {
                write!(f, "grasp stopped: a plate came down on object {object}")
            }
            Self::Place { rider, object } => write!(
                f,
                "rider {} stopped: a plate came down on object {object}",
                rider + 1
            ),
        }
    }
}

/// The riders `trip` put down.
fn placed_riders(trip: &Trip) -> impl Iterator<Item = &Rider> {
    let made = match trip.fault {
        None | Some(Fault::Grasp { .. }) => trip.plan.riders.len(),
        Some(Fault::Place { rider, .. }) => rider,
        Some(Fault::Push { .. }) => 0,
    };
    trip.plan.riders.iter().take(made)
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RunStatus {
    /// Every object reached the bin.
    Cleared,
    /// The run stopped with objects left on the table.
    Stopped {
        /// Objects left.
        remaining: Vec<ObjectId>,
        /// Why it stopped.
        reason: StopReason,
    },
}

/// Why a run stopped with objects left.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum StopReason {
    /// Every object left is lost to planning: toppled, outside the workspace, lying on another.
    NothingPlannable {
        /// Each reason with how many objects it holds for.
        lost: Vec<(String, usize)>,
    },
    /// Every object left is wider than the jaw gap.
    AllTooWide,
    /// Attempts in a row found no grasp or carried nothing.
    FailedAttempts {
        /// How many.
        count: usize,
    },
    /// The run made as many trips as it may.
    TripLimit {
        /// The limit.
        limit: usize,
    },
    /// The run was not finished (an executor fault, or the record was taken while it went on).
    Interrupted,
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NothingPlannable { lost } => {
                let counts: Vec<String> =
                    lost.iter().map(|(why, n)| format!("{n} {why}")).collect();
                write!(
                    f,
                    "nothing left that can be planned for: {}",
                    counts.join(", ")
                )
            }
            Self::AllTooWide => write!(f, "every object left is wider than the jaw gap"),
            Self::FailedAttempts { count } => write!(
                f,
                "{count} attempts in a row found no grasp or carried nothing"
            ),
            Self::TripLimit { limit } => write!(f, "trip limit of {limit} reached"),
            Self::Interrupted => write!(f, "interrupted before it ended"),
        }
    }
}

/// The record of a closed-loop run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Plan {
    /// The policy's name (`sog`, `mog`, `push-mog`).
    pub policy: String,
    /// The executor's name (`ideal`, `sim`).
    pub executor: String,
    /// Seed of the run's own choices (which cluster next).
    pub seed: u64,
    /// The policy's effective settings.
    pub settings: serde_json::Value,
    /// The trips in order. Written compactly: each trip after the first gives its scene as the
    /// change from the trip before (`file.rs`).
    #[serde(with = "file")]
    #[schemars(with = "Vec<TripRecord>")]
    pub trips: Vec<Trip>,
    /// Planning attempts that produced no grasp, with their reasons.
    pub failed_attempts: Vec<String>,
    /// How the run ended.
    pub status: RunStatus,
    /// Robot time of the run by the policy's time model: every trip and every push, seconds.
    pub seconds: f64,
}

impl Plan {
    /// Objects carried over all trips.
    pub fn objects_carried(&self) -> usize {
        self.trips.iter().map(|t| t.carried.len()).sum()
    }

    /// Objects per trip (OpT): objects carried divided by trips made; 0 for a run with no trips.
    pub fn objects_per_trip(&self) -> f64 {
        if self.trips.is_empty() {
            0.0
        } else {
            self.objects_carried() as f64 / self.trips.len() as f64
        }
    }

    /// Trips whose clustering was not proven optimal by its clusterer (`clustering.status` other
    /// than `optimal`), or `None` when no trip records a clustering status (policies that do not
    /// cluster, or plans written before statuses were recorded).
    pub fn unproven_clusterings(&self) -> Option<usize> {
        let statuses: Vec<&Status> = self
            .trips
            .iter()
            .filter_map(|t| t.plan.clustering.status.as_ref())
            .collect();
        (!statuses.is_empty()).then(|| statuses.iter().filter(|s| !s.is_proven()).count())
    }

    /// How many of the push planner's answers whose pushes were made had each status (by
    /// [`Status::name`]), over all trips; empty without pushes or in plans written before push
    /// statuses were recorded.
    pub fn push_statuses(&self) -> std::collections::BTreeMap<String, usize> {
        let mut counts = std::collections::BTreeMap::new();
        for status in self.trips.iter().flat_map(|t| &t.plan.push_statuses) {
            *counts.entry(status.name().to_string()).or_insert(0) += 1;
        }
        counts
    }

    /// Fork pushes made over all trips.
    pub fn push_count(&self) -> usize {
        self.trips.iter().map(|t| t.plan.pushes.len()).sum()
    }

    /// Total distance objects were pushed, metres.
    pub fn push_distance(&self) -> f64 {
        self.trips
            .iter()
            .flat_map(|t| &t.plan.pushes)
            .map(|p| p.distance)
            .sum::<f64>()
            + 0.0 // an empty sum is −0.0; print it as 0
    }

    /// Objects carried per hour of robot time (0 for a run that took no time).
    pub fn picks_per_hour(&self) -> f64 {
        if self.seconds > 0.0 {
            3600.0 * self.objects_carried() as f64 / self.seconds
        } else {
            0.0
        }
    }

    /// Trips that carried nothing.
    pub fn failed_grasps(&self) -> usize {
        self.trips.iter().filter(|t| t.carried.is_empty()).count()
    }

    /// Riders put down on rows: every rider of a trip, less those after a landing on the way to
    /// one (`Fault::Place`) and all of a trip stopped during its pushes.
    pub fn riders_placed(&self) -> usize {
        self.trips.iter().map(|t| placed_riders(t).count()).sum()
    }

    /// Riders put down on rows that their trip did not carry: they fell, slid or were left behind.
    pub fn riders_lost(&self) -> usize {
        self.trips
            .iter()
            .map(|t| {
                placed_riders(t)
                    .filter(|r| !t.carried.contains(&r.object))
                    .count()
            })
            .sum()
    }

    /// Trips stopped because the gripper came down on an object.
    pub fn landings(&self) -> usize {
        self.trips.iter().filter(|t| t.fault.is_some()).count()
    }

    /// Trips that took an object from past the workspace's edge (`run.reach_past_edge`): those
    /// planned on a table whose workspace is not the first trip's.
    pub fn trips_past_edge(&self) -> usize {
        let Some(first) = self.trips.first() else {
            return 0;
        };
        self.trips
            .iter()
            .filter(|t| t.scene.workspace != first.scene.workspace)
            .count()
    }
}
