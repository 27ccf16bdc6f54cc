//! Experiment configurations (TOML) and their expansion into a fixed, numbered list of runs.
//!
//! ```toml
//! name = "paper"
//! description = "The Push-MOG paper's setup"
//! seed = 1                          # seeds every run's own choices and noise
//! repetitions = 1                   # runs per (scene, policy, sweep value)
//!
//! [scenes]
//! objects = [34]                    # one or more object counts
//! count = 5                         # scenes per object count
//! first_seed = 1                    # scene seeds first_seed, first_seed + 1, …
//! workspace = [0.6, 0.45]           # metres, for 34 objects
//! keep_density = true               # grow or shrink the workspace with the object count
//! object_set = "builtin"            # or the path of an object-set JSON file
//!
//! [executor]
//! kind = "sim"                      # or "ideal"
//! noise = true                      # perception and actuation noise in the simulator
//! settings = { grip_force = 20.0 }  # simulator settings (any subset)
//!
//! [sweep]
//! bin_distance = [0.3]              # metres; each value is a variant of every run
//! friction = [0.4, 0.8]             # the simulator's pad and object friction; a variant each
//!
//! [[sweep.variants]]                # named variants of every run: simulator settings and settings
//! label = "a = 2 m/s²"              # of every policy changed together (deep-merged over the
//! sim = { carry_acceleration = 2.0 }        # executor's and each policy's own)
//! policies = { riders = { checks = { acceleration = 2.0 } } }
//!
//! [[policies]]
//! name = "push-mog"                 # sog, mog, push-mog, push-mog-milp, push-mog-socp, push-mog-opt,
//!                                   # or a named preset (push-mog-time, push-mog-time-riders,
//!                                   # push-mog-opt-riders; `settings` laid over its own)
//! settings = { }                    # policy settings (any subset)
//! settings_file = "mine.json"       # optional: settings from a JSON file, `settings` laid over it
//! clusterer = "milp"                # optional: replace the preset's clusterer (hierarchical, milp)
//! pusher = "socp"                   # optional: replace its push planner (none, toward-central, socp)
//! ```
//!
//! Runs are numbered in a fixed order — object count, scene, bin distance, friction, variant,
//! policy, repetition — so a
//! configuration always expands to the same list, which is what makes logs resumable and shardable.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::exec::SimSettings;
use crate::policy::{ClustererKind, Policy, PolicyKind, PolicySettings, PusherKind};
use crate::scene::{GeneratorSettings, MAX_OBJECTS, ObjectSet, Workspace, builtin_object_set};

pub use super::sweep::{SweepConfig, Variant};
use super::{preset_names, settings_file};

/// Most runs one experiment may hold: a million lines of log, about 1 GB; larger studies are split
/// into several experiments (or shards of one).
pub const MAX_RUNS: usize = 1_000_000;

/// A whole experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExperimentConfig {
    /// Short name; logs and tables are named after it.
    pub name: String,
    /// What the experiment is for.
    #[serde(default)]
    pub description: String,
    /// Seed of every run's own choices and noise (with the run's number).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Runs per scene, policy and sweep value.
    #[serde(default = "default_one")]
    pub repetitions: usize,
    /// The scenes.
    pub scenes: SceneConfig,
    /// The executor.
    #[serde(default)]
    pub executor: ExecutorConfig,
    /// Values swept over every run.
    #[serde(default)]
    pub sweep: SweepConfig,
    /// The policies compared.
    pub policies: Vec<PolicyConfig>,
}

fn default_seed() -> u64 {
    1
}

fn default_one() -> usize {
    1
}

