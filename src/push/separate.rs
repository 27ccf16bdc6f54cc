//! Pushing an object away from a neighbour it is stuck against, so that a plate fits between them.
//!
//! Objects pushed together (the paper's pushes end with them touching) or squeezed by a grasp that
//! carried nothing can end too close for a plate to come down between them: neither can then be
//! taken by itself, and if the grasp model refuses them together the table has a dead end. A
//! *separating push* moves object `o` by a distance `s` along a unit direction `u` that does not run
//! into its neighbour `n` (`u · (M_o − M_n) ≥ 0`: away from it or sliding along it), with the jaws
//! closed to one narrow block (a fork would put a finger on `n`) and otherwise the checks of every
//! other push ([`plan_fork`]). Straight away from `n` the fingers would have to come down
//! between the two, so the caller tries several directions. The push is refused when the object would
//! meet anything on its way (`n` included: it is checked every half millimetre, since the two may
//! start touching) or end with less than `edge_margin` between its bounding box and the workspace's
//! edges. Whether `s` was enough is for the caller to judge on the table predicted after the push (the
//! policy asks its single-object planner).

use nalgebra::Vector2;

use super::flush::CLOSED_GAP;
use super::fork::{ForkSettings, plan_fork};
use super::{Push, SkipReason};
use crate::geometry::{ConvexPolygon, cast_distance, penetration_depth};
use crate::scene::{Pose, Scene};

/// A push, with the jaws closed, of `scene`'s object at index `object` by `distance` along the unit
/// vector `direction`, which must not point into the object at index `from` it is to be separated
/// from.
///
/// # Errors
/// The [`SkipReason`] when the fingers cannot be placed or moved, the object would tip, meet another
/// object on its way, or end within `edge_margin` of the workspace's edge
/// ([`SkipReason::NoRoomToSeparate`]).
pub fn separating_push(
    scene: &Scene,
    fork: &ForkSettings,
    (object, from): (usize, usize),
    direction: &Vector2<f64>,
    distance: f64,
    edge_margin: f64,
) -> std::result::Result<Push, SkipReason> {
    let away: Vector2<f64> = scene.centroid(object) - scene.centroid(from);
    if direction.dot(&away) < 0.0 {
        return Err(SkipReason::NoRoomToSeparate);
    }
    let world: Vec<ConvexPolygon> = (0..scene.len())
        .map(|i| scene.world_polygon(i).clone())
        .collect();
    let moved = direction * distance;
    let met_on_the_way = world.iter().enumerate().any(|(other, outline)| {
        other != object
            && other != from
            && cast_distance(&world[object], direction, distance, outline).is_some()
    });
    let steps = (distance / PATH_STEP).ceil() as usize;
    let runs_into_neighbour = (1..=steps).any(|k| {
        let along = direction * (distance * k as f64 / steps as f64);
        penetration_depth(&world[object].translated(&along), &world[from]) > PATH_TOLERANCE
    });
    let room = scene
        .workspace()
        .room(world[object].translated(&moved).bounding_box());
    if met_on_the_way || runs_into_neighbour || room.iter().any(|&r| r < edge_margin) {
        return Err(SkipReason::NoRoomToSeparate);
    }
    let ids: Vec<_> = scene.objects().iter().map(|o| o.id).collect();
    let gripper = scene.gripper();
    let fork = plan_fork(
        gripper,
        fork,
        &world,
        &ids,
        object,
        scene.objects()[object].height,
        direction,
        distance,
        gripper.plate_thickness + CLOSED_GAP,
    )?;
    let from_pose = scene.objects()[object].pose;
    Ok(Push {
        object: ids[object],
        from: from_pose,
        to: Pose::new(from_pose.x + moved.x, from_pose.y + moved.y, from_pose.yaw),
        direction: *direction,
        distance,
        fork,
    })
}

/// Spacing of the checks against the neighbour along a separating push, metres.
const PATH_STEP: f64 = 0.0005;

/// Overlap with the neighbour below this counts as touching, metres.
const PATH_TOLERANCE: f64 = 1e-6;
