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
    if v.len() <= 3 || tolerance.is_nan() || tolerance <= 0.0 {
        return polygon.clone();
    }
    let kept = simplified_loop(v, tolerance);
    if kept.len() < 3 || kept.len() == v.len() {
        return polygon.clone();
    }
    // A subset of strictly convex vertices is strictly convex; fall back to the original if rounding
    // says otherwise.
    ConvexPolygon::new(kept).unwrap_or_else(|_| polygon.clone())
}

/// The convex polygon of the hull of `points`, simplified as [`simplify`] does: hull vertices
/// within `tolerance` metres of the chord between kept neighbours are dropped. Points that lie on
/// a line up to rounding, such as the corners of a prism lying on a side face seen from above,
/// would otherwise leave turns too straight for a [`ConvexPolygon`]. `None` when fewer than
/// three vertices remain (the points lie within `tolerance` of a line).
pub fn hull_polygon(points: &[Point2<f64>], tolerance: f64) -> Option<ConvexPolygon> {
    let hull = super::clip::distinct_hull(points);
    if hull.len() < 3 {
        return None;
    }
    let kept = simplified_loop(&hull, tolerance.max(0.0));
    if kept.len() < 3 {
        return None;
    }
    ConvexPolygon::new(kept).ok()
}

/// The walk of the module docs over a convex loop of distinct vertices: the vertices kept.
fn simplified_loop(v: &[Point2<f64>], tolerance: f64) -> Vec<Point2<f64>> {
    let n = v.len();
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
    kept
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

    #[test]
    fn points_on_a_line_up_to_rounding_leave_a_clean_hull() {
        // A 40 mm × 30 mm rectangle whose long sides carry points 1e-13 m off the line, some
        // outside: a side face's corners seen from above.
        let mut points = vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.04, 0.0),
            Point2::new(0.04, 0.03),
            Point2::new(0.0, 0.03),
        ];
        for k in 1..8 {
            let x = 0.005 * k as f64;
            let off = if k % 2 == 0 { 1e-13 } else { -1e-13 };
            points.push(Point2::new(x, off));
            points.push(Point2::new(x, 0.03 - off));
        }
        assert!(ConvexPolygon::new(crate::geometry::convex_hull(&points)).is_err());
        let hull = hull_polygon(&points, SIMPLIFY_TOLERANCE).unwrap();
        assert_eq!(hull.len(), 4);
        assert!((hull.area() - 0.04 * 0.03).abs() < 1e-12);
        // Every point within tolerance of the hull polygon.
        for p in &points {
            assert!(crate::geometry::point_distance(&hull, p) <= SIMPLIFY_TOLERANCE);
        }
        // Points within tolerance of one line make no polygon.
        let line: Vec<Point2<f64>> = (0..10)
            .map(|k| Point2::new(0.004 * k as f64, 1e-5 * (k % 3) as f64))
            .collect();
        assert!(hull_polygon(&line, SIMPLIFY_TOLERANCE).is_none());
    }
}
