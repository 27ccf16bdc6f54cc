//! Grasping: where to put the jaws so one closing lifts as many objects as possible, reliably.
//!
//! - [`JawPose`]: centre, closing axis and opening of the parallel jaws; the plates' footprints and the
//!   region between them.
//! - [`GraspModel`]: what a closing does. The caught objects slide into a row (`model.rs`); then by
//!   default the closing is simulated in the plane, objects sliding and turning on the table while the
//!   coupled plates close (`closing.rs`), or judged by the first, analytic model (objects slide
//!   without turning, Nguyen's condition object by object).
//!   Optionally a pressed object must also rest with friction to spare (`equilibrium.rs`).
//! - [`GraspOutcome`]: how a planner judges candidates: the model on the observed table, on noisy
//!   copies of it ([`ModelOutcome`], robust), or a rollout in the simulator (`exec::Rollout`).
//!   `ModelOutcome` remembers the closings it has judged by their exact inputs (`memory.rs`).
//! - Locality: a closing involves only the objects within reach of the jaws (`opening/2 + plate
//!   length + 2 cm`, beyond each object's own radius), found through the scene's sorted bounding discs
//!   ([`Scene::near`]), so judging a candidate costs the same on a table of 34 or 1000 objects.
//! - [`SingleObject`]: a stable frictional two-jaw grasp of one object, jaws clear of neighbours.
//! - [`MultiObject`]: an analytic stand-in for MOG-Net: candidates screened for clearance and a row,
//!   judged by the outcome model, ranked by the estimated probability that every object is carried.
//!
//! The mechanics, the noise and the measured agreement with the simulator are in
//! `formulations/grasping.md`.

mod body;
mod closing;
mod equilibrium;
mod jaws;
mod memory;
mod model;
mod multi;
mod outcome;
mod single;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::outcome::Outcome;
use crate::scene::{ObjectId, Scene};

pub use jaws::JawPose;
pub(crate) use memory::Memory;
pub use model::{Body, GraspModel, Mechanics, Squeeze, caught_objects, squeeze, squeeze_bodies};
pub use multi::{MultiObject, MultiObjectSettings, centre_line_offset};
pub use outcome::{
    GraspOutcome, Judgement, ModelOutcome, Noise, NoisyCopy, noisy_copy, sample_seed,
};
pub use single::{SingleObject, SingleObjectSettings};

/// A planned grasp: where the jaws go and what the planner expects them to carry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
