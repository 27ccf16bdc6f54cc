//! Polygon–polygon and point–polygon distance by parry2d-f64 (GJK), and the overlap test.
//!
//! This file is the only one in pushmog that talks to parry; it converts at its boundary between the
//! project's nalgebra types and parry's glam types. All polygons passed in are in one common frame
//! (usually the world frame), so parry sees them at the identity pose. Penetration, sliding and contact
//! patches are exact separating-axis computations in `sat.rs` (see there why not parry's EPA).

use nalgebra::Point2;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query;
use parry2d_f64::shape::ConvexPolygon as ParryPolygon;

use super::polygon::ConvexPolygon;
use super::sat::penetration_depth;

fn to_parry(polygon: &ConvexPolygon) -> ParryPolygon {
    let points: Vec<Vector> = polygon
        .vertices()
        .iter()
        .map(|v| Vector::new(v.x, v.y))
        .collect();
    // Invariant: a ConvexPolygon has at least three distinct vertices counter-clockwise, which is all
    // parry asks of an unmodified convex polyline.
    ParryPolygon::from_convex_polyline_unmodified(points)
        .expect("ConvexPolygon invariant: at least three distinct vertices, counter-clockwise")
}

/// Distance in metres between two polygons; `0` when they touch or overlap.
pub fn distance(first: &ConvexPolygon, second: &ConvexPolygon) -> f64 {
    let identity = Pose::IDENTITY;
    query::distance(&identity, &to_parry(first), &identity, &to_parry(second))
        .map(|d| d.distance)
        // Convex polygon pairs are always supported by parry's default dispatcher; fall back to
        // the vertex bound if that ever changes.
        .unwrap_or_else(|_| vertex_distance(first, second))
}

/// Whether the polygons overlap by more than `tolerance` metres of penetration.
pub fn overlap(first: &ConvexPolygon, second: &ConvexPolygon, tolerance: f64) -> bool {
    // Cheap rejection by bounding boxes before the exact query.
    let (lo1, hi1) = first.bounding_box();
    let (lo2, hi2) = second.bounding_box();
    if lo1.x > hi2.x || lo2.x > hi1.x || lo1.y > hi2.y || lo2.y > hi1.y {
        return false;
    }
    penetration_depth(first, second) > tolerance
}

fn vertex_distance(first: &ConvexPolygon, second: &ConvexPolygon) -> f64 {
    let mut best = f64::INFINITY;
    for a in first.vertices() {
        for b in second.vertices() {
            best = best.min(nalgebra::distance(a, b));
        }
    }
    best
}

/// Distance in metres from a point to a polygon; `0` inside.
pub fn point_distance(polygon: &ConvexPolygon, point: &Point2<f64>) -> f64 {
    use parry2d_f64::query::PointQuery;
    to_parry(polygon).distance_to_local_point(Vector::new(point.x, point.y), true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::polygon::square;

    #[test]
    fn distance_and_overlap_of_squares() {
        let a = square(0.0, 0.0, 1.0);
        assert!((distance(&a, &square(3.0, 0.0, 1.0)) - 2.0).abs() < 1e-9);
        assert!(!overlap(&a, &square(1.0, 0.0, 1.0), 1e-9));
        assert!(overlap(&a, &square(0.75, 0.0, 1.0), 1e-9));
        assert!((point_distance(&a, &Point2::new(2.0, 0.5)) - 1.0).abs() < 1e-9);
        assert_eq!(point_distance(&a, &Point2::new(0.5, 0.5)), 0.0);
    }
}
