//! The pushes and the grasp of a trip checked on the table as it stands at each moment.

use nalgebra::{Point2, Vector2};

use super::{MAX_SKEW, TOLERANCE, TOUCH};
use crate::geometry::{ConvexPolygon, cast_distance, overlap, penetration_depth};
use crate::plan::Trip;
use crate::scene::{Gripper, MAX_YAW, ObjectId, Scene};

fn fingers(
    gripper: &Gripper,
    centre: &Point2<f64>,
    jaw_angle: f64,
    opening: f64,
) -> Vec<ConvexPolygon> {
    let jaw_line = Vector2::new(jaw_angle.cos(), jaw_angle.sin());
    [1.0, -1.0]
        .iter()
        .map(|side| {
            ConvexPolygon::rectangle(
                &(centre + jaw_line * (side * opening / 2.0)),
                &jaw_line,
                gripper.plate_thickness / 2.0,
                gripper.plate_length / 2.0,
            )
        })
        .collect()
}

/// Checks the trip's pushes numbered `range`, in order on `scene`, and returns the outlines after
/// them.
pub(super) fn check_pushes(
    scene: &Scene,
    trip: &Trip,
    range: std::ops::Range<usize>,
    found: &mut Vec<String>,
) -> Vec<ConvexPolygon> {
    let mut world: Vec<ConvexPolygon> = (0..scene.len())
        .map(|i| scene.world_polygon(i).clone())
        .collect();
    let mut poses: Vec<_> = scene.objects().iter().map(|o| o.pose).collect();
    let chosen: Option<&Vec<ObjectId>> = trip
        .plan
        .cluster
        .and_then(|k| trip.plan.clustering.clusters.get(k));
    for (n, push) in trip
        .plan
        .pushes
        .iter()
        .enumerate()
        .take(range.end)
        .skip(range.start)
    {
        let Some(index) = scene.index_of(push.object) else {
            found.push(format!(
                "push {n}: object {} is not on the table",
                push.object
            ));
            continue;
        };
        if chosen.is_some_and(|c| !c.contains(&push.object))
            && !trip.plan.ahead.contains(&push.object)
        {
            found.push(format!(
                "push {n}: object {} is not in the chosen cluster",
                push.object
            ));
        }
        let pose = poses[index];
        if (pose.x - push.from.x).abs() > TOLERANCE
            || (pose.y - push.from.y).abs() > TOLERANCE
            || (pose.yaw - push.from.yaw).abs() > TOLERANCE
        {
            found.push(format!(
                "push {n}: object {} does not start where it stands",
                push.object
            ));
        }
        let direction = push.direction;
        if (direction.norm() - 1.0).abs() > 1e-9 || push.distance.is_nan() || push.distance < 0.0 {
            found.push(format!(
                "push {n}: direction is not a unit vector or distance is negative"
            ));
            continue;
        }
        let moved = direction * push.distance;
        if (push.to.x - push.from.x - moved.x).abs() > TOLERANCE
            || (push.to.y - push.from.y - moved.y).abs() > TOLERANCE
        {
            found.push(format!(
                "push {n}: the target is not the start moved along the push"
            ));
        }
        for (other, outline) in world.iter().enumerate() {
            if other == index {
                continue;
            }
            if let Some(hit) = cast_distance(&world[index], &direction, push.distance, outline)
                && hit < push.distance - TOLERANCE
            {
                found.push(format!(
                    "push {n}: object {} hits object {} after {:.1} mm",
                    push.object,
                    scene.objects()[other].id,
                    hit * 1e3
                ));
            }
        }
        if !check_fork(scene, (n, push), &world, index, found) {
            continue;
        }
        world[index] = world[index].translated(&moved);
        poses[index] = push.to;
    }
    world
}

