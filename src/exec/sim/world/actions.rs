//! What a stage does, one call per motion of the gripper: wait, travel, descend, close, open; and
//! the objects' poses read back.

use rapier3d_f64::math::{Rotation, Vector};
use rapier3d_f64::prelude::*;

use super::Stage;
use crate::exec::sim::prism::Prism;
use crate::exec::sim::settings::FingerDrive;
use crate::scene::Pose as PlanarPose;

/// Objects slower than this count as at rest, m/s. A fall or a slide is faster; rapier's contacts
/// keep a rider on a row, and the row under it, rocking at about 1.3 cm/s for seconds (traced in
/// `formulations/grasping.md`, "Objects still moving when an action ends"), which is not waited
/// out.
const REST_SPEED: f64 = 0.05;
/// And turning slower than this, rad/s (that rocking turns at up to about 1.7 rad/s).
const REST_SPIN: f64 = 2.0;

impl Stage {
    /// Lets the world run with the palm still, seconds.
    pub fn wait(&mut self, seconds: f64) {
        let steps = (seconds / self.time_step).ceil() as usize;
        for _ in 0..steps {
            self.move_palm_to(self.palm_translation);
            self.step();
        }
    }

    fn move_palm_to(&mut self, translation: Vector) {
        self.palm_translation = translation;
        if let Some(palm) = self.world.bodies.get_mut(self.palm) {
            palm.set_next_kinematic_position(Pose::from_parts(translation, self.palm_rotation));
        }
    }

    /// Moves the palm in a straight line by `offset` at `speed`, simulating each step.
    pub fn travel(&mut self, offset: Vector, speed: f64) {
        let distance = offset.length();
        if distance == 0.0 {
            return;
        }
        let steps = (distance / (speed * self.time_step)).ceil().max(1.0) as usize;
        let start = self.palm_translation;
        for k in 1..=steps {
            self.move_palm_to(start + offset * (k as f64 / steps as f64));
            self.step();
        }
    }

    /// Moves the palm in a straight line by `offset` while turning it by `turn` radians about the
    /// vertical, at `speed` (the faster of the palm's centre and the fingertips' arc), simulating
    /// each step.
    pub fn travel_turning(&mut self, offset: Vector, turn: f64, speed: f64) {
        let arc = turn.abs() * self.drive.opening / 2.0;
        let distance = offset.length().max(arc);
        if distance == 0.0 {
            return;
        }
        let steps = (distance / (speed * self.time_step)).ceil().max(1.0) as usize;
        let (start, facing) = (self.palm_translation, self.palm_rotation);
        for k in 1..=steps {
            let share = k as f64 / steps as f64;
            self.palm_rotation = Rotation::from_rotation_z(turn * share) * facing;
            self.move_palm_to(start + offset * share);
            self.step();
        }
    }

    /// Moves the palm by `offset` with a trapezoidal speed profile: `acceleration` up to `speed`
    /// (or less on a short move), then down again. The palm's position follows the profile step by
    /// step, so its speed changes by at most `acceleration × time_step` from one step to the next.
    pub fn carry(&mut self, offset: Vector, speed: f64, acceleration: f64) {
        let distance = offset.length();
        if distance == 0.0 {
            return;
        }
        let top = speed.min((distance * acceleration).sqrt());
        let ramp = top / acceleration;
        let cruise = (distance - top * ramp) / top;
        let total = 2.0 * ramp + cruise;
        let covered = |t: f64| {
            if t < ramp {
                0.5 * acceleration * t * t
            } else if t < ramp + cruise {
                0.5 * top * ramp + top * (t - ramp)
            } else {
                let left = (total - t).max(0.0);
                distance - 0.5 * acceleration * left * left
            }
        };
        let steps = (total / self.time_step).ceil().max(1.0) as usize;
        let (start, direction) = (self.palm_translation, offset / distance);
        for k in 1..=steps {
            let t = (k as f64 * self.time_step).min(total);
            self.move_palm_to(start + direction * covered(t));
            self.step();
        }
    }

    /// Height of the fingertips above the table, metres.
    pub fn tip_height(&self) -> f64 {
        self.palm_translation.z - self.half_finger
    }

    /// Lowers the palm by `depth` at `speed`, stopping at once if a finger comes down on top of an
    /// object; returns that object's index in the prisms.
    pub fn descend(&mut self, depth: f64, speed: f64) -> Option<usize> {
        if depth <= 0.0 {
            return None;
        }
        let steps = (depth / (speed * self.time_step)).ceil().max(1.0) as usize;
        let start = self.palm_translation;
        for k in 1..=steps {
            self.move_palm_to(start - Vector::Z * (depth * k as f64 / steps as f64));
            self.step();
            if let Some(index) = self.landed_on() {
                return Some(index);
            }
        }
        None
    }

