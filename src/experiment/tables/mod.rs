//! Tables built only from logs: per policy (and object count, and bin distance), the figures a paper
//! reports, in Markdown, CSV and LaTeX. Wall-clock columns go to separate timing tables, so the result
//! tables of one configuration and seed are byte-identical from run to run.

use super::log::{Log, LogRow};
use super::runner::quantile;
use crate::stats::{mean, mean_std, t_95};

mod csv_lines;
pub(super) mod table;

use table::tex;
pub use table::{Cell, Column, Table};

pub use csv_lines::{results_csv, timing_csv};

/// The Push-MOG paper's physical results (UR5 + 2F-85, 5 scenes of 34 objects, bin adjacent): objects
/// per trip, mean and standard deviation, by the policy they correspond to.
pub const PAPER_OPT: [(&str, f64, f64); 3] = [
    ("sog", 0.993, 0.014),
    ("mog", 0.986, 0.038),
    ("push-mog", 1.339, 0.145),
];

/// The figures of one group of runs.
#[derive(Clone, Debug, PartialEq)]
pub struct GroupSummary {
    /// Policy label.
    pub policy: String,
    /// Object count.
    pub objects: usize,
    /// Bin distance, metres.
    pub bin_distance: f64,
    /// The simulator's pad and object friction, when swept.
    pub friction: Option<f64>,
    /// The sweep variant's label, when the configuration has variants.
    pub variant: Option<String>,
    /// Runs in the group.
    pub runs: usize,
    /// Objects per trip: mean and sample standard deviation over runs.
    pub opt: (f64, f64),
    /// Mean trips.
    pub trips: f64,
    /// Mean pushes.
    pub pushes: f64,
    /// Mean total push distance, metres.
    pub push_distance: f64,
    /// Mean failed grasps.
    pub failed_grasps: f64,
    /// Mean trips stopped by the gripper coming down on an object.
    pub landings: f64,
    /// Riders put down on rows, over all runs.
    pub riders_placed: usize,
    /// Of those, riders their trip did not carry.
    pub riders_lost: usize,
    /// Runs that cleared the table.
    pub cleared: usize,
    /// Mean robot time, seconds.
    pub robot_seconds: f64,
    /// Mean picks per hour.
    pub picks_per_hour: f64,
    /// Half-width of the 95 % interval of the mean picks per hour (Student's t).
    pub picks_per_hour_95: f64,
    /// Picks per hour as a ratio to sog's on the same scenes (same scene seed and repetition, the
    /// same object count, bin distance, friction and variant): the mean of the per-scene ratios and the
    /// half-width of its 95 % interval. `None` for sog itself, or when the log has no sog run of
    /// those scenes.
    pub versus_sog: Option<(f64, f64)>,
    /// Median over runs of the median planning time, seconds (wall-clock).
    pub planning_median: f64,
    /// 95th percentile over runs of the 95th-percentile planning time, seconds (wall-clock).
    pub planning_p95: f64,
    /// Median over runs of the median clustering time, seconds (wall-clock).
    pub clustering_median: f64,
    /// Median over runs of a run's CPU time, seconds.
    pub cpu_median: f64,
}

/// The bits of a row's swept friction, for grouping (`u64::MAX` when not swept).
fn friction_key(friction: Option<f64>) -> u64 {
    friction.map_or(u64::MAX, f64::to_bits)
}

/// A row's sweep variant as its position in the configuration (`usize::MAX` when it has none, one
/// past the last for a label the configuration does not name).
fn variant_key(log: &Log, row: &LogRow) -> usize {
    let variants = &log.header.config.sweep.variants;
    row.variant.as_ref().map_or(usize::MAX, |label| {
        variants
            .iter()
            .position(|v| v.label == *label)
            .unwrap_or(variants.len())
    })
}

