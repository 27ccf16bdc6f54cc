//! Property tests of the geometry against independent formulas and brute force.

use std::f64::consts::{PI, TAU};

use nalgebra::{Isometry2, Point2, Vector2};
use proptest::prelude::*;
use pushmog::geometry::{
    ConvexPolygon, are_separable, cast_distance, convex_hull, distance, min_grasp_diameter,
    penetration_depth, separating_line,
};

fn width_at(polygon: &ConvexPolygon, angle: f64) -> f64 {
    polygon.width(&Vector2::new(angle.cos(), angle.sin()))
}

/// The widths over 10,000 evenly spaced closing directions in `[0, π)`.
fn sampled_widths(polygon: &ConvexPolygon) -> Vec<f64> {
    (0..SAMPLES)
        .map(|k| width_at(polygon, PI * k as f64 / SAMPLES as f64))
        .collect()
}

const SAMPLES: usize = 10_000;

/// Brute-force minimum width: 10,000 evenly spaced directions, then 10,000 more across the two
/// neighbouring steps of every sampled local minimum within 10 µm of the best. The width has a kink at
/// its minimum, so the even grid alone is off by up to (edge length) × (half a step), about 6 µm for
/// a 4 cm edge; the second pass brings that to nanometres without using any knowledge of edges.
fn brute_force_min_width(polygon: &ConvexPolygon) -> f64 {
    let widths = sampled_widths(polygon);
    let best = widths.iter().copied().fold(f64::INFINITY, f64::min);
    let step = PI / SAMPLES as f64;
    let mut refined = best;
    for k in 0..SAMPLES {
        let (before, after) = (
            widths[(k + SAMPLES - 1) % SAMPLES],
            widths[(k + 1) % SAMPLES],
        );
        if widths[k] <= before && widths[k] <= after && widths[k] <= best + 1e-5 {
            let centre = PI * k as f64 / SAMPLES as f64;
            for j in 0..=SAMPLES {
                let angle = centre - step + 2.0 * step * j as f64 / SAMPLES as f64;
                refined = refined.min(width_at(polygon, angle));
            }
        }
    }
    refined
}

/// A random convex polygon: points on an ellipse at sorted random angles, rotated and moved, with its
/// vertex list possibly reversed (clockwise) and rotated in start.
fn convex_polygon() -> impl Strategy<Value = Vec<Point2<f64>>> {
    (
        prop::collection::vec(0.0..TAU, 3..12),
        0.005..0.05f64,
        0.2..1.0f64,
        0.0..TAU,
        (-1.0..1.0f64, -1.0..1.0f64),
        any::<bool>(),
        0usize..12,
    )
        .prop_map(
            |(mut angles, radius, aspect, turn, (x, y), reverse, start)| {
                angles.sort_by(f64::total_cmp);
                let pose = Isometry2::new(Vector2::new(x, y), turn);
                let mut points: Vec<Point2<f64>> = angles
                    .iter()
                    .map(|a| pose * Point2::new(radius * a.cos(), radius * aspect * a.sin()))
                    .collect();
                if reverse {
                    points.reverse();
                }
                let n = points.len();
                points.rotate_left(start % n);
                points
            },
        )
}