/// How scenes are made.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneConfig {
    /// Object counts.
    pub objects: Vec<usize>,
    /// Scenes per object count.
    pub count: usize,
    /// Seed of the first scene.
    #[serde(default = "default_seed")]
    pub first_seed: u64,
    /// Workspace `[width, depth]` in metres for 34 objects. Default `[0.6, 0.45]`.
    #[serde(default = "default_workspace")]
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub workspace: [f64; 2],
    /// Scale the workspace by `√(n / 34)` for `n` objects, keeping the object density. Default true.
    #[serde(default = "default_true")]
    pub keep_density: bool,
    /// `builtin` or the path of an object-set JSON file (relative to the configuration file).
    #[serde(default = "default_object_set")]
    pub object_set: String,
}

fn default_workspace() -> [f64; 2] {
    [0.6, 0.45]
}

fn default_true() -> bool {
    true
}

fn default_object_set() -> String {
    "builtin".to_string()
}

/// Which executor carries the plans out.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExecutorConfig {
    /// `ideal` or `sim`.
    #[serde(default)]
    pub kind: ExecutorKind,
    /// Perception and actuation noise in the simulator. Default true.
    #[serde(default = "default_true")]
    pub noise: bool,
    /// Simulator settings.
    #[serde(default)]
    pub settings: SimSettings,
}

pub use crate::exec::ExecutorKind;

/// One policy of the comparison.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PolicyConfig {
    /// The policy. A configuration file may also name a preset (`push-mog-time`,
    /// `push-mog-time-riders`, `push-mog-opt-riders`): reading it resolves the name into its policy,
    /// settings and label (`preset_names.rs`).
    pub name: PolicyKind,
    /// A label for tables (default: the policy's name).
    #[serde(default)]
    pub label: Option<String>,
    /// Its settings.
    #[serde(default)]
    pub settings: PolicySettings,
    /// Replaces the preset's clusterer (`hierarchical` or `milp`), to compose a policy from parts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clusterer: Option<ClustererKind>,
    /// Replaces the preset's push planner (`none`, `toward-central` or `socp`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pusher: Option<PusherKind>,
    /// A JSON file of policy settings (the format of `pushmog run --settings`), relative to the
    /// configuration's folder; `settings` are laid over it key by key. Reading the configuration
    /// merges the two into `settings` and clears this, so logs and their `config_hash` are those of
    /// the settings written out inline.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settings_file: Option<String>,
}

impl PolicyConfig {
    /// The policy this entry describes, with `settings` (its own, with any sweep applied).
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn policy(&self, settings: PolicySettings) -> Result<Policy> {
        let mut builder = Policy::builder(self.name).settings(settings);
        if let Some(kind) = self.clusterer {
            builder = builder.clusterer_kind(Some(kind));
        }
        if let Some(kind) = self.pusher {
            builder = builder.pusher_kind(kind);
        }
        builder.build()
    }
}

impl PolicyConfig {
    /// The label shown in tables.
    pub fn label(&self) -> String {
        self.label
            .clone()
            .unwrap_or_else(|| self.name.name().to_string())
    }
}

/// One run of an experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Position in the expanded list.
    pub id: usize,
    /// Object count.
    pub objects: usize,
    /// Scene seed.
    pub scene_seed: u64,
    /// Bin distance, when swept.
    pub bin_distance: Option<f64>,
    /// Pad and object friction in the simulator, when swept.
    pub friction: Option<f64>,
    /// Index into `sweep.variants`, when it has any.
    pub variant: Option<usize>,
    /// Index into `policies`.
    pub policy: usize,
    /// Repetition.
    pub repetition: usize,
    /// Seed of the run's own choices and noise.
    pub run_seed: u64,
}

