//! Settings of the physics simulator, each default justified by a physical fact.

use serde::{Deserialize, Serialize};

use super::SimCamera;
use crate::error::Result;

/// How the two fingers are driven.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum FingerDrive {
    /// One motor closes both fingers symmetrically about the gripper's centre (the 2F-85's linkage);
    /// the motor stops when the mean squeeze reaches the grip force and holds it.
    #[default]
    Coupled,
    /// Each finger has its own motor, each limited to the grip force.
    Independent,
}

/// A setting checked against its range: field, value, range and why the range.
type Check = (&'static str, f64, (f64, f64), &'static str);

/// Physical parameters, motions and noise of the simulated robot and table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SimSettings {
    /// Coulomb friction between a finger pad and an object. Default 0.4, the low end of what is known:
    /// 0.4 is the plates' value in the public multi-object grasping simulation, public MuJoCo models of
    /// the 2F-85 give its silicone pads 0.6–0.7, and frictional tape on silicone may reach 0.8 (sources
    /// in `formulations/references.md`). Nobody has measured it for the paper's objects, so the
    /// experiment `friction.toml` sweeps 0.4–0.8 and the write-up says which conclusions survive.
    pub friction_finger: f64,
    /// Coulomb friction between two objects. Default 0.4: the Push-MOG objects carry frictional tape on
    /// their faces, taken as grippy as the pads (the grasp model's value too); swept with the pads.
    pub friction_object: f64,
    /// Coulomb friction between an object and the table. Default 0.3: plastic or wood on a laminate
    /// table (handbook values 0.2–0.4). The public MOG simulation's 0.05 was chosen to make planar
    /// sliding easy, not measured.
    pub friction_table: f64,
    /// Density of objects without a mass, kg/m³. Default 1000, as the grasp model.
    pub density: f64,
    /// Mass of each finger, kilograms. Default 0.05 (a 2F-85 fingertip and pad are tens of grams).
    pub finger_mass: f64,
    /// Height of each finger pad, metres. Default 0.0375: the 2F-85 fingertip pad is two stacked
    /// 22 × 18.75 mm boxes in public MuJoCo models built from the manufacturer's CAD (the pad's width,
    /// 22 mm, is the gripper's `plate_length`; `formulations/references.md`).
    pub finger_height: f64,
    /// How the fingers are driven. Default `coupled`: the 2F-85 moves both fingers from one motor
    /// through a linkage, so they close symmetrically about the gripper's centre and a finger that
    /// touches first pushes the object toward the centre. `independent` gives each finger its own
    /// force-limited motor (the simulator before this setting existed), kept for comparison.
    pub fingers: FingerDrive,
    /// Stiffness between the motor and each pad in the coupled drive, N/m. Default 20 000: a pad yields
    /// 1 mm under the 20 N grip (silicone pad and linkage play; an estimate, not a measurement). It
    /// sets how far one finger can lag the other, not the grip force.
    pub linkage_stiffness: f64,
    /// Squeezing force limit of the jaws, newtons. Default 20 (the 2F-85's lowest force setting).
    pub grip_force: f64,
    /// Closing speed of the jaws, m/s. Default 0.05 (within the 2F-85's 0.02–0.15 m/s).
    pub jaw_speed: f64,
    /// Speed of fork pushes, m/s. Default 0.05, as the time model.
    pub push_speed: f64,
    /// Vertical speed of the arm near the table, m/s. Default 0.1.
    pub vertical_speed: f64,
    /// Height of the fingertips above the table during a fork push, as a fraction of the pushed object's
    /// height. Default 0.5 (the paper lowers the gripper to the object's mid-height).
    pub push_height_fraction: f64,
    /// Height of the fingertips above the table when grasping, metres. Default 0.002.
    pub grasp_height: f64,
    /// How high a grasp lifts, metres. Default 0.1.
    pub lift: f64,
    /// With riders aboard, how far the lifted row is then carried sideways (along the plates)
    /// before what is carried is counted, metres. Default 0.3, the time model's bin distance.
    /// Without riders nothing is carried sideways: what the jaws hold after the lift stays held.
    pub carry: f64,
    /// Top speed of that carry, m/s. Default 0.25, the time model's `travel_speed`.
    pub carry_speed: f64,
    /// Acceleration and deceleration of that carry, m/s². Default 1.2, the time model's
    /// `travel_acceleration` (a UR's usual linear moves).
    pub carry_acceleration: f64,
    /// Time allowed for things to come to rest after closing and after lifting, seconds. Default 0.3.
    pub settle: f64,
    /// Longest time a stage runs on after its action, the arm still, until every object on it is at
    /// rest (slower than 5 cm/s and 2 rad/s: no longer falling or sliding), before the poses are
    /// kept, seconds. Default 2.0. Objects beyond the next actions' `reach` keep the poses kept, so
    /// one still falling would otherwise stay frozen mid-fall (`formulations/grasping.md`, "Objects
    /// still moving when an action ends"). The cell's next look comes later than this after a
    /// trip: the run to the bin and back alone is about 2.8 s of arm motion in the time model
    /// (`formulations/picks-per-hour.md`). 0 keeps the poses as the action ends, as before.
    pub rest_wait: f64,
    /// Simulation time step, seconds. Default 0.002 (500 Hz; objects move under 0.2 mm per step).
    pub time_step: f64,
    /// Natural frequency of rapier's soft contact constraints, hertz. Default 1000. A contact under
    /// force `F` on a body of mass `m` sinks about `F / (m (2π f)²)`: rapier's default 30 Hz lets a
    /// 20 N squeeze push a finger 19 mm into a 30 g object (seen here: the fingers closed through it),
    /// 1000 Hz keeps that under 0.02 mm, as between rigid plastic parts.
    pub contact_frequency: f64,
    /// Objects within this distance of an action's path take part in its simulation; the rest cannot be
    /// reached and stay as they are, metres. Default 0.12.
    pub reach: f64,
    /// Standard deviation of observed positions, metres. Default 0.002 (segmentation of an overhead RGB-D
    /// image; a fixed calibration offset is not modelled).
    pub perception_position: f64,
    /// Standard deviation of observed yaws, radians. Default 0.035 (2°).
    pub perception_yaw: f64,
    /// Standard deviation of where the gripper actually goes, metres. Default 0.001.
    pub actuation_position: f64,
    /// Standard deviation of the gripper's actual yaw, radians. Default 0.0175 (1°).
    pub actuation_yaw: f64,
    /// Objects tilted more than this from upright count as toppled, radians. Default 0.35 (20°).
    pub topple_angle: f64,
    /// An overhead depth camera whose frames are perceived at each look (`camera.rs`). Default
    /// none: each object's pose is reported with the noise above.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camera: Option<SimCamera>,
}

