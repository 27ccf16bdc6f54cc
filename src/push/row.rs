//! The second-order cone program behind [`Socp`](super::Socp): least total push distance that lines
//! one cluster up between the jaws, for a fixed closing axis `u` and a fixed order along it
//! (`formulations/pushing.md`).
//!
//! Variables: target centroids `p_i` (2 each), cone epigraphs `t_i`, and the row's centre line `c`
//! across the axis. With `v ⊥ u`, each object's outline taken about its centroid at its current yaw,
//! `h_i(d)` its support in direction `d`:
//!
//! ```text
//! minimise    Σ_i t_i
//! subject to  ‖p_i − p_i⁰‖ ≤ t_i                                         (one cone per object)
//!             u·p_(j+1) − u·p_(j) ≥ h_(j)(u) + h_(j+1)(−u) + gap         (consecutive, no overlap)
//!             u·p_(k) + h_(k)(u) − u·p_(1) + h_(1)(−u) ≤ g − margin      (the row fits the jaws)
//!             v·p_i − h_i(−v) ≤ c − s,   v·p_i + h_i(v) ≥ c + s           (each straddles the plates' centre line)
//!             |v·p_i − c| ≤ τ                                            (centroids near that line)
//!             n_iq·p_i ≥ β_iq                                            (clear of outside object q)
//!             workspace bounds on p_i (an edge margin inside),  p_i = p_i⁰ for objects held fixed
//!             p_i − p_i⁰ within `cone` of n_i, for objects pushed flush on a face of normal n_i
//! ```
//!
//! It is solved by clarabel (an interior-point method for conic programs); its status is kept.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::{Point2, Vector2};

use super::flush::turned;
use crate::geometry::ConvexPolygon;
use crate::scene::Workspace;

/// How far inside the workspace targets are kept, metres.
const INSIDE: f64 = 1e-6;

/// A fixed half-plane `normal·p_i ≥ offset` keeping member `member`'s target clear of an outside object.
#[derive(Clone, Copy, Debug)]
pub(super) struct Fence {
    /// Position of the member in the cluster.
    pub member: usize,
    /// Unit normal pointing away from the outside object.
    pub normal: Vector2<f64>,
    /// Smallest allowed `normal·p_i`, metres.
    pub offset: f64,
}

/// Everything about one cluster that does not depend on the axis or the order.
pub(super) struct RowProblem<'a> {
    /// Current centroids.
    pub starts: &'a [Point2<f64>],
    /// Outlines about their own centroids, at their current yaw.
    pub outlines: &'a [ConvexPolygon],
    /// Half-planes clear of the objects outside the cluster.
    pub fences: &'a [Fence],
    /// The workspace.
    pub workspace: &'a Workspace,
    /// How far inside the workspace's edges targets stay, or their start's distance from an edge
    /// if smaller, metres.
    pub edge: f64,
    /// Usable jaw gap minus the margin, metres.
    pub row_limit: f64,
    /// Gap kept between neighbours in the row, metres.
    pub gap: f64,
    /// How far every object reaches past the plates' centre line on both sides, metres.
    pub straddle: f64,
    /// How far a centroid may lie from the plates' centre line, metres.
    pub centring: f64,
}

/// How each member may move in one row: held where it is (`fixed`), pushed only within the cone
/// about a face's inward normal (`along`: a flush push), or anywhere; and, for flush pairs pushed
/// tight, a shorter row than the jaws allow (`limit`).
#[derive(Clone, Debug)]
pub(super) struct Motion {
    pub fixed: Vec<bool>,
    pub along: Vec<Option<Vector2<f64>>>,
    pub limit: Option<f64>,
}

impl Motion {
    /// Every one of `k` members free.
    pub fn free(k: usize) -> Self {
        Self {
            fixed: vec![false; k],
            along: vec![None; k],
            limit: None,
        }
    }

    /// The same motion with the members in `fixed` held.
    pub fn holding(&self, fixed: &[bool]) -> Self {
        Self {
            fixed: fixed.to_vec(),
            ..self.clone()
        }
    }
}

/// One solve's answer.
#[derive(Clone, Debug)]
pub(super) struct RowSolution {
    /// Target centroids (empty unless solved).
    pub targets: Vec<Point2<f64>>,
    /// Position of the plates' centre line across the axis (`c`), metres.
    pub centre_line: f64,
    /// clarabel's status.
    pub status: SolverStatus,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Seconds spent in clarabel (set-up and solve).
    pub seconds: f64,
}

