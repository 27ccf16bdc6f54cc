//! Objects named from a library: an object seen without a prior has no name, no mass and yaw 0. When
//! the cell's objects come from a known set (`ObjectSet`, as `pushmog library` prints), each such
//! object is matched to the set's shape that fits its outline best, and takes that shape's frame,
//! name and mass, so its yaw is measured as a tracked object's is (`align.rs`).
//!
//! With `Q` the outline seen and `L` a shape of the set, both about their area centroids, the fit
//! is `max_δ IoU(R(δ)·L, Q)` over the whole turn (a 5° grid refined to 0.01°). Only shapes whose
//! area is within `AREA_SHARE` of the outline's and whose height is within `height_tolerance` of
//! the top seen are tried. The best shape is taken when its fit reaches `min_iou`; otherwise the
//! object stays unnamed, as it was. The outline kept is the one seen, in the shape's frame: the
//! set names the object, it does not replace what the camera measured. A shape with symmetries fits
//! equally at each of them; the yaw is then one of them, and the outline is the same either way.

use super::align::{best_turn, in_frame};
use crate::error::Result;
use crate::geometry::ConvexPolygon;
use crate::scene::{Object, ObjectSet, Pose};

/// Largest relative difference between a shape's area and the outline's for the shape to be tried.
const AREA_SHARE: f64 = 0.2;

/// Grid of the turn search, radians (5°).
const TURN_STEP: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// How closely an outline must fit a shape of the set to take its name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Identify {
    /// Smallest IoU of the best turn of the shape onto the outline seen.
    pub min_iou: f64,
    /// Largest difference between the shape's height and the top seen, metres.
    pub height_tolerance: f64,
}

impl Default for Identify {
    /// An IoU of 0.85 (isolated objects seen with the default noise fit their own shape at 0.9 or
    /// more, `formulations/perception.md`) and 5 mm of height.
    fn default() -> Self {
        Self {
            min_iou: 0.85,
            height_tolerance: 0.005,
        }
    }
}

/// What matching one outline found: the shape's index in the set and the fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Match {
    /// Index of the shape in the set.
    pub shape: usize,
    /// IoU of its best turn onto the outline.
    pub iou: f64,
}

/// The shape of `set` that best fits `seen` (a table-frame outline) of top height `top`, with its
/// turn, or `None` when no shape is tried or none fits well enough.
///
/// # Errors
/// A shape of the set whose outline is not convex (named).
pub fn best_shape(
    seen: &ConvexPolygon,
    top: f64,
    set: &ObjectSet,
    rule: &Identify,
) -> Result<Option<(Match, f64)>> {
    let mut best: Option<(Match, f64)> = None;
    for (k, shape) in set.objects.iter().enumerate() {
        if (shape.height - top).abs() > rule.height_tolerance {
            continue;
        }
        let outline = shape.polygon()?;
        if (outline.area() - seen.area()).abs() > AREA_SHARE * outline.area() {
            continue;
        }
        let (turn, iou) = best_turn(&outline, seen, std::f64::consts::PI, TURN_STEP);
        if iou >= rule.min_iou && best.is_none_or(|(b, _)| iou > b.iou) {
            best = Some((Match { shape: k, iou }, turn));
        }
    }
    Ok(best)
}

/// `object` named from `set` when a shape fits it (its pose and outline in the shape's frame, the
/// shape's name and mass); the match, or `None` with `object` unchanged.
///
/// # Errors
/// As [`best_shape`].
pub fn name_from_set(
    object: &mut Object,
    set: &ObjectSet,
    rule: &Identify,
) -> Result<Option<Match>> {
    let seen = object.world_polygon();
    let Some((found, turn)) = best_shape(&seen, object.height, set, rule)? else {
        return Ok(None);
    };
    let shape = &set.objects[found.shape];
    let outline = shape.polygon()?;
    // The shape in its own frame at the origin, turned onto the outline seen.
    let (pose, own) = in_frame(&seen, &outline, Pose::new(0.0, 0.0, 0.0), turn);
    object.pose = pose;
    object.polygon = own;
    object.name = Some(shape.name.clone());
    object.mass = shape.mass;
    Ok(Some(found))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin_object_set;

    #[test]
    fn every_shape_of_the_library_turned_and_moved_is_named_and_its_frame_found() {
        let set = builtin_object_set();
        for (k, shape) in set.objects.iter().enumerate() {
            let outline = shape.polygon().expect("a library shape");
            let truth = Pose::new(0.2 + 0.001 * k as f64, 0.1, 0.37 * k as f64 - 3.0);
            let mut object = Object {
                id: crate::id::ObjectId(k as u32),
                name: None,
                polygon: outline.transformed(&truth.isometry()),
                pose: Pose::new(0.0, 0.0, 0.0),
                height: shape.height,
                mass: None,
            };
            let found = name_from_set(&mut object, &set, &Identify::default())
                .expect("a valid set")
                .expect("a match");
            // The shape found placed at the pose found covers the true outline: the right shape,
            // or one congruent to it, at the right turn up to its symmetries.
            let placed = set.objects[found.shape]
                .polygon()
                .expect("a library shape")
                .transformed(&object.pose.isometry());
            let fit = crate::geometry::intersection_over_union(
                &placed,
                &outline.transformed(&truth.isometry()),
            );
            assert!(fit > 0.9999, "{}: {fit}", shape.name);
            assert!(found.iou > 0.9999);
            // The outline kept is the one seen, unchanged on the table.
            let kept = object.world_polygon();
            assert!((kept.area() - outline.area()).abs() < 1e-12);
        }
    }

    #[test]
    fn an_outline_no_shape_fits_keeps_no_name() {
        let set = builtin_object_set();
        // A long bar: no library shape has its area and outline.
        let bar = ConvexPolygon::rectangle(
            &nalgebra::Point2::origin(),
            &nalgebra::Vector2::x(),
            0.05,
            0.004,
        );
        let mut object = Object {
            id: crate::id::ObjectId(0),
            name: None,
            polygon: bar,
            pose: Pose::new(0.2, 0.2, 0.0),
            height: 0.03,
            mass: None,
        };
        let before = object.clone();
        assert_eq!(
            name_from_set(&mut object, &set, &Identify::default()).expect("a valid set"),
            None
        );
        assert_eq!(object, before);
        // Nor does a library shape seen at another height.
        let square = set
            .objects
            .iter()
            .find(|s| s.name == "square-30")
            .expect("a square");
        let mut tall = Object {
            polygon: square.polygon().expect("a square"),
            height: 0.05,
            ..before
        };
        assert_eq!(
            name_from_set(&mut tall, &set, &Identify::default()).expect("a valid set"),
            None
        );
    }
}
