//! Grasping: where to put the jaws so one closing lifts as many objects as possible.
//!
//! - [`JawPose`]: centre, closing axis and opening of the parallel jaws; the plates' footprints and the
//!   region between them.
//! - [`GraspModel`]: pushmog's analytic prediction of what a closing does: which objects end up in a
//!   row between the plates and whether friction holds that row (see `model.rs`).
//! - [`SingleObject`]: a stable frictional two-jaw grasp of one object, jaws clear of neighbours.
//! - [`MultiObject`]: an analytic stand-in for MOG-Net. It samples jaw poses over a cluster and ranks
//!   them by the objects [`GraspModel`] predicts held. MOG-Net is a learned network trained on physics
//!   rollouts; this is not that network, and its predictions are only as good as the model's
//!   assumptions (objects slide along the closing axis without turning; rigid frictional contacts).

mod closing;
mod jaws;
mod model;
mod multi;
mod outcome;
mod single;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::plan::Outcome;
use crate::scene::{ObjectId, Scene};

pub use jaws::JawPose;
pub use model::{Body, GraspModel, Mechanics, Squeeze, caught_objects, squeeze, squeeze_bodies};
pub use multi::{MultiObject, MultiObjectSettings, centre_line_offset};
pub use outcome::{GraspOutcome, Judgement, ModelOutcome, Noise, noisy_copy, sample_seed};
pub use single::{SingleObject, SingleObjectSettings};

/// A planned grasp: where the jaws go and what the planner expects them to carry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grasp {
    /// The jaws before closing.
    pub jaws: JawPose,
    /// Objects predicted to be carried.
    pub objects: Vec<ObjectId>,
    /// Predicted distance between the plate faces once closed on the row, metres.
    pub width: f64,
    /// Clearance between the open plates and the nearest object not grasped, metres (capped at
    /// 5 cm); larger is more forgiving of position errors.
    pub margin: f64,
}

/// A way to choose a grasp among some target objects.
pub trait GraspPlanner {
    /// A short name for logs and tables (`single-object`, `multi-object`).
    fn name(&self) -> &'static str;

    /// Chooses a grasp that carries at least one of `targets`; `None` (with the reason in the status)
    /// when there is none.
    ///
    /// # Errors
    /// Only for misuse, such as an id that is not in the scene.
    fn plan(&self, scene: &Scene, targets: &[ObjectId]) -> Result<Outcome<Option<Grasp>>>;

    /// As [`GraspPlanner::plan`], also weighing the suggested jaw poses (for instance the grasp a push
    /// planner arranged the objects for). Planners that cannot use hints ignore them.
    ///
    /// # Errors
    /// As [`GraspPlanner::plan`].
    fn plan_with_hints(
        &self,
        scene: &Scene,
        targets: &[ObjectId],
        hints: &[JawPose],
    ) -> Result<Outcome<Option<Grasp>>> {
        let _ = hints;
        self.plan(scene, targets)
    }
}
