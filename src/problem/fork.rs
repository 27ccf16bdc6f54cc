//! The fork push's geometry settings: clearances of the lowered fingers, their height, and the
//! table friction pushes must overcome. The fork push itself lives in `push` (`push/fork.rs`,
//! `formulations/pushing.md`); both push planners and the policy share these settings.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Settings of the fork-push geometry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ForkSettings {
    /// Least gap between the lowered fingers and the object they push, in any direction, metres.
    /// Default 0.01 behind it; beside a narrow end that reaches back between the fingers, the
    /// approach backs off until the gap is this wide too. Before it did, 49 of 58 push landings in
    /// 432 simulated runs of push-mog-socp and push-mog-opt were on the pushed object itself, and
    /// on seeds 101–140 (push-mog-opt) push landings went from 17 to 0. At most 0.1.
    pub approach_clearance: f64,
    /// Least gap between a lowered finger and any other object, metres. Default 0.003: about 1.3
    /// standard deviations of the combined perception (2 mm) and actuation (1 mm) noise, so a finger
    /// rarely comes down on a neighbour.
    pub finger_clearance: f64,
    /// Preferred fingertip height as a fraction of the object's height. Default 0.5 (the paper
    /// lowers the gripper to the object's mid-height).
    pub height_fraction: f64,
    /// Lowest fingertip height above the table, metres. Default 0.003: the fingertips must clear the
    /// table by more than the arm's calibration error.
    pub min_height: f64,
    /// Coulomb friction between objects and the table that pushes must overcome, as the planner
    /// believes it. Default 0.3 (handbook values for plastic or wood on laminate, 0.2–0.4; the
    /// simulator's value).
    pub table_friction: f64,
    /// Margin kept against tipping, metres. Default 0.001.
    pub tip_margin: f64,
}

impl Default for ForkSettings {
    fn default() -> Self {
        Self {
            approach_clearance: 0.01,
            finger_clearance: 0.003,
            height_fraction: 0.5,
            min_height: 0.003,
            table_friction: 0.3,
            tip_margin: 0.001,
        }
    }
}

impl ForkSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        if !(self.finger_clearance.is_finite() && (0.0..=0.02).contains(&self.finger_clearance)) {
            return Err(Error::field(
                "fork",
                "finger_clearance",
                format!(
                    "must be between 0 and 0.02 m, got {}",
                    self.finger_clearance
                ),
            ));
        }
        for (field, value, range) in [
            ("height_fraction", self.height_fraction, (0.0, 1.0)),
            ("min_height", self.min_height, (0.0, 0.05)),
            ("table_friction", self.table_friction, (0.0, 2.0)),
            ("tip_margin", self.tip_margin, (0.0, 0.02)),
        ] {
            if !(value.is_finite() && (range.0..=range.1).contains(&value)) {
                return Err(Error::field(
                    "fork",
                    field,
                    format!("must be between {} and {}, got {value}", range.0, range.1),
                ));
            }
        }
        crate::error::in_range(
            "fork",
            "approach_clearance",
            self.approach_clearance,
            (0.0, 0.1),
            "metres; the fingers come down this far from the object they push, and beyond 10 cm \
             they would come down among the cluster's neighbours (the clustering's reach is 10 cm)",
        )?;
        Ok(())
    }
}
