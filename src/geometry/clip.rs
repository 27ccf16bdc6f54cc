//! Clipping convex polygons by half-planes, and the intersection of two convex polygons.
//!
//! A convex polygon is the intersection of its edges' half-planes `n·x ≤ d` (`n` the outward unit
//! normal). Clipping a convex vertex loop by one half-plane keeps the vertices inside and adds the two
//! points where the boundary crosses the line (Sutherland–Hodgman), so the intersection of two convex
//! polygons is the first clipped by every half-plane of the second: `O(n·m)`.

use nalgebra::{Point2, Vector2};

use super::polygon::ConvexPolygon;

/// The polygon's edges as half-planes `n·x ≤ d`, `n` the outward unit normal.
pub fn half_planes(polygon: &ConvexPolygon) -> Vec<(Vector2<f64>, f64)> {
    polygon
        .edges()
        .filter_map(|(p, q)| {
            let edge = q - p;
            let length = edge.norm();
            (length > 1e-12).then(|| {
                let normal = Vector2::new(edge.y, -edge.x) / length;
                (normal, normal.dot(&p.coords))
            })
        })
        .collect()
}

/// The part of the convex vertex loop `points` where `normal·x ≤ d` (Sutherland–Hodgman); empty when
/// none of it is.
pub fn clip(points: &[Point2<f64>], normal: &Vector2<f64>, d: f64) -> Vec<Point2<f64>> {
    let mut out = Vec::with_capacity(points.len() + 1);
    for (k, p) in points.iter().enumerate() {
        let q = &points[(k + 1) % points.len()];
        let (fp, fq) = (normal.dot(&p.coords) - d, normal.dot(&q.coords) - d);
        if fp <= 0.0 {
            out.push(*p);
        }
        if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
            out.push(p + (q - p) * (fp / (fp - fq)));
        }
    }
    out
}

/// The vertex loop of `first ∩ second` (counter-clockwise; fewer than three points when they meet in
/// at most a segment).
pub fn intersection(first: &ConvexPolygon, second: &ConvexPolygon) -> Vec<Point2<f64>> {
    let mut points = first.vertices().to_vec();
    for (normal, d) in half_planes(second) {
        if points.is_empty() {
            break;
        }
        points = clip(&points, &normal, d);
    }
    points
}

/// The convex polygon of the hull of `points`, with points nearer than a nanometre to the last kept
/// one and turns straighter than 10⁻⁷ dropped first (clipping leaves such near-copies where a vertex
/// lies on a clipping line); `None` when fewer than three points remain.
pub fn tidy_polygon(points: &[Point2<f64>]) -> Option<ConvexPolygon> {
    let mut kept = distinct_hull(points);
    let mut changed = true;
    while changed && kept.len() >= 3 {
        changed = false;
        let n = kept.len();
        for i in 0..n {
            let (a, b, c) = (kept[(i + n - 1) % n], kept[i], kept[(i + 1) % n]);
            let (incoming, outgoing) = (b - a, c - b);
            let sine = super::cross(&incoming, &outgoing) / (incoming.norm() * outgoing.norm());
            if sine.abs() <= 1e-7 {
                kept.remove(i);
                changed = true;
                break;
            }
        }
    }
    ConvexPolygon::new(kept).ok()
}

/// The hull of `points` (counter-clockwise) with points nearer than a nanometre to the last kept
/// one dropped, around the loop's end too.
pub(super) fn distinct_hull(points: &[Point2<f64>]) -> Vec<Point2<f64>> {
    let mut kept: Vec<Point2<f64>> = Vec::new();
    for p in super::convex_hull(points) {
        if kept.last().is_none_or(|q| (p - q).norm() > 1e-9) {
            kept.push(p);
        }
    }
    while kept.len() > 1 && (kept[0] - kept[kept.len() - 1]).norm() <= 1e-9 {
        kept.pop();
    }
    kept
}

/// The area of a vertex loop (shoelace; positive counter-clockwise).
pub fn loop_area(points: &[Point2<f64>]) -> f64 {
    let n = points.len();
    0.5 * (0..n)
        .map(|i| {
            let (p, q) = (points[i], points[(i + 1) % n]);
            p.x * q.y - q.x * p.y
        })
        .sum::<f64>()
}

/// Intersection over union of two convex polygons, in `[0, 1]`.
pub fn intersection_over_union(first: &ConvexPolygon, second: &ConvexPolygon) -> f64 {
    let common = loop_area(&intersection(first, second)).max(0.0);
    common / (first.area() + second.area() - common)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::polygon::square;

    #[test]
    fn overlapping_squares_share_the_quarter_the_geometry_gives() {
        // Unit squares offset by half a side in x and y share a 0.5 × 0.5 square.
        let (a, b) = (square(0.0, 0.0, 1.0), square(0.5, 0.5, 1.0));
        assert!((loop_area(&intersection(&a, &b)) - 0.25).abs() < 1e-12);
        assert!((intersection_over_union(&a, &b) - 0.25 / 1.75).abs() < 1e-12);
        assert!((intersection_over_union(&a, &a) - 1.0).abs() < 1e-12);
        assert_eq!(intersection_over_union(&a, &square(3.0, 0.0, 1.0)), 0.0);
    }
}
