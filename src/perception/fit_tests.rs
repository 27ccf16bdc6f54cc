//! Unit tests of `fit.rs`: exact pixels of random polygons, a lost tip, flips at the edge.

use super::*;
use crate::geometry::{ConvexPolygon, convex_hull, point_distance, tidy_polygon};
use crate::random::SeededRng;

const SIZE: usize = 120;

/// Whether the centre `p` lies inside the convex polygon `truth`.
fn holds(truth: &ConvexPolygon, p: &Point2<f64>) -> bool {
    point_distance(truth, p) == 0.0
}

/// The pixels for which `held` is true.
fn pixels_where(held: impl Fn(usize, &Point2<f64>) -> bool) -> Vec<usize> {
    (0..SIZE * SIZE)
        .filter(|&i| held(i, &Point2::new((i % SIZE) as f64, (i / SIZE) as f64)))
        .collect()
}

/// The hull of the centres `truth` holds, moved by the area-matching offset: the start the
/// pipeline would give without noise.
fn start_of(truth: &ConvexPolygon, keep: impl Fn(&Point2<f64>) -> bool) -> Vec<Point2<f64>> {
    let centres: Vec<Point2<f64>> = (0..SIZE * SIZE)
        .map(|i| Point2::new((i % SIZE) as f64, (i / SIZE) as f64))
        .filter(|p| holds(truth, p) && keep(p))
        .collect();
    let hull = convex_hull(&centres);
    let delta = super::super::sides::area_matching_offset(&hull, centres.len() as f64);
    super::super::footprint::offset(&hull, delta)
}

/// A random convex polygon of 3 to 6 corners in the image, every corner at least `angle` and
/// every side at least 15 pixels, or `None`.
fn polygon(rng: &mut SeededRng, angle: f64) -> Option<ConvexPolygon> {
    let centre = Point2::new(rng.uniform(40.0, 80.0), rng.uniform(40.0, 80.0));
    let points: Vec<Point2<f64>> = (0..3 + rng.index(4))
        .map(|_| {
            let (r, a) = (
                rng.uniform(12.0, 35.0),
                rng.uniform(0.0, std::f64::consts::TAU),
            );
            centre + Vector2::new(a.cos(), a.sin()) * r
        })
        .collect();
    let p = tidy_polygon(&points)?;
    let v = p.vertices();
    let n = v.len();
    (0..n)
        .all(|k| {
            let (a, b, c) = (v[(k + n - 1) % n], v[k], v[(k + 1) % n]);
            (c - b).norm() >= 15.0 && (a - b).angle(&(c - b)) >= angle
        })
        .then_some(p)
}

/// The largest distance from a corner of either outline to the other one.
fn apart(a: &ConvexPolygon, b: &ConvexPolygon) -> f64 {
    let one = a.vertices().iter().map(|v| point_distance(b, v));
    let other = b.vertices().iter().map(|v| point_distance(a, v));
    one.chain(other).fold(0.0, f64::max)
}

/// With every centre classified as the outline holds it, each corner of either outline lies
/// near the other. The image fixes a side only between the centres on either side of it, at
/// most a pixel apart, so a side placed between them is off by up to half a pixel and a corner
/// of angle `α` formed by two such sides by up to `0.5 / sin(α/2)`; a corner cut by a short
/// side where no centre lies between the two may lose up to one more pixel. A corner of the
/// truth gentle enough to be fused (turning by less than [`MERGE_TURN`], less than
/// [`MERGE_STRAY`] from the chord of its neighbours) may be off by that distance more.
#[test]
fn exact_pixels_give_the_outline_within_the_lattice() {
    let mut rng = SeededRng::new(3);
    let mut tried = 0;
    while tried < 150 {
        let Some(truth) = polygon(&mut rng, 40_f64.to_radians()) else {
            continue;
        };
        tried += 1;
        let start = start_of(&truth, |_| true);
        let above = pixels_where(|_, p| holds(&truth, p));
        let fitted = fit_outline(&start, (SIZE, SIZE), &above, |_| true).expect("an outline");
        let fitted = tidy_polygon(&fitted).expect("a polygon");
        let v = truth.vertices();
        let n = v.len();
        let sharpest = (0..n)
            .map(|k| (v[(k + n - 1) % n] - v[k]).angle(&(v[(k + 1) % n] - v[k])))
            .fold(f64::INFINITY, f64::min);
        let fused = (0..n)
            .map(|k| (v[(k + n - 1) % n], v[k], v[(k + 1) % n]))
            .filter(|(a, b, c)| (b - a).angle(&(c - b)) < MERGE_TURN)
            .map(|(a, b, c)| ((c - a).perp(&(b - a)) / (c - a).norm()).abs())
            .filter(|&stray| stray < MERGE_STRAY)
            .fold(0.0, f64::max);
        let off = apart(&fitted, &truth);
        let bound = 0.5 / (0.5 * sharpest).sin() + 1.0 + fused;
        assert!(
            off <= bound,
            "corners {off:.2} px off (bound {bound:.2}) for {v:?}"
        );
    }
}

