//! The robot configuration file (TOML): where the controller is, how the table sits in the robot's
//! base frame, heights, speeds, the gripper's calibration and the safety envelope.
//!
//! Every length is in metres, every speed in m/s, every acceleration in m/s², every time in seconds.
//! `robots/ur5-example.toml` is a commented example; `pushmog schema robot` prints the JSON Schema of
//! the same structure.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::calibration::{Calibration, Correspondence};
use crate::error::{Error, Result};

mod validate;

/// Everything the UR5 executor needs to know about one robot cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RobotConfig {
    /// Where the controller listens.
    #[serde(default)]
    pub controller: ControllerConfig,
    /// Table-to-base calibration from measured point pairs.
    pub calibration: CalibrationConfig,
    /// The tool centre point: the fingertip centre relative to the flange, as a UR pose
    /// `[x, y, z, rx, ry, rz]` (metres, axis-angle radians). Measure it; it is sent with `set_tcp`.
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub tcp: [f64; 6],
    /// Heights above the table.
    #[serde(default)]
    pub heights: HeightsConfig,
    /// Speeds and accelerations of the motions.
    #[serde(default)]
    pub speeds: SpeedsConfig,
    /// Where the bin is.
    pub bin: BinConfig,
    /// Where the arm waits while the camera looks at the table during a trip. Absent: it waits
    /// where it stopped, above its last push.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub look: Option<LookConfig>,
    /// The Robotiq gripper.
    #[serde(default)]
    pub gripper: GripperConfig,
    /// Limits checked before anything is sent.
    pub safety: SafetyConfig,
    /// How long to wait for each thing.
    #[serde(default)]
    pub timeouts: TimeoutsConfig,
}

/// Network addresses of the controller's interfaces.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ControllerConfig {
    /// Host name or IP address of the controller. Default `192.168.1.10`.
    pub host: String,
    /// Secondary interface, where URScript programs are sent. Default 30002.
    pub script_port: u16,
    /// RTDE interface, where the robot's state is read. Default 30004.
    pub rtde_port: u16,
    /// Robotiq URCap socket on the controller. Default 63352.
    pub gripper_port: u16,
    /// Output integer register the programs write when a motion is done (24–47 are the ones kept free
    /// for external RTDE clients). Default 24.
    pub done_register: u8,
    /// RTDE output frequency asked for, Hz. Default 125 (every controller generation offers it).
    pub rtde_frequency: f64,
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self {
            host: "192.168.1.10".to_string(),
            script_port: 30002,
            rtde_port: 30004,
            gripper_port: 63352,
            done_register: 24,
            rtde_frequency: 125.0,
        }
    }
}

/// Table-to-base calibration: points whose table coordinates are known (marks on the table) and
/// whose base coordinates were read from the pendant with the tool centre point touching them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CalibrationConfig {
    /// Three or more pairs, not all on one line.
    pub points: Vec<Correspondence>,
    /// Largest acceptable root-mean-square residual of the fit, metres. Default 0.003.
    #[serde(default = "default_max_residual")]
    pub max_residual: f64,
}

fn default_max_residual() -> f64 {
    0.003
}

/// Heights of the motions above the table surface, metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct HeightsConfig {
    /// Height of the table surface above the plane of the calibration points (0 when the points were
    /// touched on the table itself). Default 0.
    pub table: f64,
    /// Clearance above the tallest object for travel moves. Default 0.05.
    pub clearance: f64,
    /// Height of the fingertips above the table when the jaws close for a grasp. Default 0.005.
    pub grasp: f64,
    /// Fraction of an object's height at which a fork push touches it (the paper: mid-height).
    /// Default 0.5.
    pub push_fraction: f64,
    /// When set, every object's height instead of the heights in the plan's scenes.
    pub object_height: Option<f64>,
    /// Blend radius of a move that flows into the next through free air (a push's rise into the
    /// travel onward, the travel to a push into its descent, a grasp's lift into the run to the
    /// bin): the controller turns the corner within this distance of the waypoint instead of
    /// stopping there (URScript `movel`'s `r`). At most `clearance`, so the cut corner stays above
    /// the tallest object; each blend is also held to half of either move it joins, since blends may
    /// not overlap. 0 stops after every move; the time model's `blend_free_moves` should then be
    /// false. Default 0.02.
    pub blend_radius: f64,
}

impl Default for HeightsConfig {
    fn default() -> Self {
        Self {
            table: 0.0,
            clearance: 0.05,
            grasp: 0.005,
            push_fraction: 0.5,
            object_height: None,
            blend_radius: 0.02,
        }
    }
}

/// Speeds and accelerations of the tool, m/s and m/s².
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SpeedsConfig {
    /// Travel between poses above the table. Default 0.25 (typical of public UR code).
    pub travel: f64,
    /// Acceleration of travel moves. Default 1.2.
    pub travel_acceleration: f64,
    /// Descents to and rises from the table. Default 0.1.
    pub vertical: f64,
    /// The straight line of a fork push. Default 0.05 (slow enough for quasi-static pushing).
    pub push: f64,
    /// Acceleration of descents, rises and pushes. Default 0.5.
    pub contact_acceleration: f64,
}

impl Default for SpeedsConfig {
    fn default() -> Self {
        Self {
            travel: 0.25,
            travel_acceleration: 1.2,
            vertical: 0.1,
            push: 0.05,
            contact_acceleration: 0.5,
        }
    }
}

/// The bin: where the tool goes to drop what it holds, in the base frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BinConfig {
    /// Tool centre point above the bin when the jaws open, `[x, y, z]` in the base frame, metres.
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub drop: [f64; 3],
}

