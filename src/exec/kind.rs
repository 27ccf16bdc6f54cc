//! Which executor carries a run out, by name, and the one place where an executor is built from its
//! name: the command line (`--executor`), the experiment runner (`executor.kind`) and the Python
//! package (`Planner.run(executor=…)`) all build theirs here, so the same name, settings and run seed
//! give the same executor everywhere (and a logged run can be replayed from any of them).

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The executor kinds.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum ExecutorKind {
    /// Plans applied exactly.
    #[default]
    Ideal,
    /// The rapier3d simulator.
    Sim,
}

impl ExecutorKind {
    /// Every kind, in the order they are listed.
    pub const ALL: [Self; 2] = [Self::Ideal, Self::Sim];

    /// The name in files and on the command line (`ideal`, `sim`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Ideal => "ideal",
            Self::Sim => "sim",
        }
    }

    /// The executor of this kind for a run with seed `run_seed`: the ideal executor judging grasps
    /// with `problem`'s grasp model, or the simulator with `sim` (noise and all) whose own seed is
    /// [`super::Sim::seed_for_run`] of the run seed, as every caller seeds it.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a simulator setting is out of range.
    #[cfg(feature = "sim")]
    pub fn build(
        self,
        problem: &crate::problem::Problem,
        sim: super::SimSettings,
        run_seed: u64,
    ) -> Result<Box<dyn super::Executor + Send>> {
        Ok(match self {
            Self::Ideal => Box::new(super::Ideal::new(problem.grasp_model().clone())),
            Self::Sim => Box::new(super::Sim::new(sim, super::Sim::seed_for_run(run_seed))?),
        })
    }
}

impl std::fmt::Display for ExecutorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ExecutorKind {
    type Err = Error;

    /// A kind by its name; an unknown name is refused with the names there are (field
    /// `run.--executor`).
    fn from_str(text: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|kind| kind.name() == text)
            .ok_or_else(|| {
                Error::field(
                    "run",
                    "--executor",
                    format!(
                        "unknown executor `{text}`; available: {}",
                        Self::ALL.map(Self::name).join(", ")
                    ),
                )
            })
    }
}
