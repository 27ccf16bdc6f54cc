//! Reading a log: the header checked against its configuration, rows checked one by one against
//! the runs they name, a torn last line dropped.

use std::path::Path;

use super::{LOG_FORMAT, LOG_KIND, Log, LogHeader, LogRow, text_hash};
use crate::error::{Error, Result};
use crate::experiment::config::{ExperimentConfig, RunSpec};

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
        && row.friction.map(f64::to_bits) == spec.friction.map(f64::to_bits)
        && row.variant.as_deref()
            == spec
                .variant
                .map(|v| config.sweep.variants[v].label.as_str());
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
pub(super) fn until_end_or_error(
    done: &mut bool,
    next: Result<Option<LogRow>>,
) -> Option<Result<LogRow>> {
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
