//! The checks [`Scene`](super::Scene) runs once at construction, each failing with an error that names
//! the object and the field.

use std::collections::HashMap;

use nalgebra::Point2;

use super::object::{Object, ObjectSpec};
use super::workspace::{MAX_COORDINATE, Workspace};
use crate::error::{Error, Result, number};
use crate::geometry::{
    ConvexPolygon, Discs, SIMPLIFY_ABOVE, SIMPLIFY_TOLERANCE, min_grasp_diameter,
    penetration_depth, simplify,
};

/// Largest interpenetration of two objects still accepted as touching, metres (1 µm). Objects pushed
/// into a tight row touch; solvers place them to within this.
pub const OVERLAP_TOLERANCE: f64 = 1e-6;

/// Largest distance a vertex may lie outside the workspace, metres (1 nm, rounding only).
pub const OUTSIDE_TOLERANCE: f64 = 1e-9;

/// Most vertices an object's outline may be given with: a contour traced every 10 µm around a
/// 0.3 m object. Reading is linear in the count; the planner sees the simplified outline.
pub const MAX_VERTICES: usize = 100_000;

/// Tallest object accepted, metres. A parallel-jaw gripper takes tabletop objects from the side at
/// about mid-height; an object two metres tall is taller than the arm's reach above the table (the
/// UR5 reaches 0.85 m) and is almost always a unit mistake.
pub const MAX_HEIGHT: f64 = 2.0;

/// Flattest object accepted, metres. The fingertips clear the table by at least 3 mm
/// (`fork.min_height`); below 1 mm a pad closes on nothing but the table.
pub const MIN_HEIGHT: f64 = 0.001;

/// Heaviest object accepted, kilograms: ten times the 5 kg payload of the UR5 and of the Robotiq 2F-85
/// (both manufacturers' data sheets); nothing heavier is a tabletop pick.
pub const MAX_MASS: f64 = 50.0;

/// Lightest object accepted, kilograms (0.1 g; a paper clip weighs about 1 g). Lighter values are
/// almost always a unit slip (grams given as kilograms the other way round would be far heavier).
pub const MIN_MASS: f64 = 0.0001;

/// Largest yaw magnitude accepted, radians (16 turns). Any orientation is within ±π; larger values
/// are usually degrees, and far larger ones cannot be reduced to an angle accurately (at 1e17 rad
/// neighbouring doubles are 16 rad apart).
pub const MAX_YAW: f64 = 100.0;

/// Narrowest outline accepted, metres: its minimum grasp diameter. Below 1 mm the object is under
/// the perception noise (2 mm) and the pads' compliance; such a value is almost always a unit mistake.
pub const MIN_WIDTH: f64 = 0.001;

impl Object {
    /// Validates one object's JSON form by itself, as a scene's `objects[index]` would be (outline
    /// convex and within bounds, height and mass positive); no workspace or neighbour is checked.
    /// (Written here, beside the rules, so that `object.rs` does not depend on them.)
    ///
    /// # Errors
    /// [`crate::Error::InvalidObject`] naming the field.
    pub fn from_spec(spec: ObjectSpec, index: usize) -> Result<Self> {
        object_from_spec(index, spec)
    }
}

/// Builds a validated object from its JSON form; `index` is its position in the `objects` list.
///
/// Outlines of more than [`SIMPLIFY_ABOVE`] vertices are simplified to within
/// [`SIMPLIFY_TOLERANCE`]; more than [`MAX_VERTICES`] are refused.
pub(super) fn object_from_spec(index: usize, spec: ObjectSpec) -> Result<Object> {
    let refuse = |reason: String| Error::InvalidObject {
        id: spec.id,
        index,
        field: "vertices",
        reason,
    };
    if spec.vertices.len() > MAX_VERTICES {
        return Err(refuse(format!(
            "{} vertices; at most {MAX_VERTICES} are read (simplify the contour first)",
            spec.vertices.len()
        )));
    }
    if let Some(vertex) = spec
        .vertices
        .iter()
        .position(|v| v.iter().any(|c| c.abs() > MAX_COORDINATE))
    {
        return Err(refuse(format!(
            "vertex {vertex} is {:?}: coordinates are metres in the object's own frame and must \
             lie within ±{MAX_COORDINATE} m",
            spec.vertices[vertex]
        )));
    }
    let vertices: Vec<Point2<f64>> = spec
        .vertices
        .iter()
        .map(|&[x, y]| Point2::new(x, y))
        .collect();
    let mut polygon = ConvexPolygon::new(vertices).map_err(|e| refuse(e.to_string()))?;
    if polygon.len() > SIMPLIFY_ABOVE {
        polygon = simplify(&polygon, SIMPLIFY_TOLERANCE);
    }
    Ok(Object {
        id: spec.id,
        name: spec.name,
        polygon,
        pose: spec.pose,
        height: spec.height,
        mass: spec.mass,
    })
}

