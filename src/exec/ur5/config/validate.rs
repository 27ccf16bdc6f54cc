//! The robot file's values checked, section by section, each range with its source
//! (`formulations/ur5.md`, "What the robot file may say").

use super::{
    MAX_OPEN_GAP, MAX_REACH, MAX_TCP_OFFSET, MAX_TOOL_SPEED, MAX_WAIT, MIN_TOOL_SPEED, RobotConfig,
};
use crate::error::{Error, Result};

/// A refusal naming `field`.
fn bad(field: &str, reason: String) -> Result<()> {
    Err(Error::field("robot config", field, reason))
}

/// `value` within `(low, high)`, or a refusal naming `field` with `why`.
fn within(field: &str, value: f64, (low, high): (f64, f64), why: &str) -> Result<()> {
    crate::error::in_range("robot config", field, value, (low, high), why)
}

impl RobotConfig {
    /// Checks every value and that the calibration fits within `calibration.max_residual`.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.check_motion()?;
        self.check_heights_and_gripper()?;
        self.check_tool_and_controller()?;
        self.check_consistency()?;
        self.check_workspace()?;
        Ok(())
    }

    /// Speeds, accelerations, the stream rate, timeouts and the calibration tolerance.
    fn check_motion(&self) -> Result<()> {
        // Ranges and their sources: `formulations/ur5.md`, "What the robot file may say".
        within(
            "safety.max_speed",
            self.safety.max_speed,
            (0.001, MAX_TOOL_SPEED),
            "m/s; the UR5's joints (180°/s at 0.85 m) move the tool at most about 2.7 m/s",
        )?;
        for (field, value) in [
            ("speeds.travel", self.speeds.travel),
            ("speeds.vertical", self.speeds.vertical),
            ("speeds.push", self.speeds.push),
        ] {
            within(
                field,
                value,
                (MIN_TOOL_SPEED, self.safety.max_speed),
                "m/s, at most safety.max_speed; below 1 mm/s a motion is a standstill",
            )?;
        }
        for (field, value) in [
            (
                "speeds.travel_acceleration",
                self.speeds.travel_acceleration,
            ),
            (
                "speeds.contact_acceleration",
                self.speeds.contact_acceleration,
            ),
        ] {
            within(
                field,
                value,
                (0.01, 5.0),
                "m/s²; URScript's default tool acceleration is 1.2",
            )?;
        }
        within(
            "controller.rtde_frequency",
            self.controller.rtde_frequency,
            (1.0, 500.0),
            "Hz; CB3 controllers offer up to 125, e-Series up to 500",
        )?;
        for (field, value) in [
            ("timeouts.connect", self.timeouts.connect),
            ("timeouts.reply", self.timeouts.reply),
            ("timeouts.gripper", self.timeouts.gripper),
        ] {
            within(
                field,
                value,
                (0.01, MAX_WAIT),
                "seconds; longer than ten minutes is a hang, not a wait",
            )?;
        }
        within(
            "timeouts.motion_margin",
            self.timeouts.motion_margin,
            (0.0, MAX_WAIT),
            "seconds; longer than ten minutes is a hang, not a wait",
        )?;
        within(
            "calibration.max_residual",
            self.calibration.max_residual,
            (1e-6, 0.05),
            "metres; a fit off by more than 5 cm is no calibration",
        )?;
        Ok(())
    }

    /// Heights above the table and the gripper's gaps.
    fn check_heights_and_gripper(&self) -> Result<()> {
        within(
            "heights.clearance",
            self.heights.clearance,
            (0.0, 0.5),
            "metres above the tallest object",
        )?;
        within(
            "heights.blend_radius",
            self.heights.blend_radius,
            (0.0, self.heights.clearance),
            "metres; a blend wider than the clearance could cut a corner into the tallest object",
        )?;
        within(
            "heights.grasp",
            self.heights.grasp,
            (0.0, 0.1),
            "metres of the fingertips above the table",
        )?;
        within(
            "heights.table",
            self.heights.table,
            (-MAX_REACH, MAX_REACH),
            "metres; the UR5 reaches 0.85 m",
        )?;
        within(
            "gripper.open_gap",
            self.gripper.open_gap,
            (0.01, MAX_OPEN_GAP),
            "metres between the pads fully open; the 2F-85 opens 0.085, the 2F-140 0.140",
        )?;
        within(
            "gripper.closed_gap",
            self.gripper.closed_gap,
            (0.0, MAX_OPEN_GAP),
            "metres between the pads fully closed",
        )?;
        within(
            "gripper.plate_thickness",
            self.gripper.plate_thickness,
            (0.0, 0.05),
            "metres; the 2F-85's plates are 0.010",
        )?;
        Ok(())
    }

    /// The tool centre point and where the controller listens.
    fn check_tool_and_controller(&self) -> Result<()> {
        for (axis, &value) in self.tcp[..3].iter().enumerate() {
            within(
                &format!("tcp[{axis}]"),
                value,
                (-MAX_TCP_OFFSET, MAX_TCP_OFFSET),
                "metres from the flange; the 2F-85's fingertips are about 0.175 m from it",
            )?;
        }
        let turn = self.tcp[3..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(turn.is_finite() && turn <= std::f64::consts::TAU) {
            return bad(
                "tcp",
                format!(
                    "the rotation [rx, ry, rz] is an axis-angle vector of at most 2π rad, got a \
                     norm of {turn}"
                ),
            );
        }
        for (field, port) in [
            ("controller.script_port", self.controller.script_port),
            ("controller.rtde_port", self.controller.rtde_port),
            ("controller.gripper_port", self.controller.gripper_port),
        ] {
            if port == 0 {
                return bad(
                    field,
                    "port 0 is not a port a controller listens on".to_string(),
                );
            }
        }
        let host = &self.controller.host;
        if host.is_empty() || host.chars().any(|c| c.is_whitespace() || c.is_control()) {
            return bad(
                "controller.host",
                format!("must be a host name or IP address, got {host:?}"),
            );
        }
        Ok(())
    }

    /// Values that must agree with each other: table height, push fraction, object height, the gripper's counts and gaps, a finite tool offset.
    fn check_consistency(&self) -> Result<()> {
        if !self.heights.table.is_finite() {
            return bad("heights.table", "must be finite".to_string());
        }
        if !(0.0..=1.0).contains(&self.heights.push_fraction) {
            return bad(
                "heights.push_fraction",
                format!("must lie in [0, 1], got {}", self.heights.push_fraction),
            );
        }
        if let Some(h) = self.heights.object_height {
            within(
                "heights.object_height",
                h,
                (crate::scene::MIN_HEIGHT, crate::scene::MAX_HEIGHT),
                "metres, as an object's height in a scene",
            )?;
        }
        if self.gripper.closed_count <= self.gripper.open_count {
            return bad(
                "gripper.closed_count",
                format!(
                    "must exceed open_count ({}), got {}",
                    self.gripper.open_count, self.gripper.closed_count
                ),
            );
        }
        if !(self.gripper.open_gap.is_finite() && self.gripper.open_gap > self.gripper.closed_gap) {
            return bad(
                "gripper.open_gap",
                format!(
                    "must exceed closed_gap ({}), got {}",
                    self.gripper.closed_gap, self.gripper.open_gap
                ),
            );
        }
        if self.tcp.iter().any(|v| !v.is_finite()) {
            return bad("tcp", "every entry must be finite".to_string());
        }
        Ok(())
    }

    /// The safety box, the bin and the waiting pose in the base frame, and the calibration's fit.
    fn check_workspace(&self) -> Result<()> {
        for axis in 0..3 {
            for (field, value) in [
                (format!("safety.min[{axis}]"), self.safety.min[axis]),
                (format!("safety.max[{axis}]"), self.safety.max[axis]),
                (format!("bin.drop[{axis}]"), self.bin.drop[axis]),
            ]
            .into_iter()
            .chain(
                self.look
                    .iter()
                    .map(|look| (format!("look.wait[{axis}]"), look.wait[axis])),
            ) {
                within(
                    &field,
                    value,
                    (-MAX_REACH, MAX_REACH),
                    "metres in the base frame; the UR5 reaches 0.85 m",
                )?;
            }
            if self.safety.min[axis] >= self.safety.max[axis] {
                return bad("safety", format!("min[{axis}] must be below max[{axis}]"));
            }
        }
        let calibration = self.calibration()?;
        if calibration.rms_residual > self.calibration.max_residual {
            return bad(
                "calibration.points",
                format!(
                    "the fit's RMS residual {:.2} mm exceeds max_residual {:.2} mm (largest {:.2} \
                     mm at point {}); re-measure the points",
                    calibration.rms_residual * 1e3,
                    self.calibration.max_residual * 1e3,
                    calibration.max_residual * 1e3,
                    calibration.worst_point
                ),
            );
        }
        Ok(())
    }
}