impl ExperimentConfig {
    /// Reads and checks a configuration file.
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::InvalidField`] naming the problem (TOML errors give line and column).
    pub fn read(path: &Path) -> Result<Self> {
        let text = crate::json::read_text(path)?;
        let folder = path.parent().unwrap_or_else(|| Path::new(""));
        Self::from_toml_in(&text, &path.display().to_string(), folder)
    }

    /// Parses and checks a configuration; `name` says where it came from in error messages. A
    /// policy's `settings_file` is read relative to the current directory.
    ///
    /// # Errors
    /// As [`ExperimentConfig::read`].
    pub fn from_toml(text: &str, name: &str) -> Result<Self> {
        Self::from_toml_in(text, name, Path::new(""))
    }

    /// As [`ExperimentConfig::from_toml`], with settings files read relative to `folder`.
    ///
    /// # Errors
    /// As [`ExperimentConfig::read`].
    pub fn from_toml_in(text: &str, name: &str, folder: &Path) -> Result<Self> {
        let refuse = |e: toml::de::Error| {
            Error::field(name, "toml", e.to_string().trim().replace('\n', " "))
        };
        let mut document: toml::Table = toml::from_str(text).map_err(refuse)?;
        // Without settings files or preset names the text is read directly, so errors keep their
        // line and column.
        let config: Self = if settings_file::any(&document) || preset_names::any(&document) {
            settings_file::resolve(&mut document, folder, name)?;
            preset_names::resolve(&mut document, name)?;
            document.try_into().map_err(refuse)?
        } else {
            toml::from_str(text).map_err(refuse)?
        };
        config.validate()?;
        Ok(config)
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let component = format!("experiment `{}`", self.name);
        if self.name.is_empty() || self.name.contains(['/', '\\']) {
            return Err(Error::field(
                component,
                "name",
                "must be a plain, non-empty file name",
            ));
        }
        if self.scenes.objects.is_empty() || self.scenes.count == 0 {
            return Err(Error::field(
                component,
                "scenes",
                "needs object counts and count ≥ 1",
            ));
        }
        if self.policies.is_empty() {
            return Err(Error::field(
                component,
                "policies",
                "needs at least one policy",
            ));
        }
        if self.repetitions == 0 {
            return Err(Error::field(component, "repetitions", "must be at least 1"));
        }
        self.validate_sizes(&component)?;
        self.validate_sweep(&component)?;
        self.validate_labels(&component)?;
        self.executor.settings.validate()?;
        let files = self.policies.iter().map(|p| p.settings_file.as_deref());
        settings_file::refuse_unread(files, &component)?;
        for policy in &self.policies {
            policy.settings.validate()?;
        }
        Ok(())
    }

    /// Object counts in range, seeds that do not overflow, and at most `MAX_RUNS` runs.
    fn validate_sizes(&self, component: &str) -> Result<()> {
        if let Some(&n) = self
            .scenes
            .objects
            .iter()
            .find(|&&n| !(1..=MAX_OBJECTS).contains(&n))
        {
            return Err(Error::field(
                component.to_string(),
                "scenes.objects",
                format!("each count must be between 1 and {MAX_OBJECTS}, got {n}"),
            ));
        }
        if self
            .scenes
            .first_seed
            .checked_add(self.scenes.count as u64)
            .is_none()
        {
            return Err(Error::field(
                component.to_string(),
                "scenes.first_seed",
                "first_seed + count overflows a 64-bit seed",
            ));
        }
        let total = [
            self.scenes.objects.len(),
            self.scenes.count,
            self.sweep.bin_distance.len().max(1),
            self.sweep.friction.len().max(1),
            self.sweep.variants.len().max(1),
            self.policies.len(),
            self.repetitions,
        ]
        .iter()
        .try_fold(1usize, |acc, &n| acc.checked_mul(n))
        .filter(|&n| n <= MAX_RUNS);
        if total.is_none() {
            return Err(Error::field(
                component.to_string(),
                "scenes.count",
                format!(
                    "object counts × scenes × sweep values × policies × repetitions must be at most \
                     {MAX_RUNS} runs (each run is a line of the log); split the study into several \
                     experiments"
                ),
            ));
        }
        Ok(())
    }

    /// The sweep's values in range ([`SweepConfig::check`]) and each variant's settings fitting the
    /// simulator and every policy.
    fn validate_sweep(&self, component: &str) -> Result<()> {
        let simulated = self.executor.kind == ExecutorKind::Sim;
        self.sweep.check(simulated, component)?;
        for k in 0..self.sweep.variants.len() {
            self.sim_settings(None, Some(k))?.validate()?;
            for policy in 0..self.policies.len() {
                self.policy_settings(policy, None, Some(k))?.validate()?;
            }
        }
        Ok(())
    }

    /// One label per policy.
    fn validate_labels(&self, component: &str) -> Result<()> {
        for (second, policy) in self.policies.iter().enumerate() {
            let label = policy.label();
            if let Some(first) = self.policies[..second]
                .iter()
                .position(|p| p.label() == label)
            {
                return Err(Error::field(
                    component.to_string(),
                    "policies.label",
                    format!(
                        "policies {} and {} are both labelled `{label}`; each row of the tables is \
                         one label, so give each policy its own (`label = \"…\"`)",
                        first + 1,
                        second + 1
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Every run, numbered.
    pub fn runs(&self) -> Vec<RunSpec> {
        let points = self.sweep.points();
        let mut runs = Vec::new();
        for &objects in &self.scenes.objects {
            for scene in 0..self.scenes.count as u64 {
                for &(bin_distance, friction, variant) in &points {
                    for policy in 0..self.policies.len() {
                        for repetition in 0..self.repetitions {
                            let id = runs.len();
                            runs.push(RunSpec {
                                id,
                                objects,
                                scene_seed: self.scenes.first_seed + scene,
                                bin_distance,
                                friction,
                                variant,
                                policy,
                                repetition,
                                run_seed: self.seed.wrapping_mul(1_000_003).wrapping_add(id as u64),
                            });
                        }
                    }
                }
            }
        }
        runs
    }

