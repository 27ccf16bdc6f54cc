//! How long the robot's actions take: the seconds behind "a trip costs a grasp plus travel to the bin"
//! and "a push costs a fixed time plus distance over push speed".
//!
//! Every straight move of length `d` follows a trapezoidal speed profile with top speed `v` and
//! acceleration `a`: `d/v + v/a` when `d ≥ v²/a`, else `2√(d/a)` (a triangle). Then
//! - a **trip**: descend the approach height, close the jaws over the stroke, rise, travel to the bin,
//!   open, travel back: `2·move(h) + 2·stroke/v_jaw + 2·move(bin)`;
//! - a **push** of length `L`: descend, push at the push speed, rise:
//!   `2·move(h) + L/v_push` (the push is slow, so its ramps are negligible), plus the jaw motion to
//!   the fork-push opening.
//!
//! Travel between successive actions inside the workspace is not counted: it is short next to the bin
//! run and about the same for every plan. Defaults are a UR5-class arm's usual linear moves and a
//! Robotiq 2F-85 (`shared/reference/FACTS.md`).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::scene::Gripper;

/// Speeds, accelerations and distances of the arm and gripper.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct TimeModel {
    /// Top speed of linear arm moves, m/s. Default 0.25 (typical UR linear moves).
    pub travel_speed: f64,
    /// Acceleration of linear arm moves, m/s². Default 1.2 (typical UR linear moves).
    pub travel_acceleration: f64,
    /// Height above the table from which the gripper descends, metres. Default 0.10.
    pub approach_height: f64,
    /// Distance from the workspace to the bin, metres. Default 0.30 (a bin beside a 0.6 m workspace,
    /// as in the Push-MOG experiments).
    pub bin_distance: f64,
    /// Jaw closing and opening speed, m/s. Default 0.15 (the 2F-85's fastest setting).
    pub jaw_speed: f64,
    /// Speed of fork pushes, m/s. Default 0.05 (slow enough for quasi-static pushing).
    pub push_speed: f64,
}

impl Default for TimeModel {
    fn default() -> Self {
        Self {
            travel_speed: 0.25,
            travel_acceleration: 1.2,
            approach_height: 0.10,
            bin_distance: 0.30,
            jaw_speed: 0.15,
            push_speed: 0.05,
        }
    }
}

impl TimeModel {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        for (field, value, positive) in [
            ("travel_speed", self.travel_speed, true),
            ("travel_acceleration", self.travel_acceleration, true),
            ("approach_height", self.approach_height, false),
            ("bin_distance", self.bin_distance, false),
            ("jaw_speed", self.jaw_speed, true),
            ("push_speed", self.push_speed, true),
        ] {
            if !value.is_finite() || value < 0.0 || (positive && value == 0.0) {
                return Err(Error::field(
                    "time_model",
                    field,
                    format!(
                        "must be a finite {} number, got {value}",
                        if positive { "positive" } else { "non-negative" }
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Seconds for a straight arm move of `distance` metres.
    pub fn move_seconds(&self, distance: f64) -> f64 {
        let (v, a) = (self.travel_speed, self.travel_acceleration);
        if distance <= 0.0 {
            0.0
        } else if distance >= v * v / a {
            distance / v + v / a
        } else {
            2.0 * (distance / a).sqrt()
        }
    }

    /// Seconds for one trip: grasp, carry to the bin, drop, come back.
    pub fn trip_seconds(&self, gripper: &Gripper) -> f64 {
        2.0 * self.move_seconds(self.approach_height)
            + 2.0 * gripper.stroke / self.jaw_speed
            + 2.0 * self.move_seconds(self.bin_distance)
    }

    /// Seconds for one fork push of `distance` metres.
    pub fn push_seconds(&self, gripper: &Gripper, distance: f64) -> f64 {
        let jaw = (gripper.stroke - gripper.fork_push_opening()).abs() / self.jaw_speed;
        jaw + 2.0 * self.move_seconds(self.approach_height) + distance.max(0.0) / self.push_speed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_follow_a_trapezoid() {
        let model = TimeModel::default();
        // Long move: cruise plus one ramp time.
        assert!((model.move_seconds(0.3) - (0.3 / 0.25 + 0.25 / 1.2)).abs() < 1e-12);
        // Short move: a triangle.
        assert!((model.move_seconds(0.01) - 2.0 * (0.01f64 / 1.2).sqrt()).abs() < 1e-12);
        // The two meet at d = v²/a.
        let knee = 0.25 * 0.25 / 1.2;
        assert!((model.move_seconds(knee) - 2.0 * (knee / 1.2).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_push_is_cheaper_than_a_trip_by_default() {
        let (model, gripper) = (TimeModel::default(), Gripper::default());
        assert!(model.push_seconds(&gripper, 0.05) < model.trip_seconds(&gripper));
    }
}
