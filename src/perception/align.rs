//! The prior's frame kept: an object that the prior holds keeps its own frame, turned by the angle
//! that best fits the prior's outline onto the outline seen. So its yaw is a measurement, and a
//! library shape keeps the frame its name implies.
//!
//! With `P` the prior's outline and `Q` the one seen, both about their area centroids, the turn is
//! `δ* = argmax_{|δ| ≤ reach} IoU(R(δ)·P, Q)`, found on a 1° grid and refined by golden-section
//! search to 0.01°. The object's pose is then the prior's frame origin carried along: with `o` the
//! origin's offset from `P`'s centroid, the new origin is `c_Q + R(δ*)·o` and the yaw `θ + δ*`.
//! A symmetric outline fits equally at several turns; the search stays within `reach` of the prior.

use nalgebra::{Isometry2, Vector2};

use crate::geometry::{ConvexPolygon, intersection_over_union};
use crate::scene::{Object, Pose};

/// How far from the prior's yaw the turn is searched, radians (20°).
pub const TURN_REACH: f64 = 0.35;

/// The pose and own-frame outline of `seen` (a table-frame outline) in the frame of `prior`.
pub fn in_prior_frame(seen: &ConvexPolygon, prior: &Object) -> (Pose, ConvexPolygon) {
    let before = prior.world_polygon();
    let (turn, _) = best_turn(&before, seen, TURN_REACH, 1f64.to_radians());
    in_frame(seen, &before, prior.pose, turn)
}

/// The pose and own-frame outline of `seen` in the frame of an object whose table-frame outline is
/// `before` at `pose`, turned by `turn` about the centroids: the origin's offset from `before`'s
/// centroid is carried along.
pub fn in_frame(
    seen: &ConvexPolygon,
    before: &ConvexPolygon,
    pose: Pose,
    turn: f64,
) -> (Pose, ConvexPolygon) {
    let (c_p, c_q) = (before.centroid(), seen.centroid());
    let offset = Vector2::new(pose.x, pose.y) - c_p.coords;
    let origin = c_q.coords + Isometry2::rotation(turn) * offset;
    let pose = Pose::new(origin.x, origin.y, pose.yaw + turn);
    let own = seen.transformed(&pose.isometry().inverse());
    (pose, own)
}

/// The turn `δ*` within `reach` of 0 that best fits `before` onto `seen`, both about their area
/// centroids, with its IoU: the best point of a grid of `step`, refined by golden-section search
/// within a step either side to 0.01°.
pub fn best_turn(
    before: &ConvexPolygon,
    seen: &ConvexPolygon,
    reach: f64,
    step: f64,
) -> (f64, f64) {
    let (c_p, c_q) = (before.centroid(), seen.centroid());
    let p = before.translated(&-c_p.coords);
    let q = seen.translated(&-c_q.coords);
    let fit = |turn: f64| intersection_over_union(&p.transformed(&Isometry2::rotation(turn)), &q);
    let steps = (reach / step).round() as i32;
    let mut best = (0.0, fit(0.0));
    for k in -steps..=steps {
        let turn = f64::from(k) * step;
        let value = fit(turn);
        if value > best.1 {
            best = (turn, value);
        }
    }
    // Golden-section search within a step either side of the best grid point.
    let ratio = 0.5 * (5.0_f64.sqrt() - 1.0);
    // Each step keeps one interior point and its fit, and evaluates one new point.
    let (mut low, mut high) = (best.0 - step, best.0 + step);
    let (mut a, mut b) = (high - ratio * (high - low), low + ratio * (high - low));
    let (mut fit_a, mut fit_b) = (fit(a), fit(b));
    while high - low > 0.01_f64.to_radians() {
        if fit_a > fit_b {
            (high, b, fit_b) = (b, a, fit_a);
            a = high - ratio * (high - low);
            fit_a = fit(a);
        } else {
            (low, a, fit_a) = (a, b, fit_b);
            b = low + ratio * (high - low);
            fit_b = fit(b);
        }
    }
    let turn = 0.5 * (low + high);
    let value = fit(turn);
    if value >= best.1 { (turn, value) } else { best }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    #[test]
    fn a_turned_and_moved_copy_gives_back_the_turn_and_the_frame() {
        let outline = ConvexPolygon::new(vec![
            Point2::new(-0.01, -0.02),
            Point2::new(0.03, -0.01),
            Point2::new(0.02, 0.02),
        ])
        .unwrap();
        let prior = Object {
            id: crate::id::ObjectId(4),
            name: Some("triangle".into()),
            polygon: outline.clone(),
            pose: Pose::new(0.2, 0.1, 0.3),
            height: 0.03,
            mass: None,
        };
        let moved = Pose::new(0.23, 0.12, 0.3 + 0.1);
        let seen = outline.transformed(&moved.isometry());
        let (pose, own) = in_prior_frame(&seen, &prior);
        assert!((pose.yaw - moved.yaw).abs() < 2e-4, "{pose:?}");
        assert!(
            (pose.x - moved.x).abs() < 1e-5 && (pose.y - moved.y).abs() < 1e-5,
            "{pose:?}"
        );
        for (a, b) in own.vertices().iter().zip(outline.vertices()) {
            assert!((a - b).norm() < 1e-5);
        }
    }
}
