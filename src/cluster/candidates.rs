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
//!
//! Tightly packed small objects give combinatorially many candidates (34 squares of 5 mm on a 25 mm
//! grid give millions), so both enumerations run under a [`Budget`] of items and time and report
//! when it runs out.

use std::time::Instant;

use nalgebra::Point2;

use super::fits_jaws;
use super::separability::{SEPARATION_TOLERANCE, pairs_with_touching_boxes};
use crate::geometry::are_separable;
use crate::scene::Scene;

/// How much work enumerating candidates and clashes may take: small objects packed tightly give
/// combinatorially many clusters, so both enumerations stop at a count and a deadline.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// Most items (candidates, or clashing pairs) to produce.
    pub max_items: usize,
    /// When to stop, whatever the count.
    pub deadline: Option<Instant>,
}

impl Budget {
    /// No limit.
    pub const UNLIMITED: Budget = Budget {
        max_items: usize::MAX,
        deadline: None,
    };

    fn exhausted(&self, items: usize, steps: usize) -> bool {
        items > self.max_items
            || (steps.is_multiple_of(1024) && self.deadline.is_some_and(|d| Instant::now() >= d))
    }
}

/// Compact, capacity-feasible clusters (scene indices, ascending).
pub fn compact_candidates(scene: &Scene, max_size: usize, max_diameter: f64) -> Vec<Vec<usize>> {
    compact_candidates_where(scene, max_size, max_diameter, &|_| true, Budget::UNLIMITED)
        .unwrap_or_default()
}

/// Compact, capacity-feasible clusters that `accept` also accepts. `accept` must be monotone (a set
/// it refuses has no accepted superset), so refused sets are not grown. `None` when the enumeration
/// would exceed `budget`.
pub fn compact_candidates_where(
    scene: &Scene,
    max_size: usize,
    max_diameter: f64,
    accept: &dyn Fn(&[usize]) -> bool,
    budget: Budget,
) -> Option<Vec<Vec<usize>>> {
    let n = scene.len();
    let centroids: Vec<Point2<f64>> = (0..n).map(|i| scene.centroid(i)).collect();
    // Each object's neighbours within `max_diameter` (ascending), through the scene's discs.
    let near: Vec<Vec<usize>> = (0..n)
        .map(|i| {
            scene
                .near(&centroids[i], max_diameter)
                .into_iter()
                .filter(|&j| nalgebra::distance(&centroids[i], &centroids[j]) <= max_diameter)
                .collect()
        })
        .collect();
    let is_near = |m: usize, j: usize| near[m].binary_search(&j).is_ok();
    let mut found = Vec::new();
    let mut stack: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
    stack.reverse();
    let mut steps = 0usize;
    while let Some(set) = stack.pop() {
        steps += 1;
        if budget.exhausted(found.len() + stack.len(), steps) {
            return None;
        }
        let last = set[set.len() - 1];
        if set.len() < max_size {
            // Every member's neighbour is the first member's neighbour.
            let after = near[set[0]].partition_point(|&j| j <= last);
            for &j in near[set[0]][after..].iter().rev() {
                if set.iter().all(|&m| is_near(m, j)) {
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
    Some(found)
}

/// Pairs `(a, b)`, `a < b`, of disjoint candidates whose centroids no line separates; `None` when
/// there are more than `budget` allows or the deadline passes.
pub fn clashing_pairs(
    scene: &Scene,
    candidates: &[Vec<usize>],
    budget: Budget,
) -> Option<Vec<(usize, usize)>> {
    let points: Vec<Vec<Point2<f64>>> = candidates
        .iter()
        .map(|c| c.iter().map(|&i| scene.centroid(i)).collect())
        .collect();
    let mut pairs = Vec::new();
    let mut steps = 0usize;
    let finished = pairs_with_touching_boxes(&points, |a, b| {
        steps += 1;
        if budget.exhausted(pairs.len(), steps) {
            return false;
        }
        if !candidates[a].iter().any(|m| candidates[b].contains(m))
            && !are_separable(&points[a], &points[b], SEPARATION_TOLERANCE)
        {
            pairs.push((a.min(b), a.max(b)));
        }
        true
    });
    if !finished || pairs.len() > budget.max_items {
        return None;
    }
    pairs.sort_unstable();
    Some(pairs)
}
