//! Running an experiment: runs in parallel (rayon), rows written in run order, resumable, shardable,
//! with a progress bar and an estimate of the time left.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use super::config::{ExperimentConfig, RunSpec};
use super::log::{
    LOG_FORMAT, LOG_KIND, LogHeader, LogLock, LogRow, LogWriter, LoggedAbilities, RowTiming,
    config_hash, git_commit, machine_description, read_log,
};
use crate::error::{Error, Result};
use crate::plan::{Plan, RunStatus};
use crate::scene::{ObjectSet, generate_scene};

/// Most worker threads per core: runs are CPU-bound, so more threads only add memory.
pub const MAX_JOBS_PER_CORE: usize = 4;

/// How to run an experiment.
#[derive(Clone, Debug)]
pub struct RunnerOptions {
    /// The log to write (and resume).
    pub log: PathBuf,
    /// `(i, n)`: run only the runs with `id % n == i`.
    pub shard: (usize, usize),
    /// Worker threads (0: one per core; at most [`MAX_JOBS_PER_CORE`] per core).
    pub jobs: usize,
    /// Show a progress bar on standard error.
    pub progress: bool,
    /// Stop after this many new runs (to interrupt on purpose, e.g. in tests).
    pub limit: Option<usize>,
    /// Where to save the plan of the first run, for drawing.
    pub example_plan: Option<PathBuf>,
}

/// What each policy's planners can claim, as its settings (before any sweep) build it.
fn abilities(config: &ExperimentConfig) -> Result<Vec<LoggedAbilities>> {
    config
        .policies
        .iter()
        .enumerate()
        .map(|(k, entry)| {
            let policy = entry.policy(config.policy_settings(k, None, None)?)?;
            Ok(LoggedAbilities {
                policy: entry.label(),
                planners: policy.abilities(),
            })
        })
        .collect()
}

/// Runs one experiment run.
///
/// # Errors
/// Invalid settings or an executor fault.
pub fn run_one(
    config: &ExperimentConfig,
    set: &ObjectSet,
    spec: &RunSpec,
) -> Result<(LogRow, Plan)> {
    let started = Instant::now();
    let cpu_started = cpu_time::ThreadTime::try_now().ok();
    let scene = generate_scene(&config.generator(spec.objects), set, spec.scene_seed)?;
    let settings = config.policy_settings(spec.policy, spec.bin_distance, spec.variant)?;
    let bin_distance = settings.time_model.bin_distance;
    let policy = config.policies[spec.policy].policy(settings)?;
    // The simulator's seed follows the run seed as in `pushmog run --seed` and Python's
    // `Planner.run`, so any logged run can be replayed there with its `run_seed`.
    let mut executor = config.executor.kind.build(
        policy.problem(),
        config.sim_settings(spec.friction, spec.variant)?,
        spec.run_seed,
    )?;
    let (plan, timing) = policy.run_timed(&scene, executor.as_mut(), spec.run_seed)?;
    let (cleared, stop_reason, remaining) = match &plan.status {
        RunStatus::Cleared => (true, None, 0),
        RunStatus::Stopped { remaining, reason } => {
            (false, Some(reason.to_string()), remaining.len())
        }
    };
    let row = LogRow {
        id: spec.id,
        objects: spec.objects,
        scene_seed: spec.scene_seed,
        policy: config.policies[spec.policy].label(),
        bin_distance,
        friction: spec.friction,
        variant: spec.variant.map(|v| config.sweep.variants[v].label.clone()),
        repetition: spec.repetition,
        run_seed: spec.run_seed,
        executor: executor.name().to_string(),
        trips: plan.trips.len(),
        carried: plan.objects_carried(),
        objects_per_trip: plan.objects_per_trip(),
        pushes: plan.push_count(),
        push_distance: plan.push_distance(),
        failed_grasps: plan.failed_grasps(),
        landings: plan.landings(),
        failed_attempts: plan.failed_attempts.len(),
        unproven_clusterings: plan.unproven_clusterings(),
        push_statuses: plan.push_statuses(),
        riders_placed: plan.riders_placed(),
        riders_lost: plan.riders_lost(),
        trips_past_edge: plan.trips_past_edge(),
        cleared,
        stop_reason,
        remaining,
        robot_seconds: plan.seconds,
        picks_per_hour: plan.picks_per_hour(),
        timing: RowTiming {
            planning_median: quantile(&timing.planning, 0.5),
            planning_p95: quantile(&timing.planning, 0.95),
            clustering_median: quantile(&timing.clustering, 0.5),
            wall: started.elapsed().as_secs_f64(),
            cpu: cpu_started
                .and_then(|t| t.try_elapsed().ok())
                .map_or(0.0, |d| d.as_secs_f64()),
        },
    };
    Ok((row, plan))
}

/// A quantile by nearest rank; 0 for no values.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    crate::stats::quantile(values, q).unwrap_or(0.0)
}

/// What [`run_experiment`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct RunReport {
    /// Runs in the shard.
    pub total: usize,
    /// Runs already in the log when it started.
    pub resumed: usize,
    /// Runs made now.
    pub made: usize,
}