impl RowSolution {
    /// Whether clarabel returned a usable point.
    pub fn solved(&self) -> bool {
        matches!(
            self.status,
            SolverStatus::Solved | SolverStatus::AlmostSolved
        )
    }
}

/// A lower bound on the program's optimum for `axis` (any order), or `None` when no row along `axis`
/// can exist: the objects' widths along it (plus the gaps) exceed the jaws, or an object is too narrow
/// across it to straddle the plates' centre line.
///
/// The bound: the row's extent along `u` must shrink to the limit, so the end objects move at least
/// `σ = max(0, span − limit)` along `u` in all; across, each object must bring its centroid into a
/// window `[c + lo_i, c + hi_i]` around the common centre line `c`, so the objects move at least
/// `τ = min_c Σ_i dist(v·p_i⁰ − c, [lo_i, hi_i])` across. Since `Σ‖Δ_i‖ ≥ ‖(Σ|Δu_i|, Σ|Δv_i|)‖`, the
/// total push is at least `√(σ² + τ²)`. Used to skip axes that cannot beat the best found.
pub(super) fn lower_bound(problem: &RowProblem<'_>, axis: &Vector2<f64>) -> Option<f64> {
    let k = problem.starts.len();
    let across = Vector2::new(-axis.y, axis.x);
    let widths: f64 = problem
        .outlines
        .iter()
        .map(|o| o.support(axis) + o.support(&-axis))
        .sum();
    if widths + problem.gap * (k.saturating_sub(1)) as f64 > problem.row_limit {
        return None;
    }
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut windows = Vec::with_capacity(k);
    for (start, outline) in problem.starts.iter().zip(problem.outlines) {
        let at = start.coords.dot(axis);
        low = low.min(at - outline.support(&-axis));
        high = high.max(at + outline.support(axis));
        let lo = (problem.straddle - outline.support(&across)).max(-problem.centring);
        let hi = (outline.support(&-across) - problem.straddle).min(problem.centring);
        if lo > hi {
            return None;
        }
        windows.push((start.coords.dot(&across), lo, hi));
    }
    let shrink = (high - low - problem.row_limit).max(0.0);
    // The cost of a centre line is convex and piecewise linear; its minimum is at a breakpoint.
    let cost = |c: f64| -> f64 {
        windows
            .iter()
            .map(|&(v, lo, hi)| {
                let offset = v - c;
                (lo - offset).max(offset - hi).max(0.0)
            })
            .sum()
    };
    let across_bound = windows
        .iter()
        .flat_map(|&(v, lo, hi)| [v - lo, v - hi])
        .map(cost)
        .fold(f64::INFINITY, f64::min);
    Some(shrink.hypot(across_bound))
}

/// Rows of `A x + s = b`, grouped by cone.
struct Rows {
    entries: Vec<(usize, usize, f64)>,
    rhs: Vec<f64>,
}

impl Rows {
    fn new() -> Self {
        Self {
            entries: Vec::new(),
            rhs: Vec::new(),
        }
    }

    /// Adds the row `Σ coefficient·x ≤ bound` (or `= bound`, or the next cone entry `s = bound − a·x`).
    fn push(&mut self, terms: &[(usize, f64)], bound: f64) {
        let row = self.rhs.len();
        for &(column, coefficient) in terms {
            if coefficient != 0.0 {
                self.entries.push((row, column, coefficient));
            }
        }
        self.rhs.push(bound);
    }

    fn len(&self) -> usize {
        self.rhs.len()
    }
}

