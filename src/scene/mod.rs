//! The scene: objects on a rectangular workspace and the gripper that will clear them.
//!
//! A [`Scene`] is validated once, in [`Scene::new`] (from the JSON form [`SceneSpec`]) or
//! [`Scene::from_parts`] (from validated [`Object`]s); code that holds one trusts it: every outline is a
//! convex polygon, ids are unique, poses are finite, objects lie inside the workspace and do not overlap,
//! and every size, height, mass and yaw lies within the bounds `validation.rs` and `gripper.rs` state
//! with their reasons; a scene holds at most [`MAX_OBJECTS`] objects.
//! Each object's table-frame outline and minimum grasp diameter are computed at construction.
//!
//! The JSON form is
//! `{ "workspace": {"min": [x, y], "max": [x, y]}, "gripper": {…}, "objects": [{"id", "vertices", "height", "pose"}] }`
//! with every length in metres and every angle in radians; `pushmog schema scene` prints its JSON Schema.

mod generator;
mod gripper;
mod library;
mod object;
mod perturb;
mod validation;

use nalgebra::Point2;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::geometry::{ConvexPolygon, Discs, GraspDiameter, min_grasp_diameter};

pub use generator::{GeneratorSettings, MAX_OBJECTS, generate_scene};
pub use gripper::{Gripper, MAX_PLATE_LENGTH, MAX_STROKE};
pub use library::{LibraryObject, ObjectSet, builtin_object_set};
pub use object::{Object, ObjectId, ObjectSpec, Pose};
pub use perturb::perturb;
pub use validation::{
    MAX_HEIGHT, MAX_MASS, MAX_VERTICES, MAX_YAW, MIN_HEIGHT, MIN_MASS, MIN_WIDTH,
};
pub use validation::{OUTSIDE_TOLERANCE, OVERLAP_TOLERANCE};
pub use workspace::{MAX_COORDINATE, Workspace};

mod workspace;

/// A scene as stored in JSON, before validation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// The rectangle to clear.
    pub workspace: Workspace,
    /// The gripper; omitted fields take the Robotiq 2F-85 defaults.
    #[serde(default)]
    pub gripper: Gripper,
    /// The objects on the table.
    pub objects: Vec<ObjectSpec>,
}

/// A validated scene. Serialises to and from the [`SceneSpec`] JSON form (deserialising validates).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "SceneSpec", try_from = "SceneSpec")]
pub struct Scene {
    workspace: Workspace,
    gripper: Gripper,
    objects: Vec<Object>,
    world: Vec<ConvexPolygon>,
    diameters: Vec<GraspDiameter>,
    /// Bounding discs of `world`, for the objects near a point.
    discs: Discs,
}

impl Scene {
    /// Validates a scene in its JSON form.
    ///
    /// # Errors
    /// An [`Error`](crate::Error) naming the object (id and position) and the field, or the workspace
    /// or gripper field, for every defect listed in the module docs.
    pub fn new(spec: SceneSpec) -> Result<Self> {
        let objects = spec
            .objects
            .into_iter()
            .enumerate()
            .map(|(index, raw)| validation::object_from_spec(index, raw))
            .collect::<Result<Vec<_>>>()?;
        Self::from_parts(spec.workspace, spec.gripper, objects)
    }

    /// Validates a scene built from objects whose outlines are already convex polygons.
    ///
    /// # Errors
    /// As [`Scene::new`].
    pub fn from_parts(
        workspace: Workspace,
        gripper: Gripper,
        objects: Vec<Object>,
    ) -> Result<Self> {
        workspace.validate()?;
        gripper.validate()?;
        crate::error::count_in_range(
            "scene",
            "objects",
            objects.len(),
            (0, MAX_OBJECTS),
            "planning is measured up to 1000 objects; beyond ten times that a scene is not a table",
        )?;
        let world: Vec<ConvexPolygon> = objects.iter().map(Object::world_polygon).collect();
        let discs = Discs::of(&world);
        validation::check_objects(&workspace, &objects, &world, &discs)?;
        let diameters = objects
            .iter()
            .map(|o| min_grasp_diameter(&o.polygon))
            .collect();
        Ok(Self {
            workspace,
            gripper,
            objects,
            discs,
            world,
            diameters,
        })
    }

    /// The same workspace and gripper with other objects (for instance, predicted after pushes).
    ///
    /// # Errors
    /// As [`Scene::from_parts`].
    pub fn with_objects(&self, objects: Vec<Object>) -> Result<Self> {
        Self::from_parts(self.workspace.clone(), self.gripper.clone(), objects)
    }

