//! One table's model for the MILP: the candidate clusters that stand in a row the jaws take (plus
//! the heuristic's, so its answer is a feasible point), their costs, clash rows and rides.

use std::collections::HashSet;
use std::time::Instant;

use super::Milp;
use crate::cluster::candidates::{Budget, clashing_pairs, compact_candidates_where};
use crate::cluster::objective::{CostModel, centroid_diameter};
use crate::cluster::riders::{RideVar, ride_vars};
use crate::cluster::{Clustering, ROW_GAP, admits_row, split_unrowable};
use crate::error::Result;
use crate::push::flush::{PairRow, admits_flush_pair};
use crate::scene::Scene;

/// One table's model: the candidate clusters with their costs and clash rows, and the heuristic's
/// clustering as taken (the warm start and the fallback).
pub(super) struct Instance<'a> {
    pub candidates: Vec<Vec<usize>>,
    pub costs_model: CostModel<'a>,
    pub costs: Vec<f64>,
    pub clashes: Vec<(usize, usize)>,
    /// Positions in `candidates` of the heuristic's clusters.
    pub warm: Vec<usize>,
    /// The riders that may ride on rows (`riders.rs`).
    pub rides: Vec<RideVar>,
    /// The heuristic's clusters as taken (scene indices), and their cost.
    pub heuristic: (Vec<Vec<usize>>, f64),
}

impl Milp {
    /// The heuristic's clusters as a row-pushing planner takes them: a cluster whose members stand
    /// in no row of at most `limit` (or, with flush pushes, a pair no flush push lines up) splits
    /// into single objects.
    fn heuristic_as_taken(
        &self,
        scene: &Scene,
        heuristic: &Clustering,
        limit: f64,
    ) -> Result<Vec<Vec<usize>>> {
        let sorted = heuristic
            .clusters
            .iter()
            .map(|c| {
                let mut members = scene.indices_of(c)?;
                members.sort_unstable();
                Ok(members)
            })
            .collect::<Result<_>>()?;
        Ok(split_unrowable(scene, sorted, limit, ROW_GAP)
            .into_iter()
            .flat_map(|members| {
                if self.flush_ok(scene, limit, &members) {
                    vec![members]
                } else {
                    members.into_iter().map(|i| vec![i]).collect()
                }
            })
            .collect())
    }

    /// Whether `members` pass the flush-pair test (always, without flush pushes or for other than
    /// pairs).
    fn flush_ok(&self, scene: &Scene, limit: f64, members: &[usize]) -> bool {
        match (self.rows.flush_pairs, members) {
            (Some(flush), &[a, b]) => admits_flush_pair(
                scene,
                (a, b),
                PairRow {
                    row_limit: limit,
                    gap: ROW_GAP,
                    straddle: flush.straddle,
                    tight: Some(flush.tight),
                },
                (flush.margin, flush.cone),
            ),
            _ => true,
        }
    }

    /// The model of `scene`: candidates that stand in a row the jaws take (plus the heuristic's
    /// clusters, so its answer is a feasible point), their costs and clash rows; or, when the
    /// enumeration exceeds its budget, why not.
    pub(super) fn instance<'a>(
        &'a self,
        scene: &'a Scene,
        heuristic: &Clustering,
        held: &[Vec<crate::scene::ObjectId>],
        deadline: Instant,
    ) -> Result<std::result::Result<Instance<'a>, String>> {
        let settings = &self.settings;
        // A cluster is worth pushing only if its members can stand in one row the jaws take.
        let limit = scene.gripper().usable_gap() - self.rows.margin;
        let heuristic_clusters = self.heuristic_as_taken(scene, heuristic, limit)?;
        let Some(mut candidates) = compact_candidates_where(
            scene,
            settings.max_cluster_size,
            settings.max_diameter,
            &|c| admits_row(scene, c, limit, ROW_GAP) && self.flush_ok(scene, limit, c),
            Budget {
                max_items: settings.max_candidates,
                deadline: Some(deadline),
            },
        ) else {
            return Ok(Err(format!(
                "more than {} candidate clusters, or the time limit, while enumerating candidates",
                settings.max_candidates
            )));
        };
        let mut known: HashSet<Vec<usize>> = candidates.iter().cloned().collect();
        let mut warm = Vec::new();
        for cluster in &heuristic_clusters {
            if known.insert(cluster.clone()) {
                candidates.push(cluster.clone());
            }
            if let Some(k) = candidates.iter().position(|c| c == cluster) {
                warm.push(k);
            }
        }
        let largest = candidates
            .iter()
            .map(|c| centroid_diameter(scene, c))
            .fold(0.0, f64::max);
        let costs_model = CostModel::new(
            scene,
            settings.objective,
            self.problem.time_model(),
            self.problem.min_push(),
            largest,
        );
        let costs: Vec<f64> = candidates
            .iter()
            .map(|c| costs_model.cluster_cost(c))
            .collect();
        let Some(clashes) = clashing_pairs(
            scene,
            &candidates,
            Budget {
                max_items: settings.max_clash_rows,
                deadline: Some(deadline),
            },
        ) else {
            return Ok(Err(format!(
                "more than {} clashing pairs of the {} candidates, or the time limit",
                settings.max_clash_rows,
                candidates.len()
            )));
        };
        let heuristic_cost = costs_model.clustering_cost(&heuristic_clusters);
        let rides = match &self.rides {
            Some(options) => ride_vars(
                scene,
                &candidates,
                &costs_model,
                &self.problem,
                options,
                held,
            ),
            None => Vec::new(),
        };
        Ok(Ok(Instance {
            candidates,
            costs_model,
            costs,
            clashes,
            warm,
            rides,
            heuristic: (heuristic_clusters, heuristic_cost),
        }))
    }
}
