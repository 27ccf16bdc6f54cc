//! Making clusters pairwise separable.
//!
//! The Push-MOG paper requires any two clusters' centroid sets to be separable by a line but does not
//! say how its hierarchical clustering ensures it; agglomerative clustering usually gives separable
//! clusters, and the paper's splits keep the parts of one cluster separable, but two clusters from the
//! dendrogram can still interleave. pushmog repairs that in two stages:
//! 1. for a conflicting pair `(A, B)`, replace both by the line splits of `A ∪ B` (separable among
//!    themselves by construction), for a bounded number of rounds;
//! 2. if conflicts remain, break every cluster still in a conflict into single objects, repeatedly.
//!    Single objects have distinct centroids, so they are pairwise separable and stage 2 ends.
//!
//! The number of repairs is reported in the clustering's statistics.

use nalgebra::Point2;

use super::split::{SplitSettings, split_until_valid};
use crate::geometry::{are_separable, point_bounds};
use crate::scene::Scene;

/// Centroids closer than this to a common line (metres) count as not separable.
pub const SEPARATION_TOLERANCE: f64 = 1e-9;

fn centroids(scene: &Scene, cluster: &[usize]) -> Vec<Point2<f64>> {
    cluster.iter().map(|&i| scene.centroid(i)).collect()
}

/// Pairs of clusters (by position, `a < b`, in order) whose centroid sets no line separates.
pub fn separability_conflicts(scene: &Scene, clusters: &[Vec<usize>]) -> Vec<(usize, usize)> {
    let points: Vec<Vec<Point2<f64>>> = clusters.iter().map(|c| centroids(scene, c)).collect();
    let mut conflicts = Vec::new();
    pairs_with_touching_boxes(&points, |a, b| {
        if !are_separable(&points[a], &points[b], SEPARATION_TOLERANCE) {
            conflicts.push((a.min(b), a.max(b)));
        }
        true
    });
    conflicts.sort_unstable();
    conflicts
}

/// Visits the pairs `(a, b)` of point sets whose bounding boxes come within `2 ·`
/// [`SEPARATION_TOLERANCE`] of each other, sweeping along x. Every other pair is split by an
/// axis-parallel line with more than the tolerance on each side, so it cannot conflict; on a table
/// of `K` compact clusters this visits `O(K)` pairs instead of `K²/2`. `visit` returns `false` to
/// stop; the sweep then returns `false`.
pub(super) fn pairs_with_touching_boxes(
    points: &[Vec<Point2<f64>>],
    mut visit: impl FnMut(usize, usize) -> bool,
) -> bool {
    let boxes: Vec<(Point2<f64>, Point2<f64>)> = points.iter().map(|p| point_bounds(p)).collect();
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let gap = 2.0 * SEPARATION_TOLERANCE;
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            if boxes[b].0.x > boxes[a].1.x + gap {
                break;
            }
            let (lo_a, hi_a) = boxes[a];
            let (lo_b, hi_b) = boxes[b];
            if lo_a.y > hi_b.y + gap || lo_b.y > hi_a.y + gap {
                continue;
            }
            if !visit(a, b) {
                return false;
            }
        }
    }
    true
}

/// Whether the bounding boxes of two point sets are more than `2 ·` [`SEPARATION_TOLERANCE`] apart
/// along x or y (then an axis-parallel line separates the sets; [`pairs_with_touching_boxes`] skips
/// exactly these pairs).
pub(super) fn boxes_apart(first: &[Point2<f64>], second: &[Point2<f64>]) -> bool {
    let gap = 2.0 * SEPARATION_TOLERANCE;
    let ((lo_a, hi_a), (lo_b, hi_b)) = (point_bounds(first), point_bounds(second));
    lo_a.x > hi_b.x + gap || lo_b.x > hi_a.x + gap || lo_a.y > hi_b.y + gap || lo_b.y > hi_a.y + gap
}

/// Repairs conflicts as the module docs describe; returns the number of clusters changed.
pub fn repair_separability(
    scene: &Scene,
    clusters: &mut Vec<Vec<usize>>,
    settings: &SplitSettings,
) -> usize {
    let mut repairs = 0;
    let rounds = 2 * clusters.len().max(1);
    for _ in 0..rounds {
        let Some(&(a, b)) = separability_conflicts(scene, clusters).first() else {
            return repairs;
        };
        let mut union = clusters[a].clone();
        union.extend(clusters[b].iter().copied());
        // Split the union with the paper's rule at least once, even when it fits the jaws.
        let parts = split_at_least_once(scene, union, settings);
        clusters.remove(b);
        clusters.remove(a);
        clusters.extend(parts);
        repairs += 1;
    }
    loop {
        let conflicts = separability_conflicts(scene, clusters);
        if conflicts.is_empty() {
            return repairs;
        }
        let mut broken: Vec<usize> = conflicts
            .iter()
            .flat_map(|&(a, b)| [a, b])
            .filter(|&k| clusters[k].len() > 1)
            .collect();
        broken.sort_unstable();
        broken.dedup();
        if broken.is_empty() {
            // Only single objects conflict: impossible with distinct centroids.
            return repairs;
        }
        for &k in broken.iter().rev() {
            let cluster = clusters.remove(k);
            clusters.extend(cluster.into_iter().map(|i| vec![i]));
            repairs += 1;
        }
    }
}

fn split_at_least_once(
    scene: &Scene,
    union: Vec<usize>,
    settings: &SplitSettings,
) -> Vec<Vec<usize>> {
    let (parts, splits) = split_until_valid(scene, union.clone(), settings);
    if splits > 0 {
        return parts;
    }
    // The union fits the jaws: it is a valid cluster, and separable from the rest unless a third
    // cluster interleaves, which later rounds handle.
    vec![union]
}
