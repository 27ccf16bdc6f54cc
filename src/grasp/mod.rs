//! Grasping: where to put the jaws so one closing lifts as many objects as possible, reliably.
//!
//! - [`JawPose`]: centre, closing axis and opening of the parallel jaws; the plates' footprints and the
//!   region between them.
//! - [`GraspModel`]: what a closing does. The caught objects slide into a row (`model/row.rs`); then by
//!   default the closing is simulated in the plane, objects sliding and turning on the table while the
//!   coupled plates close (`closing/`), or judged by the first, analytic model (objects slide
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
use crate::outcome::{Abilities, Outcome};
use crate::scene::{ObjectId, Scene};

pub use jaws::JawPose;
pub(crate) use memory::Memory;
pub use model::{
    Body, GraspModel, Mechanics, Squeeze, caught_objects, closed_motions, squeeze, squeeze_bodies,
};
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

/// What a policy asks a grasp planner: a grasp that carries at least `min_objects` of `targets`.
///
/// ```
/// use pushmog::grasp::{GraspPlanner, GraspRequest, MultiObject};
/// use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
/// let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 1).unwrap();
/// let targets: Vec<_> = scene.objects().iter().take(3).map(|o| o.id).collect();
/// // Two or more of the first three objects at once, or nothing.
/// let answer = MultiObject::default().plan_request(&GraspRequest::new(&scene, &targets).several()).unwrap();
/// if let Some(grasp) = answer.value {
///     assert!(grasp.objects.len() >= 2);
/// }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct GraspRequest<'a> {
    /// The table: as observed, or as predicted after pushes.
    pub scene: &'a Scene,
    /// The objects the grasp is for.
    pub targets: &'a [ObjectId],
    /// Suggested jaw poses, for instance the grasp a push planner arranged a row for. Planners that
    /// cannot use hints ignore them.
    pub hints: &'a [JawPose],
    /// Objects standing where pushes are meant to leave them rather than where a camera saw them, so
    /// less certain of place: the built-in planner keeps its plates further from them.
    pub pushed: &'a [ObjectId],
    /// Jaws of grasps that failed before: never propose jaws in the same place
    /// ([`JawPose::same_place`]).
    pub avoid: &'a [JawPose],
    /// Fewest of `targets` the grasp must be predicted to carry: 1, or 2 when the policy asks for a
    /// multi-object grasp and would otherwise push nothing or take one object by itself.
    pub min_objects: usize,
}

impl<'a> GraspRequest<'a> {
    /// A grasp of at least one of `targets` on the table as it is, with no hints and nothing to avoid.
    pub fn new(scene: &'a Scene, targets: &'a [ObjectId]) -> Self {
        Self {
            scene,
            targets,
            hints: &[],
            pushed: &[],
            avoid: &[],
            min_objects: 1,
        }
    }

    /// With these suggested jaw poses.
    pub fn hints(self, hints: &'a [JawPose]) -> Self {
        Self { hints, ..self }
    }

    /// With these objects placed by pushes, not yet seen where they stand.
    pub fn pushed(self, pushed: &'a [ObjectId]) -> Self {
        Self { pushed, ..self }
    }

    /// Never in the same place as these jaws.
    pub fn avoiding(self, avoid: &'a [JawPose]) -> Self {
        Self { avoid, ..self }
    }

    /// Two or more of the targets, or nothing.
    pub fn several(self) -> Self {
        Self {
            min_objects: 2,
            ..self
        }
    }
}

/// A way to choose a grasp among some target objects. A policy asks its grasp planners through
/// [`GraspPlanner::plan_request`] only, so a planner of one's own plugs into any policy
/// (`PolicyBuilder::multi_object_planner` in `policy`).
pub trait GraspPlanner {
    /// A short name for logs and tables (`single-object`, `multi-object`).
    fn name(&self) -> &'static str;

    /// What its answers can claim ([`Abilities`]); by default, none.
    fn abilities(&self) -> Abilities {
        Abilities::heuristic(self.name())
    }

    /// Chooses a grasp that answers `request`; `None` (with the reason in the status) when there is
    /// none. The expected-time price reads the planner's estimate of the probability that the grasp
    /// carries every object it is planned for from the counter `probability` of the answer's stats
    /// (absent: priced as the least sure band).
    ///
    /// # Errors
    /// Only for misuse, such as an id that is not in the scene.
    fn plan_request(&self, request: &GraspRequest<'_>) -> Result<Outcome<Option<Grasp>>>;

    /// A grasp that carries at least one of `targets` on the table as it is.
    ///
    /// # Errors
    /// As [`GraspPlanner::plan_request`].
    fn plan(&self, scene: &Scene, targets: &[ObjectId]) -> Result<Outcome<Option<Grasp>>> {
        self.plan_request(&GraspRequest::new(scene, targets))
    }

    /// As [`GraspPlanner::plan`], also weighing the suggested jaw poses.
    ///
    /// # Errors
    /// As [`GraspPlanner::plan_request`].
    fn plan_with_hints(
        &self,
        scene: &Scene,
        targets: &[ObjectId],
        hints: &[JawPose],
    ) -> Result<Outcome<Option<Grasp>>> {
        self.plan_request(&GraspRequest::new(scene, targets).hints(hints))
    }
}
