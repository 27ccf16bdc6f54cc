//! An independent check of plans: geometry only, no planning code.
//!
//! For every trip, on the scene the trip was planned on:
//! - **clustering**: a partition of the objects; every cluster of two or more fits the jaws
//!   (`Σ d* ≤ usable gap`); every two clusters' centroids are split by a line;
//! - **pushes**, in order, on the table as it stands at that moment: the object starts where it is and
//!   ends where the push says; its straight sweep touches no other object; the jaw line is
//!   perpendicular to the push, or at most [`MAX_SKEW`] from it (a flush push meets a face at an
//!   angle, its jaw line along the face); the fingers at the approach point overlap no object, do
//!   not cut into the pushed object at contact, and their sweep to the end of the push touches no
//!   other object;
//! - **looks** (new observations during a trip): each after a number of pushes in order, with the
//!   trip's workspace and gripper and no object the trip's table did not hold; the pushes after a
//!   look are checked on it;
//! - **grasp**, on the table after the pushes (after the last look, on it): the jaw angle (as every
//!   push's) is finite and within ±`MAX_YAW`; the opening lies within the stroke; the open plates
//!   overlap no object; every object the grasp claims lies between the plates; the claimed closed
//!   width is positive and at most both the sum of their diameters (objects may turn while the jaws
//!   close) and the gap between the open plates (the plates are short, so they may close past parts
//!   of objects beside them);
//! - **pushes ahead**: the grasp takes no object the trip pushed ahead for a later trip, and the
//!   rows pushed ahead hold exactly those objects;
//! - **the record** ([`verify_record`]): times, objects carried once, tables that chain from trip to
//!   trip, and a status that agrees with what is left.

use nalgebra::{Point2, Vector2};

use super::{Plan, RunStatus, Trip};
use crate::cluster::Clustering;
use crate::cluster::summed_diameter;
use crate::geometry::{
    ConvexPolygon, cast_distance, overlap, penetration_depth, point_bounds, separating_line,
};
use crate::scene::{Gripper, MAX_YAW, ObjectId, Scene};

/// Numerical slack of the checks, metres.
const TOLERANCE: f64 = 1e-9;
/// Penetration accepted where two shapes are meant to touch, metres.
const TOUCH: f64 = 1e-6;
/// Largest angle between a push and the direction its fingers face, radians (40°): beyond the
/// friction cone of any pad surface the project knows (μ ≤ 0.8, atan 0.8 = 38.7°,
/// `formulations/references.md`), fingers pushing at that angle slide along the face they push.
pub const MAX_SKEW: f64 = 40.0 * std::f64::consts::PI / 180.0;

/// One broken rule.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    /// The trip (0-based), or `None` for the record as a whole.
    pub trip: Option<usize>,
    /// What is wrong.
    pub what: String,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.trip {
            Some(trip) => write!(f, "trip {trip}: {}", self.what),
            None => write!(f, "plan: {}", self.what),
        }
    }
}

/// Every violation in a plan; empty when the plan is sound: each trip by [`verify_trip`], and the
/// record as a whole by [`verify_record`].
pub fn verify(plan: &Plan) -> Vec<Violation> {
    let mut found: Vec<Violation> = plan
        .trips
        .iter()
        .enumerate()
        .flat_map(|(k, trip)| {
            verify_trip(trip).into_iter().map(move |what| Violation {
                trip: Some(k),
                what,
            })
        })
        .collect();
    found.extend(verify_record(plan));
    found
}

