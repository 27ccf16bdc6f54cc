//! How long the robot takes: the seconds behind "a trip costs a grasp plus travel to the bin" and "a
//! push costs a fixed time plus distance over push speed", fitted to timings of a real UR5 cell.
//!
//! An action is a sequence of commands, each costing its motion plus a fixed settle time:
//! - an **arm move** of length `d`: a trapezoidal speed profile with top speed `v` and acceleration
//!   `a`, `d/v + v/a` when `d ≥ v²/a`, else `2√(d/a)`, plus `arm_settle`;
//! - a **push stroke** of length `L`: `L / v_push` (slow, quasi-static; its ramps are negligible), plus
//!   `arm_settle`;
//! - a **jaw command** changing the opening by `Δ`: `|Δ| / v_jaw`, plus `gripper_settle`;
//! - a **blended move** (`blend_free_moves`, default on): an arm move through free air that flows
//!   into the next arm move without stopping, as a UR controller does given a blend radius: its
//!   motion, no settle. A push's rise (unless the loop looks after it), the travel to a push and a
//!   grasp's lift are such moves; the UR5 executor sends them blended.
//!
//! A trip starts and ends at the bin with the jaws fully open. Each fork push follows the Push-MOG
//! paper's five steps: jaws to the push's opening, travel above the approach point, descend
//! `approach_height`, push, rise; the jaw command is left out (neither sent by the UR5 executor nor
//! charged) when the jaws already stand at that opening, as they do for every fork push after a
//! trip's first. The grasp follows its six: travel above the grasp, jaws to the planned
//! opening, descend, close onto the row, lift and travel to the bin, open fully. Travel is `bin_distance`
//! from the bin to the first action, then the straight distance between successive actions inside the
//! workspace. Every observation (each trip, each planning attempt that found nothing, each look
//! during a trip) costs `perception` plus `observation` seconds: the camera, then the planner. For
//! a look during a trip the arm first leaves the camera's view, `look_away` (0 unless set; one
//! stopping move), and its next action starts that far away.
//!
//! **The fit.** Public logs of a UR5 with a Robotiq 2F-85 and the bin adjacent
//! (`experiments/data/`, 1,245 timed grasp-and-trip attempts) give a median execution of 12.2 s per
//! grasp-and-trip and a median of 1.7 s of planning per attempt. The execution hardly varies (standard
//! deviation 0.03 s) although the grasps lie up to 0.6 m apart, so that cell's time is in fixed
//! per-command costs, not in travel. One figure fixes one parameter: the settle time, taken equal for
//! arm and jaw commands, is set so the model's single-object trip (every move stopping as the real
//! cell's did: seven stops, six when blending; the arm's usual linear moves, the 2F-85's fastest
//! jaws, an object of the library's median width) takes the logs' median. The
//! observation time is the logs' median planning time; those logs do not time perception, which is
//! a cell parameter of its own (`perception`, 0 unless set). `experiments/README.md` sets the model's figures
//! beside the logs' (12.2 s per trip, 212 picks per hour for single-object picking).

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::scene::Gripper;

/// Width of the object in the model's nominal single-object trip, metres: the median minimum grasp
/// diameter of the built-in object library (28 mm).
pub const NOMINAL_WIDTH: f64 = 0.028;

/// Gap left on each side of an object when a single-object grasp opens the jaws, metres (the
/// single-object planner's default clearance).
const NOMINAL_CLEARANCE: f64 = 0.01;

