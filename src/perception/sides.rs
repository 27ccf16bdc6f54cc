//! A blob's image outline from lines fitted to its sides, with the corner tips that the 3×3 median
//! cut put back (`formulations/perception.md`, "Sides fitted, tips put back").
//!
//! The hull of a blob's pixel centres follows its outermost pixels: a flying pixel left at an edge
//! bends the side it lies on, and the median (step 2) cuts the tip of every corner sharper than a
//! right angle, leaving a short edge across it. So the hull is first simplified to its sides (a
//! Douglas–Peucker split of the closed loop at [`SIDE_TOLERANCE`]); each side at least
//! [`LONG_SIDE`] long gets the total-least-squares line through the blob's boundary pixels (the
//! outermost pixel of each row and each column) that lie along it, away from its ends. The outline
//! is the intersection of the sides' half-planes; its lines are then moved together by the offset
//! `δ` that gives it the blob's pixel count as its area (as `footprint.rs` does for the hull).
//! Last, short sides between two fitted ones are dropped when the fitted lines meet within the
//! depth a median cuts from a corner of their angle `α`, `TIP_REACH / sin(α/2)` pixels: the tip
//! comes back where the two sides say it is. The pixel count the offset matched did not hold the
//! tip, so the tip is put back after the match. Two guards against sides fitted to noise: a fit
//! that turns more than `MAX_TURN` from its side is not used, and the caller keeps the hull
//! where the outline and the hull overlap by less than [`AGREEMENT`] ([`agrees`]).

use nalgebra::{Point2, Vector2};

use crate::geometry::{clip, intersection_over_union, loop_area, tidy_polygon};

/// How far, pixels, a hull vertex may lie off a side before the side is split there.
pub const SIDE_TOLERANCE: f64 = 1.2;

/// The shortest side, pixels, whose line is fitted to its pixels; shorter sides keep the hull's edge.
pub const LONG_SIDE: f64 = 6.0;

/// Pixels within this distance of a side's line count as lying along it.
const ALONG: f64 = 1.5;

/// Pixels this close to a side's ends are left out of its fit: they belong to the corners.
const END: f64 = 2.0;

/// The most a fitted side may turn from the hull's edge, radians.
const MAX_TURN: f64 = 0.1;

/// How deep, pixels, a 3×3 median cuts a corner of angle `α`: `TIP_REACH / sin(α/2)`.
const TIP_REACH: f64 = 2.0;

/// The least overlap of the fitted outline with the hull for the fit to be kept: chosen on
/// generated scenes 1–20 (0.8 and 0.85 kept a bar whose side was fitted to noise at IoU 0.82 with
/// its truth; 0.92 and above gave back part of the gain), checked on scenes 21–40
/// (`formulations/perception.md`, "Sides fitted, tips put back").
pub const AGREEMENT: f64 = 0.9;

/// A side's line: `normal · p = d`, `normal` the outward unit normal.
#[derive(Clone, Copy, Debug)]
struct Line {
    normal: Vector2<f64>,
    d: f64,
}

/// The outermost pixel centre at each end of every row of `pixels` (indices into rows of `width`):
/// enough for the hull of all their centres.
pub fn row_ends(pixels: &[usize], width: usize) -> Vec<Point2<f64>> {
    extremes(
        pixels,
        |i| (i / width, i % width),
        |v, u| Point2::new(u as f64, v as f64),
    )
}

/// The outermost pixel centre at each end of every column of `pixels`: with [`row_ends`], the
/// boundary pixels the sides are fitted to.
pub fn column_ends(pixels: &[usize], width: usize) -> Vec<Point2<f64>> {
    extremes(
        pixels,
        |i| (i % width, i / width),
        |u, v| Point2::new(u as f64, v as f64),
    )
}

/// The two extreme pixels of each line of pixels: `split` gives a pixel's line and its place along
/// it, `point` the pixel centre from the two.
fn extremes(
    pixels: &[usize],
    split: impl Fn(usize) -> (usize, usize),
    point: impl Fn(usize, usize) -> Point2<f64>,
) -> Vec<Point2<f64>> {
    let mut lines: std::collections::BTreeMap<usize, (usize, usize)> = Default::default();
    for &i in pixels {
        let (line, at) = split(i);
        let e = lines.entry(line).or_insert((at, at));
        *e = (e.0.min(at), e.1.max(at));
    }
    lines
        .iter()
        .flat_map(|(&line, &(low, high))| [point(line, low), point(line, high)])
        .collect()
}

