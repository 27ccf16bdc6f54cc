//! Plan steps as robot steps: every fork push and every grasp with its trip becomes a short list of
//! tool motions and gripper commands in the robot's base frame.
//!
//! - Fork push (the paper's five steps): open to the fork opening (30 % of the stroke), move above
//!   the start, descend to the object's mid-height, push in a straight line to the end, rise.
//! - Grasp and trip (six steps): move above the grasp, open fully, descend, close with limited force,
//!   move to the bin (straight up first, then across), open to drop.
//!
//! A move through free air that another arm move follows (a push's rise, the move above a push's
//! start, the rise before the bin) carries the configured blend radius, and [`Translator::blend`]
//! puts it into one program with the move after it, so the controller turns that corner without
//! stopping (`formulations/ur5.md`, "Blends").
//!
//! The tool points down with the jaws' closing axis along the plan's jaw angle. With the tool frame's
//! y axis taken as the closing axis (the 2F-85 mounted as Robotiq documents it; `yaw_offset` otherwise),
//! the tool orientation in the base frame is `R · Rz(θ) · Rx(π)` with `R` the table-to-base rotation
//! and `θ = jaw angle − π/2`, folded into (−π/2, π/2] since the jaws are symmetric, which keeps wrist
//! turns short.

use nalgebra::{Point3, Rotation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use super::calibration::Calibration;
use super::config::RobotConfig;
use crate::error::{Error, Result};
use crate::grasp::Grasp;
use crate::push::Push;
use crate::scene::{Object, ObjectId, Scene};

mod rider;

/// A tool pose in the base frame in the controller's own form: position in metres and an axis-angle
/// rotation vector in radians.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToolPose {
    /// Position of the tool centre point, metres.
    pub position: [f64; 3],
    /// Rotation vector (axis × angle), radians.
    pub rotation: [f64; 3],
}

/// One straight-line move of the tool.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinearMove {
    /// Where the tool goes.
    pub to: ToolPose,
    /// Tool speed, m/s.
    pub speed: f64,
    /// Tool acceleration, m/s².
    pub acceleration: f64,
    /// Blend radius at `to`, metres: the tool turns into the next move within this distance of `to`
    /// without stopping (URScript `movel`'s `r`); 0 (the default) stops at `to`.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub blend: f64,
}

fn is_zero(value: &f64) -> bool {
    *value == 0.0
}

/// What one step does.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Action {
    /// Straight-line moves run in order by one URScript program.
    Move {
        /// The moves.
        moves: Vec<LinearMove>,
    },
    /// A gripper command through the URCap socket; the step waits until the fingers stop.
    Gripper {
        /// Requested position count (0 open … 255 closed).
        position: u8,
        /// Speed, 0–255.
        speed: u8,
        /// Force, 0–255.
        force: u8,
    },
}

/// Which part of a fork push or a grasp a step carries out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Fork push: open the jaws to the fork opening.
    OpenForPush,
    /// Fork push: move above the approach point.
    AbovePush,
    /// Fork push: descend to push height.
    DescendToPush,
    /// Fork push: the straight line that moves the object.
    Push,
    /// Fork push: rise after the push.
    RiseFromPush,
    /// Grasp: move above the grasp centre.
    AboveGrasp,
    /// Grasp: open fully.
    Open,
    /// Grasp: descend to grasp height.
    Descend,
    /// Grasp: close with limited force.
    Close,
    /// Grasp: rise and move over the bin.
    ToBin,
    /// Grasp: open over the bin.
    Drop,
    /// Rider: move above its pick.
    AbovePick,
    /// Rider: open the jaws to the pick's opening.
    OpenForPick,
    /// Rider: descend to half its height.
    DescendToPick,
    /// Rider: close on it with limited force.
    ClosePick,
    /// Rider: rise and move over the row.
    CarryRider,
    /// Rider: lower it onto the row's top.
    LowerRider,
    /// Rider: open to let it go.
    Release,
    /// Rider: rise from it.
    RiseFromRider,
    /// Look: move out of the camera's view and wait there while the table is looked at.
    OutOfView,
}

/// The tool's yaw for jaws along `jaw_angle`, folded into (−π/2, π/2] (the jaws are symmetric
/// under a half turn).
fn tool_yaw(jaw_angle: f64) -> f64 {
    let yaw = (jaw_angle - std::f64::consts::FRAC_PI_2).rem_euclid(std::f64::consts::PI);
    if yaw > std::f64::consts::FRAC_PI_2 {
        yaw - std::f64::consts::PI
    } else {
        yaw
    }
}

/// One robot step with a readable label (`trip 2, push 1 of 3: descend to mid-height`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Step {
    /// What the step is for.
    pub label: String,
    /// Which part of a push or grasp it is.
    pub phase: Phase,
    /// What it does.
    pub action: Action,
}

/// Turns plan steps into robot steps for one configuration.
#[derive(Clone, Debug)]
pub struct Translator {
    config: RobotConfig,
    calibration: Calibration,
}

