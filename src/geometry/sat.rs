//! Exact queries between convex polygons by the separating axis theorem: penetration depth, the
//! distance one polygon can slide before it cuts into another, and the contact patch of two touching
//! polygons.
//!
//! Two convex polygons overlap exactly when their projections overlap on every edge normal of both
//! (the separating axis theorem), so each query reduces to intervals on those `n + m` axes:
//! - **penetration depth**: the smallest overlap of the projections over the axes (0 if one axis
//!   separates them);
//! - **slide distance** of `A + t·d` against `B`: on each axis the projections overlap by more than
//!   `ε` for `t` in an open interval (linear in `t`); the polygons interpenetrate for `t` in the
//!   intersection of those intervals, and the slide ends at its lower end. Touching polygons that move
//!   apart or slide along each other never interpenetrate, so they do not stop each other;
//! - **contact patch**: the axis of largest separation is the contact normal (an edge normal, the
//!   edge in contact); the patch is the overlap, along that edge, of the two polygons' vertices lying on
//!   the contact line.
//!
//! Projecting both polygons on all `n + m` axes costs `(n + m)²`, which adds up on traced outlines of
//! tens of vertices. So each query first bounds an axis's projections by `Extremes` (a vertex of
//! each polygon that climbs round it as the axes turn, a few steps per axis) and projects in full
//! only on the axes whose bounds could still change the answer (for pairs of many vertices; others
//! are projected plainly, see `worth_pruning`). The answers are those of projecting
//! on every axis: each is a minimum or maximum over the axes, which does not depend on the order the
//! axes are taken in, and an axis is passed over only when no value within its bounds could change
//! it.
//!
//! These are computed here rather than by parry's GJK/EPA, which reports zero penetration for
//! overlapping polygons whose edges lie on a common line (a triangle standing on the edge of a jaw
//! region, a row of pushed objects), exactly the configurations pushing creates.

use nalgebra::{Point2, Vector2};

use super::polygon::ConvexPolygon;
use super::worth_pruning;

/// Overlap below this (metres) is not penetration: rounding in positions computed from one another.
const PENETRATION_EPSILON: f64 = 1e-12;

/// Outward unit edge normals of a counter-clockwise polygon.
fn normals(polygon: &ConvexPolygon) -> impl Iterator<Item = Vector2<f64>> + '_ {
    polygon.edges().map(|(a, b)| {
        let e = b - a;
        Vector2::new(e.y, -e.x) / e.norm()
    })
}

/// Bounds on a polygon's projections onto axes that mostly turn a little from one to the next: the
/// vertices of least and greatest projection on the last axis, climbed (forward round the polygon,
/// or else backward) while they improve. A climb can stop short of the extreme where rounding makes
/// neighbouring vertices tie, so the values returned are bounds that the polygon attains: the least
/// projection is at most the first, the greatest at least the second.
pub(crate) struct Extremes<'a> {
    vertices: &'a [Point2<f64>],
    /// Vertices of the least and the greatest projection on the last axis.
    at: (usize, usize),
}

impl<'a> Extremes<'a> {
    pub(crate) fn new(polygon: &'a ConvexPolygon) -> Self {
        Self {
            vertices: polygon.vertices(),
            at: (0, 0),
        }
    }

    /// The vertex reached from `start` by moving while `better` holds, and its projection.
    fn climb(
        &self,
        axis: &Vector2<f64>,
        start: usize,
        better: fn(f64, f64) -> bool,
    ) -> (usize, f64) {
        let n = self.vertices.len();
        let along = |j: usize| self.vertices[j].coords.dot(axis);
        let (mut at, mut value) = (start, along(start));
        for step in [1, n - 1] {
            let mut moved = false;
            for _ in 0..n {
                let next = (at + step) % n;
                let further = along(next);
                if better(further, value) {
                    (at, value, moved) = (next, further, true);
                } else {
                    break;
                }
            }
            if moved {
                break;
            }
        }
        (at, value)
    }

