//! Joining the logs of the shards of one configuration, rows in run order.

use std::path::Path;

use super::read::until_end_or_error;
use super::{Log, LogHeader, LogReader, LogRow, LogWriter, RowTiming};
use crate::error::{Error, Result};

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
