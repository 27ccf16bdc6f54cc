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

mod backend;
mod instance;
mod settings;
mod solve;

use std::collections::HashSet;
use std::sync::Arc;
use std::time::Instant;

pub use settings::{FlushPairs, MilpBackend, MilpSettings, RowTest};

use instance::Instance;

use super::decompose;
use super::hierarchical::Hierarchical;
use super::objective::ClusterObjective;
use super::reuse::{self, ClusterMemory};
use super::riders::{Ride, RideOptions, RideVar};
use super::separability::separability_conflicts;
use super::solved::Solved;
use super::{Clusterer, Clustering, Fallback};
use crate::error::Result;
use crate::outcome::{Abilities, Outcome, Stats, Status};
use crate::problem::Problem;
use crate::scene::Scene;

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
    /// Riders the model may put on rows (`riders.rs`); none when `None`.
    rides: Option<RideOptions>,
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
            rides: None,
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

    /// The same clusterer choosing riders for its rows too (`formulations/stacking.md`, "Riders in
    /// the clustering"): the clustering it returns lists them in [`Clustering::riders`]. With
    /// riders the previous optimum is not reused; every table is solved.
    ///
    /// # Errors
    /// [`Error::InvalidField`](crate::error::Error::InvalidField) (`riders`) when `carried` is
    /// outside 0 to 1 or `reach` is not positive.
    pub fn with_rides(mut self, options: RideOptions) -> Result<Self> {
        crate::error::in_range(
            "riders",
            "carried",
            options.carried,
            (0.0, 1.0),
            "the probability that a placed rider rides its trip to the bin",
        )?;
        crate::error::in_range("riders", "reach", options.reach, (1e-6, 10.0), "metres")?;
        self.rides = Some(options);
        Ok(self)
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
}

/// How the model was solved.
struct Answer {
    solved: Solved,
    reused: bool,
    parts: usize,
    parts_fell_back: usize,
    rounds: usize,
}

impl Milp {
    /// The remembered optimum minus the carried clusters when it is provably still optimal
    /// (`reuse.rs`); otherwise every independent part solved on its own (`decompose.rs`).
    fn answer(
        &self,
        scene: &Scene,
        instance: &Instance<'_>,
        memory: &ClusterMemory,
        deadline: Instant,
    ) -> Answer {
        let Instance {
            candidates,
            costs,
            clashes,
            warm,
            costs_model,
            rides,
            ..
        } = instance;
        let reused = match self.settings.objective {
            ClusterObjective::Time if self.rides.is_none() => {
                memory.still_optimal(scene, candidates, costs)
            }
            _ => None,
        };
        if let Some(chosen) = reused {
            let cost: f64 = chosen.iter().map(|&k| costs[k]).sum();
            let solved = Solved {
                status: Status::Optimal,
                chosen,
                riding: Vec::new(),
                bound: Some(cost),
                gap: Some(0.0),
                nodes: Some(0),
                iterations: Some(0),
                backend_status: "the previous proven optimum without the carried clusters \
                                 (still optimal: no candidate new or changed, none clashing \
                                 with a carried cluster)"
                    .to_string(),
            };
            return Answer {
                solved,
                reused: true,
                parts: 0,
                parts_fell_back: 0,
                rounds: 0,
            };
        }
        let (mut parts, mut rounds) = (0, 0);
        let mut solved_parts = Vec::new();
        for mut part in decompose::parts(scene.len(), candidates, costs, clashes, warm, rides) {
            parts += 1;
            let answer = match part.trivial() {
                Some(answer) => answer,
                None => self.solve_part(scene, &mut part, costs_model, deadline, &mut rounds),
            };
            solved_parts.push((part, answer));
        }
        let (solved, parts_fell_back) = decompose::merge(solved_parts);
        Answer {
            solved,
            reused: false,
            parts,
            parts_fell_back,
            rounds,
        }
    }
}

