//! The previous optimal clustering, minus the clusters that were carried away, when it is provably
//! still optimal (`formulations/clustering.md`, "Reusing the previous optimum").
//!
//! Let `C*` be a proven optimum of the set-partitioning model over the candidates `K(S)` of the
//! table `S`, under an objective that adds one cost per cluster. The robot carries away the
//! clusters `𝒦 ⊆ C*` and nothing else moves, so the new table is `S' = S ∖ ∪𝒦`. Then `C* ∖ 𝒦` is
//! optimal for `S'` when
//! 1. every candidate of `S'` was a candidate of `S` with the same cost,
//! 2. every cluster of `C* ∖ 𝒦` is a candidate of `S'`, and
//! 3. no carried cluster clashes with (is inseparable from) any candidate of `S'`:
//!
//! any feasible clustering `P'` of `S'` joined with `𝒦` is then a feasible clustering of `S`
//! (its clusters are candidates of `S`, and no clash row binds between `P'` and `𝒦`), so
//! `c(P') + c(𝒦) ≥ c(C*) = c(C* ∖ 𝒦) + c(𝒦)`. With the ideal executor this saves the solve in most
//! trips; any change to a remaining object (a push that moved it, noise in an observation) makes the
//! test fail and the model is solved afresh.

use std::collections::{HashMap, HashSet};

use nalgebra::Point2;

use super::separability::{SEPARATION_TOLERANCE, boxes_apart};
use crate::geometry::are_separable;
use crate::scene::{ObjectId, Scene};

/// A solved table and its proven optimum, by object ids.
#[derive(Clone, Debug)]
pub(super) struct Previous {
    scene: Scene,
    /// Cost bits of every candidate, by its members' ids (ascending scene order).
    costs: HashMap<Vec<ObjectId>, u64>,
    /// The optimum's clusters.
    chosen: Vec<Vec<ObjectId>>,
}

fn ids(scene: &Scene, members: &[usize]) -> Vec<ObjectId> {
    members.iter().map(|&i| scene.objects()[i].id).collect()
}

impl Previous {
    /// Remembers a proven optimum `chosen` (positions in `candidates`) of `scene`.
    pub fn new(scene: &Scene, candidates: &[Vec<usize>], costs: &[f64], chosen: &[usize]) -> Self {
        Self {
            scene: scene.clone(),
            costs: candidates
                .iter()
                .zip(costs)
                .map(|(c, cost)| (ids(scene, c), cost.to_bits()))
                .collect(),
            chosen: chosen.iter().map(|&k| ids(scene, &candidates[k])).collect(),
        }
    }

    /// The positions in `candidates` of the previous optimum without the carried clusters, when
    /// the three conditions of the module docs hold for `scene` with these candidates and costs.
    pub fn still_optimal(
        &self,
        scene: &Scene,
        candidates: &[Vec<usize>],
        costs: &[f64],
    ) -> Option<Vec<usize>> {
        if scene.gripper() != self.scene.gripper() || scene.workspace() != self.scene.workspace() {
            return None;
        }
        // Nothing left on the table has changed.
        let before: HashMap<ObjectId, usize> = self
            .scene
            .objects()
            .iter()
            .enumerate()
            .map(|(i, o)| (o.id, i))
            .collect();
        for object in scene.objects() {
            if self.scene.objects()[*before.get(&object.id)?] != *object {
                return None;
            }
        }
        // The carried objects are whole clusters of the optimum.
        let now: HashSet<ObjectId> = scene.objects().iter().map(|o| o.id).collect();
        let (kept, carried): (Vec<&Vec<ObjectId>>, Vec<&Vec<ObjectId>>) =
            self.chosen.iter().partition(|c| now.contains(&c[0]));
        if kept.iter().any(|c| c.iter().any(|id| !now.contains(id)))
            || carried.iter().any(|c| c.iter().any(|id| now.contains(id)))
        {
            return None;
        }
        // 1. Every candidate was one before, at the same cost.
        let mut position: HashMap<Vec<ObjectId>, usize> = HashMap::new();
        for (k, (candidate, cost)) in candidates.iter().zip(costs).enumerate() {
            let key = ids(scene, candidate);
            if self.costs.get(&key) != Some(&cost.to_bits()) {
                return None;
            }
            position.insert(key, k);
        }
        // 2. The kept clusters are candidates now (positions ascending, as a solve returns them).
        let mut chosen: Vec<usize> = kept
            .iter()
            .map(|c| position.get(*c).copied())
            .collect::<Option<_>>()?;
        chosen.sort_unstable();
        // 3. No carried cluster clashes with a candidate (the model's own clash test).
        for cluster in &carried {
            let gone: Vec<Point2<f64>> = cluster
                .iter()
                .map(|id| self.scene.centroid(before[id]))
                .collect();
            for candidate in candidates {
                let points: Vec<Point2<f64>> =
                    candidate.iter().map(|&i| scene.centroid(i)).collect();
                if !boxes_apart(&gone, &points)
                    && !are_separable(&gone, &points, SEPARATION_TOLERANCE)
                {
                    return None;
                }
            }
        }
        Some(chosen)
    }
}

/// What a clusterer remembers from one trip of a run to the next: the last proven optimum of the
/// time objective, reused while it provably stays optimal (the module docs), and the rows that
/// earlier trips pushed together and that wait for their grasps ([`ClusterMemory::hold`]). It
/// travels with the run (`policy::TripContext`), so a planner keeps no state between calls and two
/// runs never share one; a fresh memory (the default) makes the clusterer solve afresh.
#[derive(Clone, Debug, Default)]
pub struct ClusterMemory {
    previous: Option<Previous>,
    held: Vec<Vec<ObjectId>>,
}

impl ClusterMemory {
    /// [`Previous::still_optimal`] of the remembered optimum, if any.
    pub(super) fn still_optimal(
        &self,
        scene: &Scene,
        candidates: &[Vec<usize>],
        costs: &[f64],
    ) -> Option<Vec<usize>> {
        self.previous
            .as_ref()
            .and_then(|p| p.still_optimal(scene, candidates, costs))
    }

    /// Remembers `previous`, or forgets when `None`.
    pub(super) fn set(&mut self, previous: Option<Previous>) {
        self.previous = previous;
    }

    /// Whether an optimum is remembered.
    pub fn is_empty(&self) -> bool {
        self.previous.is_none()
    }

    /// Says which rows earlier trips pushed together and still wait for their grasps (the policy's
    /// rows pushed ahead). With riders in the model ([`super::Milp::with_rides`]) no member of
    /// such a row is offered as a rider: the push that made the row is spent, which the model's
    /// push estimate does not know (`formulations/stacking.md`, "Riders in the clustering").
    pub fn hold(&mut self, rows: Vec<Vec<ObjectId>>) {
        self.held = rows;
    }

    /// The rows said to wait for their grasps.
    pub fn held(&self) -> &[Vec<ObjectId>] {
        &self.held
    }
}