/// Violations of the record as a whole:
/// - the robot time is a finite, non-negative number of seconds;
/// - no object is carried twice;
/// - with plans applied exactly (`ideal`), each trip carries exactly what its grasp claims (unless a
///   landing stopped it) and only objects on its table, each look during a trip is its table after
///   the pushes made before the look, and each trip's table is the previous one's after its pushes
///   less what it carried;
/// - with other executors (physics, a robot), objects may topple out of view and come back, or be
///   lifted along with others: a trip's table holds only objects seen before and not yet carried, and
///   what a trip carries was seen before and not yet carried;
/// - a cleared run carried every object it saw; a stopped one left every object it saw and did not
///   carry, and carried none of those it says are left.
pub fn verify_record(plan: &Plan) -> Vec<Violation> {
    use std::collections::BTreeSet;
    let mut found = Vec::new();
    let mut add = |trip: Option<usize>, what: String| found.push(Violation { trip, what });
    if !(plan.seconds.is_finite() && plan.seconds >= 0.0) {
        add(
            None,
            format!("robot time {} s is not a duration", plan.seconds),
        );
    }
    let exact = plan.executor == "ideal";
    let mut seen: BTreeSet<ObjectId> = BTreeSet::new();
    let mut carried: BTreeSet<ObjectId> = BTreeSet::new();
    let mut expected: Option<Vec<(ObjectId, [f64; 3])>> = None;
    for (k, trip) in plan.trips.iter().enumerate() {
        let here: BTreeSet<ObjectId> = trip.scene.objects.iter().map(|o| o.id).collect();
        if k > 0 {
            for id in &here {
                if carried.contains(id) {
                    add(
                        Some(k),
                        format!("object {id} is on the table after it was carried"),
                    );
                } else if !exact && !seen.contains(id) {
                    add(Some(k), format!("object {id} appears from nowhere"));
                }
            }
        }
        if let Some(expected) = expected.take() {
            let ids: Vec<ObjectId> = expected.iter().map(|(id, _)| *id).collect();
            let now: Vec<ObjectId> = trip.scene.objects.iter().map(|o| o.id).collect();
            if ids != now {
                add(
                    Some(k),
                    "the table is not the previous trip's after its pushes and what it carried"
                        .to_string(),
                );
            } else {
                for ((id, pose), object) in expected.iter().zip(&trip.scene.objects) {
                    if pose_off(object.pose, pose) > 1e-9 {
                        add(
                            Some(k),
                            format!("object {id} is not where the previous trip left it"),
                        );
                    }
                }
            }
        }
        seen.extend(here.iter().copied());
        let mut this_trip: BTreeSet<ObjectId> = BTreeSet::new();
        for id in &trip.carried {
            if !this_trip.insert(*id) || carried.contains(id) {
                add(Some(k), format!("object {id} is carried twice"));
            }
            let known = if exact {
                here.contains(id)
            } else {
                seen.contains(id)
            };
            if !known {
                add(Some(k), format!("carried object {id} is not on the table"));
            }
        }
        if exact && trip.fault.is_none() {
            let claimed: BTreeSet<ObjectId> = trip.grasp.objects.iter().copied().collect();
            if claimed != this_trip {
                add(
                    Some(k),
                    "plans applied exactly must carry what the grasp claims".to_string(),
                );
            }
        }
        carried.extend(this_trip);
        if exact {
            // Every look: this table after the pushes made before it. The next table: this one
            // after all the pushes, less what was carried.
            let mut poses: Vec<(ObjectId, [f64; 3])> = trip
                .scene
                .objects
                .iter()
                .map(|o| (o.id, [o.pose.x, o.pose.y, o.pose.yaw]))
                .collect();
            let mut looks = trip.looks.iter().enumerate().peekable();
            for (n, push) in trip.pushes.iter().enumerate() {
                while let Some((l, look)) = looks.next_if(|(_, look)| look.after_pushes == n) {
                    if !same_table(&poses, &look.scene) {
                        add(
                            Some(k),
                            format!("look {l} is not the trip's table after its first {n} pushes"),
                        );
                    }
                }
                if let Some(entry) = poses.iter_mut().find(|(id, _)| *id == push.object) {
                    let moved = push.displacement();
                    entry.1[0] += moved.x;
                    entry.1[1] += moved.y;
                }
            }
            for (l, look) in looks {
                if !same_table(&poses, &look.scene) {
                    add(
                        Some(k),
                        format!("look {l} is not the trip's table after its pushes"),
                    );
                }
            }
            poses.retain(|(id, _)| !carried.contains(id));
            expected = Some(poses);
        }
    }
    let left: BTreeSet<ObjectId> = seen.difference(&carried).copied().collect();
    match &plan.status {
        RunStatus::Cleared => {
            if !left.is_empty() {
                add(
                    None,
                    format!("status cleared, but objects {left:?} were never carried"),
                );
            }
        }
        RunStatus::Stopped { remaining, .. } => {
            let remaining: BTreeSet<ObjectId> = remaining.iter().copied().collect();
            if let Some(id) = remaining.intersection(&carried).next() {
                add(
                    None,
                    format!("object {id} is said to be left but was carried"),
                );
            }
            if let Some(id) = left.difference(&remaining).next() {
                add(
                    None,
                    format!("object {id} was neither carried nor said to be left"),
                );
            }
        }
    }
    found
}

