//! A blob's image outline fitted to the pixels on both sides of its edge
//! (`formulations/perception.md`, "The outline fitted to both sides of the edge").
//!
//! The region a blob covers above its cut is convex (the two-plane theorem), so its outline is an
//! intersection of half-planes `s_e(p) = d_e − n_e·(p − c_e) ≥ 0`, one per side: `n_e` the outward
//! normal at angle `θ_e`, `c_e` a fixed point of the side, `d_e` its offset from there. Each pixel
//! centre `p_i` from [`BAND`] outside the starting outline to [`DEEP`] inside it says on which side of the edge it lies:
//! `y_i = +1` when the blob holds it above the cut, `−1` when its depth is known and the blob does
//! not (the table, the blob's own wall below the cut, another object). Pixels without depth say
//! nothing. The outline minimises the logistic loss
//!
//! ```text
//! L = Σ_i log(1 + exp(−y_i·s(p_i)/τ)),   s(p) = min_e s_e(p),
//! ```
//!
//! so each side settles between the last centres in and the first centres out, and a corner's tip
//! where the centres near it put it. Nothing cuts the tips first, as the 3×3 median does for the
//! hull. A flying pixel at an edge is put above the cut as often outside the edge as it is put below
//! it inside, so flying pixels do not bias the sides. Each side's `(d_e, θ_e)` takes damped Newton
//! steps on the pixels whose nearest side (the one giving the minimum) it is, starting from the
//! median hull simplified into sides as `sides.rs` does, less the corners gentler than
//! [`MERGE_TURN`]; a side moves at most [`BAND`] and turns at most [`MAX_TURNED`]. Only the pixels
//! between a row's crossings of the start widened by [`BAND`] and narrowed by [`DEEP`] are read.

use nalgebra::{Point2, Vector2};

use crate::geometry::{clip, loop_area};

/// The logistic loss's scale, pixels.
const TAU: f64 = 0.3;

/// How far outside the starting outline, pixels, a centre may lie to take part: as deep as the
/// median cuts a sharp tip, and more.
const BAND: f64 = 4.0;

/// How far inside it: the start's sides lie within a pixel or so of the edge (the area-matching
/// offset moves them by at most 1.5 pixels), so a centre deeper than this is far inside.
const DEEP: f64 = 2.0;

/// Rounds of Newton steps, at most.
const ROUNDS: usize = 8;

/// The rounds stop once no side moves more than this, pixels (a turn counted at 10 pixels per
/// radian, the lever of a side's end).
const SETTLED: f64 = 0.01;

/// `y·s/τ` beyond which a centre is taken as settled on its own side: its weight in the sums,
/// `exp(−12)` ≈ 6·10⁻⁶ of its own, is 2·10⁻⁵ of that of a centre on the edge.
const SURE: f64 = 12.0;

/// The largest step of a side's offset in one round, pixels, and of its angle, radians.
const MAX_SHIFT: f64 = 0.5;
const MAX_TURN: f64 = 0.05;

/// The most a side may turn from where it started, radians, and (as [`BAND`]) move.
const MAX_TURNED: f64 = 0.15;

/// Corners of the start that turn by less than this, radians (11.5°), are dropped before the fit.
/// The simplification keeps a corner wherever the median hull strays from a chord by more than
/// [`super::sides::SIDE_TOLERANCE`], so a long side bent by noise, or by the rounding the median
/// leaves next to a sharp corner, comes out as two sides nearly in line. Fitted apart, such sides
/// trade the pixels between them from round to round (each takes those on which it lies inside
/// the other), and the one that turns about a centre far from those pixels swings its far corner:
/// a triangle's tip 3 pixels short was traced to that (scene 36, straight down). A corner of a
/// real outline that the simplification keeps turns by more: it strays 1.2 pixels from the chord
/// of two sides of 12 pixels or less only when it turns by 0.2 or more. The side that replaces the
/// two may still turn by [`MAX_TURNED`] either way.
const MERGE_TURN: f64 = 0.2;

/// ... and that lie less than this from the chord between their neighbours, pixels.
const MERGE_STRAY: f64 = 2.4;

