//! What a clustering costs: the objectives of `formulations/clustering.md`.
//!
//! - **time** (seconds): each cluster is one trip, `T_trip`, plus one fork push for every member but
//!   the central one (the member nearest the cluster's mean centroid, as in the paper's pushes). A
//!   push is estimated as moving the member straight at the central object until their narrowest
//!   widths meet, `ℓ_o = max(0, ‖M_o − M_m‖ − (d*_o + d*_m)/2)`, costing `T_push(ℓ_o)`; members with
//!   `ℓ_o` below `min_push` are not pushed. Only the first push moves the jaws to the fork opening.
//! - **fewest clusters, then least spread**: each cluster costs `1 + ε·σ(c)` with spread
//!   `σ(c) = Σ_{o∈c} ‖M_o − M̄_c‖`. `ε` is set so the spread of a whole clustering is worth less than
//!   one cluster: `ε = 1/(1 + n·D)` with `D` the largest centroid diameter among the candidates.

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::scene::Scene;
use crate::time_model::TimeModel;

/// Which objective the optimal clustering minimises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ClusterObjective {
    /// Predicted seconds of trips and pushes.
    Time,
    /// Fewest clusters, then least spread (the paper's aim, for comparison).
    FewestClusters,
}

/// The cost of clusters of one scene under one objective.
#[derive(Clone, Debug)]
pub struct CostModel<'a> {
    scene: &'a Scene,
    objective: ClusterObjective,
    model: TimeModel,
    min_push: f64,
    epsilon: f64,
}

impl<'a> CostModel<'a> {
    /// Costs for `scene`; `largest_diameter` is the largest centroid diameter among the clusters that
    /// may be chosen (sets `ε` of the fewest-clusters objective).
    pub fn new(
        scene: &'a Scene,
        objective: ClusterObjective,
        model: &TimeModel,
        min_push: f64,
        largest_diameter: f64,
    ) -> Self {
        Self {
            scene,
            objective,
            model: model.clone(),
            min_push,
            epsilon: 1.0 / (1.0 + scene.len() as f64 * largest_diameter),
        }
    }

    /// The objective these costs are of.
    pub fn objective(&self) -> ClusterObjective {
        self.objective
    }

    /// The weight `ε` of spread in the fewest-clusters objective.
    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }

    /// The cost of one cluster (scene indices).
    pub fn cluster_cost(&self, members: &[usize]) -> f64 {
        match self.objective {
            ClusterObjective::Time => self.predicted_seconds(members),
            ClusterObjective::FewestClusters => 1.0 + self.epsilon * spread(self.scene, members),
        }
    }

    /// The cost of a whole clustering.
    pub fn clustering_cost(&self, clusters: &[Vec<usize>]) -> f64 {
        clusters.iter().map(|c| self.cluster_cost(c)).sum()
    }

    /// Predicted seconds of one cluster: its trip and its pushes.
    pub fn predicted_seconds(&self, members: &[usize]) -> f64 {
        let gripper = self.scene.gripper();
        // The first push moves the jaws to the fork opening; the later ones find them there.
        let pushes: f64 = estimated_pushes(self.scene, members)
            .into_iter()
            .filter(|&length| length >= self.min_push)
            .enumerate()
            .map(|(k, length)| match k {
                0 => self.model.nominal_push_seconds(gripper, length),
                _ => self.model.nominal_later_push_seconds(length),
            })
            .sum();
        self.model.nominal_trip_seconds(gripper) + pushes
    }
}

fn mean(scene: &Scene, members: &[usize]) -> Point2<f64> {
    let sum: Vector2<f64> = members.iter().map(|&i| scene.centroid(i).coords).sum();
    Point2::from(sum / members.len().max(1) as f64)
}

/// Estimated push length of every member but the central one, metres.
pub fn estimated_pushes(scene: &Scene, members: &[usize]) -> Vec<f64> {
    if members.len() < 2 {
        return Vec::new();
    }
    let centre = mean(scene, members);
    let central = members
        .iter()
        .copied()
        .min_by(|&a, &b| {
            nalgebra::distance(&scene.centroid(a), &centre)
                .total_cmp(&nalgebra::distance(&scene.centroid(b), &centre))
        })
        .unwrap_or(members[0]);
    members
        .iter()
        .filter(|&&o| o != central)
        .map(|&o| {
            let gap = nalgebra::distance(&scene.centroid(o), &scene.centroid(central));
            let widths = (scene.min_grasp_diameter(o) + scene.min_grasp_diameter(central)) / 2.0;
            (gap - widths).max(0.0)
        })
        .collect()
}

/// Spread of a cluster: summed distance of its centroids from their mean, metres.
pub fn spread(scene: &Scene, members: &[usize]) -> f64 {
    let centre = mean(scene, members);
    members
        .iter()
        .map(|&i| nalgebra::distance(&scene.centroid(i), &centre))
        .sum()
}

/// Largest distance between two centroids of a cluster, metres.
pub fn centroid_diameter(scene: &Scene, members: &[usize]) -> f64 {
    let mut widest: f64 = 0.0;
    for (k, &a) in members.iter().enumerate() {
        for &b in &members[k + 1..] {
            widest = widest.max(nalgebra::distance(&scene.centroid(a), &scene.centroid(b)));
        }
    }
    widest
}