/// Solves the row program for closing axis `axis` (unit), member `order` along it, with the members in
/// `motion.fixed` held where they are and every other member `i` with `motion.along[i] = Some(n)`
/// moved only within `cone` radians of the unit vector `n` (a flush push on the face of inward
/// normal `n`, [`super::flush`]): `p_i − p_i⁰` between the cone's edges `n₋` and `n₊` (`n` turned
/// by `∓cone`), `n₋⊥·(p_i − p_i⁰) ≥ 0` and `−n₊⊥·(p_i − p_i⁰) ≥ 0`; for `cone = 0`, along `n`
/// only: `n⊥·(p_i − p_i⁰) = 0` and `n·(p_i − p_i⁰) ≥ 0`. The row may span `motion.limit` when
/// given, else the problem's limit.
pub(super) fn solve_row(
    problem: &RowProblem<'_>,
    axis: &Vector2<f64>,
    order: &[usize],
    motion: &Motion,
    cone: f64,
) -> RowSolution {
    let columns = Columns {
        k: problem.starts.len(),
    };
    // Equalities first (zero cone), then inequalities (non-negative cone), then one cone per object.
    let mut zero = Rows::new();
    let mut inequalities = Rows::new();
    held_and_flush_rows(problem, motion, cone, columns, &mut zero, &mut inequalities);
    let row_limit = motion.limit.unwrap_or(problem.row_limit);
    order_rows(problem, axis, order, row_limit, columns, &mut inequalities);
    for i in 0..columns.k {
        object_rows(problem, axis, i, columns, &mut inequalities);
    }
    for fence in problem.fences {
        // normal·p ≥ offset  ⇔  −normal·p ≤ −offset.
        inequalities.push(
            &columns.along(fence.member, &fence.normal, -1.0),
            -fence.offset,
        );
    }
    let mut cones_rows = Rows::new();
    for i in 0..columns.k {
        cones_rows.push(&[(columns.t(i), -1.0)], 0.0);
        cones_rows.push(&[(columns.px(i), -1.0)], -problem.starts[i].x);
        cones_rows.push(&[(columns.py(i), -1.0)], -problem.starts[i].y);
    }
    solve_program(&zero, &inequalities, &cones_rows, columns)
}

/// The program's columns: `p_i = (2i, 2i+1)`, `t_i = 2k + i`, `c = 3k`.
#[derive(Clone, Copy)]
struct Columns {
    k: usize,
}

impl Columns {
    fn px(self, i: usize) -> usize {
        2 * i
    }

    fn py(self, i: usize) -> usize {
        2 * i + 1
    }

    fn t(self, i: usize) -> usize {
        2 * self.k + i
    }

    fn c(self) -> usize {
        3 * self.k
    }

    fn count(self) -> usize {
        3 * self.k + 1
    }

    /// The terms of `scale · d·p_i`.
    fn along(self, i: usize, d: &Vector2<f64>, scale: f64) -> [(usize, f64); 2] {
        [(self.px(i), scale * d.x), (self.py(i), scale * d.y)]
    }
}

/// Members held where they are, and members moved only within a cone about a face's normal.
fn held_and_flush_rows(
    problem: &RowProblem<'_>,
    motion: &Motion,
    cone: f64,
    columns: Columns,
    zero: &mut Rows,
    inequalities: &mut Rows,
) {
    let (fixed, flush) = (&motion.fixed, &motion.along);
    for i in (0..columns.k).filter(|&i| fixed[i]) {
        zero.push(&[(columns.px(i), 1.0)], problem.starts[i].x);
        zero.push(&[(columns.py(i), 1.0)], problem.starts[i].y);
    }
    let left = |d: &Vector2<f64>| Vector2::new(-d.y, d.x);
    for (i, normal) in flush.iter().enumerate() {
        let Some(n) = normal.filter(|_| !fixed[i]) else {
            continue;
        };
        let start = problem.starts[i].coords;
        if cone > 0.0 {
            // Counter-clockwise of n₋ and clockwise of n₊: −n₋⊥·p ≤ −n₋⊥·p⁰, n₊⊥·p ≤ n₊⊥·p⁰.
            let (low, high) = (left(&turned(&n, -cone)), left(&turned(&n, cone)));
            inequalities.push(&columns.along(i, &low, -1.0), -low.dot(&start));
            inequalities.push(&columns.along(i, &high, 1.0), high.dot(&start));
        } else {
            let across = left(&n);
            zero.push(&columns.along(i, &across, 1.0), across.dot(&start));
            inequalities.push(&columns.along(i, &n, -1.0), -n.dot(&start));
        }
    }
}

/// Neighbours in `order` apart by at least the gap, and the whole row within `row_limit`.
fn order_rows(
    problem: &RowProblem<'_>,
    axis: &Vector2<f64>,
    order: &[usize],
    row_limit: f64,
    columns: Columns,
    inequalities: &mut Rows,
) {
    let support = |i: usize, d: &Vector2<f64>| problem.outlines[i].support(d);
    for pair in order.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let needed = support(a, axis) + support(b, &-axis) + problem.gap;
        let mut terms = columns.along(a, axis, 1.0).to_vec();
        terms.extend(columns.along(b, axis, -1.0));
        inequalities.push(&terms, -needed);
    }
    if let (Some(&first), Some(&last)) = (order.first(), order.last()) {
        let limit = row_limit - support(last, axis) - support(first, &-axis);
        let mut terms = columns.along(last, axis, 1.0).to_vec();
        terms.extend(columns.along(first, axis, -1.0));
        inequalities.push(&terms, limit);
    }
}