/// Runs the configuration's runs of this shard that the log does not hold yet.
///
/// # Errors
/// [`Error::InvalidField`] when the log belongs to another configuration or shard; run errors.
pub fn run_experiment(
    config: &ExperimentConfig,
    config_dir: &Path,
    options: &RunnerOptions,
) -> Result<RunReport> {
    let (shard, shards) = options.check()?;
    let set = config.object_set(config_dir)?;
    let runs: Vec<RunSpec> = config
        .runs()
        .into_iter()
        .filter(|r| r.id % shards == shard)
        .collect();
    // Held until the run ends: a second process on this log is refused here.
    let _lock = LogLock::acquire(&options.log)?;
    let (mut writer, done) = open_log(config, options, &runs)?;
    let pending: Vec<RunSpec> = runs
        .iter()
        .skip(done)
        .take(options.limit.unwrap_or(usize::MAX))
        .cloned()
        .collect();
    let bar = progress_bar(options.progress, &config.name, runs.len(), done);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs)
        .build()
        .map_err(|e| Error::field("experiment", "--jobs", e.to_string()))?;
    let (sender, receiver) = mpsc::channel::<(usize, Result<(LogRow, Plan)>)>();
    let mut made = 0;
    let mut first_error: Option<Error> = None;
    std::thread::scope(|scope| -> Result<()> {
        let set = &set;
        let pending = &pending;
        scope.spawn(move || {
            pool.install(|| {
                pending
                    .par_iter()
                    .enumerate()
                    .for_each_with(sender, |tx, (k, spec)| {
                        let _ = tx.send((k, run_one(config, set, spec)));
                    });
            });
        });
        // Write rows in run order as they complete.
        let mut waiting: BTreeMap<usize, Result<(LogRow, Plan)>> = BTreeMap::new();
        let mut next = 0;
        for (k, result) in receiver {
            waiting.insert(k, result);
            while let Some(result) = waiting.remove(&next) {
                next += 1;
                match result {
                    Ok((row, plan)) => {
                        if first_error.is_none() {
                            writer.row(&row)?;
                            made += 1;
                            if row.id == 0
                                && let Some(path) = &options.example_plan
                            {
                                crate::json::write_text(path, &plan.to_json())?;
                            }
                        }
                    }
                    Err(e) => {
                        first_error.get_or_insert(e);
                    }
                }
                bar.inc(1);
            }
        }
        Ok(())
    })?;
    bar.finish_and_clear();
    if let Some(e) = first_error {
        return Err(e);
    }
    Ok(RunReport {
        total: runs.len(),
        resumed: done,
        made,
    })
}

impl RunnerOptions {
    /// The shard `(i, n)`, once the shard exists and the worker threads are not too many for this
    /// machine.
    fn check(&self) -> Result<(usize, usize)> {
        let (shard, shards) = self.shard;
        if shards == 0 || shard >= shards {
            return Err(Error::field(
                "experiment",
                "--shard",
                format!("shard {shard}/{shards} does not exist: use i/n with 0 ≤ i < n"),
            ));
        }
        let cores = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
        if self.jobs > MAX_JOBS_PER_CORE * cores {
            return Err(Error::field(
                "experiment",
                "--jobs",
                format!(
                    "at most {} worker threads on this machine ({MAX_JOBS_PER_CORE} per core; runs \
                     are CPU-bound), got {}",
                    MAX_JOBS_PER_CORE * cores,
                    self.jobs
                ),
            ));
        }
        Ok((shard, shards))
    }
}

/// The log to write `runs` (this shard's) to, and how many of them it already holds: a new log
/// with its header, or an existing one of the same configuration and shard whose rows are these
/// runs' first ones, in order, appended to.
fn open_log(
    config: &ExperimentConfig,
    options: &RunnerOptions,
    runs: &[RunSpec],
) -> Result<(LogWriter, usize)> {
    let (shard, shards) = options.shard;
    let hash = config_hash(config);
    let fresh = std::fs::metadata(&options.log).map_or(true, |m| m.len() == 0);
    if fresh {
        let header = LogHeader {
            kind: LOG_KIND.to_string(),
            format: LOG_FORMAT,
            crate_version: env!("CARGO_PKG_VERSION").to_string(),
            git_commit: git_commit(),
            machine: machine_description(),
            config_hash: hash,
            shard: [shard, shards],
            runs: runs.len(),
            config: config.clone(),
            abilities: abilities(config)?,
        };
        return Ok((LogWriter::create(&options.log, &header)?, 0));
    }
    let log = read_log(&options.log)?;
    if log.header.config_hash != hash || log.header.shard != [shard, shards] {
        return Err(Error::field(
            options.log.display().to_string(),
            "header",
            "this log was written by another configuration or shard; remove it or choose another output",
        ));
    }
    for (row, spec) in log.rows.iter().zip(runs) {
        if row.id != spec.id {
            return Err(Error::field(
                options.log.display().to_string(),
                "rows",
                format!("row {} is out of order (run {} expected)", row.id, spec.id),
            ));
        }
    }
    Ok((LogWriter::append(&options.log)?, log.rows.len()))
}

/// A progress bar over `total` runs, `done` of them already logged (hidden without `progress`).
fn progress_bar(progress: bool, name: &str, total: usize, done: usize) -> ProgressBar {
    if !progress {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(total as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{prefix} [{bar:30}] {pos}/{len} runs, {elapsed} spent, about {eta} left",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_prefix(name.to_string());
    bar.set_position(done as u64);
    bar.reset_eta();
    bar
}