/// The fork of push `n` (of the object at `index`, whose outline on the table before the push is
/// `world[index]`): a jaw angle, a jaw line across the push, fingers that travel with the object,
/// that come down clear of every object and touch no other on their way. False when the jaw angle
/// is no angle, so that nothing else of the push can be checked (the push is then not applied).
fn check_fork(
    scene: &Scene,
    (n, push): (usize, &crate::push::Push),
    world: &[ConvexPolygon],
    index: usize,
    found: &mut Vec<String>,
) -> bool {
    let gripper = scene.gripper();
    let direction = push.direction;
    let moved = direction * push.distance;
    let fork = &push.fork;
    if !angle_ok(fork.jaw_angle) {
        found.push(format!(
            "push {n}: jaw angle {} rad is not an angle within ±{MAX_YAW} rad",
            crate::error::number(fork.jaw_angle)
        ));
        return false;
    }
    let jaw_line = Vector2::new(fork.jaw_angle.cos(), fork.jaw_angle.sin());
    if jaw_line.dot(&direction).abs() > MAX_SKEW.sin() + 1e-9 {
        found.push(format!(
            "push {n}: the jaw line is {:.1}° from perpendicular to the push (at most {:.0}°)",
            jaw_line.dot(&direction).abs().asin().to_degrees(),
            MAX_SKEW.to_degrees()
        ));
    }
    if ((fork.end - fork.contact) - moved).norm() > TOLERANCE {
        found.push(format!(
            "push {n}: the fingers do not travel with the object"
        ));
    }
    let at_contact = fingers(gripper, &fork.contact, fork.jaw_angle, fork.opening);
    if at_contact
        .iter()
        .any(|f| penetration_depth(f, &world[index]) > TOUCH)
    {
        found.push(format!(
            "push {n}: the fingers cut into object {}",
            push.object
        ));
    }
    let at_approach = fingers(gripper, &fork.approach, fork.jaw_angle, fork.opening);
    let travel = fork.end - fork.approach;
    let length = travel.norm();
    for (other, outline) in world.iter().enumerate() {
        if at_approach.iter().any(|f| overlap(f, outline, TOLERANCE)) {
            found.push(format!(
                "push {n}: the fingers are lowered onto object {}",
                scene.objects()[other].id
            ));
        }
        if other == index || length == 0.0 {
            continue;
        }
        if at_approach
            .iter()
            .any(|f| cast_distance(f, &(travel / length), length, outline).is_some())
        {
            found.push(format!(
                "push {n}: the fingers hit object {}",
                scene.objects()[other].id
            ));
        }
    }
    true
}

/// An angle the plan may give: finite and, like an object's yaw, within ±[`MAX_YAW`] radians (far
/// larger values cannot be reduced to an angle accurately).
fn angle_ok(angle: f64) -> bool {
    angle.is_finite() && angle.abs() <= MAX_YAW
}

pub(super) fn check_grasp(
    scene: &Scene,
    world: &[ConvexPolygon],
    trip: &Trip,
    found: &mut Vec<String>,
) {
    let gripper = scene.gripper();
    let jaws = &trip.plan.grasp.jaws;
    if !angle_ok(jaws.angle) {
        found.push(format!(
            "grasp: jaw angle {} rad is not an angle within ±{MAX_YAW} rad",
            crate::error::number(jaws.angle)
        ));
        return;
    }
    if !(jaws.center.x.is_finite() && jaws.center.y.is_finite()) {
        found.push("grasp: the jaws' centre is not finite".to_string());
        return;
    }
    if !(jaws.opening > gripper.plate_thickness && jaws.opening <= gripper.stroke + TOLERANCE) {
        found.push(format!(
            "grasp: opening {:.1} mm is outside the gripper's range",
            jaws.opening * 1e3
        ));
        return;
    }
    let plates = jaws.plates(gripper);
    for (index, outline) in world.iter().enumerate() {
        if plates.iter().any(|p| overlap(p, outline, TOLERANCE)) {
            found.push(format!(
                "grasp: a plate lands on object {}",
                scene.objects()[index].id
            ));
        }
    }
    let between = jaws.between(gripper);
    let mut total = 0.0;
    for id in &trip.plan.grasp.objects {
        let Some(index) = scene.index_of(*id) else {
            found.push(format!("grasp: object {id} is not on the table"));
            continue;
        };
        if !overlap(&between, &world[index], 0.0) {
            found.push(format!("grasp: object {id} is not between the plates"));
        }
        // An object may turn while the jaws close, so it can end up to its diameter wide.
        let outline = &world[index];
        total += outline
            .vertices()
            .iter()
            .flat_map(|a| outline.vertices().iter().map(move |b| (a - b).norm()))
            .fold(0.0, f64::max);
    }
    // The plates are short: they may close past parts of an object that lie beside them, so the
    // closed width has no lower bound but zero.
    let claimed = trip.plan.grasp.width;
    if !trip.plan.grasp.objects.is_empty()
        && (claimed <= 0.0 || claimed > total + TOUCH || claimed > jaws.gap(gripper) + TOUCH)
    {
        found.push(format!(
            "grasp: closed width {:.2} mm is not in (0, min(sum of diameters {:.2} mm, gap {:.2} mm)]",
            claimed * 1e3,
            total * 1e3,
            jaws.gap(gripper) * 1e3
        ));
    }
}