/// Groups rows by object count, bin distance, friction, variant and policy, in the
/// configuration's order.
pub fn summarise(log: &Log) -> Vec<GroupSummary> {
    let order: Vec<String> = log
        .header
        .config
        .policies
        .iter()
        .map(|p| p.label())
        .collect();
    let mut keys: Vec<(usize, u64, u64, usize, usize)> = Vec::new();
    for row in &log.rows {
        let policy = order
            .iter()
            .position(|p| *p == row.policy)
            .unwrap_or(order.len());
        let key = (
            row.objects,
            row.bin_distance.to_bits(),
            friction_key(row.friction),
            variant_key(log, row),
            policy,
        );
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.sort_by(|a, b| {
        a.0.cmp(&b.0)
            .then(f64::from_bits(a.1).total_cmp(&f64::from_bits(b.1)))
            .then(f64::from_bits(a.2).total_cmp(&f64::from_bits(b.2)))
            .then(a.3.cmp(&b.3))
            .then(a.4.cmp(&b.4))
    });
    keys.into_iter()
        .map(|(objects, bin, friction, variant, policy)| {
            let label = order.get(policy).cloned().unwrap_or_default();
            let rows: Vec<&LogRow> = log
                .rows
                .iter()
                .filter(|r| {
                    r.objects == objects
                        && r.bin_distance.to_bits() == bin
                        && friction_key(r.friction) == friction
                        && variant_key(log, r) == variant
                        && r.policy == label
                })
                .collect();
            let opt: Vec<f64> = rows.iter().map(|r| r.objects_per_trip).collect();
            let medians: Vec<f64> = rows.iter().map(|r| r.timing.planning_median).collect();
            let p95s: Vec<f64> = rows.iter().map(|r| r.timing.planning_p95).collect();
            let clustering: Vec<f64> = rows.iter().map(|r| r.timing.clustering_median).collect();
            let cpu: Vec<f64> = rows.iter().map(|r| r.timing.cpu).collect();
            let picks: Vec<f64> = rows.iter().map(|r| r.picks_per_hour).collect();
            let versus_sog = (label != "sog")
                .then(|| paired_with_sog(log, &rows))
                .flatten();
            GroupSummary {
                policy: label,
                objects,
                bin_distance: f64::from_bits(bin),
                friction: (friction != u64::MAX).then(|| f64::from_bits(friction)),
                variant: rows.first().and_then(|r| r.variant.clone()),
                runs: rows.len(),
                opt: mean_std(&opt),
                trips: mean(rows.iter().map(|r| r.trips as f64)),
                pushes: mean(rows.iter().map(|r| r.pushes as f64)),
                push_distance: mean(rows.iter().map(|r| r.push_distance)),
                failed_grasps: mean(rows.iter().map(|r| r.failed_grasps as f64)),
                landings: mean(rows.iter().map(|r| r.landings as f64)),
                riders_placed: rows.iter().map(|r| r.riders_placed).sum(),
                riders_lost: rows.iter().map(|r| r.riders_lost).sum(),
                cleared: rows.iter().filter(|r| r.cleared).count(),
                robot_seconds: mean(rows.iter().map(|r| r.robot_seconds)),
                picks_per_hour: mean(picks.iter().copied()),
                picks_per_hour_95: interval_95(&picks),
                planning_median: quantile(&medians, 0.5),
                planning_p95: quantile(&p95s, 0.95),
                clustering_median: quantile(&clustering, 0.5),
                cpu_median: quantile(&cpu, 0.5),
                versus_sog,
            }
        })
        .collect()
}

/// Half-width of the 95 % interval of the mean of `values` (Student's t); 0 for fewer than two.
fn interval_95(values: &[f64]) -> f64 {
    if values.len() < 2 {
        return 0.0;
    }
    t_95(values.len()) * mean_std(values).1 / (values.len() as f64).sqrt()
}

/// The mean and 95 % half-width of `rows`' picks per hour divided by sog's on the same scene
/// (scene seed, repetition, object count, bin distance, friction and variant); `None` when no row has a sog
/// partner in `log`.
fn paired_with_sog(log: &Log, rows: &[&LogRow]) -> Option<(f64, f64)> {
    let ratios: Vec<f64> = rows
        .iter()
        .filter_map(|row| {
            let sog = log.rows.iter().find(|r| {
                r.policy == "sog"
                    && r.scene_seed == row.scene_seed
                    && r.repetition == row.repetition
                    && r.objects == row.objects
                    && r.bin_distance.to_bits() == row.bin_distance.to_bits()
                    && friction_key(r.friction) == friction_key(row.friction)
                    && r.variant == row.variant
            })?;
            (sog.picks_per_hour > 0.0).then(|| row.picks_per_hour / sog.picks_per_hour)
        })
        .collect();
    (!ratios.is_empty()).then(|| (mean(ratios.iter().copied()), interval_95(&ratios)))
}

/// The paper's figure for a group, when the group matches the paper's setup (34 objects, the bin
/// beside the workspace: the default time model's 0.3 m; no sweep variant, which changes the cell).
fn paper_reference(group: &GroupSummary) -> Option<(f64, f64)> {
    let adjacent = crate::time_model::TimeModel::default().bin_distance;
    if group.objects != 34
        || (group.bin_distance - adjacent).abs() > 1e-9
        || group.variant.is_some()
    {
        return None;
    }
    PAPER_OPT
        .iter()
        .find(|(name, _, _)| *name == group.policy)
        .map(|&(_, m, s)| (m, s))
}

/// Which keys differ between the groups (those columns are shown).
#[derive(Clone, Copy, Debug)]
struct Varies {
    objects: bool,
    bin: bool,
    friction: bool,
    variant: bool,
}

fn varies(groups: &[GroupSummary]) -> Varies {
    let first = groups.first();
    Varies {
        objects: groups
            .iter()
            .any(|g| Some(g.objects) != first.map(|f| f.objects)),
        bin: groups
            .iter()
            .any(|g| Some(g.bin_distance.to_bits()) != first.map(|f| f.bin_distance.to_bits())),
        friction: groups.iter().any(|g| g.friction.is_some()),
        variant: groups.iter().any(|g| g.variant.is_some()),
    }
}

/// The columns after the policy that tell groups apart: the object count, the bin distance, the
/// friction and the sweep variant, each only when it varies in the log.
fn key_columns(by: Varies) -> Vec<Column> {
    let mut columns = Vec::new();
    if by.objects {
        columns.push(Column::markdown("objects", 0).latex("Objects", 'r', 0));
    }
    if by.bin {
        columns.push(Column::markdown("bin distance (m)", 2).latex("Bin (m)", 'r', 2));
    }
    if by.friction {
        columns.push(Column::markdown("friction", 2).latex("$\\mu$", 'r', 2));
    }
    if by.variant {
        columns.push(
            Column::markdown("variant", 0)
                .left()
                .latex("Variant", 'l', 0),
        );
    }
    columns
}

/// A group's cells of [`key_columns`].
fn key_cells(group: &GroupSummary, by: Varies) -> Vec<Cell> {
    let mut cells = Vec::new();
    if by.objects {
        cells.push(Cell::Number(group.objects as f64));
    }
    if by.bin {
        cells.push(Cell::Number(group.bin_distance));
    }
    if by.friction {
        cells.push(group.friction.map_or(Cell::Missing, Cell::Number));
    }
    if by.variant {
        cells.push(group.variant.clone().map_or(Cell::Missing, Cell::Text));
    }
    cells
}

/// The results table, declared once for Markdown and LaTeX (LaTeX shows fewer columns).
fn results_table(log: &Log) -> Table {
    let groups = summarise(log);
    let by = varies(&groups);
    let mut columns = vec![Column::markdown("policy", 0).left().latex("Policy", 'l', 0)];
    columns.extend(key_columns(by));
    columns.extend([
        Column::markdown("runs", 0),
        Column::markdown("objects per trip", 3)
            .left()
            .latex("OpT", 'c', 3),
        Column::markdown("paper, physical UR5", 3)
            .left()
            .latex("Paper (UR5)", 'c', 3),
        Column::markdown("trips", 1).latex("Trips", 'c', 1),
        Column::markdown("pushes", 1).latex("Pushes", 'r', 1),
        Column::markdown("push distance (m)", 3),
        Column::markdown("failed grasps", 2),
        Column::markdown("landings", 2),
        Column::markdown("cleared", 0),
    ]);
    // Riders only where some run placed one, so tables of logs without riders stay as they were.
    let riders = groups.iter().any(|g| g.riders_placed > 0);
    if riders {
        columns.push(Column::markdown("riders lost / placed", 0).latex("Riders lost", 'r', 0));
    }
    columns.extend([
        Column::markdown("robot time (s)", 1).latex("Time (s)", 'r', 0),
        Column::markdown("picks per hour", 1).latex("Picks/h", 'r', 0),
        Column::markdown("picks per hour / sog's, paired", 3).latex("vs.\\ sog", 'r', 3),
    ]);
    let interval =
        |value: Option<(f64, f64)>| value.map_or(Cell::Missing, |(m, h)| Cell::Interval(m, h));
    let rows = groups
        .iter()
        .map(|g| {
            let mut cells = vec![Cell::Text(g.policy.clone())];
            cells.extend(key_cells(g, by));
            cells.extend([
                Cell::Number(g.runs as f64),
                Cell::Interval(g.opt.0, g.opt.1),
                interval(paper_reference(g)),
                Cell::Number(g.trips),
                Cell::Number(g.pushes),
                Cell::Number(g.push_distance),
                Cell::Number(g.failed_grasps),
                Cell::Number(g.landings),
                Cell::Count(g.cleared, g.runs),
            ]);
            if riders {
                cells.push(if g.riders_placed > 0 {
                    Cell::Count(g.riders_lost, g.riders_placed)
                } else {
                    Cell::Missing
                });
            }
            cells.extend([
                Cell::Number(g.robot_seconds),
                Cell::Interval(g.picks_per_hour, g.picks_per_hour_95),
                interval(g.versus_sog),
            ]);
            cells
        })
        .collect();
    Table { columns, rows }
}

/// The results table in Markdown (no wall-clock columns).
pub fn results_markdown(log: &Log) -> String {
    format!(
        "{} — {} executor, {} runs\n\n{}",
        log.header.config.name,
        executor_name(log),
        log.rows.len(),
        results_table(log).markdown()
    )
}

fn executor_name(log: &Log) -> &'static str {
    log.header.config.executor.kind.name()
}

