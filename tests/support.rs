//! Shared helpers: fixture paths and running the command-line binary.

use std::path::PathBuf;
use std::process::{Command, Output};

/// Path of a file under `tests/fixtures`.
pub fn fixture(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(relative)
}

/// Runs the `pushmog` binary with `args`.
pub fn pushmog(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pushmog"))
        .args(args)
        .output()
        .expect("the pushmog binary runs")
}

/// A fresh empty folder under the target directory for one test's files.
pub fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