/// Random points (for hulls).
fn point_cloud() -> impl Strategy<Value = Vec<Point2<f64>>> {
    prop::collection::vec((-0.05..0.05f64, -0.05..0.05f64), 3..40)
        .prop_map(|list| list.into_iter().map(|(x, y)| Point2::new(x, y)).collect())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn min_grasp_diameter_matches_brute_force(points in convex_polygon()) {
        // Sampled angles can come too close to one another and fail validation; skip those draws.
        let Ok(polygon) = ConvexPolygon::new(points) else { return Ok(()); };
        let calipers = min_grasp_diameter(&polygon).diameter;
        // The true minimum lies below every one of the 10,000 sampled widths.
        let coarse = sampled_widths(&polygon).into_iter().fold(f64::INFINITY, f64::min);
        prop_assert!(calipers <= coarse + 1e-12, "calipers {calipers} > sampled {coarse}");
        let brute = brute_force_min_width(&polygon);
        prop_assert!(calipers <= brute + 1e-12, "calipers {calipers} > brute {brute}");
        prop_assert!(brute - calipers <= 1e-6, "calipers {calipers}, brute {brute}");
    }

    #[test]
    fn min_grasp_diameter_of_hulls_matches_brute_force(points in point_cloud()) {
        let hull = convex_hull(&points);
        let Ok(polygon) = ConvexPolygon::new(hull) else { return Ok(()); };
        let calipers = min_grasp_diameter(&polygon);
        let brute = brute_force_min_width(&polygon);
        prop_assert!((brute - calipers.diameter).abs() <= 1e-6, "calipers {}, brute {brute}", calipers.diameter);
        // The contacts are a stable grasp: the segment joining them is the closing axis, of length d*,
        // and both lie on the polygon (inside or on the boundary).
        let [a, b] = calipers.contacts(&polygon);
        prop_assert!(((b - a) - calipers.axis * calipers.diameter).norm() < 1e-9);
        prop_assert!(polygon.contains_point(&a, 1e-9) && polygon.contains_point(&b, 1e-9));
        // Hull points all lie inside the polygon.
        for p in &points {
            prop_assert!(polygon.contains_point(p, 1e-12));
        }
    }

    #[test]
    fn regular_polygon_area_and_centroid(sides in 3usize..12, radius in 0.001..1.0f64,
                                         turn in 0.0..TAU, x in -5.0..5.0f64, y in -5.0..5.0f64) {
        let points: Vec<Point2<f64>> = (0..sides)
            .map(|k| {
                let a = turn + TAU * k as f64 / sides as f64;
                Point2::new(x + radius * a.cos(), y + radius * a.sin())
            })
            .collect();
        let polygon = ConvexPolygon::new(points).unwrap();
        let exact_area = 0.5 * sides as f64 * radius * radius * (TAU / sides as f64).sin();
        prop_assert!((polygon.area() - exact_area).abs() <= 1e-12 * (1.0 + exact_area) * 10.0);
        prop_assert!((polygon.centroid() - Point2::new(x, y)).norm() <= 1e-12 * (1.0 + x.abs() + y.abs()) * 10.0);
        // Width of a regular polygon: 2r cos(π/n) for even n, r (1 + cos(π/n)) for odd n.
        let n = sides as f64;
        let exact_width = if sides % 2 == 0 { 2.0 * radius * (PI / n).cos() } else { radius * (1.0 + (PI / n).cos()) };
        prop_assert!((min_grasp_diameter(&polygon).diameter - exact_width).abs() <= 1e-12 * 10.0);
    }

    #[test]
    fn triangle_area_and_centroid(a in (-1.0..1.0f64, -1.0..1.0f64), b in (-1.0..1.0f64, -1.0..1.0f64),
                                  c in (-1.0..1.0f64, -1.0..1.0f64)) {
        let points = vec![Point2::new(a.0, a.1), Point2::new(b.0, b.1), Point2::new(c.0, c.1)];
        let twice = ((b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)).abs();
        let Ok(polygon) = ConvexPolygon::new(points) else {
            // Only near-degenerate triangles may be refused.
            prop_assert!(twice < 1e-6);
            return Ok(());
        };
        prop_assert!((polygon.area() - twice / 2.0).abs() < 1e-12);
        let mean = Point2::new((a.0 + b.0 + c.0) / 3.0, (a.1 + b.1 + c.1) / 3.0);
        prop_assert!((polygon.centroid() - mean).norm() < 1e-9);
    }

    #[test]
    fn rectangle_area_centroid_and_width(w in 0.001..1.0f64, h in 0.001..1.0f64, turn in 0.0..TAU,
                                         x in -1.0..1.0f64, y in -1.0..1.0f64) {
        let pose = Isometry2::new(Vector2::new(x, y), turn);
        let corners = [(-w / 2.0, -h / 2.0), (w / 2.0, -h / 2.0), (w / 2.0, h / 2.0), (-w / 2.0, h / 2.0)];
        let polygon = ConvexPolygon::new(corners.iter().map(|&(u, v)| pose * Point2::new(u, v)).collect()).unwrap();
        prop_assert!((polygon.area() - w * h).abs() < 1e-12);
        prop_assert!((polygon.centroid() - Point2::new(x, y)).norm() < 1e-12);
        prop_assert!((min_grasp_diameter(&polygon).diameter - w.min(h)).abs() < 1e-12);
    }

    #[test]
    fn separation_agrees_with_a_direction_sweep(a in point_cloud(), b in point_cloud(), shift in -0.12..0.12f64) {
        let b: Vec<Point2<f64>> = b.iter().map(|p| p + Vector2::new(shift, 0.0)).collect();
        match separating_line(&a, &b, 0.0) {
            Some(line) => {
                // The returned line really splits the sets.
                prop_assert!(a.iter().all(|p| line.signed_distance(p) < 0.0));
                prop_assert!(b.iter().all(|p| line.signed_distance(p) > 0.0));
            }
            None => {
                // No direction of a fine sweep separates them by more than rounding.
                for k in 0..3600 {
                    let angle = TAU * k as f64 / 3600.0;
                    let n = Vector2::new(angle.cos(), angle.sin());
                    let a_max = a.iter().map(|p| p.coords.dot(&n)).fold(f64::NEG_INFINITY, f64::max);
                    let b_min = b.iter().map(|p| p.coords.dot(&n)).fold(f64::INFINITY, f64::min);
                    prop_assert!(b_min - a_max <= 1e-12, "direction {angle} separates");
                }
            }
        }
        prop_assert_eq!(are_separable(&a, &b, 0.0), are_separable(&b, &a, 0.0));
    }

    #[test]
    fn sliding_stops_exactly_at_contact(a in convex_polygon(), b in convex_polygon(), angle in 0.0..TAU) {
        let (Ok(a), Ok(b)) = (ConvexPolygon::new(a), ConvexPolygon::new(b)) else { return Ok(()); };
        // Start apart: move `a` 0.2 m against the direction of travel.
        let d = Vector2::new(angle.cos(), angle.sin());
        let a = a.translated(&(-d * 0.2 + (b.centroid() - a.centroid())));
        prop_assume!(penetration_depth(&a, &b) == 0.0);
        match cast_distance(&a, &d, 1.0, &b) {
            Some(t) => {
                // Just before: apart (positive distance by GJK); just after: interpenetrating.
                prop_assert!(distance(&a.translated(&(d * (t - 1e-6).max(0.0))), &b) > 0.0 || t < 1e-6);
                prop_assert!(penetration_depth(&a.translated(&(d * (t + 1e-6))), &b) > 0.0);
                prop_assert!(distance(&a.translated(&(d * t)), &b) < 1e-9);
            }
            None => {
                for k in 0..=100 {
                    let moved = a.translated(&(d * (k as f64 / 100.0)));
                    prop_assert!(penetration_depth(&moved, &b) < 1e-9);
                }
            }
        }
    }
}
