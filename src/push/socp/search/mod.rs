//! The search over rows for one cluster (the module docs of [`super`]): candidate axes with their
//! bounds, each row solved and turned into pushes, the cheapest held row kept.

use std::cell::Cell;
use std::time::Instant;

use clarabel::solver::SolverStatus;
use nalgebra::{Point2, Vector2};

mod attempt;
mod candidates;

use super::Socp;
use super::rows::permutations;
use crate::error::Result;
use crate::geometry::ConvexPolygon;
use crate::outcome::{Outcome, Stats, Status};
use crate::push::flush::{Face, flush_faces};
use crate::push::row::{Fence, Motion, RowProblem, RowSolution, solve_row};
use crate::push::{Push, PushPlan, SkipReason, SkippedPush};
use crate::scene::{Gripper, ObjectId, Scene};

/// A solved row turned into pushes.
struct Attempt {
    plan: PushPlan,
    held: bool,
    objective: f64,
    axis: Vector2<f64>,
    status: SolverStatus,
}

/// A row to try: its closing axis, its lower bound on the pushes, whether a perfect row along it is
/// held by the grasp model, the members' order along it, and how they may move (`None`: flush
/// pushes turned to the nearest face normal once solved).
struct Candidate {
    bound: f64,
    axis: Vector2<f64>,
    proxy: bool,
    order: Vec<usize>,
    motion: Option<Motion>,
}

/// Largest angle through which a flush push of a larger cluster turns a member's planned push to
/// its nearest face normal, radians (45°).
const SNAP: f64 = std::f64::consts::FRAC_PI_4;

/// Push plans whose times differ by at most this are taken as equally fast, seconds: 2.5 mm of
/// pushing at the time model's default push speed (0.05 m/s).
const EQUAL_TIME: f64 = 0.05;

/// Pushes in order, the targets they reach and the plates' centre line across the axis.
type Realised = (Vec<Push>, Vec<Point2<f64>>, f64);

/// Why a row could not be pushed into place: the object whose push was refused, and why.
type Refusal = (ObjectId, SkipReason);

/// One cluster being planned: its members as the programs see them, and the solver's counts.
struct Search<'a> {
    socp: &'a Socp,
    scene: &'a Scene,
    gripper: &'a Gripper,
    started: Instant,
    /// Scene indices of the members.
    members: Vec<usize>,
    /// Their centroids.
    starts: Vec<Point2<f64>>,
    /// Their outlines about their centroids.
    outlines: Vec<ConvexPolygon>,
    masses: Vec<f64>,
    fences: Vec<Fence>,
    /// The faces a flush push may meet, per member.
    faces: Vec<Vec<Face>>,
    solves: Cell<usize>,
    solver_seconds: Cell<f64>,
    iterations: Cell<u64>,
    last_status: Cell<SolverStatus>,
    /// Whether `socp.time_limit` ended the search before every row was solved.
    cut_short: Cell<bool>,
}

/// The SOCP planner's answer for `cluster` on `scene`.
pub(super) fn plan(socp: &Socp, scene: &Scene, cluster: &[ObjectId]) -> Result<Outcome<PushPlan>> {
    let started = Instant::now();
    let members = scene.indices_of(cluster)?;
    // Nothing to push. The answer is trivially the best, but the status claims no more than the
    // planner's abilities say it can (`BestFound`, as for every row it finds).
    if members.len() < 2 {
        return Ok(finish(
            started,
            PushPlan::default(),
            Status::BestFound,
            None,
            Vec::new(),
        ));
    }
    let starts: Vec<Point2<f64>> = members.iter().map(|&i| scene.centroid(i)).collect();
    let outlines: Vec<ConvexPolygon> = members
        .iter()
        .map(|&i| {
            scene
                .world_polygon(i)
                .translated(&-scene.centroid(i).coords)
        })
        .collect();
    let masses: Vec<f64> = members
        .iter()
        .map(|&i| socp.problem.grasp_model().mass_of(&scene.objects()[i]))
        .collect();
    let fences = socp.fences(scene, &members, &outlines);
    let faces: Vec<Vec<Face>> = outlines
        .iter()
        .map(|o| flush_faces(o, socp.settings.flush_margin))
        .collect();
    let search = Search {
        socp,
        scene,
        gripper: scene.gripper(),
        started,
        members,
        starts,
        outlines,
        masses,
        fences,
        faces,
        solves: Cell::new(0),
        solver_seconds: Cell::new(0.0),
        iterations: Cell::new(0),
        last_status: Cell::new(SolverStatus::Unsolved),
        cut_short: Cell::new(false),
    };
    Ok(search.run())
}

