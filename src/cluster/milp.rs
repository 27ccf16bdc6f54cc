//! Optimal clustering as a set-partitioning MILP (`formulations/clustering.md`), solved with good_lp.
//!
//! Variables `x_S ∈ {0, 1}` over the candidate clusters `K` ([`super::compact_candidates`] plus the
//! clusters of the hierarchical heuristic, each split into single objects when its members cannot
//! stand in one row, so the heuristic's answer so split is always a feasible point):
//!
//! ```text
//! minimise   Σ_S c_S x_S
//! subject to Σ_{S ∋ o} x_S = 1        for every object o      (a partition)
//!            x_S + x_T ≤ 1            for every clashing pair  (separable clusters)
//! ```
//!
//! with `c_S` from [`CostModel`]. The default backend is the pure-Rust `microlp`; the `highs` feature
//! adds HiGHS. The heuristic's clustering is passed as a warm start; when the solver stops without an
//! answer as good as the heuristic's (time limit, failure) the heuristic's clustering is returned with
//! the solver's status. After every solve the chosen clusters are checked geometrically; a clash the
//! model missed would be added as a row and the model solved again. Under the time objective the last
//! proven optimum is kept in the caller's [`ClusterMemory`] ([`Clusterer::cluster_remembering`]), and
//! on the next table (the same one minus carried clusters) it is returned without a solve when
//! provably still optimal (`reuse.rs`, `formulations/clustering.md`).

use std::collections::HashSet;
use std::sync::Arc;
use std::time::Instant;

use good_lp::solvers::{
    Solution as _, SolverModel, WithInitialSolution, WithMipGap, WithTimeLimit,
};
use good_lp::{Constraint, Expression, ProblemVariables, ResolutionError, Variable, variable};
use serde::{Deserialize, Serialize};

use super::candidates::{Budget, clashing_pairs, compact_candidates_where};
use super::decompose;
use super::hierarchical::Hierarchical;
use super::objective::{ClusterObjective, CostModel, centroid_diameter, spread};
use super::reuse::{self, ClusterMemory};
use super::separability::separability_conflicts;
use super::solved::Solved;
use super::{Clusterer, Clustering};
use super::{ROW_GAP, admits_row, split_unrowable};
use crate::error::{Error, Result};
use crate::outcome::{Outcome, Stats, Status};
use crate::problem::Problem;
use crate::push::flush::{PairRow, admits_flush_pair};
use crate::scene::Scene;

/// The push planner's flush-push settings, for the clustering's pair test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlushPairs {
    /// How far each member must reach past the plates' centre line on both sides, metres.
    pub straddle: f64,
    /// How far a finger must overlap the face it pushes, metres.
    pub margin: f64,
    /// Largest angle between a flush push and its face's normal, radians.
    pub cone: f64,
    /// Gap a flush push leaves between a pair, at most, metres.
    pub tight: f64,
}

/// Which MILP solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum MilpBackend {
    /// microlp, pure Rust (always available).
    Microlp,
    /// HiGHS (needs the `highs` feature: cmake and libclang at build time).
    Highs,
}

/// Largest finite `max_diameter`, metres: the diagonal of a ±1000 m workspace (2000·√2 ≈ 2829 m), so
/// any larger value would mean the same as no limit.
const NO_DIAMETER_LIMIT: f64 = 2830.0;

/// Settings of [`Milp`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MilpSettings {
    /// What to minimise. Default `time`.
    pub objective: ClusterObjective,
    /// Largest number of objects in a candidate cluster. Default 12: capacity decides (the summed
    /// minimum grasp diameters fit the gap and the members stand in one row within it), and this
    /// only bounds the enumeration (ten 7 mm bars fill the 75 mm gap).
    pub max_cluster_size: usize,
    /// Largest distance between two centroids of a candidate cluster (push reach), metres. Default
    /// 0.10, the hierarchical clustering's default cut height.
    pub max_diameter: f64,
    /// Wall-clock limit of one clustering (enumeration and every solve), seconds. Default 10.
    pub time_limit: f64,
    /// Most candidate clusters the model may hold; beyond it (tightly packed small objects) the
    /// heuristic's clustering is returned with status `heuristic`. Default 20 000 (paper scenes of
    /// 34 objects give a few hundred; each candidate is a variable and a list of members).
    pub max_candidates: usize,
    /// Most clash rows the model may hold, with the same fallback. Default 200 000.
    pub max_clash_rows: usize,
    /// Relative gap at which the solver may stop. Default 0 (prove optimality).
    pub mip_gap: f64,
    /// The solver. Default `microlp`.
    pub backend: MilpBackend,
    /// Solve the fewest-clusters objective in two stages (count, then spread among clusterings with
    /// that count) rather than as one weighted sum. Default true: the weighted sum's near-ties slow
    /// the proof by orders of magnitude (`formulations/clustering.md`).
    pub two_stage_fewest_clusters: bool,
}