/// Whether `scene` holds exactly these objects at these poses, in order.
fn same_table(poses: &[(ObjectId, [f64; 3])], scene: &super::SharedScene) -> bool {
    poses.len() == scene.objects.len()
        && poses
            .iter()
            .zip(&scene.objects)
            .all(|((id, pose), object)| *id == object.id && pose_off(object.pose, pose) <= 1e-9)
}

/// How far `pose` is from `[x, y, yaw]`: the sum of the absolute differences.
fn pose_off(pose: crate::scene::Pose, expected: &[f64; 3]) -> f64 {
    (pose.x - expected[0]).abs() + (pose.y - expected[1]).abs() + (pose.yaw - expected[2]).abs()
}

/// Every violation in one trip.
pub fn verify_trip(trip: &Trip) -> Vec<String> {
    let scene = match Scene::new(trip.scene.to_spec()) {
        Ok(scene) => scene,
        Err(e) => return vec![format!("the trip's scene is invalid: {e}")],
    };
    let mut found = Vec::new();
    check_clustering(&scene, trip, &mut found);
    if !trip.ahead_rows.is_empty() {
        let mut rows: Vec<ObjectId> = trip
            .ahead_rows
            .iter()
            .flat_map(|r| r.objects.clone())
            .collect();
        let mut ahead = trip.ahead.clone();
        rows.sort_unstable();
        ahead.sort_unstable();
        if rows != ahead {
            found.push("the rows pushed ahead do not hold exactly the objects pushed ahead".into());
        }
    }
    if let Some(id) = trip.ahead.iter().find(|id| trip.grasp.objects.contains(id)) {
        found.push(format!(
            "grasp: takes object {id}, which the trip pushed ahead for a later trip"
        ));
    }
    // The pushes up to the first look on the trip's scene, each later run of pushes on the look
    // before it, the grasp after the last run.
    let mut tables = vec![(scene, 0)];
    let here: std::collections::BTreeSet<ObjectId> = trip.scene.ids().collect();
    for (n, look) in trip.looks.iter().enumerate() {
        let start = tables.last().map_or(0, |t| t.1);
        if look.after_pushes < start || look.after_pushes > trip.pushes.len() {
            found.push(format!(
                "look {n}: after push {} is out of order (the trip has {} pushes)",
                look.after_pushes,
                trip.pushes.len()
            ));
            return found;
        }
        if look.scene.workspace != trip.scene.workspace || look.scene.gripper != trip.scene.gripper
        {
            found.push(format!(
                "look {n}: its workspace or gripper is not the trip's"
            ));
        }
        if let Some(new) = look.scene.objects.iter().find(|o| !here.contains(&o.id)) {
            found.push(format!(
                "look {n}: object {} was not on the trip's table",
                new.id
            ));
        }
        match Scene::new(look.scene.to_spec()) {
            Ok(seen) => tables.push((seen, look.after_pushes)),
            Err(e) => {
                found.push(format!("look {n}: its scene is invalid: {e}"));
                return found;
            }
        }
    }
    let mut world = Vec::new();
    for (k, (table, start)) in tables.iter().enumerate() {
        let end = tables.get(k + 1).map_or(trip.pushes.len(), |t| t.1);
        world = check_pushes(table, trip, *start..end, &mut found);
    }
    if let Some((table, _)) = tables.last() {
        check_grasp(table, &world, trip, &mut found);
    }
    found
}

fn check_clustering(scene: &Scene, trip: &Trip, found: &mut Vec<String>) {
    let clusters = &trip.clustering.clusters;
    if clusters.is_empty() {
        if trip.cluster.is_some() {
            found.push("a cluster is chosen from an empty clustering".to_string());
        }
        return;
    }
    if let Some(k) = trip.cluster
        && k >= clusters.len()
    {
        found.push(format!(
            "cluster {k} chosen from {} clusters",
            clusters.len()
        ));
    }
    found.extend(verify_clustering(scene, &trip.clustering));
}

