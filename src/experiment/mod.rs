//! Experiments: every number the users publish comes from one command and a seed.
//!
//! `pushmog experiment experiments/<name>.toml` expands a configuration ([`ExperimentConfig`]) into a
//! numbered list of runs, carries them out in parallel, appends one JSON Lines row per run to a log
//! after a header describing the configuration, the code and the machine ([`log`]), and then builds
//! tables ([`tables`]) and figures ([`figures`]) from the log alone. Logs resume after interruption,
//! split into shards for batch schedulers, and merge back (`pushmog merge`). The log format is
//! described in `experiments/README.md`.

pub mod agreement;
pub mod break_even;
mod cluster_comparison;
mod config;
pub mod figures;
pub mod log;
mod preset_names;
mod push_comparison;
mod report;
mod runner;
mod settings_file;
mod sweep;
pub mod tables;

pub use cluster_comparison::{
    SceneComparison, compare_clustering, comparison_markdown, per_scene_markdown,
};
pub use config::{
    ExecutorConfig, ExecutorKind, ExperimentConfig, MAX_RUNS, PolicyConfig, RunSpec, SceneConfig,
    SweepConfig, Variant,
};
pub use log::{
    Log, LogHeader, LogReader, LogRow, LoggedAbilities, merge_logs, merge_logs_into, read_log,
    write_log,
};
pub use push_comparison::{
    PushComparison, PushFigures, SharedClusters, compare_pushing, push_comparison_markdown,
};
pub use report::{ReportPaths, write_report};
pub use runner::{RunReport, RunnerOptions, quantile, run_experiment, run_one};