/// Speeds, accelerations, distances and fixed costs of the arm, the gripper and the cell.
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
    /// Fixed time of every arm move beyond its motion (sending the command, the controller's ramp and
    /// settling, confirming the end), seconds. Default: fitted to the real cell's 12.2 s trips (see the
    /// module docs).
    pub arm_settle: f64,
    /// Fixed time of every jaw command beyond its motion (the gripper's command round trip and its
    /// settling), seconds. Default: the fitted settle time, as `arm_settle`.
    pub gripper_settle: f64,
    /// Planning per observation of the table, seconds. Default 1.715: the median planning time per
    /// attempt in the real cell's logs, timed from the arrival of the object state to the publication
    /// of the grasp (so it holds the planner's compute, not the camera's).
    pub observation: f64,
    /// Perception per observation, seconds: taking the camera's frame and turning it into a scene,
    /// charged with `observation`. Default 0: no public log of the real cell times its perception,
    /// which ran apart from the timed planner. Set it for the camera of your cell.
    pub perception: f64,
    /// Whether an arm move through free air that flows into another (a push's rise into the travel
    /// to the next push or to the grasp, the travel to a push into its descent, a grasp's lift into
    /// the run to the bin) blends through its waypoint instead of stopping there, as a UR controller
    /// does for a `movel` given a blend radius. Such a move is charged its motion and no settle.
    /// Default true. `false` stops after every move, as the real cell whose trips fixed the settle
    /// time did (the fit is made that way whatever this says).
    pub blend_free_moves: bool,
    /// Distance the arm travels from where it stops above the table to a pose out of the camera's
    /// view for a look during a trip (after pushes), metres; its next action starts the same
    /// distance away. The move there stops (the look waits for it). Default 0: the arm waits where
    /// it stopped, so the camera must see the table past it. An overhead camera sees the gripper
    /// above the table; set this to the way to where the arm waits (`bin_distance` for an arm that
    /// waits beside the bin), and the UR5 executor's `look.wait` to that pose. Left out of
    /// written settings when 0, so settings written before it existed hash alike.
    #[serde(skip_serializing_if = "is_zero")]
    pub look_away: f64,
}

fn is_zero(value: &f64) -> bool {
    *value == 0.0
}

/// The fitted settle time per command, seconds (`fit_settle` on the real cell's logs; the test
/// `time_model_fit` in `tests/time_model.rs` derives it again from `experiments/data/`).
const FITTED_SETTLE: f64 = 1.0792;

/// The real cell's median perception and planning time per attempt, seconds (same test).
const FITTED_OBSERVATION: f64 = 1.715;

impl Default for TimeModel {
    fn default() -> Self {
        Self {
            travel_speed: 0.25,
            travel_acceleration: 1.2,
            approach_height: 0.10,
            bin_distance: 0.30,
            jaw_speed: 0.15,
            push_speed: 0.05,
            arm_settle: FITTED_SETTLE,
            gripper_settle: FITTED_SETTLE,
            observation: FITTED_OBSERVATION,
            perception: 0.0,
            blend_free_moves: true,
            look_away: 0.0,
        }
    }
}

/// One command of an action, as the time model charges it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Command {
    /// An arm move of this length, metres, that stops at its end.
    Arm(f64),
    /// An arm move of this length, metres, that blends into the next arm move without stopping:
    /// charged its motion (as if it stopped: the corner cut by the blend is not credited), no settle.
    Through(f64),
    /// A push stroke of this length, metres.
    Push(f64),
    /// A jaw command changing the opening by this much, metres.
    Jaws(f64),
}

/// Seconds of a straight move of `distance` metres with a trapezoidal speed profile of top speed `v`
/// (m/s) and acceleration `a` (m/s²): `d/v + v/a` when `d ≥ v²/a`, else `2√(d/a)`; 0 for no distance.
pub fn trapezoid_seconds(distance: f64, v: f64, a: f64) -> f64 {
    if distance <= 0.0 {
        0.0
    } else if distance >= v * v / a {
        distance / v + v / a
    } else {
        2.0 * (distance / a).sqrt()
    }
}

/// Where the arm is between two actions of a trip.
#[derive(Clone, Copy)]
enum At {
    /// Away from the table, this far from every point of the workspace, metres.
    Away(f64),
    /// Above this point of the table.
    Over(Point2<f64>),
}