    /// A value at least the least projection on `axis` and a value at most the greatest, both
    /// computed as [`ConvexPolygon::projection`] computes them.
    pub(crate) fn bounds(&mut self, axis: &Vector2<f64>) -> (f64, f64) {
        let (low, low_value) = self.climb(axis, self.at.0, |a, b| a < b);
        let (high, high_value) = self.climb(axis, self.at.1, |a, b| a > b);
        self.at = (low, high);
        (low_value, high_value)
    }
}

/// How deep two polygons interpenetrate, metres: the smallest translation that separates them; 0
/// when they are apart or only touch.
pub fn penetration_depth(first: &ConvexPolygon, second: &ConvexPolygon) -> f64 {
    penetration_depth_with(first, second, worth_pruning(first.len(), second.len()))
}

/// [`penetration_depth`], with `prune`: an axis whose overlap, bounded from the extreme vertices
/// climbed to so far, cannot lower the depth is not projected in full. The same answer either way.
fn penetration_depth_with(first: &ConvexPolygon, second: &ConvexPolygon, prune: bool) -> f64 {
    let mut depth = f64::INFINITY;
    // The axes in two runs, each turning counter-clockwise: `first`'s edge normals, then `second`'s.
    let mut extremes = prune.then(|| (Extremes::new(first), Extremes::new(second)));
    for axis in normals(first).chain(normals(second)) {
        if let Some((a, b)) = extremes.as_mut() {
            // The overlap on this axis is at least this (rounding is monotone).
            let ((a0, a1), (b0, b1)) = (a.bounds(&axis), b.bounds(&axis));
            let least = a1.min(b1) - a0.max(b0);
            if least > 0.0 && least >= depth {
                continue;
            }
        }
        let (a0, a1) = first.projection(&axis);
        let (b0, b1) = second.projection(&axis);
        let overlap = a1.min(b1) - a0.max(b0);
        if overlap <= 0.0 {
            return 0.0;
        }
        depth = depth.min(overlap);
    }
    depth
}

/// How far `moving` can slide along the unit vector `direction` before it cuts into `obstacle`,
/// metres, or `None` when it slides `max_distance` freely. `Some(0.0)` when they already overlap.
pub fn cast_distance(
    moving: &ConvexPolygon,
    direction: &Vector2<f64>,
    max_distance: f64,
    obstacle: &ConvexPolygon,
) -> Option<f64> {
    let prune = worth_pruning(moving.len(), obstacle.len());
    cast_distance_with(moving, direction, max_distance, obstacle, prune)
}

/// The times of overlap on an axis moving at `speed` (not near 0), from the projections of the
/// moving polygon (a) and the obstacle (b): a1 + t·v > b0 + ε and b1 − ε > a0 + t·v.
fn overlap_times((a0, a1): (f64, f64), (b0, b1): (f64, f64), speed: f64) -> (f64, f64) {
    let eps = PENETRATION_EPSILON;
    if speed > 0.0 {
        ((b0 + eps - a1) / speed, (b1 - eps - a0) / speed)
    } else {
        ((b1 - eps - a0) / speed, (b0 + eps - a1) / speed)
    }
}

/// [`cast_distance`], with `prune`: an axis whose interval of overlap times, bounded from the
/// extreme vertices climbed to so far, cannot narrow the interval found is not projected in full.
/// The same answer either way.
fn cast_distance_with(
    moving: &ConvexPolygon,
    direction: &Vector2<f64>,
    max_distance: f64,
    obstacle: &ConvexPolygon,
    prune: bool,
) -> Option<f64> {
    let eps = PENETRATION_EPSILON;
    let (mut enter, mut exit) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut extremes = prune.then(|| (Extremes::new(moving), Extremes::new(obstacle)));
    for axis in normals(moving).chain(normals(obstacle)) {
        let speed = axis.dot(direction);
        if let Some((a, b)) = extremes.as_mut() {
            let ((a0, a1), (b0, b1)) = (a.bounds(&axis), b.bounds(&axis));
            if speed.abs() >= 1e-15 {
                // From the bounds, the latest `low` and the earliest `high` the axis can have: the
                // true lower ends are at most `a0` and `b0`, the upper ends at least `a1` and `b1`,
                // and each end of the interval is monotone in them.
                let (latest_low, earliest_high) = overlap_times((a0, a1), (b0, b1), speed);
                if latest_low <= enter && earliest_high >= exit {
                    continue;
                }
            }
        }
        let (a0, a1) = moving.projection(&axis);
        let (b0, b1) = obstacle.projection(&axis);
        if speed.abs() < 1e-15 {
            if a1 > b0 + eps && b1 > a0 + eps {
                continue;
            }
            return None;
        }
        let (low, high) = overlap_times((a0, a1), (b0, b1), speed);
        enter = enter.max(low);
        exit = exit.min(high);
        if enter >= exit {
            return None;
        }
    }
    if exit <= 0.0 || enter > max_distance {
        return None;
    }
    Some(enter.max(0.0))
}