/// The counter-clockwise convex loop `hull` simplified to its sides: the indices of the hull
/// vertices that stay corners, in order.
pub(super) fn corners(hull: &[Point2<f64>]) -> Vec<usize> {
    let n = hull.len();
    // Split the loop at its two vertices farthest apart, then each half where it bends most.
    let (mut a, mut b, mut far) = (0, 0, -1.0);
    for i in 0..n {
        for j in i + 1..n {
            let d = (hull[j] - hull[i]).norm_squared();
            if d > far {
                (a, b, far) = (i, j, d);
            }
        }
    }
    let mut kept = vec![a];
    split(hull, a, b, &mut kept);
    kept.push(b);
    split(hull, b, a + n, &mut kept);
    kept
}

/// Adds to `kept`, in order, the vertices strictly between `from` and `to` (indices modulo the
/// loop's length) that the Douglas–Peucker split keeps.
fn split(hull: &[Point2<f64>], from: usize, to: usize, kept: &mut Vec<usize>) {
    let n = hull.len();
    let (p, q) = (hull[from % n], hull[to % n]);
    let chord = q - p;
    let length = chord.norm();
    let (mut worst, mut at) = (SIDE_TOLERANCE, None);
    for k in from + 1..to {
        let r = hull[k % n] - p;
        let off = if length > 1e-12 {
            (chord.perp(&r) / length).abs()
        } else {
            r.norm()
        };
        if off > worst {
            (worst, at) = (off, Some(k));
        }
    }
    if let Some(k) = at {
        split(hull, from, k, kept);
        kept.push(k % n);
        split(hull, k, to, kept);
    }
}

/// The side from `a` to `b` of a counter-clockwise loop, as a line through both.
fn through(a: Point2<f64>, b: Point2<f64>) -> Line {
    let edge = b - a;
    let normal = Vector2::new(edge.y, -edge.x) / edge.norm();
    Line {
        normal,
        d: normal.dot(&a.coords),
    }
}

/// The total-least-squares line through the points of `boundary` along the side from `a` to `b`
/// (within [`ALONG`] of it, [`END`] or more from its ends), its normal on the side's outward side;
/// `None` with fewer than four such points.
fn fitted(a: Point2<f64>, b: Point2<f64>, boundary: &[Point2<f64>]) -> Option<Line> {
    let side = through(a, b);
    let edge = b - a;
    let length = edge.norm();
    let along: Vec<Point2<f64>> = boundary
        .iter()
        .copied()
        .filter(|p| {
            let t = edge.dot(&(p - a)) / length;
            (side.normal.dot(&p.coords) - side.d).abs() <= ALONG && t >= END && t <= length - END
        })
        .collect();
    if along.len() < 4 {
        return None;
    }
    let mean = along.iter().fold(Vector2::zeros(), |s, p| s + p.coords) / along.len() as f64;
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for p in &along {
        let r = p.coords - mean;
        (xx, xy, yy) = (xx + r.x * r.x, xy + r.x * r.y, yy + r.y * r.y);
    }
    // The direction of least spread is the line's normal.
    let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
    let mut normal = Vector2::new(-angle.sin(), angle.cos());
    if normal.dot(&side.normal) < 0.0 {
        normal = -normal;
    }
    // A fit turned further from the hull's side than the side's own pixels allow is noise.
    if normal.dot(&side.normal) < MAX_TURN.cos() {
        return None;
    }
    Some(Line {
        normal,
        d: normal.dot(&mean),
    })
}

/// The convex region inside every line of `lines`, within `bounds` (a loop around it).
fn inside(lines: &[Line], bounds: &[Point2<f64>]) -> Vec<Point2<f64>> {
    lines.iter().fold(bounds.to_vec(), |region, line| {
        clip(&region, &line.normal, line.d)
    })
}