/// Every violation of a clustering of `scene`: not a partition, a cluster over capacity, two clusters
/// no line separates.
pub fn verify_clustering(scene: &Scene, clustering: &Clustering) -> Vec<String> {
    let clusters = &clustering.clusters;
    let mut found = Vec::new();
    let mut seen = vec![0usize; scene.len()];
    let mut indices: Vec<Vec<usize>> = Vec::new();
    for cluster in clusters {
        let mut members = Vec::new();
        for id in cluster {
            match scene.index_of(*id) {
                Some(i) => {
                    seen[i] += 1;
                    members.push(i);
                }
                None => found.push(format!("clustered object {id} is not on the table")),
            }
        }
        indices.push(members);
    }
    for (i, count) in seen.iter().enumerate() {
        if *count != 1 {
            found.push(format!(
                "object {} is in {count} clusters",
                scene.objects()[i].id
            ));
        }
    }
    let gap = scene.gripper().usable_gap();
    for (k, members) in indices.iter().enumerate() {
        let total = summed_diameter(scene, members);
        if members.len() > 1 && total > gap + TOLERANCE {
            found.push(format!(
                "cluster {k}: summed grasp diameters {:.2} mm exceed the {:.2} mm gap",
                total * 1e3,
                gap * 1e3
            ));
        }
    }
    let centroids: Vec<Vec<Point2<f64>>> = indices
        .iter()
        .map(|m| m.iter().map(|&i| scene.centroid(i)).collect())
        .collect();
    // Clusters whose centroid boxes lie more than twice the tolerance apart along x or y are split
    // by an axis-parallel line; only the others need the exact test (a sweep along x).
    let boxes: Vec<(Point2<f64>, Point2<f64>)> = centroids
        .iter()
        .map(|points| point_bounds(points))
        .collect();
    let mut by_x: Vec<usize> = (0..boxes.len()).collect();
    by_x.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut inseparable = Vec::new();
    for (k, &a) in by_x.iter().enumerate() {
        for &b in &by_x[k + 1..] {
            if boxes[b].0.x > boxes[a].1.x + 2.0 * TOLERANCE {
                break;
            }
            if boxes[a].0.y > boxes[b].1.y + 2.0 * TOLERANCE
                || boxes[b].0.y > boxes[a].1.y + 2.0 * TOLERANCE
            {
                continue;
            }
            if separating_line(&centroids[a], &centroids[b], TOLERANCE).is_none() {
                inseparable.push((a.min(b), a.max(b)));
            }
        }
    }
    inseparable.sort_unstable();
    for (a, b) in inseparable {
        found.push(format!("clusters {a} and {b} are not separable by a line"));
    }
    found
}

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
fn check_pushes(
    scene: &Scene,
    trip: &Trip,
    range: std::ops::Range<usize>,
    found: &mut Vec<String>,
) -> Vec<ConvexPolygon> {
    let gripper = scene.gripper();
    let mut world: Vec<ConvexPolygon> = (0..scene.len())
        .map(|i| scene.world_polygon(i).clone())
        .collect();
    let mut poses: Vec<_> = scene.objects().iter().map(|o| o.pose).collect();
    let chosen: Option<&Vec<ObjectId>> = trip.cluster.and_then(|k| trip.clustering.clusters.get(k));
    for (n, push) in trip
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
        if chosen.is_some_and(|c| !c.contains(&push.object)) && !trip.ahead.contains(&push.object) {
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
        let fork = &push.fork;
        if !angle_ok(fork.jaw_angle) {
            found.push(format!(
                "push {n}: jaw angle {} rad is not an angle within ±{MAX_YAW} rad",
                crate::error::number(fork.jaw_angle)
            ));
            continue;
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
        world[index] = world[index].translated(&moved);
        poses[index] = push.to;
    }
    world
}

/// An angle the plan may give: finite and, like an object's yaw, within ±[`MAX_YAW`] radians (far
/// larger values cannot be reduced to an angle accurately).
fn angle_ok(angle: f64) -> bool {
    angle.is_finite() && angle.abs() <= MAX_YAW
}

fn check_grasp(scene: &Scene, world: &[ConvexPolygon], trip: &Trip, found: &mut Vec<String>) {
    let gripper = scene.gripper();
    let jaws = &trip.grasp.jaws;
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
    for id in &trip.grasp.objects {
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
    let claimed = trip.grasp.width;
    if !trip.grasp.objects.is_empty()
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