/// Field checks per object, unique ids, containment in the workspace, no overlaps.
pub(super) fn check_objects(
    workspace: &Workspace,
    objects: &[Object],
    world: &[ConvexPolygon],
    discs: &Discs,
) -> Result<()> {
    for (index, object) in objects.iter().enumerate() {
        check_fields(index, object)?;
    }
    let mut first_use = HashMap::new();
    for (index, object) in objects.iter().enumerate() {
        if let Some(&first) = first_use.get(&object.id) {
            return Err(Error::DuplicateId {
                id: object.id,
                first,
                second: index,
            });
        }
        first_use.insert(object.id, index);
    }
    for (index, (object, outline)) in objects.iter().zip(world).enumerate() {
        check_scale(workspace, index, object)?;
        check_inside(workspace, index, object, outline)?;
    }
    check_overlaps(objects, world, discs)
}

fn invalid(index: usize, object: &Object, field: &'static str, reason: String) -> Error {
    Error::InvalidObject {
        id: object.id,
        index,
        field,
        reason,
    }
}

fn check_fields(index: usize, object: &Object) -> Result<()> {
    if !object.pose.is_finite() {
        return Err(invalid(
            index,
            object,
            "pose",
            format!("x, y and yaw must be finite, got {:?}", object.pose),
        ));
    }
    if object.pose.yaw.abs() > MAX_YAW {
        return Err(invalid(
            index,
            object,
            "pose",
            format!(
                "yaw {} rad: an angle in radians, within ±{MAX_YAW} (were degrees given?)",
                number(object.pose.yaw)
            ),
        ));
    }
    if !(object.height.is_finite() && (MIN_HEIGHT..=MAX_HEIGHT).contains(&object.height)) {
        return Err(invalid(
            index,
            object,
            "height",
            format!(
                "must be between {MIN_HEIGHT} and {MAX_HEIGHT} m (a tabletop object the jaws take \
                 from the side), got {}",
                number(object.height)
            ),
        ));
    }
    if let Some(mass) = object.mass
        && !(mass.is_finite() && (MIN_MASS..=MAX_MASS).contains(&mass))
    {
        return Err(invalid(
            index,
            object,
            "mass",
            format!(
                "must be between {MIN_MASS} and {MAX_MASS} kg (the arm and gripper carry 5 kg), \
                 got {}",
                number(mass)
            ),
        ));
    }
    Ok(())
}

/// An outline that cannot fit the workspace in any pose is almost always given in the wrong unit.
fn check_scale(workspace: &Workspace, index: usize, object: &Object) -> Result<()> {
    let polygon = &object.polygon;
    let span = polygon
        .vertices()
        .iter()
        .flat_map(|a| polygon.vertices().iter().map(move |b| (a - b).norm()))
        .fold(0.0, f64::max);
    let narrowest = min_grasp_diameter(polygon).diameter;
    if narrowest < MIN_WIDTH {
        return Err(invalid(
            index,
            object,
            "vertices",
            format!(
                "the outline is {:.3e} m at its narrowest, under {MIN_WIDTH} m; lengths are in \
                 metres (were kilometres given?)",
                narrowest
            ),
        ));
    }
    let shorter_side = workspace.width().min(workspace.depth());
    if span > workspace.diagonal() || narrowest > shorter_side {
        return Err(invalid(
            index,
            object,
            "vertices",
            format!(
                "the outline ({span:.3} m across) is larger than the {:.3} m × {:.3} m workspace; \
                 lengths are in metres (were millimetres given?)",
                workspace.width(),
                workspace.depth()
            ),
        ));
    }
    Ok(())
}

fn check_inside(
    workspace: &Workspace,
    index: usize,
    object: &Object,
    outline: &ConvexPolygon,
) -> Result<()> {
    for (vertex, point) in outline.vertices().iter().enumerate() {
        let outside = workspace.outside_by(point);
        if outside > OUTSIDE_TOLERANCE {
            return Err(invalid(
                index,
                object,
                "pose",
                format!(
                    "vertex {vertex} lies at ({:.4}, {:.4}) m, {:.2} mm outside the workspace \
                     [{}, {}] × [{}, {}]",
                    point.x,
                    point.y,
                    outside * 1e3,
                    workspace.min[0],
                    workspace.max[0],
                    workspace.min[1],
                    workspace.max[1]
                ),
            ));
        }
    }
    Ok(())
}

fn check_overlaps(objects: &[Object], world: &[ConvexPolygon], discs: &Discs) -> Result<()> {
    // Only objects whose bounding discs meet can overlap.
    for i in 0..objects.len() {
        for j in discs.within(&discs.centre(i), discs.radius(i)) {
            if j <= i {
                continue;
            }
            let depth = penetration_depth(&world[i], &world[j]);
            if depth > OVERLAP_TOLERANCE {
                return Err(Error::Overlap {
                    first: objects[i].id,
                    second: objects[j].id,
                    depth,
                });
            }
        }
    }
    Ok(())
}
