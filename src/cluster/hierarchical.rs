//! The Push-MOG paper's clustering (Algorithm 2): agglomerative clustering of object centroids, cut at
//! a height, then separating-line splits of every cluster that does not fit the jaws.
//!
//! Linkage is computed by the `kodama` crate on Euclidean distances between area centroids. The
//! dendrogram is cut at `cut_height`: two objects end in one cluster when they are joined by merges of
//! linkage distance at most `cut_height`. With the default complete linkage, every pair of centroids
//! in a cluster is then at most `cut_height` apart. Clusters that do not fit the jaws are split
//! ([`split_until_valid`]); any two clusters that are not separable by a line are repaired
//! ([`repair_separability`]).

use std::time::Instant;

use kodama::Method;
use serde::{Deserialize, Serialize};

use super::separability::repair_separability;
use super::split::{SplitSettings, split_until_valid};
use super::{Clusterer, Clustering};
use crate::error::Result;
use crate::outcome::{Outcome, Stats, Status};
use crate::scene::Scene;

/// The linkage rule: how the distance between two clusters follows from their members' distances.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Linkage {
    /// Nearest pair.
    Single,
    /// Furthest pair: a cluster's diameter.
    Complete,
    /// Mean over pairs.
    Average,
    /// Ward's minimum-variance rule.
    Ward,
}

/// Settings of [`Hierarchical`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct HierarchicalSettings {
    /// Linkage rule. Default `complete`, so a cut height bounds each cluster's centroid diameter.
    pub linkage: Linkage,
    /// Dendrogram cut height, metres. Default 0.10: with complete linkage, objects whose centroids are
    /// all within 10 cm (about three object widths of the built-in set) may be pushed together.
    pub cut_height: f64,
    /// Separating-line split of clusters that do not fit the jaws.
    pub split: SplitSettings,
}

impl Default for HierarchicalSettings {
    fn default() -> Self {
        Self {
            linkage: Linkage::Complete,
            cut_height: 0.10,
            split: SplitSettings::default(),
        }
    }
}

impl HierarchicalSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        crate::error::in_range(
            "clustering",
            "cut_height",
            self.cut_height,
            (0.0, 100.0),
            "metres",
        )?;
        self.split.validate()
    }
}

/// Hierarchical clustering with separating-line splits (the paper's Algorithm 2).
#[derive(Clone, Debug, Default)]
pub struct Hierarchical {
    settings: HierarchicalSettings,
}

impl Hierarchical {
    /// A clusterer with these settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: HierarchicalSettings) -> Result<Self> {
        settings.validate()?;
        Ok(Self { settings })
    }

    /// The effective settings.
    pub fn settings(&self) -> &HierarchicalSettings {
        &self.settings
    }

    /// The dendrogram cut: groups of scene indices.
    fn cut(&self, scene: &Scene) -> Vec<Vec<usize>> {
        let n = scene.len();
        if n < 2 {
            return (0..n).map(|i| vec![i]).collect();
        }
        let centroids: Vec<_> = (0..n).map(|i| scene.centroid(i)).collect();
        let mut condensed = Vec::with_capacity(n * (n - 1) / 2);
        for i in 0..n {
            for j in i + 1..n {
                condensed.push(nalgebra::distance(&centroids[i], &centroids[j]));
            }
        }
        let method = match self.settings.linkage {
            Linkage::Single => Method::Single,
            Linkage::Complete => Method::Complete,
            Linkage::Average => Method::Average,
            Linkage::Ward => Method::Ward,
        };
        let dendrogram = kodama::linkage(&mut condensed, n, method);
        // Union the merges at or below the cut; label n + k is the cluster made by step k.
        let mut members: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
        let mut alive: Vec<bool> = vec![true; n];
        for step in dendrogram.steps() {
            let merged = if step.dissimilarity <= self.settings.cut_height {
                let mut union = std::mem::take(&mut members[step.cluster1]);
                union.extend(std::mem::take(&mut members[step.cluster2]));
                alive[step.cluster1] = false;
                alive[step.cluster2] = false;
                union
            } else {
                Vec::new()
            };
            alive.push(!merged.is_empty());
            members.push(merged);
        }
        members
            .into_iter()
            .zip(alive)
            .filter(|(m, alive)| *alive && !m.is_empty())
            .map(|(m, _)| m)
            .collect()
    }
}

impl Clusterer for Hierarchical {
    fn name(&self) -> &'static str {
        "hierarchical"
    }

    fn cluster(&self, scene: &Scene) -> Result<Outcome<Clustering>> {
        let started = Instant::now();
        let mut clusters = Vec::new();
        let mut splits = 0;
        for group in self.cut(scene) {
            let (parts, made) = split_until_valid(scene, group, &self.settings.split);
            splits += made;
            clusters.extend(parts);
        }
        let repairs = repair_separability(scene, &mut clusters, &self.settings.split);
        let clustering = Clustering::from_indices(scene, &clusters).normalised();
        let stats = Stats {
            seconds: started.elapsed().as_secs_f64(),
            counters: vec![
                ("splits".to_string(), splits as f64),
                ("separability_repairs".to_string(), repairs as f64),
                ("clusters".to_string(), clustering.len() as f64),
            ],
            ..Stats::default()
        };
        Ok(Outcome {
            value: clustering,
            status: Status::Heuristic,
            stats,
        })
    }
}
