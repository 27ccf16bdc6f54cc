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
//!
//! Here the plan and its record; one trip and its clustering in `trip.rs`; its pushes and grasp in
//! `actions.rs`.

use super::{Plan, RunStatus};
use crate::scene::ObjectId;

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
/// - with plans applied exactly (`ideal`), each trip carries exactly what its grasp claims and its
///   riders (unless a
///   landing stopped it) and only objects on its table, each look during a trip is its table after
///   the pushes made before the look, and each trip's table is the previous one's after its pushes
///   less what it carried;
/// - with other executors (physics, a robot), objects may topple out of view and come back, or be
///   lifted along with others: a trip's table and its looks hold only objects seen before and not
///   yet carried, and what a trip carries was seen before and not yet carried (with plans applied
///   exactly, a look holds only objects of its trip's table);
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
        // A look shows the trip's table after some of its pushes: with plans applied exactly only
        // objects of that table; in physics also one seen before that was out of view (toppled,
        // or a rider standing on another object) and has come back.
        for (n, look) in trip.looks.iter().enumerate() {
            for id in look.scene.ids() {
                if carried.contains(&id) || !(here.contains(&id) || !exact && seen.contains(&id)) {
                    add(
                        Some(k),
                        format!("look {n}: object {id} was not on the trip's table"),
                    );
                }
            }
        }
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
            let claimed: BTreeSet<ObjectId> = trip
                .plan
                .grasp
                .objects
                .iter()
                .chain(trip.plan.riders.iter().map(|r| &r.object))
                .copied()
                .collect();
            if claimed != this_trip {
                add(
                    Some(k),
                    "plans applied exactly must carry what the grasp claims".to_string(),
                );
            }
        }
        carried.extend(this_trip);
        if exact {
            let mut poses = pushed_table(trip, &mut |what| add(Some(k), what));
            poses.retain(|(id, _)| !carried.contains(id));
            expected = Some(poses);
        }
    }
    check_status(&plan.status, &seen, &carried, &mut |what| add(None, what));
    found
}

/// Plans applied exactly: the trip's table after all its pushes, each look checked to be its table
/// after the pushes made before it (what is wrong goes to `add`).
fn pushed_table(trip: &super::Trip, add: &mut dyn FnMut(String)) -> Vec<(ObjectId, [f64; 3])> {
    let mut poses: Vec<(ObjectId, [f64; 3])> = trip
        .scene
        .objects
        .iter()
        .map(|o| (o.id, [o.pose.x, o.pose.y, o.pose.yaw]))
        .collect();
    let mut looks = trip.looks.iter().enumerate().peekable();
    for (n, push) in trip.plan.pushes.iter().enumerate() {
        while let Some((l, look)) = looks.next_if(|(_, look)| look.after_pushes == n) {
            if !same_table(&poses, &look.scene) {
                add(format!(
                    "look {l} is not the trip's table after its first {n} pushes"
                ));
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
            add(format!("look {l} is not the trip's table after its pushes"));
        }
    }
    poses
}

/// The run's final status against the objects `seen` and `carried` over its trips (what is wrong
/// goes to `add`).
fn check_status(
    status: &RunStatus,
    seen: &std::collections::BTreeSet<ObjectId>,
    carried: &std::collections::BTreeSet<ObjectId>,
    add: &mut dyn FnMut(String),
) {
    use std::collections::BTreeSet;
    let left: BTreeSet<ObjectId> = seen.difference(carried).copied().collect();
    match status {
        RunStatus::Cleared => {
            if !left.is_empty() {
                add(format!(
                    "status cleared, but objects {left:?} were never carried"
                ));
            }
        }
        RunStatus::Stopped { remaining, .. } => {
            let remaining: BTreeSet<ObjectId> = remaining.iter().copied().collect();
            if let Some(id) = remaining.intersection(carried).next() {
                add(format!("object {id} is said to be left but was carried"));
            }
            if let Some(id) = left.difference(&remaining).next() {
                add(format!(
                    "object {id} was neither carried nor said to be left"
                ));
            }
        }
    }
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

mod actions;
mod riders;
mod trip;

pub use trip::{verify_clustering, verify_trip};
