//! Simplifying a detailed convex outline (a dense segmentation contour) to few vertices within a
//! stated tolerance.
//!
//! Keeping a subset of a convex polygon's vertices gives a convex polygon inside the original. Every
//! dropped vertex lies between two kept neighbours `a` and `b`, and the outlines differ there by the
//! dropped vertex's distance from the chord `ab`. The walk below starts at a kept vertex and extends
//! each chord as far as every skipped vertex stays within `tolerance` of it, so the simplified outline
//! lies inside the original and no point of the original is farther than `tolerance` from it (the
//! Hausdorff distance is at most `tolerance`). Each chord is checked against the vertices it skips, so
//! the walk costs O(n·k) for runs of k skipped vertices: linear in n for a contour sampled at a fixed
//! spacing.

use nalgebra::Point2;

use super::polygon::{ConvexPolygon, cross};

/// Vertices above which an outline is simplified when a scene is read: planning queries are
/// quadratic in the vertex count of a pair, and 64 vertices already trace a 5 cm disc to 0.06 mm.
pub const SIMPLIFY_ABOVE: usize = 64;

/// The tolerance of that simplification, metres (0.1 mm): far below the 2 mm perception noise the
/// planner allows for.
pub const SIMPLIFY_TOLERANCE: f64 = 1e-4;

/// Distance from `p` to the line through `a` and `b`.
fn distance_to_chord(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> f64 {
    let chord = b - a;
    let length = chord.norm();
    if length == 0.0 {
        return (p - a).norm();
    }
    cross(&chord, &(p - a)).abs() / length
}

/// `polygon` with vertices dropped wherever the outline moves by at most `tolerance` metres; the
/// result lies inside `polygon` and keeps at least three vertices. Returns `polygon` unchanged when
/// nothing can be dropped.
pub fn simplify(polygon: &ConvexPolygon, tolerance: f64) -> ConvexPolygon {
    let v = polygon.vertices();
    let n = v.len();
    if n <= 3 || tolerance.is_nan() || tolerance <= 0.0 {
        return polygon.clone();
    }
    // Start at the vertex with the sharpest turn: it is kept by any good simplification.
    let start = (0..n)
        .max_by(|&i, &j| {
            let turn = |k: usize| {
                let incoming = v[k] - v[(k + n - 1) % n];
                let outgoing = v[(k + 1) % n] - v[k];
                cross(&incoming.normalize(), &outgoing.normalize())
            };
            turn(i).total_cmp(&turn(j))
        })
        .unwrap_or(0);
    let mut kept = vec![v[start]];
    let mut from = 0; // offset from `start` of the last kept vertex
    while from < n {
        // Extend the chord from `from` to the farthest `to` whose skipped vertices stay within tolerance.
        let mut to = from + 1;
        while to < n {
            let candidate = to + 1;
            let a = v[(start + from) % n];
            let b = v[(start + candidate) % n];
            let fits = (from + 1..candidate)
                .all(|k| distance_to_chord(&v[(start + k) % n], &a, &b) <= tolerance);
            if !fits {
                break;
            }
            to = candidate;
        }
        if to < n {
            kept.push(v[(start + to) % n]);
        }
        from = to;
    }
    if kept.len() < 3 || kept.len() == n {
        return polygon.clone();
    }
    // A subset of strictly convex vertices is strictly convex; fall back to the original if rounding
    // says otherwise.
    ConvexPolygon::new(kept).unwrap_or_else(|_| polygon.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc(radius: f64, n: usize) -> ConvexPolygon {
        ConvexPolygon::new(
            (0..n)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / n as f64;
                    Point2::new(radius * a.cos(), radius * a.sin())
                })
                .collect(),
        )
        .unwrap()
    }

    #[test]
    fn a_dense_disc_keeps_few_vertices_within_tolerance() {
        let dense = disc(0.05, 10_000);
        let simple = simplify(&dense, SIMPLIFY_TOLERANCE);
        assert!(simple.len() <= SIMPLIFY_ABOVE, "{} vertices", simple.len());
        // Every original vertex within tolerance of the simplified outline, which lies inside.
        for p in dense.vertices() {
            let gap = crate::geometry::point_distance(&simple, p);
            assert!(gap <= SIMPLIFY_TOLERANCE + 1e-12, "{gap}");
        }
        for p in simple.vertices() {
            assert!(dense.contains_point(p, 1e-12));
        }
        assert!(dense.area() - simple.area() > 0.0);
    }

    #[test]
    fn a_square_is_left_alone() {
        let square =
            ConvexPolygon::rectangle(&Point2::origin(), &nalgebra::Vector2::x(), 0.01, 0.015);
        assert_eq!(simplify(&square, SIMPLIFY_TOLERANCE), square);
    }
}