/// A side: `s(p) = d − n(θ)·(p − c)`.
#[derive(Clone, Copy, Debug)]
struct Side {
    c: Point2<f64>,
    theta: f64,
    d: f64,
    /// The angle it started at.
    theta0: f64,
    /// `n(θ)`, kept with `θ`.
    n: Vector2<f64>,
}

impl Side {
    fn new(c: Point2<f64>, theta: f64, d: f64) -> Self {
        Self {
            c,
            theta,
            d,
            theta0: theta,
            n: Vector2::new(theta.cos(), theta.sin()),
        }
    }

    fn turn(&mut self, by: f64) {
        self.theta += by;
        self.n = Vector2::new(self.theta.cos(), self.theta.sin());
    }

    fn value(&self, p: &Point2<f64>) -> f64 {
        self.d - self.n.dot(&(p - self.c))
    }
}

/// What the pixels near the edge say: each centre, `+1` inside or `−1` outside, and the
/// [`CANDIDATES`] sides nearest it at the start, among which its nearest side stays.
struct EdgeEvidence {
    points: Vec<Point2<f64>>,
    sides: Vec<f64>,
    near: Vec<[usize; CANDIDATES]>,
}

/// How many of the sides nearest a centre at the start it is weighed against later: the two
/// sides of a corner and a short side across its tip.
const CANDIDATES: usize = 3;

/// The outline of a blob fitted to the pixels on both sides of its edge (module docs), from the
/// counter-clockwise image loop `start` (pixels, `(u, v)`), in an image `width` × `height`: `above`
/// are the pixels the blob holds above its cut, `known(i)` says whether pixel `i` has depth. `None`
/// when fewer than three sides remain or too few pixels speak.
pub fn fit_outline(
    start: &[Point2<f64>],
    size: (usize, usize),
    above: &[usize],
    known: impl Fn(usize) -> bool,
) -> Option<Vec<Point2<f64>>> {
    let sides = sides_of(start);
    if sides.len() < 3 {
        return None;
    }
    let evidence = evidence(start, &sides, size, above, known);
    fitted(start, sides, &evidence)
}

/// The pixels from [`BAND`] outside `sides` to [`DEEP`] inside them, as [`fit_outline`] reads them.
fn evidence(
    start: &[Point2<f64>],
    sides: &[Side],
    (width, height): (usize, usize),
    above: &[usize],
    known: impl Fn(usize) -> bool,
) -> EdgeEvidence {
    let (lo, hi) = crate::geometry::point_bounds(start);
    let clampu = |x: f64| x.clamp(0.0, width.saturating_sub(1) as f64) as usize;
    let clampv = |x: f64| x.clamp(0.0, height.saturating_sub(1) as f64) as usize;
    let (u0, u1) = (clampu((lo.x - BAND).floor()), clampu((hi.x + BAND).ceil()));
    let (v0, v1) = (clampv((lo.y - BAND).floor()), clampv((hi.y + BAND).ceil()));
    // The blob's pixels above the cut, as a bitmap of the box looked at.
    let box_width = u1 - u0 + 1;
    let mut held = vec![false; box_width * (v1 - v0 + 1)];
    for &i in above {
        let (u, v) = (i % width, i / width);
        if (u0..=u1).contains(&u) && (v0..=v1).contains(&v) {
            held[(v - v0) * box_width + (u - u0)] = true;
        }
    }
    let mut out = EdgeEvidence {
        points: Vec::new(),
        sides: Vec::new(),
        near: Vec::new(),
    };
    for v in v0..=v1 {
        // The row's pixels from `BAND` outside to `DEEP` inside; the others are not looked at.
        let Some((from, to)) = row_span(sides, v as f64, -BAND) else {
            continue;
        };
        let inner = row_span(sides, v as f64, DEEP);
        let (from, to) = (clampu(from.floor()).max(u0), clampu(to.ceil()).min(u1));
        for u in from..=to {
            if inner.is_some_and(|(a, b)| (a..=b).contains(&(u as f64))) {
                continue;
            }
            let p = Point2::new(u as f64, v as f64);
            let (s, near) = candidates(sides, &p);
            if !(-BAND..=DEEP).contains(&s) {
                continue;
            }
            let is_in = held[(v - v0) * box_width + (u - u0)];
            if is_in || known(v * width + u) {
                out.points.push(p);
                out.sides.push(if is_in { 1.0 } else { -1.0 });
                out.near.push(near);
            }
        }
    }
    out
}

