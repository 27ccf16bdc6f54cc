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

use std::io::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::config::{ExperimentConfig, RunSpec};
use crate::error::{Error, Result};

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
fn text_hash(text: &str) -> String {
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

/// Reads a log; a torn last line (an interrupted write) is ignored. The rows must be the runs of the
/// header's shard, each once, in order (a duplicated or missing row is refused, naming its line).
///
/// # Errors
/// [`Error::Io`] or [`Error::Json`] for a missing file, a bad header or a bad complete row (with its
/// line number counted from the top of the file); [`Error::InvalidField`] for rows out of sequence.
pub fn read_log(path: &Path) -> Result<Log> {
    let mut reader = LogReader::open(path)?;
    let rows = reader.by_ref().collect::<Result<Vec<_>>>()?;
    Ok(Log {
        header: reader.header,
        rows,
    })
}

/// A log read one row at a time, with the checks of [`read_log`], so that a log of any length is
/// read in constant memory.
pub struct LogReader {
    /// The log's header.
    pub header: LogHeader,
    reader: std::io::BufReader<std::fs::File>,
    name: String,
    /// Rows read so far.
    read: usize,
    done: bool,
    /// The runs of the header's shard, in order.
    runs: Vec<RunSpec>,
}

impl LogReader {
    /// Opens a log and reads its header.
    ///
    /// # Errors
    /// As [`read_log`].
    pub fn open(path: &Path) -> Result<Self> {
        let name = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut reader = std::io::BufReader::new(file);
        let header_line = match next_line(&mut reader, &name, 1)? {
            Some(Line::Complete(text) | Line::Torn(text)) => text,
            None => return Err(Error::field(&name, "header", "the log is empty")),
        };
        let header: LogHeader = crate::json::from_json(&header_line, &name)?;
        if header.kind != LOG_KIND || header.format != LOG_FORMAT {
            return Err(Error::field(
                &name,
                "header",
                format!("not a pushmog log of format {LOG_FORMAT}"),
            ));
        }
        // The hash is of the configuration as it was written (fields added since would change a
        // fresh serialisation): the header's own `config` text, in its order.
        let written = serde_json::from_str::<serde_json::Value>(&header_line)
            .ok()
            .and_then(|v| v.get("config").map(ToString::to_string))
            .unwrap_or_default();
        let runs = header_runs(&header, &text_hash(&written))
            .map_err(|reason| Error::field(&name, "header", reason))?;
        Ok(Self {
            header,
            reader,
            name,
            read: 0,
            done: false,
            runs,
        })
    }

    fn next_row(&mut self) -> Result<Option<LogRow>> {
        let number = self.read + 2;
        let Some(Line::Complete(line)) = next_line(&mut self.reader, &self.name, number)? else {
            return Ok(None); // the end, or a line torn by an interruption
        };
        let row: LogRow = crate::json::from_json(&line, &format!("{}, line {number}", self.name))?;
        let [shard, shards] = self.header.shard;
        let step = shards.max(1);
        let expected = shard + self.read * step;
        if row.id != expected {
            // The rows so far are shard, shard + step, …, expected − step.
            let repeated =
                row.id < expected && row.id >= shard && (row.id - shard).is_multiple_of(step);
            let what = if repeated {
                format!("run {} is logged twice", row.id)
            } else {
                format!("run {} where run {expected} was expected", row.id)
            };
            return Err(Error::field(
                &self.name,
                format!("line {number}"),
                format!(
                    "{what}: the log is damaged; remove that line and what follows, then run again"
                ),
            ));
        }
        if let Err(reason) = self
            .runs
            .get(self.read)
            .ok_or_else(|| {
                format!(
                    "run {} is not one of the header's {} runs",
                    row.id,
                    self.runs.len()
                )
            })
            .and_then(|spec| row_agrees(&row, spec, &self.header.config))
        {
            return Err(Error::field(
                &self.name,
                format!("line {number}"),
                format!("{reason}: the log is damaged or was edited"),
            ));
        }
        self.read += 1;
        Ok(Some(row))
    }
}

/// The runs of a header's shard, once the header agrees with itself.
fn header_runs(header: &LogHeader, expected: &str) -> std::result::Result<Vec<RunSpec>, String> {
    if header.config_hash != expected {
        return Err(format!(
            "config_hash {} is not its configuration's ({expected}): the header was edited",
            header.config_hash
        ));
    }
    header
        .config
        .validate()
        .map_err(|e| format!("its configuration is invalid: {e}"))?;
    let [shard, shards] = header.shard;
    if shards == 0 || shard >= shards {
        return Err(format!("shard {shard} of {shards} does not exist"));
    }
    let runs: Vec<RunSpec> = header
        .config
        .runs()
        .into_iter()
        .filter(|r| r.id % shards == shard)
        .collect();
    if header.runs != runs.len() {
        return Err(format!(
            "runs is {}, but its configuration has {} runs in shard {shard} of {shards}",
            header.runs,
            runs.len()
        ));
    }
    Ok(runs)
}

/// Whether a row is the run `spec` of `config` and its counts are possible.
fn row_agrees(
    row: &LogRow,
    spec: &RunSpec,
    config: &ExperimentConfig,
) -> std::result::Result<(), String> {
    let label = config.policies[spec.policy].label();
    let same = row.objects == spec.objects
        && row.scene_seed == spec.scene_seed
        && row.policy == label
        && row.repetition == spec.repetition
        && row.run_seed == spec.run_seed
        && spec
            .bin_distance
            .is_none_or(|d| d.to_bits() == row.bin_distance.to_bits())
        && row.friction.map(f64::to_bits) == spec.friction.map(f64::to_bits);
    if !same {
        return Err(format!(
            "run {} is not the configuration's run {} ({} objects, scene seed {}, policy {label}, \
             repetition {})",
            row.id, spec.id, spec.objects, spec.scene_seed, spec.repetition
        ));
    }
    if row.carried > row.objects || row.remaining > row.objects {
        return Err(format!(
            "run {} carried {} and left {} of {} objects",
            row.id, row.carried, row.remaining, row.objects
        ));
    }
    Ok(())
}

impl Iterator for LogReader {
    type Item = Result<LogRow>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let next = self.next_row();
        until_end_or_error(&mut self.done, next)
    }
}