impl Clusterer for Milp {
    fn name(&self) -> &'static str {
        "milp"
    }

    /// Proves its optimum when `mip_gap` is 0; stops at `time_limit`.
    fn abilities(&self) -> Abilities {
        Abilities {
            name: self.name().to_string(),
            proves_optimality: self.settings.mip_gap == 0.0,
            time_limit: Some(self.settings.time_limit),
        }
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
        let deadline = started + std::time::Duration::from_secs_f64(settings.time_limit);
        let instance = match self.instance(scene, &heuristic.value, memory.held(), deadline)? {
            Ok(instance) => instance,
            Err(what) => return Ok(gave_up(&what, heuristic.value, started)),
        };
        let clash_rows = instance.clashes.len();
        let Answer {
            solved,
            reused,
            parts,
            parts_fell_back,
            rounds,
        } = self.answer(scene, &instance, memory, deadline);
        let Instance {
            candidates,
            costs_model,
            costs,
            rides,
            heuristic: (heuristic_clusters, heuristic_cost),
            ..
        } = instance;
        let chosen_rides: Vec<RideVar> = solved.riding.iter().map(|&k| rides[k]).collect();

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
        let separable = is_partition && separability_conflicts(scene, &picked).is_empty();
        let rides_hold = rides_hold(&chosen_rides, &solved.chosen);
        let solver_cost = costs_model.clustering_cost(&picked)
            - chosen_rides.iter().map(|r| r.worth).sum::<f64>();
        let fallback = if picked.is_empty() && !scene.is_empty() {
            Some(Fallback::NoAnswer)
        } else if !is_partition {
            Some(Fallback::NotAPartition)
        } else if !separable {
            Some(Fallback::NotSeparable)
        } else if !rides_hold {
            Some(Fallback::NotAPartition)
        } else if solver_cost > heuristic_cost + 1e-9 {
            Some(Fallback::DearerThanHeuristic)
        } else if parts_fell_back > 0 {
            Some(Fallback::Parts {
                count: parts_fell_back,
            })
        } else {
            None
        };
        let whole_fallback = !(separable && rides_hold && solver_cost <= heuristic_cost + 1e-9);
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
        memory.set(
            (proven && self.rides.is_none())
                .then(|| reuse::Previous::new(scene, &candidates, &costs, &solved.chosen)),
        );
        let ids = |members: &[usize]| -> Vec<crate::scene::ObjectId> {
            let mut ids: Vec<_> = members.iter().map(|&i| scene.objects()[i].id).collect();
            ids.sort_unstable();
            ids
        };
        let mut riders: Vec<Ride> = if whole_fallback {
            Vec::new()
        } else {
            chosen_rides
                .iter()
                .map(|r| Ride {
                    rider: scene.objects()[candidates[r.single][0]].id,
                    row: ids(&candidates[r.row]),
                })
                .collect()
        };
        riders.sort();
        let clustering = Clustering {
            fallback,
            riders,
            ..Clustering::from_indices(scene, &clusters).normalised()
        };
        let mut counters = vec![
            ("candidates".to_string(), candidates.len() as f64),
            ("clash_rows".to_string(), clash_rows as f64),
            ("variables".to_string(), candidates.len() as f64),
            ("constraints".to_string(), (scene.len() + clash_rows) as f64),
            ("solves".to_string(), rounds as f64),
            ("reused".to_string(), if reused { 1.0 } else { 0.0 }),
            ("parts".to_string(), parts as f64),
            ("parts_fell_back".to_string(), parts_fell_back as f64),
            ("heuristic_objective".to_string(), heuristic_cost),
            ("fell_back".to_string(), if fell_back { 1.0 } else { 0.0 }),
            ("clusters".to_string(), clustering.len() as f64),
        ];
        if self.rides.is_some() {
            counters.push(("rides_offered".to_string(), rides.len() as f64));
            counters.push(("riders".to_string(), clustering.riders.len() as f64));
        }
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

/// Whether every chosen ride stands on a chosen row and a chosen single, one rider per row and one
/// row per rider (the model's rows say so; checked as the partition is).
fn rides_hold(rides: &[RideVar], chosen: &[usize]) -> bool {
    let mut rows = HashSet::new();
    let mut singles = HashSet::new();
    rides.iter().all(|r| {
        chosen.contains(&r.row)
            && chosen.contains(&r.single)
            && rows.insert(r.row)
            && singles.insert(r.single)
    })
}

/// The heuristic's clustering, with no optimality claim, when the model could not be built within
/// its budget (`what` says which).
fn gave_up(what: &str, heuristic: Clustering, started: Instant) -> Outcome<Clustering> {
    let clusters = heuristic.len() as f64;
    let fallback = Some(Fallback::OverBudget {
        what: what.to_string(),
    });
    Outcome {
        value: Clustering {
            fallback,
            ..heuristic
        },
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
                ("clusters".to_string(), clusters),
            ],
        },
    }
}