/// Where the row `v` crosses the region `min_e s_e(p) ≥ t`, as `(u_min, u_max)`, widened by a
/// micropixel for `t < 0` (so that it holds every such pixel) and narrowed by one for `t > 0` (so
/// that it holds only such pixels); `None` where it misses. Each side gives `n_x·u ≤ d − t + n·c −
/// n_y·v`.
fn row_span(sides: &[Side], v: f64, t: f64) -> Option<(f64, f64)> {
    let slack = 1e-6 * t.signum();
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for side in sides {
        let r = side.d - t + side.n.dot(&side.c.coords) - side.n.y * v;
        if side.n.x.abs() < 1e-12 {
            // The side bounds `v` alone: the row is in (by the slack) or out.
            if r < slack {
                return None;
            }
        } else if side.n.x > 0.0 {
            hi = hi.min(r / side.n.x);
        } else {
            lo = lo.max(r / side.n.x);
        }
    }
    let (lo, hi) = (lo + slack, hi - slack);
    (lo <= hi).then_some((lo, hi))
}

/// One side per pair of consecutive corners of `start` simplified as `sides.rs` splits a hull into
/// sides, each through its two corners, after the corners that turn by less than [`MERGE_TURN`]
/// are dropped.
fn sides_of(start: &[Point2<f64>]) -> Vec<Side> {
    let mut kept = super::sides::corners(start);
    // Corners that turn by less than `MERGE_TURN`, gentlest first, are dropped: their two sides
    // become one, through the corners on either side.
    while kept.len() > 3 {
        let m = kept.len();
        let turn = |j: usize| {
            let (a, b, c) = (
                start[kept[(j + m - 1) % m]],
                start[kept[j]],
                start[kept[(j + 1) % m]],
            );
            let stray = ((c - a).perp(&(b - a)) / (c - a).norm()).abs();
            if stray < MERGE_STRAY {
                (b - a).angle(&(c - b))
            } else {
                f64::INFINITY
            }
        };
        let (gentlest, angle) = (0..m)
            .map(|j| (j, turn(j)))
            .fold((0, f64::INFINITY), |x, y| if y.1 < x.1 { y } else { x });
        if angle >= MERGE_TURN {
            break;
        }
        kept.remove(gentlest);
    }
    let m = kept.len();
    (0..m)
        .filter_map(|j| {
            let (a, b) = (start[kept[j]], start[kept[(j + 1) % m]]);
            let edge = b - a;
            let length = edge.norm();
            if length < 1e-9 {
                return None;
            }
            let normal = Vector2::new(edge.y, -edge.x) / length;
            Some(Side::new(
                nalgebra::center(&a, &b),
                normal.y.atan2(normal.x),
                0.0,
            ))
        })
        .collect()
}

/// `min_e s_e(p)`, and the [`CANDIDATES`] sides with the smallest `s_e(p)`, smallest first
/// (repeating the last when there are fewer).
fn candidates(sides: &[Side], p: &Point2<f64>) -> (f64, [usize; CANDIDATES]) {
    let mut best = [(f64::INFINITY, 0); CANDIDATES];
    for (k, side) in sides.iter().enumerate() {
        let s = side.value(p);
        // Insertion into the short sorted list; ties keep the earlier side first.
        if let Some(at) = best.iter().position(|b| s < b.0) {
            best.copy_within(at..CANDIDATES - 1, at + 1);
            best[at] = (s, k);
        }
    }
    let found = sides.len().min(CANDIDATES);
    let near = std::array::from_fn(|j| best[j.min(found.saturating_sub(1))].1);
    (best[0].0, near)
}