/// The outcome with `plan`: its objective the total push distance.
fn finish(
    started: Instant,
    plan: PushPlan,
    status: Status,
    backend: Option<String>,
    counters: Vec<(String, f64)>,
) -> Outcome<PushPlan> {
    let objective = plan.pushes.iter().map(|p| p.distance).sum::<f64>() + 0.0;
    Outcome {
        value: plan,
        status,
        stats: Stats {
            seconds: started.elapsed().as_secs_f64(),
            objective: Some(objective),
            backend_status: backend,
            counters,
            ..Stats::default()
        },
    }
}

/// The cheapest attempt (of the held ones only, if `held_only`): its position and objective.
fn cheapest(attempts: &[Attempt], held_only: bool) -> Option<(usize, f64)> {
    attempts
        .iter()
        .enumerate()
        .filter(|(_, a)| a.held || !held_only)
        .min_by(|a, b| a.1.objective.total_cmp(&b.1.objective))
        .map(|(k, a)| (k, a.objective))
}

impl Search<'_> {
    fn problem(&self) -> RowProblem<'_> {
        let settings = &self.socp.settings;
        RowProblem {
            starts: &self.starts,
            outlines: &self.outlines,
            fences: &self.fences,
            workspace: self.scene.workspace(),
            edge: settings.edge_margin,
            row_limit: self.gripper.usable_gap() - settings.margin,
            gap: settings.gap,
            straddle: settings.straddle,
            centring: settings.centring,
        }
    }

    /// The row along `axis` in `order` with `motion`, counted.
    fn solve(&self, axis: &Vector2<f64>, order: &[usize], motion: &Motion) -> RowSolution {
        let solution = solve_row(
            &self.problem(),
            axis,
            order,
            motion,
            self.socp.settings.flush_cone,
        );
        self.solves.set(self.solves.get() + 1);
        self.solver_seconds
            .set(self.solver_seconds.get() + solution.seconds);
        self.iterations
            .set(self.iterations.get() + u64::from(solution.iterations));
        self.last_status.set(solution.status);
        solution
    }

    /// Whether the search has run past `socp.time_limit` (noted, so the answer says so).
    fn out_of_time(&self) -> bool {
        let out = self
            .socp
            .settings
            .time_limit
            .is_some_and(|limit| self.started.elapsed().as_secs_f64() >= limit);
        if out {
            self.cut_short.set(true);
        }
        out
    }

    /// The members in the order of their centroids along `axis`.
    fn natural(&self, axis: &Vector2<f64>) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.members.len()).collect();
        order.sort_by(|&a, &b| {
            self.starts[a]
                .coords
                .dot(axis)
                .total_cmp(&self.starts[b].coords.dot(axis))
        });
        order
    }

    /// The search, then the cheapest held row (or the cheapest row), or why there is none.
    fn run(self) -> Outcome<PushPlan> {
        let axes = self.candidates();
        let mut attempts: Vec<Attempt> = Vec::new();
        let mut failure: Option<Refusal> = None;
        let mut tried = vec![false; axes.len()];
        let mut solved_any = false;
        // Phase 1: every axis, those whose perfect row is held first, each in order of its bound,
        // skipping any whose bound cannot beat the cheapest held row found.
        // Phase 2 (no held row found, or held rows not preferred): the axes not yet solved, in order
        // of their bound, until none can beat the cheapest row that can be pushed into place.
        let mut held_first: Vec<usize> = (0..axes.len()).collect();
        held_first.sort_by_key(|&k| !axes[k].proxy);
        for held_phase in [true, false] {
            if held_phase && !self.socp.settings.prefer_held_rows {
                continue;
            }
            let visit: Vec<usize> = if held_phase {
                held_first.clone()
            } else {
                (0..axes.len()).collect()
            };
            for k in visit {
                let (bound, axis) = (axes[k].bound, axes[k].axis);
                if tried[k] {
                    continue;
                }
                if cheapest(&attempts, held_phase).is_some_and(|(_, best)| bound >= best - 1e-12) {
                    if held_phase {
                        continue;
                    }
                    break;
                }
                tried[k] = true;
                let order = &axes[k].order;
                let Some((solution, motion)) =
                    self.solve_candidate(&axis, order, axes[k].motion.as_ref())
                else {
                    continue;
                };
                solved_any = true;
                match self.attempt(&axis, order, &solution, &motion) {
                    Ok(found) => attempts.push(found),
                    Err(reason) => failure = Some(reason),
                }
            }
            if held_phase && cheapest(&attempts, true).is_some() {
                break;
            }
        }
        self.other_orders(&mut attempts);
        self.answer(&axes, attempts, failure, solved_any)
    }

    /// Other orders along the chosen axis (two objects can only swap by passing each other, which
    /// never shortens the pushes, so pairs keep their natural order).
    fn other_orders(&self, attempts: &mut Vec<Attempt>) {
        let held_found = cheapest(attempts, true).is_some();
        if self.members.len() >= 3
            && let Some((k, _)) = cheapest(attempts, held_found)
        {
            let axis = attempts[k].axis;
            let free = (!self.socp.settings.flush).then(|| Motion::free(self.members.len()));
            for order in permutations(&self.natural(&axis), self.socp.settings.max_orders)
                .into_iter()
                .skip(1)
            {
                if let Some((solution, motion)) = self.solve_candidate(&axis, &order, free.as_ref())
                    && let Ok(found) = self.attempt(&axis, &order, &solution, &motion)
                {
                    attempts.push(found);
                }
            }
        }
    }

    /// The cheapest held row if there is one, else the cheapest row; with none, infeasible (no row
    /// on any axis) or failed (rows, but no push sequence).
    fn answer(
        &self,
        axes: &[Candidate],
        mut attempts: Vec<Attempt>,
        failure: Option<Refusal>,
        solved_any: bool,
    ) -> Outcome<PushPlan> {
        let held_found = cheapest(&attempts, true).is_some();
        let mut counters = vec![
            ("socp_solves".to_string(), self.solves.get() as f64),
            ("solver_seconds".to_string(), self.solver_seconds.get()),
            ("iterations".to_string(), self.iterations.get() as f64),
            ("axes".to_string(), axes.len() as f64),
            (
                "held_axes".to_string(),
                axes.iter().filter(|a| a.proxy).count() as f64,
            ),
            ("fences".to_string(), self.fences.len() as f64),
        ];
        if let Some((k, _)) = cheapest(&attempts, held_found) {
            let chosen = attempts.swap_remove(k);
            counters.push(("axis".to_string(), chosen.axis.y.atan2(chosen.axis.x)));
            // Each row is optimal for its axis and order; over the axes and orders sampled, the
            // cheapest is the best found (of those solved before the time limit, if it struck).
            let status = if self.cut_short.get() {
                Status::TimeLimit
            } else {
                Status::BestFound
            };
            return finish(
                self.started,
                chosen.plan,
                status,
                Some(format!("clarabel: {:?}", chosen.status)),
                counters,
            );
        }
        let ids: Vec<ObjectId> = self
            .members
            .iter()
            .map(|&i| self.scene.objects()[i].id)
            .collect();
        let no_row: Vec<SkippedPush> = ids
            .iter()
            .map(|&object| SkippedPush {
                object,
                reason: SkipReason::NoRow,
            })
            .collect();
        // A search the time limit ended proves nothing about the rows it did not solve.
        let limit = self
            .cut_short
            .get()
            .then(|| self.socp.settings.time_limit.unwrap_or_default());
        let (status, skipped) = match (failure, limit) {
            (Some((object, reason)), _) if solved_any => (
                Status::Failed {
                    reason: match limit {
                        Some(limit) => format!(
                            "no push sequence for any row solved before the time limit \
                             ({limit} s): object {object}: {reason}"
                        ),
                        None => {
                            format!("no push sequence for any row: object {object}: {reason}")
                        }
                    },
                },
                vec![SkippedPush { object, reason }],
            ),
            (_, Some(limit)) => (
                Status::Failed {
                    reason: format!(
                        "the time limit ({limit} s) ended the search before a row was found"
                    ),
                },
                no_row,
            ),
            _ => (Status::Infeasible, no_row),
        };
        finish(
            self.started,
            PushPlan {
                pushes: Vec::new(),
                skipped,
                intended_grasp: None,
                row_held: None,
            },
            status,
            Some(format!("clarabel: {:?}", self.last_status.get())),
            counters,
        )
    }
}