/// The wall-clock table in Markdown (planning and clustering times; machine-dependent).
pub fn timing_markdown(log: &Log) -> String {
    let groups = summarise(log);
    let by = varies(&groups);
    let mut columns = vec![
        Column::markdown("policy", 0).left(),
        Column::markdown("objects", 0),
        Column::markdown("bin distance (m)", 2),
    ];
    if by.friction {
        columns.push(Column::markdown("friction", 2));
    }
    if by.variant {
        columns.push(Column::markdown("variant", 0).left());
    }
    columns.extend([
        Column::markdown("planning median (ms)", 3),
        Column::markdown("planning p95 (ms)", 3),
        Column::markdown("clustering median (ms)", 3),
        Column::markdown("CPU per run, median (s)", 2),
    ]);
    let rows = groups
        .iter()
        .map(|g| {
            let mut cells = vec![
                Cell::Text(g.policy.clone()),
                Cell::Number(g.objects as f64),
                Cell::Number(g.bin_distance),
            ];
            if by.friction {
                cells.push(g.friction.map_or(Cell::Missing, Cell::Number));
            }
            if by.variant {
                cells.push(g.variant.clone().map_or(Cell::Missing, Cell::Text));
            }
            cells.extend([
                Cell::Number(g.planning_median * 1e3),
                Cell::Number(g.planning_p95 * 1e3),
                Cell::Number(g.clustering_median * 1e3),
                cpu_cell(g.cpu_median),
            ]);
            cells
        })
        .collect();
    format!(
        "{} — planning times on {} (wall-clock, not reproducible)\n\n{}",
        log.header.config.name,
        log.header.machine,
        Table { columns, rows }.markdown()
    )
}

/// A CPU time in seconds, or missing when the log did not record it (0).
fn cpu_cell(seconds: f64) -> Cell {
    if seconds > 0.0 {
        Cell::Number(seconds)
    } else {
        Cell::Missing
    }
}

/// The results as a LaTeX table body (booktabs), to `\\input` in a `table` environment.
pub fn results_latex(log: &Log) -> String {
    let table = results_table(log);
    format!(
        "% Generated by `pushmog experiment` from {}; do not edit.\n\\begin{{tabular}}{{{}}}\n\\toprule\n{}\\bottomrule\n\\end{{tabular}}\n",
        tex(&log.header.config.name),
        table.latex_columns(),
        table.latex_body()
    )
}