impl Default for SimSettings {
    fn default() -> Self {
        Self {
            friction_finger: 0.4,
            friction_object: 0.4,
            friction_table: 0.3,
            density: 1000.0,
            finger_mass: 0.05,
            finger_height: 0.0375,
            fingers: FingerDrive::Coupled,
            linkage_stiffness: 20_000.0,
            grip_force: 20.0,
            jaw_speed: 0.05,
            push_speed: 0.05,
            vertical_speed: 0.1,
            push_height_fraction: 0.5,
            grasp_height: 0.002,
            lift: 0.1,
            carry: 0.3,
            carry_speed: 0.25,
            carry_acceleration: 1.2,
            settle: 0.3,
            rest_wait: 2.0,
            time_step: 0.002,
            contact_frequency: 1000.0,
            reach: 0.12,
            perception_position: 0.002,
            perception_yaw: 0.035,
            actuation_position: 0.001,
            actuation_yaw: 0.0175,
            topple_angle: 0.35,
            camera: None,
        }
    }
}

impl SimSettings {
    /// The settings with every noise set to zero.
    pub fn noiseless() -> Self {
        Self::noiseless_from(&Self::default())
    }

    /// `settings` with every noise set to zero (the camera's depth noise too, if there is a camera).
    pub fn noiseless_from(settings: &Self) -> Self {
        Self {
            perception_position: 0.0,
            perception_yaw: 0.0,
            actuation_position: 0.0,
            actuation_yaw: 0.0,
            camera: settings.camera.clone().map(|camera| SimCamera {
                noise: crate::perception::DepthNoise {
                    sigma_per_square_metre: 0.0,
                    dropped: 0.0,
                    flying: 0.0,
                    ..camera.noise
                },
                ..camera
            }),
            ..settings.clone()
        }
    }

    /// Checks every field against its range; each range has a physical or computational reason,
    /// given in the error.
    ///
    /// # Errors
    /// [`crate::Error::InvalidField`] naming the field and the range.
    pub fn validate(&self) -> Result<()> {
        let checks = [
            self.material_checks(),
            self.motion_checks(),
            self.noise_checks(),
        ];
        for (field, value, range, why) in checks.into_iter().flatten() {
            crate::error::in_range("sim", field, value, range, why)?;
        }
        self.camera.as_ref().map_or(Ok(()), SimCamera::validate)
    }

