//! The parallel-jaw gripper: dimensions that decide what fits between the jaws.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// A parallel-jaw gripper. Defaults are a Robotiq 2F-85: stroke 85 mm between plate centres, plates
/// 10 mm thick and 22 mm long (the fingertip pad's width), so the usable gap between the plate faces
/// is 75 mm; fork pushes open the jaws to 30 % of the stroke (the Push-MOG paper's setting).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Gripper {
    /// Largest distance between the two plate centres, metres. Default 0.085.
    pub stroke: f64,
    /// Thickness of each jaw plate along the closing axis, metres. Default 0.010.
    pub plate_thickness: f64,
    /// Length of each jaw plate across the closing axis, metres. Default 0.022: the width of the
    /// 2F-85 fingertip pad in public MuJoCo models built from the manufacturer's CAD
    /// (`formulations/references.md`).
    pub plate_length: f64,
    /// Opening for fork pushes as a fraction of the stroke (between plate centres). Default 0.30.
    pub fork_push_opening_fraction: f64,
}

impl Default for Gripper {
    fn default() -> Self {
        Self {
            stroke: 0.085,
            plate_thickness: 0.010,
            plate_length: 0.022,
            fork_push_opening_fraction: 0.30,
        }
    }
}

/// Widest stroke accepted, metres. Parallel-jaw grippers for tabletop picking open well under this
/// (the 2F-85 0.085 m, the 2F-140 0.140 m); a larger value is almost always a unit mistake.
pub const MAX_STROKE: f64 = 0.5;

/// Longest jaw plate accepted, metres: ten times the 2F-85 fingertip pad. A longer plate is a paddle,
/// not a finger the grasp model describes.
pub const MAX_PLATE_LENGTH: f64 = 0.22;

impl Gripper {
    /// The widest row of objects the jaws can close on, metres: the stroke minus one plate thickness
    /// (half a plate on each side of the plate centres).
    pub fn usable_gap(&self) -> f64 {
        self.stroke - self.plate_thickness
    }

    /// Distance between plate centres during a fork push, metres.
    pub fn fork_push_opening(&self) -> f64 {
        self.fork_push_opening_fraction * self.stroke
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field when a value is not finite or not positive, the stroke
    /// exceeds [`MAX_STROKE`] or the plates [`MAX_PLATE_LENGTH`], the plates are as thick as the
    /// stroke, or the fork-push fraction is outside `(0, 1]`.
    pub fn validate(&self) -> Result<()> {
        for (field, value) in [
            ("stroke", self.stroke),
            ("plate_thickness", self.plate_thickness),
            ("plate_length", self.plate_length),
            (
                "fork_push_opening_fraction",
                self.fork_push_opening_fraction,
            ),
        ] {
            if !value.is_finite() || value <= 0.0 {
                return Err(Error::field(
                    "gripper",
                    field,
                    format!(
                        "must be a positive finite number, got {}",
                        crate::error::number(value)
                    ),
                ));
            }
        }
        for (field, value, most, why) in [
            (
                "stroke",
                self.stroke,
                MAX_STROKE,
                "parallel-jaw grippers open well under this; the 2F-85 opens 0.085 m",
            ),
            (
                "plate_length",
                self.plate_length,
                MAX_PLATE_LENGTH,
                "ten times the 2F-85 fingertip pad; a longer plate is a paddle",
            ),
        ] {
            if value > most {
                return Err(Error::field(
                    "gripper",
                    field,
                    format!(
                        "{} m is more than {most} m: {why} (were millimetres given?)",
                        crate::error::number(value)
                    ),
                ));
            }
        }
        if self.plate_thickness >= self.stroke {
            return Err(Error::field(
                "gripper",
                "plate_thickness",
                format!(
                    "{} m leaves no gap within the {} m stroke",
                    self.plate_thickness, self.stroke
                ),
            ));
        }
        if self.fork_push_opening_fraction > 1.0 {
            return Err(Error::field(
                "gripper",
                "fork_push_opening_fraction",
                format!(
                    "is a fraction of the stroke in (0, 1], got {}",
                    self.fork_push_opening_fraction
                ),
            ));
        }
        Ok(())
    }
}
