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
//! - [`simplify`]: a detailed outline reduced to few vertices, moving it by at most a stated tolerance.

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
pub use simplify::{SIMPLIFY_ABOVE, SIMPLIFY_TOLERANCE, simplify};
