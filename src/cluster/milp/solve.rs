//! One table's model solved: part by part, each under the configured objective (the fewest-clusters
//! objective in two stages), and each stage again with any clash the rows missed.

use std::time::Instant;

use super::Milp;
use super::backend::Model;
use crate::cluster::decompose;
use crate::cluster::objective::{ClusterObjective, CostModel, spread};
use crate::cluster::separability::separability_conflicts;
use crate::cluster::solved::Solved;
use crate::outcome::Status;
use crate::scene::Scene;

impl Milp {
    /// Solves one stage, adding any clash the rows missed (checked geometrically) and solving again.
    #[allow(clippy::too_many_arguments)]
    fn stage(
        &self,
        scene: &Scene,
        candidates: &[Vec<usize>],
        covering: &[Vec<usize>],
        clashes: &mut Vec<(usize, usize)>,
        model: Model<'_>,
        deadline: Instant,
        rounds: &mut usize,
    ) -> Solved {
        loop {
            *rounds += 1;
            let remaining = deadline
                .saturating_duration_since(Instant::now())
                .as_secs_f64();
            let solved = self.solve(&Model {
                covering,
                clashes,
                time_limit: remaining.max(1e-3),
                ..model
            });
            let picked: Vec<Vec<usize>> = solved
                .chosen
                .iter()
                .map(|&k| candidates[k].clone())
                .collect();
            let missed: Vec<(usize, usize)> = separability_conflicts(scene, &picked)
                .into_iter()
                .map(|(a, b)| {
                    let (a, b) = (solved.chosen[a], solved.chosen[b]);
                    (a.min(b), a.max(b))
                })
                .filter(|pair| !clashes.contains(pair))
                .collect();
            if missed.is_empty() || *rounds >= 20 {
                return solved;
            }
            clashes.extend(missed);
        }
    }

    /// Solves one part under the configured objective (two stages for fewest clusters).
    pub(super) fn solve_part(
        &self,
        scene: &Scene,
        part: &mut decompose::Part,
        costs_model: &CostModel<'_>,
        deadline: Instant,
        rounds: &mut usize,
    ) -> Solved {
        let settings = &self.settings;
        let decompose::Part {
            candidates,
            costs,
            covering,
            clashes,
            warm,
            rides,
            ..
        } = part;
        // Each ride's cost: its saving, negative, or (second stage of fewest clusters) its
        // distance, as spread.
        let ride_costs = |cost: &dyn Fn(&crate::cluster::riders::RideVar) -> f64| {
            rides
                .iter()
                .map(|r| (r.row, r.single, cost(r)))
                .collect::<Vec<_>>()
        };
        let saving = ride_costs(&|r| -r.worth);
        let one_trip = ride_costs(&|_| -1.0);
        let distance = ride_costs(&|r| r.distance);
        let mut stage = |costs: &[f64],
                         rides: &[(usize, usize, f64)],
                         gap: f64,
                         count: Option<usize>,
                         warm: (&[usize], &[usize])| {
            self.stage(
                scene,
                candidates,
                covering,
                clashes,
                Model {
                    costs,
                    covering,
                    clashes: &[],
                    rides,
                    warm: warm.0,
                    warm_riding: warm.1,
                    count,
                    mip_gap: gap,
                    time_limit: 0.0,
                },
                deadline,
                rounds,
            )
        };
        match settings.objective {
            ClusterObjective::Time => stage(costs, &saving, settings.mip_gap, None, (warm, &[])),
            ClusterObjective::FewestClusters if !settings.two_stage_fewest_clusters => {
                stage(costs, &saving, settings.mip_gap, None, (warm, &[]))
            }
            ClusterObjective::FewestClusters => {
                // Stage 1: fewest clusters. The count is an integer, so a gap below one cluster
                // proves it; stage 2: least spread among clusterings with that count.
                let ones = vec![1.0; candidates.len()];
                let proof_gap = settings.mip_gap.max(0.99 / warm.len().max(1) as f64);
                let first = stage(&ones, &one_trip, proof_gap, None, (warm, &[]));
                if first.chosen.is_empty() {
                    return first;
                }
                // Trips: clusters less the riders, who take none of their own.
                let count = first.chosen.len() - first.riding.len();
                let count_proven = first.status == Status::Optimal
                    || first
                        .bound
                        .is_some_and(|b| (b - 1e-6).ceil() >= count as f64);
                let spreads: Vec<f64> = candidates.iter().map(|c| spread(scene, c)).collect();
                let second = stage(
                    &spreads,
                    &distance,
                    settings.mip_gap,
                    Some(count),
                    (&first.chosen, &first.riding),
                );
                let epsilon = costs_model.epsilon();
                let status = match (&second.status, count_proven) {
                    (Status::Optimal, true) => Status::Optimal,
                    (Status::Optimal | Status::Feasible, _) => Status::Feasible,
                    (other, _) => other.clone(),
                };
                let (chosen, riding) = if second.chosen.is_empty() {
                    (first.chosen, first.riding)
                } else {
                    (second.chosen, second.riding)
                };
                Solved {
                    status,
                    chosen,
                    riding,
                    bound: match (count_proven, second.bound) {
                        (true, Some(b)) => Some(count as f64 + epsilon * b),
                        _ => first.bound,
                    },
                    gap: second.gap,
                    nodes: first.nodes.zip(second.nodes).map(|(a, b)| a + b),
                    iterations: first.iterations.zip(second.iterations).map(|(a, b)| a + b),
                    backend_status: format!(
                        "{}; then {}",
                        first.backend_status, second.backend_status
                    ),
                }
            }
        }
    }
}