    /// The scene generator's settings for `objects` objects.
    pub fn generator(&self, objects: usize) -> GeneratorSettings {
        let [width, depth] = self.scenes.workspace;
        let scale = if self.scenes.keep_density {
            (objects as f64 / 34.0).sqrt()
        } else {
            1.0
        };
        GeneratorSettings {
            objects,
            workspace: Workspace::new(width * scale, depth * scale),
            ..GeneratorSettings::default()
        }
    }

    /// The object set, reading a file relative to `base` (the configuration's folder).
    ///
    /// # Errors
    /// As reading and checking an object set.
    pub fn object_set(&self, base: &Path) -> Result<ObjectSet> {
        if self.scenes.object_set == "builtin" {
            return Ok(builtin_object_set());
        }
        let path: PathBuf = base.join(&self.scenes.object_set);
        let set: ObjectSet =
            crate::json::from_json(&crate::json::read_text(&path)?, &path.display().to_string())?;
        set.validate()?;
        Ok(set)
    }

    /// The settings of `policy` for a run with this bin distance and variant.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when the variant's settings do not fit the policy's.
    pub fn policy_settings(
        &self,
        policy: usize,
        bin_distance: Option<f64>,
        variant: Option<usize>,
    ) -> Result<PolicySettings> {
        let mut settings = self.policies[policy].settings.clone();
        if let Some(v) = variant.map(|v| &self.sweep.variants[v]) {
            settings = v.policy_settings(&settings)?;
        }
        if let Some(distance) = bin_distance {
            settings.time_model.bin_distance = distance;
        }
        Ok(settings)
    }

    /// The simulator's settings (noise removed when `noise` is off; friction and variant as swept).
    ///
    /// # Errors
    /// [`Error::InvalidField`] when the variant's settings do not fit the simulator's.
    pub fn sim_settings(
        &self,
        friction: Option<f64>,
        variant: Option<usize>,
    ) -> Result<SimSettings> {
        let mut settings = self.executor.settings.clone();
        if let Some(v) = variant.map(|v| &self.sweep.variants[v]) {
            settings = v.sim_settings(&settings)?;
        }
        if let Some(friction) = friction {
            settings.friction_finger = friction;
            settings.friction_object = friction;
        }
        Ok(if self.executor.noise {
            settings
        } else {
            SimSettings::noiseless_from(&settings)
        })
    }
}
