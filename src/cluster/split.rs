//! Splitting a cluster that does not fit the jaws, by the Push-MOG paper's separating-line rule.
//!
//! For a cluster `c` with `Σ d* > g`, try lines through the mean of its centroids `M_c` with direction
//! `v = (cos θ, sin θ)` for `θ ∈ [−π/4, π/4]` at a set resolution; a line puts each object on one side
//! by the sign of `v × (M_o − M_c)`. Keep the `θ` that minimises `|Σ_{c1} d* − Σ_{c2} d*|` among
//! splits with both sides non-empty (first such `θ` on ties), split there, and recurse on each side
//! until every part fits. The two sides of a line are separable from each other, so repeated splits
//! keep the parts of one cluster pairwise separable.
//!
//! The paper's range covers half of all line directions. When no line in it splits a cluster (all
//! centroids on one line at an angle outside the range, for instance), the full half-turn is tried.

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::{fits_jaws, summed_diameter};
use crate::error::Result;
use crate::geometry::cross;
use crate::scene::Scene;

/// Settings of the separating-line split.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SplitSettings {
    /// Angle step of the line search over `[−π/4, π/4]`, radians. Default π/180 (1°).
    pub angle_step: f64,
}

impl Default for SplitSettings {
    fn default() -> Self {
        Self {
            angle_step: std::f64::consts::PI / 180.0,
        }
    }
}

impl SplitSettings {
    /// Checks the step is positive and at most π/4.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming `angle_step`.
    pub fn validate(&self) -> Result<()> {
        crate::error::in_range(
            "clustering.split",
            "angle_step",
            self.angle_step,
            (1e-4, std::f64::consts::FRAC_PI_4),
            "radians; each step is a split line tried",
        )
    }
}

/// Splits `members` (scene indices) until every part fits the jaws; returns the parts and the number of
/// splits made.
pub fn split_until_valid(
    scene: &Scene,
    members: Vec<usize>,
    settings: &SplitSettings,
) -> (Vec<Vec<usize>>, usize) {
    let mut done = Vec::new();
    let mut pending = vec![members];
    let mut splits = 0;
    while let Some(cluster) = pending.pop() {
        if fits_jaws(scene, &cluster) {
            done.push(cluster);
            continue;
        }
        match best_split(scene, &cluster, settings) {
            Some((first, second)) => {
                splits += 1;
                pending.push(second);
                pending.push(first);
            }
            // Distinct centroids always admit a split; this is only reachable with coincident ones,
            // which a valid scene cannot hold. Fall back to singletons.
            None => done.extend(cluster.into_iter().map(|i| vec![i])),
        }
    }
    (done, splits)
}

fn best_split(
    scene: &Scene,
    cluster: &[usize],
    settings: &SplitSettings,
) -> Option<(Vec<usize>, Vec<usize>)> {
    let quarter = std::f64::consts::FRAC_PI_4;
    let steps = (2.0 * quarter / settings.angle_step).round() as usize;
    let in_range = (0..=steps).map(|k| -quarter + 2.0 * quarter * k as f64 / steps as f64);
    best_split_over(scene, cluster, in_range).or_else(|| {
        let half_turn = (std::f64::consts::PI / settings.angle_step).ceil() as usize;
        best_split_over(
            scene,
            cluster,
            (0..half_turn).map(|k| std::f64::consts::PI * k as f64 / half_turn as f64),
        )
    })
}

fn best_split_over(
    scene: &Scene,
    cluster: &[usize],
    angles: impl Iterator<Item = f64>,
) -> Option<(Vec<usize>, Vec<usize>)> {
    let centroids: Vec<Point2<f64>> = cluster.iter().map(|&i| scene.centroid(i)).collect();
    let mean = Point2::from(
        centroids.iter().map(|p| p.coords).sum::<Vector2<f64>>() / centroids.len() as f64,
    );
    let mut best: Option<(f64, Vec<usize>, Vec<usize>)> = None;
    for theta in angles {
        let direction = Vector2::new(theta.cos(), theta.sin());
        let (mut first, mut second) = (Vec::new(), Vec::new());
        for (&index, centroid) in cluster.iter().zip(&centroids) {
            if cross(&direction, &(centroid - mean)) >= 0.0 {
                first.push(index);
            } else {
                second.push(index);
            }
        }
        if first.is_empty() || second.is_empty() {
            continue;
        }
        let imbalance = (summed_diameter(scene, &first) - summed_diameter(scene, &second)).abs();
        if best.as_ref().is_none_or(|(b, _, _)| imbalance < *b) {
            best = Some((imbalance, first, second));
        }
    }
    best.map(|(_, first, second)| (first, second))
}
