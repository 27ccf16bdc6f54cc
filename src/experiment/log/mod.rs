//! Experiment logs: JSON Lines, one header line then one row per run, in run order.
//!
//! The header describes the log: format, crate version, git commit, machine, the effective
//! configuration and its fingerprint, and the shard. Rows hold every figure of a run; wall-clock
//! measurements are kept in the `timing` object so that everything else is reproducible. A log is
//! always a prefix of its shard's runs in order: an interrupted experiment resumes after its last
//! complete row, and a torn last line is dropped.
//!
//! Reading checks that the log agrees with itself: the header's `config_hash` is its configuration's,
//! `runs` is the number of its shard's runs, and every row is the run its id names (object count,
//! scene seed, policy label, repetition, run seed, swept values) and carried no more objects than its
//! scene held.
//!
//! Here the header and row types; reading and its checks in `read.rs`, writing and the lock that
//! keeps a second process off a log in `write.rs`, the joining of shards in `merge.rs`.

use serde::{Deserialize, Serialize};

use super::config::ExperimentConfig;
use crate::policy::PolicyAbilities;

/// Identifies the log format.
pub const LOG_KIND: &str = "pushmog-experiment-log";
/// Version of the row layout.
pub const LOG_FORMAT: u32 = 1;

/// The first line of a log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogHeader {
    /// Always [`LOG_KIND`].
    pub kind: String,
    /// Always [`LOG_FORMAT`].
    pub format: u32,
    /// pushmog's version.
    pub crate_version: String,
    /// The git commit of the working tree, when known.
    pub git_commit: String,
    /// Host name, cores and operating system.
    pub machine: String,
    /// Fingerprint of the configuration (logs of one configuration can be merged).
    pub config_hash: String,
    /// `[i, n]`: the `i`-th of `n` shards (runs with `id % n == i`); `[0, 1]` for a whole run.
    pub shard: [usize; 2],
    /// Runs in this shard.
    pub runs: usize,
    /// The effective configuration (every default filled in).
    pub config: ExperimentConfig,
    /// What each policy's planners can claim of their answers (can they prove an optimum, do they
    /// stop at a time limit), in the order of `config.policies`; empty in logs written before it
    /// was recorded.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub abilities: Vec<LoggedAbilities>,
}

/// One policy's planners' abilities, by its label.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoggedAbilities {
    /// The policy's label.
    pub policy: String,
    /// Its planners'.
    pub planners: PolicyAbilities,
}

/// Wall-clock measurements of a run, seconds (not reproducible).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RowTiming {
    /// Median planning time per attempt.
    pub planning_median: f64,
    /// 95th percentile of planning time per attempt.
    pub planning_p95: f64,
    /// Median clustering time per attempt (0 for policies that do not cluster).
    pub clustering_median: f64,
    /// Wall-clock time of the whole run (planning and execution).
    pub wall: f64,
    /// CPU time of the whole run on its worker thread (scene, planning, execution), seconds; 0 in
    /// logs written before it was recorded, or where the platform has no thread clock.
    #[serde(default)]
    pub cpu: f64,
}

/// One run's figures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogRow {
    /// Run number.
    pub id: usize,
    /// Object count.
    pub objects: usize,
    /// Scene seed.
    pub scene_seed: u64,
    /// Policy label.
    pub policy: String,
    /// Bin distance of the run's time model, metres.
    pub bin_distance: f64,
    /// Pad and object friction of the simulator, when the configuration sweeps it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// The label of the configuration's sweep variant, when it has variants.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// Repetition.
    pub repetition: usize,
    /// Seed of the run's choices and noise.
    pub run_seed: u64,
    /// `ideal` or `sim`.
    pub executor: String,
    /// Trips made.
    pub trips: usize,
    /// Objects carried to the bin.
    pub carried: usize,
    /// Objects per trip.
    pub objects_per_trip: f64,
    /// Fork pushes made.
    pub pushes: usize,
    /// Total push distance, metres.
    pub push_distance: f64,
    /// Trips that carried nothing.
    pub failed_grasps: usize,
    /// Trips stopped because the gripper came down on an object.
    #[serde(default)]
    pub landings: usize,
    /// Planning attempts that found no grasp.
    pub failed_attempts: usize,
    /// Trips whose clustering was not proven optimal (`Plan::unproven_clusterings`); absent for
    /// policies that do not cluster and in logs written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unproven_clusterings: Option<usize>,
    /// How many push plans whose pushes were made had each status (`Plan::push_statuses`):
    /// `best_found` for the SOCP's search, `time_limit` when its time limit cut one short,
    /// `heuristic` for the paper's pushes. Absent without pushes and in logs written before it was
    /// recorded.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub push_statuses: std::collections::BTreeMap<String, usize>,
    /// Riders put down on rows (`Plan::riders_placed`); absent when none was.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub riders_placed: usize,
    /// Riders put down that their trip did not carry (`Plan::riders_lost`); absent when none was
    /// lost.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub riders_lost: usize,
    /// Trips that took an object from past the workspace's edge (`Plan::trips_past_edge`);
    /// absent when none did.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub trips_past_edge: usize,
    /// Whether the table was cleared.
    pub cleared: bool,
    /// Objects left, and why, when not cleared.
    pub stop_reason: Option<String>,
    /// Objects left on the table.
    pub remaining: usize,
    /// Robot time by the time model, seconds.
    pub robot_seconds: f64,
    /// Objects carried per hour of robot time.
    pub picks_per_hour: f64,
    /// Wall-clock measurements.
    pub timing: RowTiming,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// A log read from disk.
#[derive(Clone, Debug, PartialEq)]
pub struct Log {
    /// Its header.
    pub header: LogHeader,
    /// Its complete rows, in order.
    pub rows: Vec<LogRow>,
}

/// A fingerprint of a configuration: FNV-1a over its canonical JSON.
pub fn config_hash(config: &ExperimentConfig) -> String {
    text_hash(&serde_json::to_string(config).unwrap_or_default())
}

/// The FNV-1a hash of a configuration's compact JSON text, as 16 hex digits.
pub(super) fn text_hash(text: &str) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in text.bytes() {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{hash:016x}")
}

/// The machine, as one line: host name, logical cores, operating system.
pub fn machine_description() -> String {
    let host = std::fs::read_to_string("/etc/hostname")
        .ok()
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown-host".to_string());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!(
        "{host}, {cores} cores, {} {}",
        std::env::consts::OS,
        std::env::consts::ARCH
    )
}

/// The git commit the library was built from, with `-dirty` appended when its code (`src/`,
/// `Cargo.toml`, `Cargo.lock`) differed from that commit, so a log never claims a commit its code did
/// not come from; `unknown` when it was built outside a repository. Recorded at build time
/// (`build.rs`): a binary run from another checkout still names its own.
pub fn git_commit() -> String {
    option_env!("PUSHMOG_GIT_COMMIT")
        .unwrap_or("unknown")
        .to_string()
}

mod merge;
mod read;
mod write;

pub use merge::{merge_logs, merge_logs_into};
pub use read::{LogReader, read_log};
pub use write::{LogLock, LogWriter, write_log};