/// Member `i` between the plates, near their centre line, and inside the workspace.
fn object_rows(
    problem: &RowProblem<'_>,
    axis: &Vector2<f64>,
    i: usize,
    columns: Columns,
    inequalities: &mut Rows,
) {
    let support = |d: &Vector2<f64>| problem.outlines[i].support(d);
    let across = Vector2::new(-axis.y, axis.x);
    let c = columns.c();
    // v·p_i − h_i(−v) ≤ c − s   and   −v·p_i − h_i(v) ≤ −c − s.
    let mut below = columns.along(i, &across, 1.0).to_vec();
    below.push((c, -1.0));
    inequalities.push(&below, support(&-across) - problem.straddle);
    let mut above = columns.along(i, &across, -1.0).to_vec();
    above.push((c, 1.0));
    inequalities.push(&above, support(&across) - problem.straddle);
    // |v·p_i − c| ≤ τ: the centroid near the plates' centre line.
    let mut near = columns.along(i, &across, 1.0).to_vec();
    near.push((c, -1.0));
    inequalities.push(&near, problem.centring);
    let mut near = columns.along(i, &across, -1.0).to_vec();
    near.push((c, 1.0));
    inequalities.push(&near, problem.centring);
    // Workspace: min + h(−e) + k ≤ p ≤ max − h(e) − k on both axes, k the edge margin (or the
    // start's own distance from that edge, if smaller) plus 1 µm, so that neither push error nor
    // the solver's tolerance puts a vertex outside.
    for (dimension, unit) in [(0, Vector2::x()), (1, Vector2::y())] {
        let column = if dimension == 0 {
            columns.px(i)
        } else {
            columns.py(i)
        };
        let start = problem.starts[i][dimension];
        let high = problem.workspace.max[dimension] - support(&unit);
        let low = problem.workspace.min[dimension] + support(&-unit);
        let kept = |room: f64| problem.edge.min(room.max(0.0)) + INSIDE;
        inequalities.push(&[(column, 1.0)], high - kept(high - start));
        inequalities.push(&[(column, -1.0)], -(low + kept(start - low)));
    }
}

/// Minimises `Σ t_i` subject to the three blocks of rows (equalities, inequalities, one
/// second-order cone `t_i ≥ ‖p_i − p_i⁰‖` per member) with Clarabel.
fn solve_program(
    zero: &Rows,
    inequalities: &Rows,
    cones_rows: &Rows,
    columns: Columns,
) -> RowSolution {
    let k = columns.k;
    let (mut rows, mut cols, mut values, mut rhs) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut offset = 0;
    for block in [zero, inequalities, cones_rows] {
        for &(r, col, v) in &block.entries {
            rows.push(offset + r);
            cols.push(col);
            values.push(v);
        }
        rhs.extend_from_slice(&block.rhs);
        offset += block.len();
    }
    let count = columns.count();
    let a = CscMatrix::new_from_triplets(offset, count, rows, cols, values);
    let p = CscMatrix::zeros((count, count));
    let mut q = vec![0.0; count];
    for i in 0..k {
        q[columns.t(i)] = 1.0;
    }
    let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
    if zero.len() > 0 {
        cones.push(SupportedConeT::ZeroConeT(zero.len()));
    }
    cones.push(SupportedConeT::NonnegativeConeT(inequalities.len()));
    for _ in 0..k {
        cones.push(SupportedConeT::SecondOrderConeT(3));
    }
    let settings = DefaultSettings {
        verbose: false,
        max_threads: 1,
        ..DefaultSettings::default()
    };
    let started = std::time::Instant::now();
    let Ok(mut solver) = DefaultSolver::new(&p, &q, &a, &rhs, &cones, settings) else {
        return RowSolution {
            targets: Vec::new(),
            centre_line: 0.0,
            status: SolverStatus::NumericalError,
            iterations: 0,
            seconds: 0.0,
        };
    };
    solver.solve();
    let solution = &solver.solution;
    let status = solution.status;
    let solved = matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved);
    let targets: Vec<Point2<f64>> = if solved {
        (0..k)
            .map(|i| Point2::new(solution.x[columns.px(i)], solution.x[columns.py(i)]))
            .collect()
    } else {
        Vec::new()
    };
    RowSolution {
        targets,
        centre_line: solution.x[columns.c()],
        status,
        iterations: solution.iterations,
        seconds: started.elapsed().as_secs_f64(),
    }
}