/// The point where two lines meet, `None` when they are near parallel.
fn meet(p: &Line, q: &Line) -> Option<Point2<f64>> {
    let det = p.normal.perp(&q.normal);
    if det.abs() < 1e-9 {
        return None;
    }
    Some(Point2::new(
        (p.d * q.normal.y - q.d * p.normal.y) / det,
        (p.normal.x * q.d - q.normal.x * p.d) / det,
    ))
}

/// The blob's outline from its hull (pixel centres, counter-clockwise), its boundary pixels and its
/// pixel count, as the module explains; `None` when fewer than three sides remain.
pub fn fitted_outline(
    hull: &[Point2<f64>],
    boundary: &[Point2<f64>],
    count: f64,
) -> Option<Vec<Point2<f64>>> {
    let kept = corners(hull);
    let m = kept.len();
    if m < 3 {
        return None;
    }
    let ends = |j: usize| (hull[kept[j]], hull[kept[(j + 1) % m]]);
    let long: Vec<bool> = (0..m)
        .map(|j| {
            let (a, b) = ends(j);
            (b - a).norm() >= LONG_SIDE
        })
        .collect();
    let lines: Vec<Line> = (0..m)
        .map(|j| {
            let (a, b) = ends(j);
            let hull_line = through(a, b);
            if long[j] {
                fitted(a, b, boundary).unwrap_or(hull_line)
            } else {
                hull_line
            }
        })
        .collect();
    let (lo, hi) = crate::geometry::point_bounds(hull);
    let margin = 0.5 * ((hi - lo).norm() + 10.0);
    let bounds = [
        Point2::new(lo.x - margin, lo.y - margin),
        Point2::new(hi.x + margin, lo.y - margin),
        Point2::new(hi.x + margin, hi.y + margin),
        Point2::new(lo.x - margin, hi.y + margin),
    ];
    let region = inside(&lines, &bounds);
    if region.len() < 3 {
        return None;
    }
    let delta = area_matching_offset(&region, count);
    let moved: Vec<Line> = lines
        .iter()
        .map(|l| Line {
            normal: l.normal,
            d: l.d + delta,
        })
        .collect();
    // Runs of short sides across the tip of a corner between two fitted sides are dropped.
    let mut tips = vec![false; m];
    for before in (0..m).filter(|&j| long[j]) {
        let run: Vec<usize> = (1..m)
            .map(|k| (before + k) % m)
            .take_while(|&j| !long[j])
            .collect();
        let after = (before + run.len() + 1) % m;
        if run.is_empty() || after == before {
            continue;
        }
        let Some(tip) = meet(&moved[before], &moved[after]) else {
            continue;
        };
        // The corner's angle: π less the turn between the two sides' outward normals.
        let angle = std::f64::consts::PI - moved[before].normal.angle(&moved[after].normal);
        let middle = nalgebra::center(&ends(run[0]).0, &ends(run[run.len() - 1]).1);
        if angle > 0.0 && (tip - middle).norm() <= TIP_REACH / (0.5 * angle).sin() {
            for &j in &run {
                tips[j] = true;
            }
        }
    }
    let outline: Vec<Line> = moved
        .iter()
        .zip(&tips)
        .filter(|&(_, &tip)| !tip)
        .map(|(l, _)| *l)
        .collect();
    let region = inside(&outline, &bounds);
    (region.len() >= 3 && loop_area(&region) > 0.0).then_some(region)
}

/// Whether the fitted outline `fitted` and the hull offset to the same area, `hull`, overlap by
/// at least [`AGREEMENT`] (intersection over union). Tips put back and straightened sides move the
/// outline by a pixel or two; more than that means a side was fitted to noise, and the hull is
/// kept.
pub fn agrees(fitted: &[Point2<f64>], hull: &[Point2<f64>]) -> bool {
    match (tidy_polygon(fitted), tidy_polygon(hull)) {
        (Some(a), Some(b)) => intersection_over_union(&a, &b) >= AGREEMENT,
        _ => false,
    }
}

