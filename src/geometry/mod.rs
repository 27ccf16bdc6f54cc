//! Plane geometry of extruded convex objects: polygons, widths, grasp diameters, separation, contact.
//!
//! Everything is in metres and radians, in the right-handed table frame seen from above (x, y).
//!
//! - [`ConvexPolygon`]: validated, counter-clockwise vertices; area, area centroid, support function
//!   `h(d) = max_v v·d` and width `w(u) = h(u) + h(−u)` along a unit direction `u`.
//! - [`min_grasp_diameter`]: the narrowest stable two-jaw grasp, `d* = min_θ w(θ)`, by rotating calipers
//!   (the stable-contact argument is in that module's docs).
//! - [`separating_line`]: whether two point sets are split by a line (object centroids of two clusters).
//! - [`distance`], [`overlap`]: polygon distances through parry2d-f64 (`queries.rs`, the only place in
//!   the crate that uses parry).
//! - [`penetration_depth`], [`cast_distance`], [`contact_patch`]: exact separating-axis queries for
//!   pushing and squeezing (`sat.rs`); [`contact_points`]: clipped contact points for the planar
//!   closing simulation (`manifold.rs`).
//! - [`Discs`]: bounding discs of many polygons, sorted along x, for the question "which objects can
//!   reach this point" in `O(log N + k)` instead of a scan of every object.
//! - [`intersection`], [`clip`]: convex polygons clipped by half-planes and by each other
//!   (`clip.rs`), and [`intersection_over_union`].
//! - [`simplify`]: a detailed outline reduced to few vertices, moving it by at most a stated tolerance;
//!   [`hull_polygon`]: the hull of a point set so reduced, for points that lie on a line up to rounding.

mod clip;
mod discs;
mod grasp_diameter;
mod manifold;
mod polygon;
mod queries;
mod sat;
mod separation;
mod simplify;

pub use clip::{clip, half_planes, intersection, intersection_over_union, loop_area, tidy_polygon};
pub use discs::Discs;

/// `angle` wrapped into (−π, π], radians: a turn the short way round.
pub fn wrap_angle(angle: f64) -> f64 {
    let wrapped = angle.rem_euclid(std::f64::consts::TAU);
    if wrapped > std::f64::consts::PI {
        wrapped - std::f64::consts::TAU
    } else {
        wrapped
    }
}
pub use grasp_diameter::{GraspDiameter, edge_grasps, min_grasp_diameter};
pub use manifold::{ContactPoint, contact_points};
pub use polygon::{ConvexPolygon, PolygonError, cross, point_bounds};
pub use queries::{distance, overlap, point_distance};
pub(crate) use sat::Extremes;
pub use sat::{ContactPatch, cast_distance, contact_patch, max_separation, penetration_depth};
pub use separation::{SeparatingLine, are_separable, convex_hull, separating_line};
pub use simplify::{SIMPLIFY_ABOVE, SIMPLIFY_TOLERANCE, hull_polygon, simplify};

/// Whether a query between outlines of `n` and `m` vertices should prune (`sat.rs`, `manifold.rs`,
/// the MILP's row test) rather than scan plainly. Both give the same answers; the bounds pay for
/// themselves only on outlines of many vertices. Measured by `cargo bench --bench planners`
/// (push-mog-time's median planning per trip, seeds 1–5): pruning everywhere took the library's
/// outlines (3 to 8 vertices) from 12.8–13.3 ms to 14.4–14.8 ms, and rounded corners (18 to 48)
/// from 40.2–42.9 ms to 37.1–38.4 ms (pruning only where this says so: 13.6–13.8 and 37.1–38.4).
pub(crate) fn worth_pruning(n: usize, m: usize) -> bool {
    n * m > 64
}

/// Pairs of convex outlines for checking the pruned queries against plain ones: `count` random
/// ellipses sampled at 3 to 48 angles (traced outlines have up to 48 vertices), the second placed
/// `offset` metres away in x and y, so that pairs lie apart, touching and overlapping; then unit
/// squares side by side, corner to corner and face to face, where axes tie.
#[cfg(test)]
pub(crate) fn test_pairs(
    seed: u64,
    count: usize,
    offset: (f64, f64),
) -> Vec<(ConvexPolygon, ConvexPolygon)> {
    use crate::random::SeededRng;
    let ellipse = |random: &mut SeededRng, x: f64, y: f64| {
        let vertices = 3 + random.index(46);
        let mut angles: Vec<f64> = (0..vertices)
            .map(|_| random.uniform(0.0, std::f64::consts::TAU))
            .collect();
        angles.sort_by(f64::total_cmp);
        let (a, b) = (random.uniform(0.01, 0.06), random.uniform(0.01, 0.06));
        let points = angles
            .iter()
            .map(|t| nalgebra::Point2::new(x + a * t.cos(), y + b * t.sin()));
        ConvexPolygon::new(points.collect()).ok()
    };
    let mut random = SeededRng::new(seed);
    let mut pairs = Vec::new();
    while pairs.len() < count {
        let x = random.uniform(offset.0, offset.1);
        let y = random.uniform(offset.0, offset.1);
        if let (Some(p), Some(q)) = (ellipse(&mut random, 0.0, 0.0), ellipse(&mut random, x, y)) {
            pairs.push((p, q));
        }
    }
    let square = |x: f64, y: f64| {
        ConvexPolygon::rectangle(
            &nalgebra::Point2::new(x + 0.5, y + 0.5),
            &nalgebra::Vector2::x(),
            0.5,
            0.5,
        )
    };
    for (x, y) in [
        (1.0, 0.0),
        (1.0, 1.0),
        (1.0, 0.5),
        (0.0, 1.0),
        (-1.0, -1.0),
        (0.5, 0.5),
    ] {
        pairs.push((square(0.0, 0.0), square(x, y)));
    }
    pairs
}
