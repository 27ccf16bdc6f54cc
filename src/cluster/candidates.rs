//! The candidate clusters of the set-partitioning model and the pairs of them that clash.
//!
//! A candidate is a set `S` of objects with `|S| ≤ s_max`, every pair of centroids at most `D` apart,
//! and `Σ_{o∈S} d*_o ≤ g` when `|S| ≥ 2` (every single object is a candidate, so a partition always
//! exists). They are enumerated depth-first in increasing index order, extending a set only by objects
//! within `D` of all its members, which visits each candidate once.
//!
//! Two disjoint candidates *clash* when no line separates their centroids; the model then forbids
//! choosing both. Candidates whose centroid bounding boxes are apart are separated by an axis line and
//! are not tested further.

use nalgebra::Point2;

use super::fits_jaws;
use super::separability::SEPARATION_TOLERANCE;
use crate::geometry::are_separable;
use crate::scene::Scene;

/// Compact, capacity-feasible clusters (scene indices, ascending).
pub fn compact_candidates(scene: &Scene, max_size: usize, max_diameter: f64) -> Vec<Vec<usize>> {
    compact_candidates_where(scene, max_size, max_diameter, &|_| true)
}

/// Compact, capacity-feasible clusters that `accept` also accepts. `accept` must be monotone (a set
/// it refuses has no accepted superset), so refused sets are not grown.
pub fn compact_candidates_where(
    scene: &Scene,
    max_size: usize,
    max_diameter: f64,
    accept: &dyn Fn(&[usize]) -> bool,
) -> Vec<Vec<usize>> {
    let n = scene.len();
    let centroids: Vec<Point2<f64>> = (0..n).map(|i| scene.centroid(i)).collect();
    let near: Vec<Vec<bool>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| nalgebra::distance(&centroids[i], &centroids[j]) <= max_diameter)
                .collect()
        })
        .collect();
    let mut found = Vec::new();
    let mut stack: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
    stack.reverse();
    while let Some(set) = stack.pop() {
        let last = set[set.len() - 1];
        if set.len() < max_size {
            for j in (last + 1..n).rev() {
                if set.iter().all(|&m| near[m][j]) {
                    let mut grown = set.clone();
                    grown.push(j);
                    if fits_jaws(scene, &grown) && accept(&grown) {
                        stack.push(grown);
                    }
                }
            }
        }
        found.push(set);
    }
    found
}

/// Pairs `(a, b)`, `a < b`, of disjoint candidates whose centroids no line separates.
pub fn clashing_pairs(scene: &Scene, candidates: &[Vec<usize>]) -> Vec<(usize, usize)> {
    let points: Vec<Vec<Point2<f64>>> = candidates
        .iter()
        .map(|c| c.iter().map(|&i| scene.centroid(i)).collect())
        .collect();
    let boxes: Vec<(Point2<f64>, Point2<f64>)> = points.iter().map(|p| bounds(p)).collect();
    // Sweep along x: only boxes that overlap in x can clash.
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut pairs = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            if boxes[b].0.x > boxes[a].1.x + 2.0 * SEPARATION_TOLERANCE {
                break;
            }
            let (lo_a, hi_a) = boxes[a];
            let (lo_b, hi_b) = boxes[b];
            if lo_a.y > hi_b.y + 2.0 * SEPARATION_TOLERANCE
                || lo_b.y > hi_a.y + 2.0 * SEPARATION_TOLERANCE
            {
                continue;
            }
            if candidates[a].iter().any(|m| candidates[b].contains(m)) {
                continue;
            }
            if !are_separable(&points[a], &points[b], SEPARATION_TOLERANCE) {
                pairs.push((a.min(b), a.max(b)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

fn bounds(points: &[Point2<f64>]) -> (Point2<f64>, Point2<f64>) {
    points.iter().fold(
        (
            Point2::new(f64::INFINITY, f64::INFINITY),
            Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        ),
        |(lo, hi), p| {
            (
                Point2::new(lo.x.min(p.x), lo.y.min(p.y)),
                Point2::new(hi.x.max(p.x), hi.y.max(p.y)),
            )
        },
    )
}
