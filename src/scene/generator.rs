//! Seeded random scenes, generated the way the Push-MOG paper set up its experiments.
//!
//! Circle centres are sampled uniformly over the workspace (shrunk by the circle radius `R`, so every
//! circle lies inside); a sample is kept when its circle does not overlap any kept circle
//! (`‖c_i − c_j‖ ≥ 2R`). `R` is the largest centroid-to-vertex distance of any shape in the object set,
//! so each object, centred on its circle with a uniform random yaw in `[−π, π)`, cannot touch another or
//! leave the workspace. Shapes are drawn from the set without replacement; when more objects are asked
//! for than the set holds, a fresh copy of the set is drawn from once the current one is used up. After
//! `max_samples` rejected and accepted samples in total the generator stops with
//! [`Error::Placement`](crate::Error::Placement).
//!
//! The same settings and seed give the same scene, bit for bit (see [`crate::random`]).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::library::ObjectSet;
use super::object::{Object, ObjectId, Pose};
use super::{Gripper, Scene, Workspace};
use crate::error::{Error, Result};
use crate::random::SeededRng;

/// Settings of the scene generator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct GeneratorSettings {
    /// Number of objects to place. Default 34 (the paper's scenes).
    pub objects: usize,
    /// The workspace. Default 0.6 m × 0.45 m.
    pub workspace: Workspace,
    /// The gripper written into the scene. Default Robotiq 2F-85.
    pub gripper: Gripper,
    /// Radius in metres of the circle kept clear around each object; default (`None`): the object
    /// set's largest centroid-to-vertex distance.
    pub clearance_radius: Option<f64>,
    /// Position samples to draw in total before giving up. Default 100 000.
    pub max_samples: usize,
}

impl Default for GeneratorSettings {
    fn default() -> Self {
        Self {
            objects: 34,
            workspace: Workspace::new(0.6, 0.45),
            gripper: Gripper::default(),
            clearance_radius: None,
            max_samples: 100_000,
        }
    }
}

/// Most objects in one generated scene. Planning is measured up to 1000 objects; beyond ten times
/// that a scene no longer describes a table.
pub const MAX_OBJECTS: usize = 10_000;

impl GeneratorSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.workspace.validate()?;
        self.gripper.validate()?;
        // An empty table is a valid scene.
        crate::error::count_in_range(
            "generator",
            "objects",
            self.objects,
            (0, MAX_OBJECTS),
            "planning is measured up to 1000 objects",
        )?;
        crate::error::count_in_range(
            "generator",
            "max_samples",
            self.max_samples,
            (1, 100_000_000),
            "each sample is an overlap test",
        )?;
        if let Some(radius) = self.clearance_radius
            && !(radius.is_finite() && radius > 0.0)
        {
            return Err(Error::field(
                "generator",
                "clearance_radius",
                format!("must be a positive finite number of metres, got {radius}"),
            ));
        }
        Ok(())
    }
}

/// Generates a scene from `set` with `seed`.
///
/// # Errors
/// [`Error::InvalidField`] for bad settings or a bad object set; [`Error::Placement`] when the objects
/// do not fit after `max_samples` samples.
///
/// # Example
/// ```
/// use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
/// let settings = GeneratorSettings::default();
/// let a = generate_scene(&settings, &builtin_object_set(), 7).unwrap();
/// let b = generate_scene(&settings, &builtin_object_set(), 7).unwrap();
/// assert_eq!(a, b);
/// ```
pub fn generate_scene(settings: &GeneratorSettings, set: &ObjectSet, seed: u64) -> Result<Scene> {
    settings.validate()?;
    set.validate()?;
    let radius = match settings.clearance_radius {
        Some(radius) => radius,
        None => set.max_radius()?,
    };
    let polygons = set
        .objects
        .iter()
        .map(|shape| shape.polygon())
        .collect::<Result<Vec<_>>>()?;
    let workspace = &settings.workspace;
    let (x_low, x_high) = (workspace.min[0] + radius, workspace.max[0] - radius);
    let (y_low, y_high) = (workspace.min[1] + radius, workspace.max[1] - radius);
    let placement_error = |placed, samples| Error::Placement {
        requested: settings.objects,
        placed,
        samples,
        radius,
        width: workspace.width(),
        depth: workspace.depth(),
    };
    if settings.objects > 0 && (x_low > x_high || y_low > y_high) {
        return Err(placement_error(0, 0));
    }

    let mut rng = SeededRng::new(seed);
    let mut centres: Vec<(f64, f64)> = Vec::with_capacity(settings.objects);
    let mut samples = 0;
    let min_gap_squared = 4.0 * radius * radius;
    let mut draw_pile: Vec<usize> = Vec::new();
    let mut objects = Vec::with_capacity(settings.objects);
    while centres.len() < settings.objects {
        if samples >= settings.max_samples {
            return Err(placement_error(centres.len(), samples));
        }
        samples += 1;
        let (x, y) = (rng.uniform(x_low, x_high), rng.uniform(y_low, y_high));
        let clear = centres
            .iter()
            .all(|&(cx, cy)| (x - cx).powi(2) + (y - cy).powi(2) >= min_gap_squared);
        if !clear {
            continue;
        }
        centres.push((x, y));
        if draw_pile.is_empty() {
            draw_pile = (0..set.objects.len()).collect();
            rng.shuffle(&mut draw_pile);
        }
        let Some(shape_index) = draw_pile.pop() else {
            // Unreachable: a validated set holds at least one shape, so the pile was just refilled.
            return Err(Error::field("generator", "object set", "holds no shapes"));
        };
        let shape = &set.objects[shape_index];
        let yaw = rng.uniform(-std::f64::consts::PI, std::f64::consts::PI);
        // Put the shape's area centroid on the circle centre, keeping its vertices as the set gives them.
        let polygon = polygons[shape_index].clone();
        let offset = nalgebra::Rotation2::new(yaw) * polygon.centroid().coords;
        let (x, y) = (x - offset.x, y - offset.y);
        objects.push(Object {
            id: ObjectId(objects.len() as u32),
            name: Some(shape.name.clone()),
            polygon,
            pose: Pose::new(x, y, yaw),
            height: shape.height,
            mass: shape.mass,
        });
    }
    Scene::from_parts(workspace.clone(), settings.gripper.clone(), objects)
}