impl Translator {
    /// A translator for `config`.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when the configuration is invalid.
    pub fn new(config: RobotConfig) -> Result<Self> {
        config.validate()?;
        let calibration = config.calibration()?;
        Ok(Self {
            config,
            calibration,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &RobotConfig {
        &self.config
    }

    /// The fitted calibration.
    pub fn calibration(&self) -> &Calibration {
        &self.calibration
    }

    fn height_of(&self, scene: &Scene, id: ObjectId) -> f64 {
        self.config.heights.object_height.unwrap_or_else(|| {
            scene
                .objects()
                .iter()
                .find(|o| o.id == id)
                .map_or(0.0, |o| o.height)
        })
    }

    /// Travel height above the table: the tallest object plus the clearance.
    fn travel_height(&self, scene: &Scene) -> f64 {
        self.travel_height_over(scene.objects().iter())
    }

    /// The travel height over `objects`: the configured object height, else the tallest of them,
    /// plus the clearance.
    fn travel_height_over<'a>(&self, objects: impl Iterator<Item = &'a Object>) -> f64 {
        let tallest = self
            .config
            .heights
            .object_height
            .unwrap_or_else(|| objects.map(|o| o.height).fold(0.0, f64::max));
        tallest + self.config.heights.clearance
    }

    /// A tool pose above table point (x, y) at height z over the table, jaws along `jaw_angle`.
    pub fn tool_pose(&self, x: f64, y: f64, z: f64, jaw_angle: f64) -> ToolPose {
        self.tool_pose_at_yaw(x, y, z, tool_yaw(jaw_angle))
    }

    /// A tool pose above table point (x, y) at height z, turned by the tool yaw `yaw` (not folded
    /// into a half turn: a held rider must turn by exactly its planned turn).
    fn tool_pose_at_yaw(&self, x: f64, y: f64, z: f64, yaw: f64) -> ToolPose {
        let position = self
            .calibration
            .to_base(x, y, z + self.config.heights.table);
        let orientation = self.calibration.rotation
            * Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
            * Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
        // The quaternion's logarithm keeps the axis at half-turns, where the rotation matrix's
        // antisymmetric part (and so `Rotation3::scaled_axis`) vanishes; a tool pointing down is one.
        let rv = UnitQuaternion::from_rotation_matrix(&orientation).scaled_axis();
        ToolPose {
            position: [position.x, position.y, position.z],
            rotation: [rv.x, rv.y, rv.z],
        }
    }

    fn travel(&self, to: ToolPose) -> LinearMove {
        LinearMove {
            to,
            speed: self.config.speeds.travel,
            acceleration: self.config.speeds.travel_acceleration,
            blend: 0.0,
        }
    }

    fn contact(&self, to: ToolPose, speed: f64) -> LinearMove {
        LinearMove {
            to,
            speed,
            acceleration: self.config.speeds.contact_acceleration,
            blend: 0.0,
        }
    }

    /// `m`, flowing into whatever move follows it (the configured blend radius; [`Translator::blend`]
    /// narrows it, or stops the move when no move follows).
    fn flowing(&self, m: LinearMove) -> LinearMove {
        LinearMove {
            blend: self.config.heights.blend_radius,
            ..m
        }
    }

    fn moves(phase: Phase, label: String, moves: Vec<LinearMove>) -> Step {
        Step {
            label,
            phase,
            action: Action::Move { moves },
        }
    }

    fn gripper(&self, phase: Phase, label: String, position: u8) -> Step {
        Step {
            label,
            phase,
            action: Action::Gripper {
                position,
                speed: self.config.gripper.speed,
                force: self.config.gripper.force,
            },
        }
    }

    /// The five steps of a fork push planned on `scene`, or four when the jaws already stand at its
    /// opening (`jaws`, the opening of the gripper's last command, if that was a push's): a jaw
    /// command that would not move them is not sent, and the time model does not charge it. `name`
    /// prefixes the labels.
    pub fn fork_push(
        &self,
        scene: &Scene,
        push: &Push,
        name: &str,
        jaws: Option<f64>,
    ) -> Vec<Step> {
        let fork = &push.fork;
        let travel = self.travel_height(scene);
        // The planned fingertip height (chosen so the object slides), or the configured fraction of
        // the object's height for plans that carry none.
        let (mid, which) = match fork.height {
            Some(height) => (height, "push height"),
            None => (
                self.config.heights.push_fraction * self.height_of(scene, push.object),
                "mid-height",
            ),
        };
        let vertical = self.config.speeds.vertical;
        let opening = fork.opening;
        let pose = |p: nalgebra::Point2<f64>, z| self.tool_pose(p.x, p.y, z, fork.jaw_angle);
        let open = (jaws != Some(opening)).then(|| {
            self.gripper(
                Phase::OpenForPush,
                format!(
                    "{name}: open to the fork opening ({:.1} mm between plate centres)",
                    opening * 1e3
                ),
                self.config.gripper.count_for_opening(opening),
            )
        });
        open.into_iter()
            .chain([
                Self::moves(
                    Phase::AbovePush,
                    format!("{name}: move above the start"),
                    vec![self.flowing(self.travel(pose(fork.approach, travel)))],
                ),
                Self::moves(
                    Phase::DescendToPush,
                    format!(
                        "{name}: descend to {which} of object {} ({:.1} mm)",
                        push.object,
                        mid * 1e3
                    ),
                    vec![self.contact(pose(fork.approach, mid), vertical)],
                ),
                Self::moves(
                    Phase::Push,
                    format!("{name}: push {:.1} mm to the end", push.distance * 1e3),
                    vec![self.contact(pose(fork.end, mid), self.config.speeds.push)],
                ),
                Self::moves(
                    Phase::RiseFromPush,
                    format!("{name}: rise"),
                    vec![self.flowing(self.contact(pose(fork.end, travel), vertical))],
                ),
            ])
            .collect()
    }

    /// The move out of the camera's view before a look during a trip (`look.wait`), the tool
    /// turned as `rotation` (as it stood); `None` when the configuration has no waiting pose and
    /// the arm waits where it stopped. The move stops there: the look waits for it.
    pub fn out_of_view(&self, rotation: [f64; 3], name: &str) -> Option<Step> {
        let look = self.config.look.as_ref()?;
        let to = ToolPose {
            position: look.wait,
            rotation,
        };
        Some(Self::moves(
            Phase::OutOfView,
            format!("{name}: move out of the camera's view and wait for the look"),
            vec![self.travel(to)],
        ))
    }

    /// The six steps of a grasp and its trip to the bin, planned on `scene`.
    pub fn grasp_and_trip(&self, scene: &Scene, grasp: &Grasp, name: &str) -> Vec<Step> {
        self.grasp_and_trip_over(scene, &[], grasp, name)
    }

    /// As [`Translator::grasp_and_trip`], with `also` objects off the scene (lying past the
    /// workspace's edge) that the travel height must clear as well.
    pub fn grasp_and_trip_over(
        &self,
        scene: &Scene,
        also: &[Object],
        grasp: &Grasp,
        name: &str,
    ) -> Vec<Step> {
        let jaws = &grasp.jaws;
        let travel = self
            .travel_height(scene)
            .max(self.travel_height_over(also.iter()));
        let vertical = self.config.speeds.vertical;
        let pose = |z| self.tool_pose(jaws.center.x, jaws.center.y, z, jaws.angle);
        let over_bin = ToolPose {
            position: self.config.bin.drop,
            rotation: pose(travel).rotation,
        };
        let objects = grasp
            .objects
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ");
        vec![
            Self::moves(
                Phase::AboveGrasp,
                format!("{name}: move above the grasp of objects [{objects}]"),
                vec![self.travel(pose(travel))],
            ),
            self.gripper(
                Phase::Open,
                format!("{name}: open fully"),
                self.config.gripper.open_count,
            ),
            Self::moves(
                Phase::Descend,
                format!("{name}: descend"),
                vec![self.contact(pose(self.config.heights.grasp), vertical)],
            ),
            self.gripper(
                Phase::Close,
                format!("{name}: close with limited force"),
                self.config.gripper.closed_count,
            ),
            Self::moves(
                Phase::ToBin,
                format!("{name}: move to the bin"),
                vec![
                    self.flowing(self.contact(pose(travel), vertical)),
                    self.travel(over_bin),
                ],
            ),
            self.gripper(
                Phase::Drop,
                format!("{name}: open to drop"),
                self.config.gripper.open_count,
            ),
        ]
    }

    /// Checks every step against the safety envelope and speed limit; `first_index` is the index of
    /// `steps[0]` in the whole run (for the error message).
    ///
    /// # Errors
    /// [`Error::UnsafeMotion`] naming the first step that breaks a limit.
    pub fn check(&self, steps: &[Step], first_index: usize) -> Result<()> {
        let safety = &self.config.safety;
        for (k, step) in steps.iter().enumerate() {
            let refuse = |reason: String| {
                Err(Error::UnsafeMotion {
                    step: first_index + k,
                    label: step.label.clone(),
                    reason,
                })
            };
            let Action::Move { moves } = &step.action else {
                continue;
            };
            for m in moves {
                if !(m.speed.is_finite() && m.speed > 0.0 && m.speed <= safety.max_speed) {
                    return refuse(format!(
                        "speed {:.3} m/s exceeds the limit {:.3} m/s",
                        m.speed, safety.max_speed
                    ));
                }
                let p = Point3::from(m.to.position);
                for axis in 0..3 {
                    if !(p[axis] >= safety.min[axis] && p[axis] <= safety.max[axis]) {
                        return refuse(format!(
                            "pose ({:.4}, {:.4}, {:.4}) m leaves the envelope along {} \
                             ([{:.4}, {:.4}] m)",
                            p.x,
                            p.y,
                            p.z,
                            ["x", "y", "z"][axis],
                            safety.min[axis],
                            safety.max[axis]
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

/// Expected duration of a straight move of `length` metres at `speed` with `acceleration`
/// (a trapezoidal or triangular speed profile), seconds.
pub fn move_duration(length: f64, speed: f64, acceleration: f64) -> f64 {
    crate::time_model::trapezoid_seconds(length, speed, acceleration)
}
