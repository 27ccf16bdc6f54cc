//! Why a policy plans no trip on a table, typed, and the answer of [`super::Policy::plan_trip`]
//! that carries either a trip or that reason.
//!
//! The closed loop counts such answers as fruitless attempts and stops after
//! `run.max_failed_attempts` in a row; a plan file keeps each one's text (`failed_attempts`), which
//! is the reason's [`std::fmt::Display`].

use std::fmt;

use serde::{Deserialize, Serialize};

use super::TripPlan;
use crate::outcome::{Stats, Status};
use crate::scene::ObjectId;

/// Why there is no trip to make. More reasons may come: match with a wildcard arm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum NoTrip {
    /// Nothing is on the table.
    EmptyTable,
    /// Every object is wider than the jaw gap (`sog`).
    NothingFitsTheJaws,
    /// No cluster holds an object narrower than the jaw gap.
    NoClusterFitsTheJaws,
    /// The single-object grasp planner found no grasp of this object (`sog`; with grasps that
    /// failed before to avoid, of any object: the first object tried).
    NoGraspOfObject {
        /// The object tried first.
        object: ObjectId,
        /// The grasp planner's status for it, with its reason.
        grasp: Status,
    },
    /// The chosen cluster could be taken neither pushed, nor together as it lies, nor one object by
    /// itself, nor after pushing two of its objects apart.
    NoGraspOfCluster {
        /// The cluster's objects.
        members: Vec<ObjectId>,
        /// The single-object grasp planner's status for them, with its reason.
        grasp: Status,
    },
}

impl fmt::Display for NoTrip {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmptyTable => write!(f, "the table is empty"),
            Self::NothingFitsTheJaws => write!(f, "no object narrower than the jaw gap"),
            Self::NoClusterFitsTheJaws => {
                write!(f, "no cluster with an object narrower than the jaw gap")
            }
            Self::NoGraspOfObject { object, grasp } => {
                write!(f, "object {object}: {}", why(grasp))
            }
            Self::NoGraspOfCluster { members, grasp } => {
                let ids: Vec<u32> = members.iter().map(|id| id.0).collect();
                write!(f, "cluster {ids:?}: {}", why(grasp))
            }
        }
    }
}

/// A grasp planner's reason for no answer, or its status when it gave none.
fn why(status: &Status) -> String {
    match status {
        Status::Failed { reason } => reason.clone(),
        other => format!("{other:?}"),
    }
}

/// A policy's answer for the next trip: the trip, or why there is none, and what planning it took.
/// The trip's own statuses are in it: its clustering's and each push answer's
/// ([`TripPlan::push_statuses`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TripAnswer {
    /// The trip, or why there is none.
    pub trip: Result<TripPlan, NoTrip>,
    /// Planning time, and the clustering's in the counter `clustering_seconds`.
    pub stats: Stats,
}

impl TripAnswer {
    /// The trip, if there is one.
    pub fn into_trip(self) -> Option<TripPlan> {
        self.trip.ok()
    }

    /// The status a generic planner answer would carry: [`Status::Heuristic`] for a trip (a
    /// policy's trip claims no optimum; its stages' statuses are in the trip), and
    /// [`Status::Failed`] with the reason's text for none.
    pub fn status(&self) -> Status {
        match &self.trip {
            Ok(_) => Status::Heuristic,
            Err(no_trip) => Status::Failed {
                reason: no_trip.to_string(),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::NoTrip;
    use crate::outcome::Status;
    use crate::scene::ObjectId;

    #[test]
    fn a_reason_reads_as_the_loop_has_always_written_it() {
        let grasp = Status::Failed {
            reason: "too wide".to_string(),
        };
        let cluster = NoTrip::NoGraspOfCluster {
            members: vec![ObjectId(4), ObjectId(9)],
            grasp: grasp.clone(),
        };
        assert_eq!(cluster.to_string(), "cluster [4, 9]: too wide");
        let object = NoTrip::NoGraspOfObject {
            object: ObjectId(4),
            grasp: Status::Infeasible,
        };
        assert_eq!(object.to_string(), "object 4: Infeasible");
        let written = serde_json::to_value(&cluster).unwrap();
        assert_eq!(
            written["no_grasp_of_cluster"]["members"],
            serde_json::json!([4, 9])
        );
        let read: NoTrip = serde_json::from_value(written).unwrap();
        assert_eq!(read, cluster);
    }
}
