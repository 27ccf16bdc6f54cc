//! Whether two finite point sets can be split by a straight line, and the line that does it.
//!
//! Two finite point sets `A`, `B` are strictly separable by a line exactly when their convex hulls are
//! disjoint. For disjoint convex polygons in the plane, some edge normal of one of them is a separating
//! axis (the separating axis theorem). Hulls may be degenerate here (a point or a segment), so the
//! candidate axes are: every edge normal of both hulls, the direction of any hull that is a segment, and
//! the direction between the two hulls' centres. That set contains a separating axis whenever one exists:
//! point–point pairs are split along their difference, collinear segments along their common direction,
//! and every other case by an edge normal.
//!
//! Clustering uses this on object centroids: two clusters may be pushed independently only when a line
//! separates their centroids (`formulations/clustering.md`).

use nalgebra::{Point2, Vector2};

use super::polygon::cross;

/// A line `{p : normal·p = offset}` with `A` on the negative side and `B` on the positive side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeparatingLine {
    /// Unit normal, pointing from the first set toward the second.
    pub normal: Vector2<f64>,
    /// Offset in metres: the line is `normal·p = offset`, halfway between the sets along `normal`.
    pub offset: f64,
    /// Half the gap between the sets along `normal`, in metres (the largest over the candidate axes).
    pub margin: f64,
}

impl SeparatingLine {
    /// Signed distance in metres of `point` from the line, positive on the second set's side.
    pub fn signed_distance(&self, point: &Point2<f64>) -> f64 {
        self.normal.dot(&point.coords) - self.offset
    }
}

/// Convex hull of a point set, counter-clockwise, without collinear points (Andrew's monotone chain).
///
/// Returns one point for a set of coincident points, two for collinear points, and nothing for an empty
/// set.
pub fn convex_hull(points: &[Point2<f64>]) -> Vec<Point2<f64>> {
    let mut sorted: Vec<Point2<f64>> = points.to_vec();
    sorted.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let mut hull: Vec<Point2<f64>> = Vec::with_capacity(2 * sorted.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point2<f64>>> = if pass == 0 {
            Box::new(sorted.iter())
        } else {
            Box::new(sorted.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2 {
                let a = hull[hull.len() - 2];
                let b = hull[hull.len() - 1];
                if cross(&(b - a), &(p - a)) <= 0.0 {
                    hull.pop();
                } else {
                    break;
                }
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull
}

/// A line that strictly separates `first` from `second` with at least `tolerance` metres on each side,
/// or `None` when none exists (the hulls touch or overlap).
///
/// When either set is empty, any line far from the other set separates them.
pub fn separating_line(
    first: &[Point2<f64>],
    second: &[Point2<f64>],
    tolerance: f64,
) -> Option<SeparatingLine> {
    let hull_a = convex_hull(first);
    let hull_b = convex_hull(second);
    if hull_a.is_empty() || hull_b.is_empty() {
        let normal = Vector2::x();
        let (offset, margin) = match (hull_a.first(), hull_b.first()) {
            (Some(_), None) => (max_along(&hull_a, &normal) + 1.0, f64::INFINITY),
            (None, Some(_)) => (min_along(&hull_b, &normal) - 1.0, f64::INFINITY),
            _ => (0.0, f64::INFINITY),
        };
        return Some(SeparatingLine {
            normal,
            offset,
            margin,
        });
    }
    let mut axes: Vec<Vector2<f64>> = Vec::new();
    for hull in [&hull_a, &hull_b] {
        let n = hull.len();
        if n >= 2 {
            for i in 0..n {
                let edge = hull[(i + 1) % n] - hull[i];
                axes.push(Vector2::new(edge.y, -edge.x));
            }
        }
        if n == 2 {
            axes.push(hull[1] - hull[0]);
        }
    }
    axes.push(mean(&hull_b) - mean(&hull_a));
    let mut best: Option<SeparatingLine> = None;
    for axis in axes {
        let norm = axis.norm();
        if norm == 0.0 || !norm.is_finite() {
            continue;
        }
        for normal in [axis / norm, -axis / norm] {
            let a_max = max_along(&hull_a, &normal);
            let b_min = min_along(&hull_b, &normal);
            let margin = (b_min - a_max) / 2.0;
            if best.is_none_or(|line| margin > line.margin) {
                best = Some(SeparatingLine {
                    normal,
                    offset: (a_max + b_min) / 2.0,
                    margin,
                });
            }
        }
    }
    best.filter(|line| line.margin > tolerance)
}

/// Whether a line separates `first` from `second` with more than `tolerance` metres on each side.
pub fn are_separable(first: &[Point2<f64>], second: &[Point2<f64>], tolerance: f64) -> bool {
    separating_line(first, second, tolerance).is_some()
}

fn max_along(points: &[Point2<f64>], direction: &Vector2<f64>) -> f64 {
    points
        .iter()
        .map(|p| p.coords.dot(direction))
        .fold(f64::NEG_INFINITY, f64::max)
}

fn min_along(points: &[Point2<f64>], direction: &Vector2<f64>) -> f64 {
    points
        .iter()
        .map(|p| p.coords.dot(direction))
        .fold(f64::INFINITY, f64::min)
}

fn mean(points: &[Point2<f64>]) -> Point2<f64> {
    let sum: Vector2<f64> = points.iter().map(|p| p.coords).sum();
    Point2::from(sum / points.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(list: &[(f64, f64)]) -> Vec<Point2<f64>> {
        list.iter().map(|&(x, y)| Point2::new(x, y)).collect()
    }

    #[test]
    fn hull_drops_inner_and_collinear_points() {
        let hull = convex_hull(&pts(&[
            (0.0, 0.0),
            (1.0, 0.0),
            (2.0, 0.0),
            (2.0, 2.0),
            (0.0, 2.0),
            (1.0, 1.0),
        ]));
        assert_eq!(hull.len(), 4);
    }

    #[test]
    fn degenerate_sets() {
        // Two points.
        assert!(are_separable(&pts(&[(0.0, 0.0)]), &pts(&[(1.0, 1.0)]), 0.0));
        assert!(!are_separable(
            &pts(&[(0.0, 0.0)]),
            &pts(&[(0.0, 0.0)]),
            0.0
        ));
        // Collinear segments, apart and interleaved.
        let a = pts(&[(0.0, 0.0), (1.0, 0.0)]);
        assert!(are_separable(&a, &pts(&[(2.0, 0.0), (3.0, 0.0)]), 0.0));
        assert!(!are_separable(&a, &pts(&[(0.5, 0.0), (3.0, 0.0)]), 0.0));
        // Crossing segments.
        assert!(!are_separable(&a, &pts(&[(0.5, -1.0), (0.5, 1.0)]), 0.0));
        // A point inside a triangle.
        let tri = pts(&[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)]);
        assert!(!are_separable(&tri, &pts(&[(1.0, 1.0)]), 0.0));
        assert!(are_separable(&tri, &pts(&[(3.0, 3.0)]), 0.0));
    }

    #[test]
    fn the_line_splits_the_sets() {
        let a = pts(&[(0.0, 0.0), (1.0, 0.2), (0.3, 1.0)]);
        let b = pts(&[(2.0, 2.0), (3.0, 1.5), (2.5, 3.0)]);
        let line = separating_line(&a, &b, 0.0).unwrap();
        assert!(a.iter().all(|p| line.signed_distance(p) < 0.0));
        assert!(b.iter().all(|p| line.signed_distance(p) > 0.0));
    }
}