/// An item of a row iterator that ends at the last row or at its first error: `next` as an item,
/// setting `done` unless it is a row.
fn until_end_or_error(done: &mut bool, next: Result<Option<LogRow>>) -> Option<Result<LogRow>> {
    let item = next.transpose();
    *done = !matches!(item, Some(Ok(_)));
    item
}

/// One line of a log: complete (ended by a newline, which is dropped) or torn.
enum Line {
    Complete(String),
    Torn(String),
}

fn next_line(
    reader: &mut impl std::io::BufRead,
    name: &str,
    number: usize,
) -> Result<Option<Line>> {
    let mut bytes = Vec::new();
    reader
        .read_until(b'\n', &mut bytes)
        .map_err(|source| Error::Io {
            path: name.into(),
            source,
        })?;
    if bytes.is_empty() {
        return Ok(None);
    }
    let complete = bytes.last() == Some(&b'\n');
    if complete {
        bytes.pop();
    }
    let text = crate::json::text_from_bytes(bytes, &format!("{name}, line {number}"))?;
    Ok(Some(if complete {
        Line::Complete(text)
    } else {
        Line::Torn(text)
    }))
}

/// Appends lines to a log, flushing each so an interruption loses at most the line being written.
pub struct LogWriter {
    file: std::fs::File,
    path: std::path::PathBuf,
}

impl LogWriter {
    /// Starts a new log with `header`.
    ///
    /// # Errors
    /// [`Error::Io`].
    pub fn create(path: &Path, header: &LogHeader) -> Result<Self> {
        crate::json::write_text(path, "")?;
        let mut writer = Self::append(path)?;
        // The header and its newline in one write, flushed before any row.
        writer.line(&serde_json::to_string(header).unwrap_or_default())?;
        Ok(writer)
    }

    /// Continues an existing log after its last complete line (a torn line is cut off).
    ///
    /// # Errors
    /// [`Error::Io`].
    pub fn append(path: &Path) -> Result<Self> {
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        let text = std::fs::read_to_string(path).map_err(io)?;
        let complete = text.rfind('\n').map_or(0, |k| k + 1);
        // A header written without its newline is complete all the same: finish it rather than cut.
        let header_only = complete == 0 && serde_json::from_str::<LogHeader>(&text).is_ok();
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(io)?;
        if !header_only {
            file.set_len(complete as u64).map_err(io)?;
        }
        let mut file = file;
        use std::io::Seek as _;
        file.seek(std::io::SeekFrom::End(0)).map_err(io)?;
        if header_only {
            file.write_all(b"\n").map_err(io)?;
        }
        Ok(Self {
            file,
            path: path.to_path_buf(),
        })
    }

    /// Writes a row.
    ///
    /// # Errors
    /// [`Error::Io`].
    pub fn row(&mut self, row: &LogRow) -> Result<()> {
        self.line(&serde_json::to_string(row).unwrap_or_default())
    }

    fn line(&mut self, text: &str) -> Result<()> {
        let io = |source| Error::Io {
            path: self.path.clone(),
            source,
        };
        let mut line = String::with_capacity(text.len() + 1);
        line.push_str(text);
        line.push('\n');
        self.file.write_all(line.as_bytes()).map_err(io)?;
        self.file.flush().map_err(io)
    }
}