impl Default for MilpSettings {
    fn default() -> Self {
        Self {
            objective: ClusterObjective::Time,
            max_cluster_size: 12,
            max_diameter: 0.10,
            time_limit: 10.0,
            max_candidates: 20_000,
            max_clash_rows: 200_000,
            mip_gap: 0.0,
            backend: MilpBackend::Microlp,
            two_stage_fewest_clusters: true,
        }
    }
}

impl MilpSettings {
    /// Checks every field, and that the chosen backend is compiled in.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        if !(1..=20).contains(&self.max_cluster_size) {
            return Err(Error::field(
                "milp",
                "max_cluster_size",
                format!(
                    "must be between 1 and 20 (candidates grow combinatorially with it), got {}",
                    self.max_cluster_size
                ),
            ));
        }
        // The diameter may be infinite: no compactness limit (small instances, brute-force checks).
        // From a file, the workspace's longest diagonal already means no limit.
        if self.max_diameter.is_nan()
            || self.max_diameter < 0.0
            || (self.max_diameter.is_finite() && self.max_diameter > NO_DIAMETER_LIMIT)
        {
            return Err(Error::field(
                "milp",
                "max_diameter",
                format!(
                    "must be between 0 and {NO_DIAMETER_LIMIT} m (the diagonal of the largest \
                     workspace, ±1000 m, which already means no limit), got {}",
                    self.max_diameter
                ),
            ));
        }
        crate::error::in_range(
            "milp",
            "mip_gap",
            self.mip_gap,
            (0.0, 1.0),
            "a relative gap",
        )?;
        crate::error::in_range(
            "milp",
            "time_limit",
            self.time_limit,
            (0.001, 3600.0),
            "seconds; under a millisecond not even the candidates are enumerated",
        )?;
        for (field, value, high) in [
            ("max_candidates", self.max_candidates, 5_000_000),
            ("max_clash_rows", self.max_clash_rows, 50_000_000),
        ] {
            crate::error::count_in_range(
                "milp",
                field,
                value,
                (1, high),
                "each is a model row or column held in memory",
            )?;
        }
        if self.backend == MilpBackend::Highs && !cfg!(feature = "highs") {
            return Err(Error::field(
                "milp",
                "backend",
                "HiGHS is not compiled in: build with `--features highs` (needs cmake and libclang)",
            ));
        }
        Ok(())
    }
}

/// Which clusters may be candidates: those whose members stand in a row the push planner can make.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowTest {
    /// Room a candidate cluster's row must leave in the usable jaw gap, metres: a cluster of two or
    /// more is a candidate only if its members can stand in a row (1 mm apart) of at most the gap
    /// less this, along some axis at their current yaws. Default 0.010; in a policy, the push
    /// planner's (`socp.margin`).
    pub margin: f64,
    /// With flush pushes (`socp.flush`), pairs are candidates only when a flush push of one member
    /// lines them up ([`crate::push::flush::admits_flush_pair`]), with the push planner's straddle
    /// and face margin. `None` (default): any pair that stands in a row.
    pub flush_pairs: Option<FlushPairs>,
}

impl Default for RowTest {
    fn default() -> Self {
        Self {
            margin: 0.010,
            flush_pairs: None,
        }
    }
}

/// Optimal clustering by set partitioning.
#[derive(Clone, Debug)]
pub struct Milp {
    settings: MilpSettings,
    /// What every stage agrees on: the time model and `min_push` price the candidates.
    problem: Arc<Problem>,
    /// Which clusters are candidates.
    rows: RowTest,
    /// The heuristic whose clusters join the candidates and warm-start the solver.
    heuristic: Hierarchical,
}