    /// Friction, density and the fingers' build: field, value, range and why.
    fn material_checks(&self) -> Vec<Check> {
        const FRICTION: (f64, f64) = (0.0, 2.0);
        const FRICTION_WHY: &str = "Coulomb friction of dry solids";
        vec![
            (
                "friction_finger",
                self.friction_finger,
                FRICTION,
                FRICTION_WHY,
            ),
            (
                "friction_object",
                self.friction_object,
                FRICTION,
                FRICTION_WHY,
            ),
            (
                "friction_table",
                self.friction_table,
                FRICTION,
                FRICTION_WHY,
            ),
            (
                "density",
                self.density,
                (100.0, 20_000.0),
                "kg/m³, from foam to tungsten",
            ),
            (
                "finger_mass",
                self.finger_mass,
                (0.005, 1.0),
                "kg; a 2F-85 fingertip is tens of grams",
            ),
            (
                "finger_height",
                self.finger_height,
                (0.005, 0.1),
                "m; the 2F-85 pad is 37.5 mm",
            ),
            (
                "linkage_stiffness",
                self.linkage_stiffness,
                (1e3, 1e6),
                "N/m; softer lets a finger sag centimetres, stiffer needs shorter steps",
            ),
            (
                "grip_force",
                self.grip_force,
                (1.0, 235.0),
                "N; the 2F-85 grips with 20–235 N",
            ),
        ]
    }

    /// Speeds, forces, heights and the time step.
    fn motion_checks(&self) -> Vec<Check> {
        vec![
            (
                "jaw_speed",
                self.jaw_speed,
                (0.005, 0.5),
                "m/s; the 2F-85 closes at 0.02–0.15 m/s",
            ),
            (
                "push_speed",
                self.push_speed,
                (0.005, 0.5),
                "m/s; slower takes hours to simulate, faster is not quasi-static",
            ),
            (
                "vertical_speed",
                self.vertical_speed,
                (0.005, 1.0),
                "m/s; a UR5 tool moves at most about 1 m/s",
            ),
            (
                "push_height_fraction",
                self.push_height_fraction,
                (0.01, 1.0),
                "of the object's height",
            ),
            (
                "grasp_height",
                self.grasp_height,
                (0.0, 0.05),
                "m above the table; the objects are a few centimetres tall",
            ),
            (
                "lift",
                self.lift,
                (0.01, 0.5),
                "m; enough to see what is carried, short enough to simulate",
            ),
            (
                "carry",
                self.carry,
                (0.0, 2.0),
                "m; a bin within a few metres",
            ),
            (
                "carry_speed",
                self.carry_speed,
                (0.01, 2.0),
                "m/s; a UR5 tool moves at most about 1 m/s",
            ),
            (
                "carry_acceleration",
                self.carry_acceleration,
                (0.05, 20.0),
                "m/s²; a UR's linear moves default to 1.2",
            ),
            (
                "settle",
                self.settle,
                (0.0, 5.0),
                "s of simulated waiting after a lift",
            ),
            (
                "rest_wait",
                self.rest_wait,
                (0.0, 10.0),
                "s of simulated waiting for objects still moving after an action",
            ),
            (
                "time_step",
                self.time_step,
                (1e-5, 1e-2),
                "s; below 10 µs a second of motion is over 100,000 steps, above 10 ms contacts are unstable",
            ),
            (
                "contact_frequency",
                self.contact_frequency,
                (10.0, 1e4),
                "Hz of the soft contact constraints",
            ),
            ("reach", self.reach, (0.02, 1.0), "m around an action"),
        ]
    }

    /// Perception and actuation noise, and when an object counts as toppled.
    fn noise_checks(&self) -> Vec<Check> {
        vec![
            (
                "perception_position",
                self.perception_position,
                (0.0, 0.05),
                "m of noise",
            ),
            (
                "perception_yaw",
                self.perception_yaw,
                (0.0, 0.5),
                "rad of noise",
            ),
            (
                "actuation_position",
                self.actuation_position,
                (0.0, 0.05),
                "m of noise",
            ),
            (
                "actuation_yaw",
                self.actuation_yaw,
                (0.0, 0.5),
                "rad of noise",
            ),
            (
                "topple_angle",
                self.topple_angle,
                (0.01, 1.57),
                "rad from upright",
            ),
        ]
    }
}