/// A fork push as the time model sees it: where the fingers are lowered and where they rise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PushPath {
    /// Gripper centre where the fingers are lowered.
    pub approach: Point2<f64>,
    /// Gripper centre where the push ends.
    pub end: Point2<f64>,
    /// Opening between plate centres during the push, metres (the fork opening for a fork push).
    pub opening: f64,
    /// Whether the arm stops after this push's rise for a look at the table (the loop looks after
    /// pushing), so the rise does not blend into the next move.
    pub look_after: bool,
}

/// A rider as the time model sees it: its pick, and where the jaws let it go on the row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RiderPath {
    /// The single-object grasp that picks it.
    pub pick: GraspPath,
    /// Gripper centre where the jaws open to let it go.
    pub release: Point2<f64>,
}

/// A grasp as the time model sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GraspPath {
    /// Gripper centre.
    pub center: Point2<f64>,
    /// Opening between plate centres before closing, metres.
    pub opening: f64,
    /// Opening between plate centres once closed on the row, metres.
    pub closed: f64,
}

impl TimeModel {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let checks: [(&str, f64, (f64, f64), &str); 11] = [
            (
                "travel_speed",
                self.travel_speed,
                (0.01, 5.0),
                "m/s of an arm's linear moves",
            ),
            (
                "travel_acceleration",
                self.travel_acceleration,
                (0.01, 50.0),
                "m/s² of an arm's linear moves",
            ),
            (
                "approach_height",
                self.approach_height,
                (0.0, 1.0),
                "m above the table",
            ),
            (
                "bin_distance",
                self.bin_distance,
                (0.0, 100.0),
                "m to the bin",
            ),
            ("jaw_speed", self.jaw_speed, (0.005, 1.0), "m/s of the jaws"),
            (
                "push_speed",
                self.push_speed,
                (0.001, 1.0),
                "m/s of a fork push",
            ),
            ("arm_settle", self.arm_settle, (0.0, 60.0), "s per arm move"),
            (
                "gripper_settle",
                self.gripper_settle,
                (0.0, 60.0),
                "s per jaw command",
            ),
            (
                "observation",
                self.observation,
                (0.0, 600.0),
                "s of planning per observation",
            ),
            (
                "perception",
                self.perception,
                (0.0, 600.0),
                "s of perception per observation",
            ),
            (
                "look_away",
                self.look_away,
                (0.0, 100.0),
                "m to where the arm waits out of the camera's view",
            ),
        ];
        for (field, value, range, why) in checks {
            crate::error::in_range("time_model", field, value, range, why)?;
        }
        Ok(())
    }

    /// Seconds of one observation of the table: perception, then planning on what it saw.
    pub fn look_seconds(&self) -> f64 {
        self.perception + self.observation
    }

    /// Seconds a look during a trip adds to the arm's commands, at most: the move out of the
    /// camera's view ([`TimeModel::look_away`]) with its settle, and the motion of the way back
    /// (which replaces the travel from where the arm stopped; 0 when the arm waits where it
    /// stopped). The look itself is [`TimeModel::look_seconds`].
    pub fn look_away_seconds(&self) -> f64 {
        if self.look_away > 0.0 {
            self.seconds(&[Command::Arm(self.look_away)]) + self.move_seconds(self.look_away)
        } else {
            0.0
        }
    }

    /// Seconds of the motion of a straight arm move of `distance` metres (no settle time).
    pub fn move_seconds(&self, distance: f64) -> f64 {
        trapezoid_seconds(distance, self.travel_speed, self.travel_acceleration)
    }

    /// Seconds of these commands, each its motion plus its settle time.
    pub fn seconds(&self, commands: &[Command]) -> f64 {
        commands
            .iter()
            .map(|command| match *command {
                Command::Arm(d) => self.move_seconds(d) + self.arm_settle,
                Command::Through(d) => self.move_seconds(d),
                Command::Push(d) => d.max(0.0) / self.push_speed + self.arm_settle,
                Command::Jaws(d) => d.abs() / self.jaw_speed + self.gripper_settle,
            })
            .sum()
    }

    /// Seconds of one trip as executed: its fork pushes, then the grasp and the run to the bin and
    /// back (no observation time).
    pub fn trip_seconds(&self, gripper: &Gripper, pushes: &[PushPath], grasp: &GraspPath) -> f64 {
        self.seconds(&self.trip_commands(gripper, pushes, grasp))
    }

    /// Seconds of a trip that puts `riders` on its row before the grasp (no observation time).
    pub fn trip_seconds_with_riders(
        &self,
        gripper: &Gripper,
        pushes: &[PushPath],
        riders: &[RiderPath],
        grasp: &GraspPath,
    ) -> f64 {
        self.seconds(&self.trip_commands_with_riders(gripper, pushes, riders, grasp))
    }

    /// The commands of one trip, in order, as [`TimeModel::trip_seconds`] charges them: per push a
    /// jaw command to its opening (left out when the jaws stand there already), travel, descend,
    /// push, rise; then travel to the grasp, jaws to the grasp's opening, descend, close, lift, to the
    /// bin, open fully. With [`TimeModel::blend_free_moves`] the travel to a push, a push's rise
    /// (unless a look or a jaw command follows it) and the lift are [`Command::Through`]: each flows
    /// into the next arm move, which is always one through free air. A push the loop looks after is
    /// followed by the move out of the camera's view when [`TimeModel::look_away`] is set.
    pub fn trip_commands(
        &self,
        gripper: &Gripper,
        pushes: &[PushPath],
        grasp: &GraspPath,
    ) -> Vec<Command> {
        self.trip_commands_with_riders(gripper, pushes, &[], grasp)
    }

    /// As [`TimeModel::trip_commands`], with each rider put on the row after the pushes and before
    /// the grasp (`formulations/stacking.md`): travel to its pick, jaws to the pick's opening,
    /// descend, close on it, lift (blended into the next move), travel to where it is let go,
    /// descend, open to the pick's opening, rise (blended into the travel that follows).
    pub fn trip_commands_with_riders(
        &self,
        gripper: &Gripper,
        pushes: &[PushPath],
        riders: &[RiderPath],
        grasp: &GraspPath,
    ) -> Vec<Command> {
        let mut commands = Vec::with_capacity(5 * pushes.len() + 7);
        // Where the arm is: `Away(d)` is `d` from every point of the workspace (the bin, or where
        // it waits out of the camera's view for a look).
        let mut at = At::Away(self.bin_distance);
        let mut jaws = gripper.stroke;
        let travel = |to: Point2<f64>, at: &mut At| {
            let distance = match *at {
                At::Away(d) => d,
                At::Over(from) => nalgebra::distance(&from, &to),
            };
            *at = At::Over(to);
            distance
        };
        let flowing = |distance: f64, blends: bool| {
            if blends && self.blend_free_moves {
                Command::Through(distance)
            } else {
                Command::Arm(distance)
            }
        };
        for (k, push) in pushes.iter().enumerate() {
            if push.opening != jaws {
                commands.push(Command::Jaws(jaws - push.opening));
                jaws = push.opening;
            }
            commands.push(flowing(travel(push.approach, &mut at), true));
            commands.push(Command::Arm(self.approach_height));
            commands.push(Command::Push(nalgebra::distance(&push.approach, &push.end)));
            // The rise stops for a look, or for the jaw command of a push at another opening.
            let jaws_next = pushes
                .get(k + 1)
                .is_some_and(|next| next.opening != push.opening);
            commands.push(flowing(
                self.approach_height,
                !push.look_after && !jaws_next,
            ));
            at = At::Over(push.end);
            if push.look_after && self.look_away > 0.0 {
                // Out of the camera's view for the look, stopping there.
                commands.push(Command::Arm(self.look_away));
                at = At::Away(self.look_away);
            }
        }
        for rider in riders {
            let pick = &rider.pick;
            commands.push(Command::Arm(travel(pick.center, &mut at)));
            commands.push(Command::Jaws(pick.opening - jaws));
            commands.push(Command::Arm(self.approach_height));
            commands.push(Command::Jaws(pick.opening - pick.closed));
            commands.push(flowing(self.approach_height, true));
            commands.push(Command::Arm(travel(rider.release, &mut at)));
            commands.push(Command::Arm(self.approach_height));
            commands.push(Command::Jaws(pick.opening - pick.closed));
            commands.push(flowing(self.approach_height, true));
            jaws = pick.opening;
        }
        commands.push(Command::Arm(travel(grasp.center, &mut at)));
        commands.push(Command::Jaws(grasp.opening - jaws));
        commands.push(Command::Arm(self.approach_height));
        commands.push(Command::Jaws(grasp.opening - grasp.closed));
        commands.push(flowing(self.approach_height, true));
        commands.push(Command::Arm(self.bin_distance));
        commands.push(Command::Jaws(gripper.stroke - grasp.closed));
        commands
    }

    /// The grasp of a single object of [`NOMINAL_WIDTH`], jaws opened by the single-object planner's
    /// clearance on each side.
    pub fn nominal_grasp(gripper: &Gripper) -> GraspPath {
        let closed = NOMINAL_WIDTH + gripper.plate_thickness;
        GraspPath {
            center: Point2::origin(),
            opening: (closed + 2.0 * NOMINAL_CLEARANCE).min(gripper.stroke),
            closed,
        }
    }

    /// Seconds of a trip without pushes that grasps a single object of the nominal width: the
    /// planning estimate of a trip's cost.
    pub fn nominal_trip_seconds(&self, gripper: &Gripper) -> f64 {
        self.trip_seconds(gripper, &[], &Self::nominal_grasp(gripper))
    }

    /// Seconds one fork push of `distance` metres adds to a trip as its first push, estimated with
    /// the fingers lowered `distance` from where the previous action ended: the planning estimate of a
    /// push's cost.
    pub fn nominal_push_seconds(&self, gripper: &Gripper, distance: f64) -> f64 {
        // Jaws to the fork opening, then the push's own moves.
        self.seconds(&[Command::Jaws(gripper.stroke - gripper.fork_push_opening())])
            + self.nominal_later_push_seconds(distance)
    }

    /// Seconds a fork push of `distance` metres adds to a trip after another fork push, the jaws
    /// already at the fork opening: travel, descend, push, rise (the travel and the rise flowing on
    /// without a stop when [`TimeModel::blend_free_moves`]).
    pub fn nominal_later_push_seconds(&self, distance: f64) -> f64 {
        let distance = distance.max(0.0);
        let flowing = |d: f64| {
            if self.blend_free_moves {
                Command::Through(d)
            } else {
                Command::Arm(d)
            }
        };
        self.seconds(&[
            flowing(distance),
            Command::Arm(self.approach_height),
            Command::Push(distance),
            flowing(self.approach_height),
        ])
    }

    /// The settle time per command that makes the nominal single-object trip last `trip_seconds`
    /// with the other parameters as they are (equal for arm and jaw commands), every move stopping
    /// as the real cell's did (whatever [`TimeModel::blend_free_moves`] says); `None` when the
    /// motions alone already take longer.
    pub fn fit_settle(&self, trip_seconds: f64) -> Option<f64> {
        let bare = Self {
            arm_settle: 0.0,
            gripper_settle: 0.0,
            blend_free_moves: false,
            ..self.clone()
        };
        let motion = bare.nominal_trip_seconds(&Gripper::default());
        // The nominal trip has 7 commands: travel, open, descend, close, lift, to the bin, open.
        let settle = (trip_seconds - motion) / 7.0;
        (settle >= 0.0).then_some(settle)
    }
}

#[cfg(test)]
mod tests;
