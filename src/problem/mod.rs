//! The problem every planning stage shares: what a closing of the jaws does (the grasp model), how a
//! fork push is made (its geometry), the shortest push worth making, and what a second of robot time
//! is spent on (the time model, the objective of the time-priced clustering and pushes).
//!
//! A policy builds one [`Problem`] from its settings (`PolicySettings::grasp_model`, `fork`,
//! `min_push` and `time_model`), validates it once, and hands the same `Arc<Problem>` to its
//! clusterer, push planner and grasp planners, so no stage can disagree with another about the cell.
//! A stage built on its own takes [`Problem::default`]. The maths each part stands for is in
//! `formulations/grasping.md` (the grasp model), `formulations/pushing.md` (the fork push) and
//! `formulations/time-model.md` (the time model).

mod fork;
mod grasp_model;

use std::sync::{Arc, LazyLock};

pub use fork::ForkSettings;
pub use grasp_model::{GraspModel, Mechanics};

use crate::error::{Error, Result};
use crate::time_model::TimeModel;

/// Standard gravity, m/s²: the one value every stage weighs with.
pub const GRAVITY: f64 = 9.81;

/// Pushes shorter than this are not made by default, metres: objects already within 3 mm of their
/// targets are held where they are (`formulations/pushing.md`, the SOCP's rule 7).
pub const DEFAULT_MIN_PUSH: f64 = 0.003;

/// What every stage of a policy agrees on, validated once. Read-only: build a new one to change it.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    grasp_model: GraspModel,
    fork: ForkSettings,
    min_push: f64,
    time_model: TimeModel,
}

impl Problem {
    /// A problem from its parts, each checked.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the first field out of range (`policy.min_push` for
    /// `min_push`, outside 0 to 0.1 m).
    pub fn new(
        grasp_model: GraspModel,
        fork: ForkSettings,
        min_push: f64,
        time_model: TimeModel,
    ) -> Result<Arc<Self>> {
        if !(min_push.is_finite() && (0.0..=0.1).contains(&min_push)) {
            return Err(Error::field(
                "policy",
                "min_push",
                format!("must be between 0 and 0.1 m, got {min_push}"),
            ));
        }
        grasp_model.validate()?;
        fork.validate()?;
        time_model.validate()?;
        Ok(Arc::new(Self {
            grasp_model,
            fork,
            min_push,
            time_model,
        }))
    }

    /// The same problem judged by another grasp model (say the "fits the jaws" test,
    /// [`GraspModel::unlimited_friction`]).
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a field of `grasp_model` is out of range.
    pub fn with_grasp_model(&self, grasp_model: GraspModel) -> Result<Arc<Self>> {
        grasp_model.validate()?;
        Ok(Arc::new(Self {
            grasp_model,
            ..self.clone()
        }))
    }

    /// The defaults of every part, shared: what a stage built on its own plans for.
    pub fn shared_default() -> Arc<Self> {
        static DEFAULT: LazyLock<Arc<Problem>> = LazyLock::new(|| Arc::new(Problem::default()));
        DEFAULT.clone()
    }

    /// What a closing does, for every stage that asks.
    pub fn grasp_model(&self) -> &GraspModel {
        &self.grasp_model
    }

    /// Fork-push geometry, for both push planners.
    pub fn fork(&self) -> &ForkSettings {
        &self.fork
    }

    /// Pushes shorter than this are not made, metres, by the push planners and in the clustering's
    /// estimates.
    pub fn min_push(&self) -> f64 {
        self.min_push
    }

    /// Seconds of each command, observation and trip: the objective of the time-priced stages.
    pub fn time_model(&self) -> &TimeModel {
        &self.time_model
    }
}

impl Default for Problem {
    fn default() -> Self {
        Self {
            grasp_model: GraspModel::default(),
            fork: ForkSettings::default(),
            min_push: DEFAULT_MIN_PUSH,
            time_model: TimeModel::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_valid_and_bad_parts_are_named() {
        let d = Problem::default();
        let built = Problem::new(
            d.grasp_model.clone(),
            d.fork.clone(),
            d.min_push,
            d.time_model.clone(),
        )
        .unwrap();
        assert_eq!(*built, d);
        let err = Problem::new(
            GraspModel::default(),
            ForkSettings::default(),
            0.2,
            TimeModel::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("min_push"), "{err}");
        let bad_model = GraspModel {
            grip_force: -1.0,
            ..GraspModel::default()
        };
        let err = Problem::new(
            bad_model,
            ForkSettings::default(),
            0.003,
            TimeModel::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("grip_force"), "{err}");
    }
}