/// The model's data, independent of the backend.
struct Model<'a> {
    costs: &'a [f64],
    covering: &'a [Vec<usize>],
    clashes: &'a [(usize, usize)],
    warm: &'a [usize],
    /// Fix the number of clusters (the second stage of the fewest-clusters objective).
    count: Option<usize>,
    mip_gap: f64,
    time_limit: f64,
}

impl Default for Milp {
    fn default() -> Self {
        Self::new(MilpSettings::default(), Problem::shared_default())
            .expect("the default settings are valid")
    }
}

impl Milp {
    /// A clusterer with these settings, pricing clusters by the problem's time model and
    /// `min_push`, proposing clusters that pass the default [`RowTest`], seeded by the default
    /// hierarchical clustering.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range or the backend is not compiled in.
    pub fn new(settings: MilpSettings, problem: Arc<Problem>) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            settings,
            problem,
            rows: RowTest::default(),
            heuristic: Hierarchical::default(),
        })
    }

    /// The same clusterer proposing the clusters that pass `rows` (in a policy, the push planner's).
    ///
    /// # Errors
    /// [`Error::InvalidField`] (`socp.margin`) when the margin is outside 0 to 0.05 m.
    pub fn with_rows(mut self, rows: RowTest) -> Result<Self> {
        crate::error::in_range("socp", "margin", rows.margin, (0.0, 0.05), "metres")?;
        self.rows = rows;
        Ok(self)
    }

    /// The same clusterer seeded by `heuristic` (in a policy, the policy's `clustering`).
    pub fn seeded_by(mut self, heuristic: Hierarchical) -> Self {
        self.heuristic = heuristic;
        self
    }

    /// The effective settings.
    pub fn settings(&self) -> &MilpSettings {
        &self.settings
    }

    /// The problem whose time model and `min_push` price the candidates.
    pub fn problem(&self) -> &Arc<Problem> {
        &self.problem
    }

    /// Which clusters may be candidates.
    pub fn rows(&self) -> RowTest {
        self.rows
    }

    /// The heuristic that seeds the solver.
    pub fn heuristic(&self) -> &Hierarchical {
        &self.heuristic
    }

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
    fn solve_part(
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
            ..
        } = part;
        let mut stage = |costs: &[f64], gap: f64, count: Option<usize>, warm: &[usize]| {
            self.stage(
                scene,
                candidates,
                covering,
                clashes,
                Model {
                    costs,
                    covering,
                    clashes: &[],
                    warm,
                    count,
                    mip_gap: gap,
                    time_limit: 0.0,
                },
                deadline,
                rounds,
            )
        };
        match settings.objective {
            ClusterObjective::Time => stage(costs, settings.mip_gap, None, warm),
            ClusterObjective::FewestClusters if !settings.two_stage_fewest_clusters => {
                stage(costs, settings.mip_gap, None, warm)
            }
            ClusterObjective::FewestClusters => {
                // Stage 1: fewest clusters. The count is an integer, so a gap below one cluster
                // proves it; stage 2: least spread among clusterings with that count.
                let ones = vec![1.0; candidates.len()];
                let proof_gap = settings.mip_gap.max(0.99 / warm.len().max(1) as f64);
                let first = stage(&ones, proof_gap, None, warm);
                if first.chosen.is_empty() {
                    return first;
                }
                let count = first.chosen.len();
                let count_proven = first.status == Status::Optimal
                    || first
                        .bound
                        .is_some_and(|b| (b - 1e-6).ceil() >= count as f64);
                let spreads: Vec<f64> = candidates.iter().map(|c| spread(scene, c)).collect();
                let second = stage(&spreads, settings.mip_gap, Some(count), &first.chosen);
                let epsilon = costs_model.epsilon();
                let status = match (&second.status, count_proven) {
                    (Status::Optimal, true) => Status::Optimal,
                    (Status::Optimal | Status::Feasible, _) => Status::Feasible,
                    (other, _) => other.clone(),
                };
                let chosen = if second.chosen.is_empty() {
                    first.chosen
                } else {
                    second.chosen
                };
                Solved {
                    status,
                    chosen,
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

    fn solve(&self, model: &Model<'_>) -> Solved {
        match self.settings.backend {
            MilpBackend::Microlp => self.solve_microlp(model),
            #[cfg(feature = "highs")]
            MilpBackend::Highs => self.solve_highs(model),
            #[cfg(not(feature = "highs"))]
            MilpBackend::Highs => failed("HiGHS is not compiled in".to_string()),
        }
    }

    fn solve_microlp(&self, model: &Model<'_>) -> Solved {
        let (problem, x, rows) = build(model);
        let mut solver = problem
            .using(good_lp::microlp)
            .with_time_limit(model.time_limit)
            .with_initial_solution(warm_start(model, &x));
        if model.mip_gap > 0.0 {
            match solver.with_mip_gap(model.mip_gap as f32) {
                Ok(with_gap) => solver = with_gap,
                Err(e) => return failed(format!("mip gap: {e}")),
            }
        }
        for row in rows {
            solver.add_constraint(row);
        }
        match solver.solve() {
            Ok(solution) => {
                let chosen = chosen(&x, |v| solution.value(v));
                let inner = solution.into_inner();
                let stats = inner.stats();
                let reason = inner.termination_reason();
                let status = match reason {
                    microlp::TerminationReason::ProvenOptimal => Status::Optimal,
                    microlp::TerminationReason::MipGap => Status::Feasible,
                    microlp::TerminationReason::TimeLimit => Status::TimeLimit,
                    microlp::TerminationReason::NodeLimit => Status::NodeLimit,
                    other => Status::Failed {
                        reason: format!("microlp stopped: {other:?}"),
                    },
                };
                Solved {
                    status,
                    chosen,
                    bound: stats.best_bound,
                    gap: inner.gap(),
                    nodes: Some(stats.nodes_solved),
                    iterations: Some(stats.lp_iterations),
                    backend_status: format!("microlp: {reason:?}"),
                }
            }
            Err(error) => resolution_failure(error),
        }
    }

    #[cfg(feature = "highs")]
    fn solve_highs(&self, model: &Model<'_>) -> Solved {
        let (problem, x, rows) = build(model);
        let mut solver = problem
            .using(good_lp::highs)
            .with_time_limit(model.time_limit)
            .with_initial_solution(warm_start(model, &x));
        if model.mip_gap > 0.0 {
            match solver.with_mip_gap(model.mip_gap as f32) {
                Ok(with_gap) => solver = with_gap,
                Err(e) => return failed(format!("mip gap: {e}")),
            }
        }
        for row in rows {
            solver.add_constraint(row);
        }
        match solver.solve() {
            Ok(solution) => {
                let status = match solution.status() {
                    good_lp::SolutionStatus::Optimal => Status::Optimal,
                    good_lp::SolutionStatus::GapLimit => Status::Feasible,
                    _ => Status::TimeLimit,
                };
                Solved {
                    chosen: chosen(&x, |v| solution.value(v)),
                    backend_status: format!("highs: {:?}", solution.status()),
                    status,
                    bound: None,
                    gap: None,
                    nodes: None,
                    iterations: None,
                }
            }
            Err(error) => resolution_failure(error),
        }
    }
}

fn failed(reason: String) -> Solved {
    Solved {
        backend_status: reason.clone(),
        status: Status::Failed { reason },
        chosen: Vec::new(),
        bound: None,
        gap: None,
        nodes: None,
        iterations: None,
    }
}

fn resolution_failure(error: ResolutionError) -> Solved {
    match error {
        ResolutionError::Infeasible => Solved {
            status: Status::Infeasible,
            ..failed("infeasible".to_string())
        },
        ResolutionError::Other(message) if message.contains("Time limit") => Solved {
            status: Status::TimeLimit,
            ..failed(message.to_string())
        },
        other => failed(other.to_string()),
    }
}

/// The backend-independent model: variables, objective and rows.
fn build(
    model: &Model<'_>,
) -> (
    good_lp::variable::UnsolvedProblem,
    Vec<Variable>,
    Vec<Constraint>,
) {
    let mut variables = ProblemVariables::new();
    let x: Vec<Variable> = model
        .costs
        .iter()
        .map(|_| variables.add(variable().binary()))
        .collect();
    let objective: Expression = x.iter().zip(model.costs).map(|(&v, &c)| c * v).sum();
    let mut rows = Vec::with_capacity(model.covering.len() + model.clashes.len());
    for cover in model.covering {
        let sum: Expression = cover.iter().map(|&k| x[k]).sum();
        rows.push(good_lp::constraint::eq(sum, 1.0));
    }
    for &(a, b) in model.clashes {
        rows.push(good_lp::constraint::leq(x[a] + x[b], 1.0));
    }
    if let Some(count) = model.count {
        let all: Expression = x.iter().copied().sum();
        rows.push(good_lp::constraint::eq(all, count as f64));
    }
    (variables.minimise(objective), x, rows)
}

fn warm_start(model: &Model<'_>, x: &[Variable]) -> Vec<(Variable, f64)> {
    x.iter()
        .enumerate()
        .map(|(k, &v)| (v, if model.warm.contains(&k) { 1.0 } else { 0.0 }))
        .collect()
}

fn chosen(x: &[Variable], value: impl Fn(Variable) -> f64) -> Vec<usize> {
    x.iter()
        .enumerate()
        .filter(|&(_, &v)| value(v) > 0.5)
        .map(|(k, _)| k)
        .collect()
}

impl Clusterer for Milp {
    fn name(&self) -> &'static str {
        "milp"
    }

    fn cluster(&self, scene: &Scene) -> Result<Outcome<Clustering>> {
        self.cluster_remembering(scene, &mut ClusterMemory::default())
    }

    fn cluster_remembering(
        &self,
        scene: &Scene,
        memory: &mut ClusterMemory,
    ) -> Result<Outcome<Clustering>> {
        let started = Instant::now();
        let settings = &self.settings;
        let heuristic = self.heuristic.cluster(scene)?;
        // A cluster is worth pushing only if its members can stand in one row the jaws take.
        let limit = scene.gripper().usable_gap() - self.rows.margin;
        // The heuristic's clusters join the candidates, so that its answer is a feasible point; one
        // that cannot stand in a row is split into single objects, as it would be taken.
        let flush_ok = |members: &[usize]| match (self.rows.flush_pairs, members) {
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
        };
        let heuristic_clusters: Vec<Vec<usize>> = split_unrowable(
            scene,
            heuristic
                .value
                .clusters
                .iter()
                .map(|c| {
                    let mut members = scene.indices_of(c)?;
                    members.sort_unstable();
                    Ok(members)
                })
                .collect::<Result<_>>()?,
            limit,
            ROW_GAP,
        )
        .into_iter()
        .flat_map(|members| {
            if flush_ok(&members) {
                vec![members]
            } else {
                members.into_iter().map(|i| vec![i]).collect()
            }
        })
        .collect();
        let deadline = started + std::time::Duration::from_secs_f64(settings.time_limit);
        let give_up = |what: String| Outcome {
            value: heuristic.value.clone(),
            status: Status::Heuristic,
            stats: Stats {
                seconds: started.elapsed().as_secs_f64(),
                objective: None,
                bound: None,
                gap: None,
                backend_status: Some(format!(
                    "{what}: the model was not built; the heuristic's clustering, with no \
                     optimality claim"
                )),
                counters: vec![
                    ("budget_exceeded".to_string(), 1.0),
                    ("fell_back".to_string(), 1.0),
                    ("clusters".to_string(), heuristic.value.len() as f64),
                ],
            },
        };
        let Some(mut candidates) = compact_candidates_where(
            scene,
            settings.max_cluster_size,
            settings.max_diameter,
            &|c| admits_row(scene, c, limit, ROW_GAP) && flush_ok(c),
            Budget {
                max_items: settings.max_candidates,
                deadline: Some(deadline),
            },
        ) else {
            return Ok(give_up(format!(
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
        let mut covering: Vec<Vec<usize>> = vec![Vec::new(); scene.len()];
        for (k, candidate) in candidates.iter().enumerate() {
            for &o in candidate {
                covering[o].push(k);
            }
        }
        let Some(clashes) = clashing_pairs(
            scene,
            &candidates,
            Budget {
                max_items: settings.max_clash_rows,
                deadline: Some(deadline),
            },
        ) else {
            return Ok(give_up(format!(
                "more than {} clashing pairs of the {} candidates, or the time limit",
                settings.max_clash_rows,
                candidates.len()
            )));
        };
        let heuristic_cost = costs_model.clustering_cost(&heuristic_clusters);
        let clash_rows = clashes.len();

        let mut rounds = 0;
        // The previous optimum minus the carried clusters, when provably still optimal (`reuse.rs`).
        let reused = match settings.objective {
            ClusterObjective::Time => memory.still_optimal(scene, &candidates, &costs),
            ClusterObjective::FewestClusters => None,
        };
        let mut parts = 0;
        let was_reused = reused.is_some();
        let (solved, parts_fell_back) = match reused {
            Some(chosen) => {
                let cost: f64 = chosen.iter().map(|&k| costs[k]).sum();
                let solved = Solved {
                    status: Status::Optimal,
                    chosen,
                    bound: Some(cost),
                    gap: Some(0.0),
                    nodes: Some(0),
                    iterations: Some(0),
                    backend_status: "the previous proven optimum without the carried clusters \
                                     (still optimal: no candidate new or changed, none clashing \
                                     with a carried cluster)"
                        .to_string(),
                };
                (solved, 0)
            }
            None => {
                // Independent parts are solved one by one (`decompose.rs`).
                let mut solved_parts = Vec::new();
                for mut part in decompose::parts(scene.len(), &candidates, &costs, &clashes, &warm)
                {
                    parts += 1;
                    let answer = match part.trivial() {
                        Some(answer) => answer,
                        None => {
                            self.solve_part(scene, &mut part, &costs_model, deadline, &mut rounds)
                        }
                    };
                    solved_parts.push((part, answer));
                }
                decompose::merge(solved_parts)
            }
        };

        let picked: Vec<Vec<usize>> = solved
            .chosen
            .iter()
            .map(|&k| candidates[k].clone())
            .collect();
        let is_partition = {
            let mut all: Vec<usize> = picked.iter().flatten().copied().collect();
            all.sort_unstable();
            all == (0..scene.len()).collect::<Vec<_>>()
        };
        let usable = is_partition && separability_conflicts(scene, &picked).is_empty();
        let solver_cost = costs_model.clustering_cost(&picked);
        let whole_fallback = !(usable && solver_cost <= heuristic_cost + 1e-9);
        let (clusters, objective, fell_back) = if whole_fallback {
            (heuristic_clusters, heuristic_cost, true)
        } else {
            (picked, solver_cost, parts_fell_back > 0)
        };
        // The heuristic's clustering carries no claim: an optimum the solver proved but that could
        // not be used (not a partition, or clusters not separable) does not make it optimal.
        let status = if whole_fallback && solved.status == Status::Optimal {
            Status::Heuristic
        } else {
            solved.status.clone()
        };
        let proven = settings.objective == ClusterObjective::Time
            && solved.status == Status::Optimal
            && !fell_back;
        memory
            .set(proven.then(|| reuse::Previous::new(scene, &candidates, &costs, &solved.chosen)));
        let clustering = Clustering::from_indices(scene, &clusters).normalised();
        let mut counters = vec![
            ("candidates".to_string(), candidates.len() as f64),
            ("clash_rows".to_string(), clash_rows as f64),
            ("variables".to_string(), candidates.len() as f64),
            ("constraints".to_string(), (scene.len() + clash_rows) as f64),
            ("solves".to_string(), rounds as f64),
            ("reused".to_string(), if was_reused { 1.0 } else { 0.0 }),
            ("parts".to_string(), parts as f64),
            ("parts_fell_back".to_string(), parts_fell_back as f64),
            ("heuristic_objective".to_string(), heuristic_cost),
            ("fell_back".to_string(), if fell_back { 1.0 } else { 0.0 }),
            ("clusters".to_string(), clustering.len() as f64),
        ];
        if let Some(nodes) = solved.nodes {
            counters.push(("nodes".to_string(), nodes as f64));
        }
        if let Some(iterations) = solved.iterations {
            counters.push(("lp_iterations".to_string(), iterations as f64));
        }
        Ok(Outcome {
            value: clustering,
            status,
            stats: Stats {
                seconds: started.elapsed().as_secs_f64(),
                objective: Some(objective),
                bound: solved.bound,
                gap: solved.gap,
                backend_status: Some(solved.backend_status),
                counters,
            },
        })
    }
}