/// A 30° tip whose centres within 4 pixels of it are gone from the start, as a median leaves
/// it: the pixels beyond the start's cut put it back within a pixel and a half of the truth.
#[test]
fn a_tip_the_start_lost_comes_back() {
    let truth = tidy_polygon(&[
        Point2::new(20.3, 40.2),
        Point2::new(95.6, 60.3),
        Point2::new(20.8, 80.5),
    ])
    .expect("a triangle");
    let tip = Point2::new(95.6, 60.3);
    let start = start_of(&truth, |p| (p - tip).norm() > 4.0);
    let above = pixels_where(|_, p| holds(&truth, p));
    let fitted = fit_outline(&start, (SIZE, SIZE), &above, |_| true).expect("an outline");
    let fitted = tidy_polygon(&fitted).expect("a polygon");
    let start = tidy_polygon(&start).expect("a polygon");
    assert!(
        point_distance(&start, &tip) > 2.0,
        "the start has lost its tip"
    );
    let back = point_distance(&fitted, &tip);
    assert!(back <= 1.5, "the tip is {back:.2} px outside the fit");
}

/// Pixels just inside and just outside the edge flipped alike, as flying pixels flip them: the
/// sides of 200 squares come out where they come out without the flips, on average within a
/// twentieth of a pixel.
#[test]
fn flips_on_both_sides_of_an_edge_do_not_move_it() {
    let mut rng = SeededRng::new(5);
    let mut shifts = Vec::new();
    for _ in 0..200 {
        let (c, a) = (
            Point2::new(rng.uniform(50.0, 70.0), rng.uniform(50.0, 70.0)),
            rng.uniform(0.0, std::f64::consts::TAU),
        );
        let corners: Vec<Point2<f64>> = (0..4)
            .map(|k| {
                let t = a + f64::from(k) * std::f64::consts::FRAC_PI_2;
                c + Vector2::new(t.cos(), t.sin()) * 25.0
            })
            .collect();
        let truth = tidy_polygon(&corners).expect("a square");
        let start = start_of(&truth, |_| true);
        let boundary_distance = |p: &Point2<f64>| {
            let inside = point_distance(&truth, p);
            if inside > 0.0 {
                inside
            } else {
                // Distance to the boundary from inside: the least over the sides.
                let v = truth.vertices();
                (0..4)
                    .map(|k| {
                        let e = v[(k + 1) % 4] - v[k];
                        (e.perp(&(p - v[k])) / e.norm()).abs()
                    })
                    .fold(f64::INFINITY, f64::min)
            }
        };
        let flips: Vec<bool> = (0..SIZE * SIZE)
            .map(|i| {
                let p = Point2::new((i % SIZE) as f64, (i / SIZE) as f64);
                boundary_distance(&p) < 1.0 && rng.unit() < 0.25
            })
            .collect();
        let area = |flip: bool| {
            let above = pixels_where(|i, p| holds(&truth, p) != (flip && flips[i]));
            let fitted = fit_outline(&start, (SIZE, SIZE), &above, |_| true).expect("an outline");
            loop_area(&fitted)
        };
        // The mean outward shift of the four sides, from the area: A = (50 + 2s)².
        shifts.push(0.5 * (area(true).sqrt() - area(false).sqrt()));
    }
    let mean = shifts.iter().sum::<f64>() / shifts.len() as f64;
    assert!(
        mean.abs() < 0.05,
        "the flips moved the sides by {mean:.3} px on average"
    );
}
