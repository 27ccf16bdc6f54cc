//! A trip's riders checked (`formulations/stacking.md`): each is an object on the table after the
//! pushes that the trip neither pushes nor grasps, picked by a single-object grasp whose plates land
//! on nothing, let go where its jaws have carried it, standing on the row's top (its centroid over
//! what it covers of the top faces it rests on) and clear of the pads along the closing axis.

use std::collections::BTreeSet;

use nalgebra::{Isometry2, Vector2};

use super::TOLERANCE;
use crate::geometry::{ConvexPolygon, overlap};
use crate::plan::{Rider, Trip};
use crate::scene::{ObjectId, Scene};
use crate::stack::standing_margin;

/// Every violation of the trip's riders on `scene` (the table the grasp was planned on) with
/// `world`, its outlines after the trip's pushes.
pub(super) fn check_riders(
    scene: &Scene,
    world: &[ConvexPolygon],
    trip: &Trip,
    found: &mut Vec<String>,
) {
    let grasp = &trip.plan.grasp;
    let pushed: BTreeSet<ObjectId> = trip.plan.pushes.iter().map(|p| p.object).collect();
    let mut gone: Vec<usize> = Vec::new();
    for (k, rider) in trip.plan.riders.iter().enumerate() {
        let mut say = |what: String| found.push(format!("rider {k}: {what}"));
        let Some(index) = scene.index_of(rider.object) else {
            say(format!("object {} is not on the table", rider.object));
            continue;
        };
        if grasp.objects.contains(&rider.object)
            || pushed.contains(&rider.object)
            || trip.plan.ahead.contains(&rider.object)
            || gone.contains(&index)
        {
            say(format!(
                "object {} is also grasped, pushed or placed by the trip",
                rider.object
            ));
        }
        if rider.pick.objects != [rider.object] {
            say("its pick does not take exactly the rider".to_string());
        }
        let gripper = scene.gripper();
        let plates = rider.pick.jaws.plates(gripper);
        for (i, outline) in world.iter().enumerate() {
            if !gone.contains(&i) && plates.iter().any(|p| overlap(p, outline, TOLERANCE)) {
                say(format!(
                    "a plate of its pick lands on object {}",
                    scene.objects()[i].id
                ));
            }
        }
        if !overlap(&rider.pick.jaws.between(gripper), &world[index], 0.0) {
            say("it is not between the plates of its pick".to_string());
        }
        check_release(rider, &scene.objects()[index].pose, &mut say);
        check_standing(scene, world, trip, rider, index, &mut say);
        gone.push(index);
    }
}

/// The jaws let the rider go where they carried it: the pick's jaws moved with the object from
/// where it lay to its place.
fn check_release(rider: &Rider, lay: &crate::scene::Pose, say: &mut dyn FnMut(String)) {
    let jaws = &rider.pick.jaws;
    let held = lay.isometry().inverse() * Isometry2::new(jaws.center.coords, jaws.angle);
    let at = rider.place.isometry() * held;
    let turn = rider.release.angle - jaws.angle - (rider.place.yaw - lay.yaw);
    let off = (at.translation.vector - rider.release.center.coords).norm();
    if off > 1e-6 || turn.sin().abs() > 1e-6 || (rider.release.opening - jaws.opening).abs() > 1e-9
    {
        say("the jaws are not let go where they carried it".to_string());
    }
}

/// The rider stands on the row's top, clear of the pads, with nothing else above the top under it.
fn check_standing(
    scene: &Scene,
    world: &[ConvexPolygon],
    trip: &Trip,
    rider: &Rider,
    index: usize,
    say: &mut dyn FnMut(String),
) {
    let grasp = &trip.plan.grasp;
    let row: Vec<usize> = grasp
        .objects
        .iter()
        .filter_map(|&id| scene.index_of(id))
        .collect();
    if rider.on.is_empty() || rider.on.iter().any(|id| !grasp.objects.contains(id)) {
        say("it does not rest on objects the grasp takes".to_string());
        return;
    }
    let top = row
        .iter()
        .map(|&i| scene.objects()[i].height)
        .fold(f64::NEG_INFINITY, f64::max);
    if (rider.base - top).abs() > 1e-9 {
        say(format!(
            "its base {:.1} mm is not the row's top {:.1} mm",
            rider.base * 1e3,
            top * 1e3
        ));
    }
    let object = &scene.objects()[index];
    let footprint = object.polygon.transformed(&rider.place.isometry());
    let tops: Vec<ConvexPolygon> = rider
        .on
        .iter()
        .filter_map(|&id| scene.index_of(id))
        .map(|i| world[i].clone())
        .collect();
    if standing_margin(&tops, &footprint) < 0.0 {
        say("its centroid is not over the top faces it rests on".to_string());
    }
    let axis = Vector2::new(grasp.jaws.angle.cos(), grasp.jaws.angle.sin());
    let (lo, hi) = row
        .iter()
        .map(|&i| world[i].projection(&axis))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
            (lo.min(a), hi.max(b))
        });
    let (front, back) = footprint.projection(&axis);
    if front < lo - TOLERANCE || back > hi + TOLERANCE {
        say("it reaches past the row's faces where the pads close".to_string());
    }
    for (i, outline) in world.iter().enumerate() {
        if i != index
            && !row.contains(&i)
            && scene.objects()[i].height > rider.base
            && overlap(outline, &footprint, 0.0)
        {
            say(format!(
                "object {} stands above the row's top under it",
                scene.objects()[i].id
            ));
        }
    }
}
