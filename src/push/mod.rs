//! Pushing: move a cluster's objects together with fork pushes so one grasp can lift them.
//!
//! A *fork push* (Push-MOG paper) opens the jaws partly (30 % of the stroke by default) with the jaw
//! line perpendicular to the push, lowers the fingers behind the object and moves them in a straight
//! line; a vertex can sit between the fingers and an edge rests against both, so the object follows
//! the fingers without turning much. [`fork`] holds that geometry and its collision checks;
//! [`TowardCentral`] is the paper's Algorithm 3; [`Socp`] places targets by a second-order cone
//! program of least total push distance (`formulations/pushing.md`); [`predict`] moves objects to their
//! targets, as the paper does to plan the grasp before executing the pushes; [`separating_push`]
//! moves an object away from a neighbour it is stuck against, so one of them can be taken alone.
//! [`flush`] holds the geometry of flush pushes, which meet one face of the object flat so that it
//! slides without turning (the SOCP's `flush` setting).

mod central;
pub mod flush;
pub mod fork;
mod predict;
mod row;
mod separate;
mod socp;

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::outcome::{Abilities, Outcome};
use crate::scene::{ObjectId, Pose, Scene};

pub use central::{TowardCentral, TowardCentralSettings};
pub use fork::{ForkPush, ForkSettings, push_height};
pub use predict::predict;
pub use separate::separating_push;
pub use socp::{Socp, SocpSettings};

/// One planned fork push: an object translated along a straight line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Push {
    /// The object pushed.
    pub object: ObjectId,
    /// Its pose before the push.
    pub from: Pose,
    /// Its planned pose after the push (same yaw: pushes plan translations only, as in the paper).
    pub to: Pose,
    /// Unit push direction in the table frame.
    #[schemars(with = "[f64; 2]")]
    pub direction: Vector2<f64>,
    /// Push length, metres.
    pub distance: f64,
    /// The gripper's motion.
    pub fork: ForkPush,
}

impl Push {
    /// The displacement of the object, metres.
    pub fn displacement(&self) -> Vector2<f64> {
        self.direction * self.distance
    }

    /// Where the object's pose origin starts, metres.
    pub fn start_point(&self) -> Point2<f64> {
        Point2::new(self.from.x, self.from.y)
    }
}

/// Why an object of a cluster is not pushed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SkipReason {
    /// It is already within the stopping gap of its target; nothing to do.
    AlreadyInPlace,
    /// Its path meets an object outside the cluster before it comes close to the cluster.
    BlockedBy {
        /// The object in the way.
        object: ObjectId,
    },
    /// The fingers cannot be lowered behind it without touching another object.
    NoRoomForFingers {
        /// The object in the way.
        object: ObjectId,
    },
    /// The fingers would hit another object on their way.
    FingersHit {
        /// The object in the way.
        object: ObjectId,
    },
    /// The fingers would not meet the object (it fits between them).
    NoFingerContact,
    /// No row of the cluster fits the jaws on any axis tried (the push program is infeasible).
    NoRow,
    /// Pushed at any fingertip height the fingers can reach, the object would tip over rather than
    /// slide.
    WouldTip,
    /// Planned, but the grasp planner found no multi-object grasp on the table predicted after the
    /// pushes, so they were not made.
    NoGraspAfter,
    /// Planned, but after the pushes some pushed object could not be taken by itself if the
    /// multi-object grasp failed, so they were not made.
    DeadEnd,
    /// Planned, but when this object was pushed before in the run a finger came down on an object
    /// the camera does not see (outside the workspace), and this push would lower the fingers near
    /// there again, so the pushes were not made.
    LandedBefore {
        /// The object the finger came down on then.
        object: ObjectId,
    },
    /// A push to separate the object from a neighbour it is stuck against would meet another object,
    /// or leave it too near the workspace's edge.
    NoRoomToSeparate,
    /// With flush pushes (`socp.flush`), no face of the object lies flat across the push with room
    /// for the fingers, so the push would turn it.
    NotFlush,
    /// It would end against `object`, held in place and within `socp.held_edge_margin` of the
    /// workspace's edge along the push: pushed a little too far, it shoves `object` out of the
    /// workspace.
    WouldShoveOut {
        /// The object held in place near the edge.
        object: ObjectId,
    },
    /// Planned, but by the expected-time price (`formulations/picks-per-hour.md`) the pushes and the
    /// look after them cost more seconds than the trips they are expected to save.
    DoesNotPay {
        /// Expected seconds saved (positive) or lost (negative) by pushing.
        saving: f64,
    },
}

impl std::fmt::Display for SkipReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::AlreadyInPlace => write!(f, "already in place"),
            Self::BlockedBy { object } => write!(f, "path blocked by object {object}"),
            Self::NoRoomForFingers { object } => {
                write!(f, "no room to lower the fingers (object {object})")
            }
            Self::FingersHit { object } => write!(f, "fingers would hit object {object}"),
            Self::NoFingerContact => write!(f, "the object fits between the fingers"),
            Self::NoRow => write!(f, "no row of the cluster fits the jaws"),
            Self::WouldTip => write!(f, "it would tip over rather than slide"),
            Self::NotFlush => write!(f, "no face of it lies flat across the push"),
            Self::NoGraspAfter => write!(f, "no multi-object grasp after the pushes"),
            Self::WouldShoveOut { object } => write!(
                f,
                "it would end against object {object}, held near the workspace's edge"
            ),
            Self::DoesNotPay { saving } => {
                write!(
                    f,
                    "pushing would lose {:.1} s by the expected-time price",
                    -saving
                )
            }
            Self::LandedBefore { object } => write!(
                f,
                "a finger came down on object {object} when pushed before"
            ),
            Self::DeadEnd => write!(f, "it could not be taken alone after the pushes"),
            Self::NoRoomToSeparate => write!(f, "no clear path to push it away from its neighbour"),
        }
    }
}

/// An object that is not pushed, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SkippedPush {
    /// The object.
    pub object: ObjectId,
    /// Why.
    pub reason: SkipReason,
}

/// The pushes planned for one cluster.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PushPlan {
    /// Pushes in execution order.
    pub pushes: Vec<Push>,
    /// Objects not pushed, with reasons (never dropped silently).
    pub skipped: Vec<SkippedPush>,
    /// The grasp the pushes arrange the objects for, when the planner knows it.
    pub intended_grasp: Option<crate::grasp::JawPose>,
    /// Whether the planner's grasp model predicts the row held at the intended grasp (`None` for
    /// planners that do not judge their rows, such as the paper's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub row_held: Option<bool>,
}

/// A way to plan the pushes that bring one cluster together.
pub trait PushPlanner {
    /// A short name for logs and tables (`toward-central`, `socp`).
    fn name(&self) -> &'static str;

    /// What its answers can claim ([`Abilities`]); by default, none.
    fn abilities(&self) -> Abilities {
        Abilities::heuristic(self.name())
    }

    /// Plans the pushes for `cluster` (object ids of `scene`).
    ///
    /// # Errors
    /// Only for misuse, such as an id that is not in the scene.
    fn plan(&self, scene: &Scene, cluster: &[ObjectId]) -> Result<Outcome<PushPlan>>;
}