/// The separating axis of largest separation between two polygons: the unit normal pointing out of
/// `first` toward `second`, and the separation along it in metres (negative when they overlap; then
/// its magnitude is the penetration depth). The first such axis when several tie, `first`'s normals
/// before `second`'s.
pub fn max_separation(first: &ConvexPolygon, second: &ConvexPolygon) -> (Vector2<f64>, f64) {
    max_separation_with(first, second, worth_pruning(first.len(), second.len()))
}

/// [`max_separation`], with `prune`: an axis whose separation, bounded from the extreme vertices
/// climbed to so far, cannot beat the best is not projected in full. The same answer either way.
fn max_separation_with(
    first: &ConvexPolygon,
    second: &ConvexPolygon,
    prune: bool,
) -> (Vector2<f64>, f64) {
    let mut best = (Vector2::x(), f64::NEG_INFINITY);
    // `first`'s outward normals, then `second`'s turned to point out of `first`.
    let mut extremes = prune.then(|| (Extremes::new(first), Extremes::new(second)));
    for axis in normals(first).chain(normals(second).map(|n| -n)) {
        if let Some((a, b)) = extremes.as_mut() {
            // The separation on this axis is at most this.
            let ((_, a1), (b0, _)) = (a.bounds(&axis), b.bounds(&axis));
            if b0 - a1 <= best.1 {
                continue;
            }
        }
        let separation = second.projection(&axis).0 - first.projection(&axis).1;
        if separation > best.1 {
            best = (axis, separation);
        }
    }
    best
}

/// Where two touching (or nearly touching) polygons meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPatch {
    /// Unit contact normal, pointing out of the first polygon into the second (the normal of the edge
    /// in contact).
    pub normal: Vector2<f64>,
    /// Ends of the contact segment (equal for a point contact), on the first polygon's boundary.
    pub ends: [Point2<f64>; 2],
}

