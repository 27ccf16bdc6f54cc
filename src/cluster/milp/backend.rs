//! The set-partitioning model handed to a MILP solver, and the two backends that solve it: microlp
//! (pure Rust, always) and HiGHS (the `highs` feature). Both read the same model ([`build`]) and
//! report a [`Solved`] with the solver's own status kept verbatim.

use good_lp::solvers::{
    Solution as _, SolverModel, WithInitialSolution, WithMipGap, WithTimeLimit,
};
use good_lp::{Constraint, Expression, ProblemVariables, ResolutionError, Variable, variable};

use super::{Milp, MilpBackend};
use crate::cluster::solved::Solved;
use crate::outcome::Status;

/// The model's data, independent of the backend.
pub(super) struct Model<'a> {
    pub costs: &'a [f64],
    pub covering: &'a [Vec<usize>],
    pub clashes: &'a [(usize, usize)],
    /// Riders that may ride on rows, with the costs of their `y` (`riders.rs`): `(row, single,
    /// cost)`, the cost negative for a saving.
    pub rides: &'a [(usize, usize, f64)],
    pub warm: &'a [usize],
    /// Positions of the rides taken in the warm start.
    pub warm_riding: &'a [usize],
    /// Fix the number of trips, clusters less riders (the second stage of the fewest-clusters
    /// objective).
    pub count: Option<usize>,
    pub mip_gap: f64,
    pub time_limit: f64,
}

impl Milp {
    pub(super) fn solve(&self, model: &Model<'_>) -> Solved {
        match self.settings.backend {
            MilpBackend::Microlp => self.solve_microlp(model),
            #[cfg(feature = "highs")]
            MilpBackend::Highs => self.solve_highs(model),
            #[cfg(not(feature = "highs"))]
            MilpBackend::Highs => failed("HiGHS is not compiled in".to_string()),
        }
    }

    fn solve_microlp(&self, model: &Model<'_>) -> Solved {
        let (problem, x, y, rows) = build(model);
        let solver = match configured(problem.using(good_lp::microlp), model, &x, &y, rows) {
            Ok(solver) => solver,
            Err(reason) => return failed(reason),
        };
        match solver.solve() {
            Ok(solution) => {
                let chosen = chosen(&x, |v| solution.value(v));
                let riding = self::chosen(&y, |v| solution.value(v));
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
                    riding,
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
        let (problem, x, y, rows) = build(model);
        let solver = match configured(problem.using(good_lp::highs), model, &x, &y, rows) {
            Ok(solver) => solver,
            Err(reason) => return failed(reason),
        };
        match solver.solve() {
            Ok(solution) => {
                let status = match solution.status() {
                    good_lp::SolutionStatus::Optimal => Status::Optimal,
                    good_lp::SolutionStatus::GapLimit => Status::Feasible,
                    _ => Status::TimeLimit,
                };
                Solved {
                    chosen: chosen(&x, |v| solution.value(v)),
                    riding: chosen(&y, |v| solution.value(v)),
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

/// `solver` with the model's time limit, warm start, MIP gap (when positive) and rows: the set-up
/// both backends share (the error: why the gap was refused).
fn configured<S>(
    mut solver: S,
    model: &Model<'_>,
    x: &[Variable],
    y: &[Variable],
    rows: Vec<Constraint>,
) -> Result<S, String>
where
    S: SolverModel + WithTimeLimit + WithInitialSolution + WithMipGap,
{
    solver = solver
        .with_time_limit(model.time_limit)
        .with_initial_solution(warm_start(model, x, y));
    if model.mip_gap > 0.0 {
        solver = solver
            .with_mip_gap(model.mip_gap as f32)
            .map_err(|e| format!("mip gap: {e}"))?;
    }
    for row in rows {
        solver.add_constraint(row);
    }
    Ok(solver)
}

fn failed(reason: String) -> Solved {
    Solved {
        backend_status: reason.clone(),
        status: Status::Failed { reason },
        chosen: Vec::new(),
        riding: Vec::new(),
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

/// The backend-independent model: variables (`x` per candidate, `y` per ride), objective and rows.
fn build(
    model: &Model<'_>,
) -> (
    good_lp::variable::UnsolvedProblem,
    Vec<Variable>,
    Vec<Variable>,
    Vec<Constraint>,
) {
    let mut variables = ProblemVariables::new();
    let x: Vec<Variable> = model
        .costs
        .iter()
        .map(|_| variables.add(variable().binary()))
        .collect();
    let y: Vec<Variable> = model
        .rides
        .iter()
        .map(|_| variables.add(variable().binary()))
        .collect();
    let objective: Expression = x
        .iter()
        .zip(model.costs)
        .map(|(&v, &c)| c * v)
        .chain(y.iter().zip(model.rides).map(|(&v, &(_, _, c))| c * v))
        .sum();
    let mut rows = Vec::with_capacity(model.covering.len() + model.clashes.len());
    for cover in model.covering {
        let sum: Expression = cover.iter().map(|&k| x[k]).sum();
        rows.push(good_lp::constraint::eq(sum, 1.0));
    }
    for &(a, b) in model.clashes {
        rows.push(good_lp::constraint::leq(x[a] + x[b], 1.0));
    }
    // One rider per chosen row; a rider on one row, and only while it is a cluster of its own.
    let mut on_row: std::collections::BTreeMap<usize, Expression> = Default::default();
    let mut of_single: std::collections::BTreeMap<usize, Expression> = Default::default();
    for (&v, &(row, single, _)) in y.iter().zip(model.rides) {
        *on_row.entry(row).or_default() += v;
        *of_single.entry(single).or_default() += v;
    }
    for (k, sum) in on_row.into_iter().chain(of_single) {
        rows.push(good_lp::constraint::leq(sum, x[k]));
    }
    if let Some(count) = model.count {
        let all: Expression =
            x.iter().copied().sum::<Expression>() - y.iter().copied().sum::<Expression>();
        rows.push(good_lp::constraint::eq(all, count as f64));
    }
    (variables.minimise(objective), x, y, rows)
}

fn warm_start(model: &Model<'_>, x: &[Variable], y: &[Variable]) -> Vec<(Variable, f64)> {
    x.iter()
        .enumerate()
        .map(|(k, &v)| (v, if model.warm.contains(&k) { 1.0 } else { 0.0 }))
        .chain(y.iter().enumerate().map(|(k, &v)| {
            (
                v,
                if model.warm_riding.contains(&k) {
                    1.0
                } else {
                    0.0
                },
            )
        }))
        .collect()
}

fn chosen(x: &[Variable], value: impl Fn(Variable) -> f64) -> Vec<usize> {
    x.iter()
        .enumerate()
        .filter(|&(_, &v)| value(v) > 0.5)
        .map(|(k, _)| k)
        .collect()
}