/// A look at the table during a trip (after pushes, when the loop looks before its grasp): an
/// overhead camera sees the gripper above the table, so the arm first moves out of its view.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LookConfig {
    /// Tool centre point where the arm waits, out of the camera's view, `[x, y, z]` in the base
    /// frame, metres: reached by one straight move from above the last push, and left by one
    /// straight move to the next action, so both lines must be clear, as the way to the bin is.
    /// Set the time model's `look_away` to the length of that way.
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub wait: [f64; 3],
}

/// The Robotiq 2F-85 and its calibration (position counts against the gap between the pads).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct GripperConfig {
    /// Position count read when fully open (after activation, about 3). Default 3.
    pub open_count: u8,
    /// Gap between the pads measured when fully open, metres. Default 0.085.
    pub open_gap: f64,
    /// Position count read when fully closed on nothing (about 230). Default 230.
    pub closed_count: u8,
    /// Gap between the pads when fully closed, metres. Default 0.
    pub closed_gap: f64,
    /// Thickness of each pad plate along the closing axis, metres: plans give openings between plate
    /// centres, which are gap + thickness. Default 0.010.
    pub plate_thickness: f64,
    /// Closing speed, 0–255. Default 128.
    pub speed: u8,
    /// Grip force, 0–255. Default 100.
    pub force: u8,
}

impl Default for GripperConfig {
    fn default() -> Self {
        Self {
            open_count: 3,
            open_gap: 0.085,
            closed_count: 230,
            closed_gap: 0.0,
            plate_thickness: 0.010,
            speed: 128,
            force: 100,
        }
    }
}

impl GripperConfig {
    /// The position count that leaves `opening` metres between the plate centres, by linear
    /// interpolation between the two calibration readings, clamped to them.
    pub fn count_for_opening(&self, opening: f64) -> u8 {
        let gap = opening - self.plate_thickness;
        let t = ((gap - self.open_gap) / (self.closed_gap - self.open_gap)).clamp(0.0, 1.0);
        let count = f64::from(self.open_count)
            + t * (f64::from(self.closed_count) - f64::from(self.open_count));
        count.round().clamp(0.0, 255.0) as u8
    }

    /// The opening between plate centres, metres, at a position count (the inverse of
    /// [`GripperConfig::count_for_opening`], not clamped).
    pub fn opening_at(&self, count: u8) -> f64 {
        let t = (f64::from(count) - f64::from(self.open_count))
            / (f64::from(self.closed_count) - f64::from(self.open_count));
        self.open_gap + t * (self.closed_gap - self.open_gap) + self.plate_thickness
    }
}

/// The safety envelope: every commanded pose and speed is checked against it before sending.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SafetyConfig {
    /// Lower corner of the box the tool centre point must stay in, base frame, metres.
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub min: [f64; 3],
    /// Upper corner of the box, base frame, metres.
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub max: [f64; 3],
    /// Largest tool speed any motion may command, m/s.
    pub max_speed: f64,
}

/// Time limits, seconds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct TimeoutsConfig {
    /// Opening a connection. Default 3.
    pub connect: f64,
    /// Waiting for one reply of the gripper socket or one RTDE package. Default 2.
    pub reply: f64,
    /// Waiting for the gripper to activate or finish a move. Default 5.
    pub gripper: f64,
    /// Added to a motion's expected duration before it counts as timed out. Default 5.
    pub motion_margin: f64,
}

impl Default for TimeoutsConfig {
    fn default() -> Self {
        Self {
            connect: 3.0,
            reply: 2.0,
            gripper: 5.0,
            motion_margin: 5.0,
        }
    }
}

/// Fastest tool speed a robot file may ask for, m/s. The UR5's joints turn at most 180°/s (data
/// sheet), which at its 0.85 m reach moves the tool at most about 2.7 m/s; its typical tool speed is
/// 1 m/s.
pub const MAX_TOOL_SPEED: f64 = 3.0;

/// Slowest tool speed, m/s: at 1 mm/s a 0.5 m travel takes over eight minutes; anything slower
/// commands a standstill.
pub const MIN_TOOL_SPEED: f64 = 0.001;

/// Longest wait, seconds: ten minutes.
const MAX_WAIT: f64 = 600.0;

/// Largest coordinate of a pose in the base frame, metres: a little over the UR5's 0.85 m reach
/// (data sheet), for a base mounted off the table's plane.
pub const MAX_REACH: f64 = 1.0;

/// Largest offset of the tool centre point from the flange, metres.
const MAX_TCP_OFFSET: f64 = 0.5;

/// Widest gap between open pads, metres: the Robotiq 2F-140's 140 mm, the widest gripper the same
/// URCap socket drives, with a margin.
pub const MAX_OPEN_GAP: f64 = 0.15;

impl RobotConfig {
    /// Reads and checks a TOML configuration file.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read, [`Error::InvalidField`] for a parse error or a bad
    /// value (the message names the field).
    pub fn load(path: &Path) -> Result<Self> {
        let text = crate::json::read_text(path)?;
        Self::from_toml(&text, &path.display().to_string())
    }

    /// Parses and checks a configuration; `name` says where it came from in error messages.
    ///
    /// # Errors
    /// As [`RobotConfig::load`].
    pub fn from_toml(text: &str, name: &str) -> Result<Self> {
        let config: Self =
            toml::from_str(text).map_err(|e| Error::field(name, "toml", e.to_string()))?;
        config.validate()?;
        Ok(config)
    }

    /// The table-to-base transform fitted to the calibration points.
    ///
    /// # Errors
    /// [`Error::InvalidField`] for fewer than three points or points on one line.
    pub fn calibration(&self) -> Result<Calibration> {
        Calibration::fit(&self.calibration.points)
    }
}
