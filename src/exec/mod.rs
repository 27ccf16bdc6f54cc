//! Executors: what carries out pushes and grasps and reports the table afterwards.
//!
//! The closed loop talks to an [`Executor`] only: it resets it to a scene, asks for pushes and grasps,
//! and observes the table after each trip. [`Ideal`] applies plans exactly (a planner's own
//! prediction); [`Sim`] carries them out in a physics engine (`sim/`); [`ur5::Ur5`] drives a real UR5 with a
//! Robotiq 2F-85 over the controller's own interfaces (`ur5/`).

mod ideal;
mod kind;
#[cfg(feature = "sim")]
pub mod sim;
#[cfg(feature = "robot")]
pub mod ur5;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::grasp::Grasp;
use crate::plan::Rider;
use crate::push::Push;
use crate::scene::{Object, ObjectId, Scene};

pub use ideal::Ideal;
pub use kind::ExecutorKind;
#[cfg(feature = "sim")]
pub use sim::{CalibrationError, Closing, FingerDrive, Rollout, Sim, SimCamera, SimSettings};

/// Why a rider still standing on another object (its row was not carried) cannot be planned for:
/// the reason [`Executor::lost`] gives for it.
pub const RIDER_LEFT: &str = "a rider left on another object";

/// A finger or plate came down on top of an object while the gripper descended, so the action was
/// stopped there (a real arm would have been stopped, or would have crushed the object).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Landing {
    /// The object landed on.
    pub object: ObjectId,
}

/// What a grasp did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GraspResult {
    /// Objects carried to the bin (empty for a failed grasp).
    pub carried: Vec<ObjectId>,
    /// Set when the descent stopped on an object; nothing is carried then.
    pub landing: Option<Landing>,
}

impl GraspResult {
    /// A grasp that went as far as the lift and carried `carried`.
    pub fn carried(carried: Vec<ObjectId>) -> Self {
        Self {
            carried,
            landing: None,
        }
    }
}

/// Something that carries out pushes and grasps.
pub trait Executor {
    /// A short name for logs and tables (`ideal`, `sim`, `ur5`).
    fn name(&self) -> &'static str;

    /// Sets the table to `scene`.
    ///
    /// # Errors
    /// When the executor cannot represent the scene.
    fn reset(&mut self, scene: &Scene) -> Result<()>;

    /// Carries out one fork push; returns the landing that stopped it, if its fingers came down on an
    /// object.
    ///
    /// # Errors
    /// Environment faults only (a lost robot link); a push that goes badly shows in the next
    /// observation.
    fn push(&mut self, push: &Push) -> Result<Option<Landing>>;

    /// Lowers the open jaws, closes them as planned, lifts and carries what they hold to the bin.
    ///
    /// # Errors
    /// Environment faults only.
    fn grasp(&mut self, grasp: &Grasp) -> Result<GraspResult>;

    /// Picks the rider's object with its single-object grasp, carries it over the row and puts it
    /// down on the row's top at its place, then opens the jaws and rises
    /// (`formulations/stacking.md`). Returns the landing that stopped it, if the gripper came down
    /// on an object while descending to the pick. The default refuses: an executor that cannot
    /// place riders says so.
    ///
    /// # Errors
    /// [`crate::Error::Misuse`] from an executor without the place action; environment faults.
    fn place(&mut self, rider: &Rider) -> Result<Option<Landing>> {
        Err(crate::Error::misuse(
            self.name(),
            format!(
                "this executor cannot place riders (object {} was to ride)",
                rider.object
            ),
        ))
    }

    /// The table as the executor sees it now.
    ///
    /// # Errors
    /// Environment faults only.
    fn observe(&mut self) -> Result<Scene>;

    /// Objects still on the table that the last observation left out because nothing can be planned
    /// for them, with the reason (toppled, outside the workspace). Empty by default.
    fn lost(&self) -> Vec<(ObjectId, &'static str)> {
        Vec::new()
    }

    /// Of the objects the last observation reported lost as outside the workspace, those the camera
    /// still sees lying on the table past its edge, at their poses as seen (with the camera's
    /// error), each outline wholly outside or straddling the edge. The closed loop may take them
    /// one at a time by themselves once nothing else is left (`run.reach_past_edge`). Empty by
    /// default: an executor that does not look past the edge reports nothing there.
    fn past_edge(&self) -> Vec<Object> {
        Vec::new()
    }
}