    /// The scene without the objects whose ids are in `removed` (objects carried to the bin).
    pub fn without(&self, removed: &[ObjectId]) -> Self {
        let keep: Vec<usize> = (0..self.objects.len())
            .filter(|&i| !removed.contains(&self.objects[i].id))
            .collect();
        Self {
            workspace: self.workspace.clone(),
            gripper: self.gripper.clone(),
            objects: keep.iter().map(|&i| self.objects[i].clone()).collect(),
            world: keep.iter().map(|&i| self.world[i].clone()).collect(),
            diameters: keep.iter().map(|&i| self.diameters[i]).collect(),
            discs: Discs::new(
                keep.iter().map(|&i| self.discs.centre(i)).collect(),
                keep.iter().map(|&i| self.discs.radius(i)).collect(),
            ),
        }
    }

    /// The JSON form.
    pub fn to_spec(&self) -> SceneSpec {
        SceneSpec {
            workspace: self.workspace.clone(),
            gripper: self.gripper.clone(),
            objects: self.objects.iter().map(Object::to_spec).collect(),
        }
    }

    /// The workspace rectangle.
    pub fn workspace(&self) -> &Workspace {
        &self.workspace
    }

    /// The gripper.
    pub fn gripper(&self) -> &Gripper {
        &self.gripper
    }

    /// The objects, in the order given.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// Number of objects.
    pub fn len(&self) -> usize {
        self.objects.len()
    }

    /// Whether the table is clear.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// Position in [`Scene::objects`] of the object with this id.
    pub fn index_of(&self, id: ObjectId) -> Option<usize> {
        self.objects.iter().position(|o| o.id == id)
    }

    /// Positions in [`Scene::objects`] of these ids, in the same order.
    ///
    /// # Errors
    /// [`Error::InvalidField`](crate::Error::InvalidField) naming an id that is not in the scene.
    pub fn indices_of(&self, ids: &[ObjectId]) -> Result<Vec<usize>> {
        ids.iter()
            .map(|&id| {
                self.index_of(id).ok_or_else(|| {
                    crate::Error::field("objects", "id", format!("object {id} is not in the scene"))
                })
            })
            .collect()
    }

    /// Outline of object `index` in the table frame.
    pub fn world_polygon(&self, index: usize) -> &ConvexPolygon {
        &self.world[index]
    }

    /// Area centroid of object `index` in the table frame, metres.
    pub fn centroid(&self, index: usize) -> Point2<f64> {
        self.discs.centre(index)
    }

    /// Largest distance of object `index`'s outline from its centroid, metres.
    pub fn radius(&self, index: usize) -> f64 {
        self.discs.radius(index)
    }

    /// Indices, ascending, of the objects that may come within `reach` of `point`: those whose
    /// bounding disc about the centroid does (`|c − point| ≤ reach + radius`). Costs `O(log N + k)`
    /// ([`Discs`]).
    pub fn near(&self, point: &Point2<f64>, reach: f64) -> Vec<usize> {
        self.discs.within(point, reach)
    }

    /// The narrowest stable grasp of object `index`, in the object's own frame.
    pub fn grasp_diameter(&self, index: usize) -> &GraspDiameter {
        &self.diameters[index]
    }

    /// Minimum grasp diameter `d*` of object `index`, metres.
    pub fn min_grasp_diameter(&self, index: usize) -> f64 {
        self.diameters[index].diameter
    }

    /// Whether object `index` fits between the jaws at all: `d* ≤ usable gap`.
    pub fn is_graspable(&self, index: usize) -> bool {
        self.min_grasp_diameter(index) <= self.gripper.usable_gap()
    }

    /// Ids of the objects wider than the usable jaw gap in every direction. Such objects are accepted
    /// in a scene but no grasp can carry them.
    pub fn ungraspable(&self) -> Vec<ObjectId> {
        (0..self.len())
            .filter(|&i| !self.is_graspable(i))
            .map(|i| self.objects[i].id)
            .collect()
    }
}

impl From<Scene> for SceneSpec {
    fn from(scene: Scene) -> Self {
        scene.to_spec()
    }
}

impl TryFrom<SceneSpec> for Scene {
    type Error = crate::Error;
    fn try_from(spec: SceneSpec) -> Result<Self> {
        Scene::new(spec)
    }
}
