//! Writing a log: appending flushed lines, and the lock that keeps a second process off it.

use std::io::Write as _;
use std::path::Path;

use super::{Log, LogHeader, LogRow};
use crate::error::{Error, Result};

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