/// `min s_e(p)` over the sides `among`, and the side giving it.
fn nearest_among(sides: &[Side], among: &[usize], p: &Point2<f64>) -> (f64, usize) {
    among
        .iter()
        .map(|&k| (sides[k].value(p), k))
        .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a })
}

/// Newton rounds on `sides` (module docs) until they settle or [`ROUNDS`] have run.
fn settle(sides: &mut [Side], evidence: &EdgeEvidence) {
    // Per side: the gradient `(g_d, g_θ)` and the Hessian `[[h_dd, h_dθ], [h_dθ, h_θθ]]`.
    let mut sums = vec![[0.0_f64; 5]; sides.len()];
    for _ in 0..ROUNDS {
        sums.iter_mut().for_each(|s| *s = [0.0; 5]);
        for ((p, &y), among) in evidence
            .points
            .iter()
            .zip(&evidence.sides)
            .zip(&evidence.near)
        {
            let (s, k) = nearest_among(sides, among, p);
            let u = y * s / TAU;
            // A centre this far on its own side adds next to nothing to either sum.
            if u > SURE {
                continue;
            }
            let side = &sides[k];
            // ∂s/∂d = 1, ∂s/∂θ = −n'(θ)·(p − c), n' = (−n_y, n_x).
            let r = p - side.c;
            let jt = side.n.y * r.x - side.n.x * r.y;
            let wrong = sigmoid(-u);
            let g = -y * wrong / TAU;
            let w = wrong * (1.0 - wrong) / (TAU * TAU);
            let e = &mut sums[k];
            e[0] += g;
            e[1] += g * jt;
            e[2] += w;
            e[3] += w * jt;
            e[4] += w * jt * jt;
        }
        let mut largest: f64 = 0.0;
        for (side, &[gd, gt, hdd, hdt, htt]) in sides.iter_mut().zip(&sums) {
            let damping = 1e-3 * (hdd + htt) + 1e-6;
            let (a, b, c) = (hdd + damping, hdt, htt + damping);
            let det = a * c - b * b;
            if !(det.is_finite() && det > 0.0) {
                continue;
            }
            // The Newton step −H⁻¹·g of the 2 × 2 system.
            let (step_d, step_t) = ((-c * gd + b * gt) / det, (b * gd - a * gt) / det);
            let (d, theta) = (side.d, side.theta - side.theta0);
            side.d = (d + step_d.clamp(-MAX_SHIFT, MAX_SHIFT)).clamp(-BAND, BAND);
            let turned = (theta + step_t.clamp(-MAX_TURN, MAX_TURN)).clamp(-MAX_TURNED, MAX_TURNED);
            side.turn(turned - theta);
            largest = largest.max(step_d.abs()).max(step_t.abs() * 10.0);
        }
        if largest < SETTLED {
            break;
        }
    }
}

/// The logistic function.
fn sigmoid(x: f64) -> f64 {
    1.0 / (1.0 + (-x).exp())
}

/// `sides` fitted to `evidence` (module docs), as the counter-clockwise loop of their half-planes
/// within a box round `start`; `None` with fewer than three pixels a side.
fn fitted(
    start: &[Point2<f64>],
    mut sides: Vec<Side>,
    evidence: &EdgeEvidence,
) -> Option<Vec<Point2<f64>>> {
    if evidence.points.len() < 3 * sides.len() {
        return None;
    }
    settle(&mut sides, evidence);
    let (lo, hi) = crate::geometry::point_bounds(start);
    let margin = (hi - lo).norm() + 10.0;
    let bounds = vec![
        Point2::new(lo.x - margin, lo.y - margin),
        Point2::new(hi.x + margin, lo.y - margin),
        Point2::new(hi.x + margin, hi.y + margin),
        Point2::new(lo.x - margin, hi.y + margin),
    ];
    let region = sides.iter().fold(bounds, |region, side| {
        clip(&region, &side.n, side.d + side.n.dot(&side.c.coords))
    });
    (region.len() >= 3 && loop_area(&region) > 0.0).then_some(region)
}

#[cfg(test)]
#[path = "fit_tests.rs"]
mod tests;