/// The contact of two polygons no more than `tolerance` metres apart (and not interpenetrating by more
/// than `tolerance`), or `None` when they are further apart.
pub fn contact_patch(
    first: &ConvexPolygon,
    second: &ConvexPolygon,
    tolerance: f64,
) -> Option<ContactPatch> {
    let (normal, separation) = max_separation(first, second);
    if separation.abs() > tolerance {
        return None;
    }
    let tangent = Vector2::new(-normal.y, normal.x);
    let line = first.projection(&normal).1;
    let interval = |polygon: &ConvexPolygon, on_line: &dyn Fn(f64) -> bool| {
        polygon
            .vertices()
            .iter()
            .filter(|v| on_line(v.coords.dot(&normal)))
            .map(|v| v.coords.dot(&tangent))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s), hi.max(s))
            })
    };
    let (a_lo, a_hi) = interval(first, &|h| h >= line - tolerance);
    let other = second.projection(&normal).0;
    let (b_lo, b_hi) = interval(second, &|h| h <= other + tolerance);
    let (mut lo, mut hi) = (a_lo.max(b_lo), a_hi.min(b_hi));
    if lo > hi {
        // Corner against corner, offset by rounding: meet halfway.
        let middle = (lo + hi) / 2.0;
        (lo, hi) = (middle, middle);
    }
    let at = |s: f64| Point2::from(normal * line + tangent * s);
    Some(ContactPatch {
        normal,
        ends: [at(lo), at(hi)],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polygon(points: &[(f64, f64)]) -> ConvexPolygon {
        ConvexPolygon::new(points.iter().map(|&(x, y)| Point2::new(x, y)).collect()).unwrap()
    }

    fn square(x: f64, y: f64, side: f64) -> ConvexPolygon {
        polygon(&[(x, y), (x + side, y), (x + side, y + side), (x, y + side)])
    }

    #[test]
    fn a_triangle_standing_on_a_rectangle_edge_line_overlaps_it() {
        // The case parry's EPA gets wrong: the triangle's base lies on the rectangle's lower edge.
        let triangle = polygon(&[(0.2, 0.2), (0.228, 0.2), (0.214, 0.2242)]);
        let band = polygon(&[(0.1905, 0.2), (0.2655, 0.2), (0.2655, 0.22), (0.1905, 0.22)]);
        let depth = penetration_depth(&triangle, &band);
        assert!(depth > 0.01, "{depth}");
    }

    #[test]
    fn sliding_stops_at_first_contact_and_ignores_grazing() {
        let a = square(0.0, 0.0, 1.0);
        let b = square(3.0, 0.5, 1.0);
        assert!((cast_distance(&a, &Vector2::x(), 10.0, &b).unwrap() - 2.0).abs() < 1e-9);
        assert_eq!(cast_distance(&a, &-Vector2::x(), 10.0, &b), None);
        assert_eq!(cast_distance(&a, &Vector2::x(), 1.5, &b), None);
        // Touching, then moving apart or sliding along: no hit.
        let right = square(1.0, 0.0, 1.0);
        assert_eq!(cast_distance(&a, &-Vector2::x(), 1.0, &right), None);
        assert_eq!(cast_distance(&a, &Vector2::y(), 1.0, &right), None);
        // Touching and moving in: hit at once (within the penetration epsilon).
        assert!(cast_distance(&a, &Vector2::x(), 1.0, &right).unwrap() < 1e-9);
        // Diagonal approach onto a corner.
        let c = square(2.0, 2.0, 1.0);
        let d = Vector2::new(1.0, 1.0).normalize();
        let hit = cast_distance(&a, &d, 10.0, &c).unwrap();
        assert!((hit - 2f64.sqrt()).abs() < 1e-9, "{hit}");
    }

    #[test]
    fn contact_patches_of_edges_and_vertices() {
        let a = square(0.0, 0.0, 1.0);
        let b = square(1.0, 0.5, 1.0);
        let patch = contact_patch(&a, &b, 1e-9).unwrap();
        assert!((patch.normal - Vector2::x()).norm() < 1e-12);
        assert!((patch.ends[0] - Point2::new(1.0, 0.5)).norm() < 1e-12);
        assert!((patch.ends[1] - Point2::new(1.0, 1.0)).norm() < 1e-12);
        // A triangle's apex on a square's top edge: the normal is the edge's, the patch a point.
        let apex_down = polygon(&[(0.5, 1.0), (1.0, 2.0), (0.0, 2.0)]);
        let patch = contact_patch(&a, &apex_down, 1e-9).unwrap();
        assert!((patch.normal - Vector2::y()).norm() < 1e-12);
        assert!((patch.ends[0] - patch.ends[1]).norm() < 1e-12);
        assert!((patch.ends[0] - Point2::new(0.5, 1.0)).norm() < 1e-12);
        assert_eq!(contact_patch(&a, &square(1.1, 0.0, 1.0), 1e-9), None);
    }

    #[test]
    fn pruned_queries_answer_as_projecting_on_every_axis() {
        let pairs = crate::geometry::test_pairs(11, 20_000, (-0.1, 0.1));
        let mut random = crate::random::SeededRng::new(12);
        for (p, q) in &pairs {
            assert_eq!(
                penetration_depth_with(p, q, true),
                penetration_depth_with(p, q, false)
            );
            assert_eq!(
                max_separation_with(p, q, true),
                max_separation_with(p, q, false)
            );
            let angle = random.uniform(0.0, std::f64::consts::TAU);
            for direction in [
                Vector2::new(angle.cos(), angle.sin()),
                (q.centroid() - p.centroid()).normalize(),
                Vector2::x(),
            ] {
                assert_eq!(
                    cast_distance_with(p, &direction, 0.2, q, true),
                    cast_distance_with(p, &direction, 0.2, q, false)
                );
            }
        }
    }
}