/// The offset δ (pixels, within −1.5 and 1) that moves every edge of the counter-clockwise convex
/// loop `region` outward so that its area is `count`: a mitred offset has area `A + P·δ + K·δ²`,
/// `K = Σ tan(φ/2)` over the exterior angles φ.
pub fn area_matching_offset(region: &[Point2<f64>], count: f64) -> f64 {
    let n = region.len();
    let area = loop_area(region);
    let perimeter: f64 = (0..n)
        .map(|k| (region[(k + 1) % n] - region[k]).norm())
        .sum();
    let bend: f64 = (0..n)
        .map(|k| {
            let (a, b, c) = (region[(k + n - 1) % n], region[k], region[(k + 1) % n]);
            let (e1, e2) = (b - a, c - b);
            if e1.norm() < 1e-12 || e2.norm() < 1e-12 {
                return 0.0;
            }
            let (e1, e2) = (e1.normalize(), e2.normalize());
            (0.5 * e1.perp(&e2).atan2(e1.dot(&e2))).tan()
        })
        .sum();
    let excess = count - area;
    (2.0 * excess / (perimeter + (perimeter.powi(2) + 4.0 * bend * excess).max(0.0).sqrt()))
        .clamp(-1.5, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::convex_hull;

    /// The pixels whose centres lie inside the counter-clockwise convex loop `outline`.
    fn raster(outline: &[Point2<f64>], width: usize) -> Vec<usize> {
        let n = outline.len();
        (0..width * width)
            .filter(|&i| {
                let p = Point2::new((i % width) as f64, (i / width) as f64);
                (0..n).all(|k| {
                    let line = through(outline[k], outline[(k + 1) % n]);
                    line.normal.dot(&p.coords) <= line.d
                })
            })
            .collect()
    }

    /// A sharp triangle whose tip pixels are gone, as the median leaves it: the fitted outline
    /// puts the tip back near where it was, and its area stays the pixels' within a pixel's worth
    /// of perimeter.
    #[test]
    fn a_cut_tip_comes_back_where_the_sides_meet() {
        let width = 80;
        let triangle = [
            Point2::new(10.3, 20.2),
            Point2::new(70.6, 31.1),
            Point2::new(14.8, 40.7),
        ];
        let tip = triangle[1];
        let pixels: Vec<usize> = raster(&triangle, width)
            .into_iter()
            .filter(|&i| {
                let p = Point2::new((i % width) as f64, (i / width) as f64);
                (p - tip).norm() > 4.0
            })
            .collect();
        let hull = convex_hull(&centres(&pixels, width));
        assert!(reach_of(&hull, tip) > 3.5, "the tip is cut");
        let outline = fitted_outline(&hull, &boundary(&pixels, width), pixels.len() as f64)
            .expect("an outline");
        let reach = reach_of(&outline, tip);
        assert!(reach < 1.5, "tip {reach:.2} px away");
        let kept = [triangle[0], triangle[2]].map(|c| reach_of(&outline, c));
        assert!(kept.iter().all(|&d| d < 1.5), "{kept:?}");
    }

    /// The boundary pixels' centres, as `image_hull` gathers them for the fit.
    fn boundary(pixels: &[usize], width: usize) -> Vec<Point2<f64>> {
        let mut points = row_ends(pixels, width);
        points.extend(column_ends(pixels, width));
        points
    }

    /// The centres of `pixels`.
    fn centres(pixels: &[usize], width: usize) -> Vec<Point2<f64>> {
        pixels
            .iter()
            .map(|&i| Point2::new((i % width) as f64, (i / width) as f64))
            .collect()
    }

    /// How far the nearest corner of `outline` lies from `corner`.
    fn reach_of(outline: &[Point2<f64>], corner: Point2<f64>) -> f64 {
        outline
            .iter()
            .map(|p| (p - corner).norm())
            .fold(f64::INFINITY, f64::min)
    }

    /// A square of pixels is its own outline: sides fitted, no tip to put back, the pixel count as
    /// area.
    #[test]
    fn a_square_of_pixels_keeps_its_corners() {
        let width = 30;
        let pixels: Vec<usize> = (5..25)
            .flat_map(|v| (3..23).map(move |u| v * width + u))
            .collect();
        let hull = convex_hull(&centres(&pixels, width));
        let outline = fitted_outline(&hull, &boundary(&pixels, width), 400.0).unwrap();
        assert!((loop_area(&outline) - 400.0).abs() < 1e-6);
        assert_eq!(outline.len(), 4);
        assert!(reach_of(&outline, Point2::new(2.5, 4.5)) < 1e-6);
    }
}