/// An exclusive lock on a log for as long as it lives, so that two `pushmog experiment` processes
/// never write one log. The operating system releases it when the process ends, however it ends.
pub struct LogLock {
    _file: std::fs::File,
}

impl LogLock {
    /// Locks `path` (creating an empty file when there is none).
    ///
    /// # Errors
    /// [`Error::Busy`] when another process holds the lock; [`Error::Io`].
    pub fn acquire(path: &Path) -> Result<Self> {
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(io)?;
        }
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .read(true)
            .write(true)
            .open(path)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => Ok(Self { _file: file }),
            Err(std::fs::TryLockError::WouldBlock) => Err(Error::Busy {
                path: path.to_path_buf(),
                reason: "another `pushmog experiment` is writing this log: wait for it to finish, \
                         or give another --log"
                    .into(),
            }),
            Err(std::fs::TryLockError::Error(source)) => Err(io(source)),
        }
    }
}

/// Joins the logs of the shards of one configuration into one log, rows in run order.
///
/// # Errors
/// [`Error::InvalidField`] when the logs come from different configurations or a run appears twice
/// with different figures; [`Error::Io`] and [`Error::Json`] from reading.
pub fn merge_logs(paths: &[&Path]) -> Result<Log> {
    let mut merged = MergedRows::open(paths)?;
    let rows = merged.by_ref().collect::<Result<Vec<_>>>()?;
    Ok(Log {
        header: merged.header,
        rows,
    })
}

/// As [`merge_logs`], writing the merged log to `output` row by row (a log of any length is merged
/// in constant memory). Returns the header written and the number of rows.
///
/// # Errors
/// As [`merge_logs`], and [`Error::Io`] from writing.
pub fn merge_logs_into(paths: &[&Path], output: &Path) -> Result<(LogHeader, usize)> {
    let mut merged = MergedRows::open(paths)?;
    let mut writer = LogWriter::create(output, &merged.header)?;
    let mut count = 0;
    for row in merged.by_ref() {
        writer.row(&row?)?;
        count += 1;
    }
    Ok((merged.header, count))
}

/// The rows of several shard logs in run order: each log is in run order, so the next row is the
/// smallest next row of any log. A run logged by two shards must have the same figures in both.
struct MergedRows {
    header: LogHeader,
    logs: Vec<(LogReader, Option<LogRow>)>,
    done: bool,
}

impl MergedRows {
    fn open(paths: &[&Path]) -> Result<Self> {
        let mut logs = Vec::with_capacity(paths.len());
        for path in paths {
            let mut reader = LogReader::open(path)?;
            let first = reader.next().transpose()?;
            logs.push((reader, first));
        }
        let Some((first, _)) = logs.first() else {
            return Err(Error::field("merge", "logs", "no logs given"));
        };
        let mut header = first.header.clone();
        for ((log, _), path) in logs.iter().zip(paths) {
            if log.header.config_hash != header.config_hash {
                return Err(Error::field(
                    path.display().to_string(),
                    "config_hash",
                    "written by a different configuration than the first log",
                ));
            }
        }
        header.shard = [0, 1];
        header.runs = header.config.runs().len();
        Ok(Self {
            header,
            logs,
            done: false,
        })
    }

    fn next_row(&mut self) -> Result<Option<LogRow>> {
        let Some(id) = self
            .logs
            .iter()
            .filter_map(|(_, next)| next.as_ref().map(|r| r.id))
            .min()
        else {
            return Ok(None);
        };
        let mut taken: Option<LogRow> = None;
        for (reader, next) in &mut self.logs {
            if next.as_ref().map(|r| r.id) != Some(id) {
                continue;
            }
            let row = std::mem::replace(next, reader.next().transpose()?);
            let Some(row) = row else { continue };
            match &taken {
                None => taken = Some(row),
                Some(first) => {
                    let (mut a, mut b) = (first.clone(), row);
                    a.timing = RowTiming::default();
                    b.timing = RowTiming::default();
                    if a != b {
                        return Err(Error::field(
                            "merge",
                            "rows",
                            format!("run {id} appears twice with different figures"),
                        ));
                    }
                }
            }
        }
        Ok(taken)
    }
}

impl Iterator for MergedRows {
    type Item = Result<LogRow>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let next = self.next_row();
        until_end_or_error(&mut self.done, next)
    }
}

/// Writes a whole log.
///
/// # Errors
/// [`Error::Io`].
pub fn write_log(path: &Path, log: &Log) -> Result<()> {
    let mut writer = LogWriter::create(path, &log.header)?;
    for row in &log.rows {
        writer.row(row)?;
    }
    Ok(())
}