    /// Closes the jaws at `speed` with at most `force` per finger, until they stop moving (or are shut);
    /// returns the final opening between plate centres.
    pub fn close(&mut self, speed: f64, force: f64, timeout: f64) -> f64 {
        match self.drive.kind {
            FingerDrive::Coupled => self.drive.closing = Some((speed, force)),
            FingerDrive::Independent => {
                for (side, handle) in [-1.0, 1.0].into_iter().zip(self.joints) {
                    if let Some(joint) = self.world.impulse_joints.get_mut(handle, true) {
                        joint
                            .data
                            .set_motor_velocity(JointAxis::LinX, -side * speed, 1000.0);
                        joint.data.set_motor_max_force(JointAxis::LinX, force);
                    }
                }
            }
        }
        let steps = (timeout / self.time_step).ceil() as usize;
        let mut still = 0;
        let mut last = self.opening();
        for _ in 0..steps {
            self.move_palm_to(self.palm_translation);
            self.step();
            let now = self.opening();
            // Stopped: under a tenth of the commanded speed for 0.05 s.
            if (last - now).abs() < 0.1 * speed * self.time_step {
                still += 1;
                if still as f64 * self.time_step >= 0.05 {
                    break;
                }
            } else {
                still = 0;
            }
            last = now;
        }
        self.opening()
    }

    /// Current distance between the plate centres, metres.
    pub fn opening(&self) -> f64 {
        let position = |h: RigidBodyHandle| {
            self.world
                .bodies
                .get(h)
                .map_or(Vector::ZERO, |b| b.translation())
        };
        (position(self.fingers[1]) - position(self.fingers[0])).length()
    }

    /// Opens the jaws to `opening` between plate centres at `speed`, then waits until they get there.
    pub fn open(&mut self, opening: f64, speed: f64) {
        self.drive.closing = None;
        let from = self.opening();
        self.drive.opening = opening;
        let (stiffness, damping) = (self.drive.stiffness, self.drive.damping);
        for (side, handle) in [-1.0, 1.0].into_iter().zip(self.joints) {
            if let Some(joint) = self.world.impulse_joints.get_mut(handle, true) {
                match self.drive.kind {
                    FingerDrive::Coupled => {
                        joint.data.set_motor_position(
                            JointAxis::LinX,
                            side * opening / 2.0,
                            stiffness,
                            damping,
                        );
                    }
                    FingerDrive::Independent => {
                        joint.data.set_motor_position(
                            JointAxis::LinX,
                            side * opening / 2.0,
                            2000.0,
                            100.0,
                        );
                        joint.data.set_motor_max_force(JointAxis::LinX, 200.0);
                    }
                }
            }
        }
        self.wait((opening - from).abs() / speed + 0.05);
    }

    /// Each member's index in the prisms and its planar pose now.
    pub fn poses(&self) -> Vec<(usize, PlanarPose)> {
        self.members
            .iter()
            .filter_map(|&(index, handle)| {
                let body = self.world.bodies.get(handle)?;
                let x_axis = *body.rotation() * Vector::X;
                let t = body.translation();
                Some((index, PlanarPose::new(t.x, t.y, x_axis.y.atan2(x_axis.x))))
            })
            .collect()
    }

    /// Whether every object on the stage is at rest: slower than [`REST_SPEED`] and turning slower
    /// than [`REST_SPIN`]. Read after an action's last wait (50 ms or more), an object in the air has
    /// been falling for longer than the 5 ms it takes to pass `REST_SPEED`.
    fn at_rest(&self) -> bool {
        self.members.iter().all(|&(_, handle)| {
            self.world.bodies.get(handle).is_none_or(|body| {
                body.linvel().length() <= REST_SPEED && body.angvel().length() <= REST_SPIN
            })
        })
    }

    /// Lets the world run on with the palm still until every object is at rest, or `rest_wait`
    /// has passed, then writes the simulated poses back into `prisms`. An object still falling
    /// when its poses are kept would stay mid-fall wherever no later action reaches it.
    pub fn write_back(&mut self, prisms: &mut [Prism]) {
        let steps = (self.rest_wait / self.time_step).ceil() as usize;
        for _ in 0..steps {
            if self.at_rest() {
                break;
            }
            self.move_palm_to(self.palm_translation);
            self.step();
        }
        for &(index, handle) in &self.members {
            if let Some(body) = self.world.bodies.get(handle) {
                prisms[index].translation = body.translation();
                prisms[index].rotation = *body.rotation();
            }
        }
    }
}
