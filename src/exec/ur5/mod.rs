//! The UR5 + Robotiq 2F-85 executor: plans become robot motions over the controller's own interfaces.
//!
//! - [`RobotConfig`] (`config.rs`): the cell, read from TOML; [`Calibration`] (`calibration.rs`) fits
//!   the table-to-base transform to measured point pairs by least squares and reports the residual.
//! - [`Translator`] (`motion.rs`): fork pushes (five steps) and grasps with their trips (six steps) as
//!   tool moves and gripper commands in the base frame, checked against the safety envelope.
//! - `blend.rs`: a trip's steps, free-air moves joined with the next into one blended program.
//! - `urscript.rs`: each motion step as one URScript program; the listings of a dry run.
//! - [`RobotLink`] (`link.rs`): [`DryRun`] records, [`Live`] talks to the secondary interface (30002),
//!   RTDE (30004) and the Robotiq URCap socket (63352). `rtde.rs` holds the RTDE packages.
//! - [`fake`]: loopback fakes of the controller and the gripper that speak the same protocols, with
//!   scripted faults; the tests drive whole plans through them.
//! - [`Ur5`]: an [`Executor`] over a link and an observation source, for the closed loop;
//!   [`execute_plan`] runs a recorded plan open-loop.
//!
//! Safety: every step is checked against the envelope before any byte of it is sent (a whole plan
//! before its first step; in the closed loop, each push or grasp before its own steps). After a fault
//! (lost connection, gripper fault, timeout) nothing more is sent: the error names the step reached
//! and the last known state. The geometry is written out in `formulations/ur5.md`.

mod blend;
mod calibration;
mod camera;
mod config;
pub mod fake;
mod fits;
mod link;
mod motion;
mod observation;
mod rtde;
mod tally;
mod urscript;

use serde::{Deserialize, Serialize};

pub use calibration::{Calibration, Correspondence};
pub use camera::{DepthLook, Look};
pub use config::{
    BinConfig, CalibrationConfig, ControllerConfig, GripperConfig, HeightsConfig, LookConfig,
    RobotConfig, SafetyConfig, SpeedsConfig, TimeoutsConfig,
};
pub use fits::{FIT_TOLERANCE, check_trip_fits};
pub use link::{DryRun, Fault, Live, RobotLink};
pub use motion::{Action, LinearMove, Phase, Step, ToolPose, Translator, move_duration};
pub use observation::Observation;
pub use rtde::RobotState;
pub use tally::{MATCH_RADIUS, NOT_IN_VIEW, OUTSIDE};
pub use urscript::{gripper_command, gripper_line, listing, motion_program, program, step_list};

use crate::error::{Error, Result};
use crate::exec::{Executor, GraspResult, Landing};
use crate::grasp::Grasp;
use crate::plan::{Plan, Rider};
use crate::push::Push;
use crate::scene::{Object, ObjectId, Scene, SceneSpec};

/// Carries out robot steps over a link, numbering them, checking them and stopping for good at the
/// first fault.
#[derive(Debug)]
pub struct StepRunner<L: RobotLink> {
    translator: Translator,
    link: L,
    steps: Vec<Step>,
    next_token: Option<i32>,
    stopped: Option<String>,
    progress: Option<fn(usize, &Step)>,
}

impl<L: RobotLink> StepRunner<L> {
    /// A runner for a translator's configuration over `link`.
    pub fn new(translator: Translator, link: L) -> Self {
        Self {
            translator,
            link,
            steps: Vec::new(),
            next_token: None,
            stopped: None,
            progress: None,
        }
    }

    /// Calls `report(index, step)` after each step completes (a command line prints it).
    #[must_use]
    pub fn with_progress(mut self, report: fn(usize, &Step)) -> Self {
        self.progress = Some(report);
        self
    }

    /// The translator.
    pub fn translator(&self) -> &Translator {
        &self.translator
    }

    /// The link.
    pub fn link(&self) -> &L {
        &self.link
    }

    /// Every step carried out so far, in order.
    pub fn steps(&self) -> &[Step] {
        &self.steps
    }

    /// Checks `steps` against the envelope, then carries them out one by one.
    ///
    /// # Errors
    /// [`Error::UnsafeMotion`] before anything is sent; [`Error::RobotStopped`] at the first fault,
    /// after which every later call fails at once without sending.
    pub fn run(&mut self, steps: Vec<Step>) -> Result<()> {
        let first = self.steps.len();
        if let Some(reason) = &self.stopped {
            return Err(Error::RobotStopped {
                step: first,
                label: steps.first().map_or_else(String::new, |s| s.label.clone()),
                reason: format!("not sent: the robot stopped earlier ({reason})"),
                completed: first,
                last_state: self.link.last_state(),
            });
        }
        self.translator.check(&steps, first)?;
        for step in steps {
            let index = self.steps.len();
            let outcome = match &step.action {
                Action::Move { moves } => {
                    let token = *self
                        .next_token
                        .get_or_insert_with(|| self.link.first_token());
                    self.next_token = Some(token.wrapping_add(1).max(1));
                    let expected = self.expected_duration(moves);
                    let text =
                        motion_program(self.translator.config(), &step.label, moves, index, token);
                    self.link.run_program(&text, token, expected)
                }
                &Action::Gripper {
                    position,
                    speed,
                    force,
                } => self
                    .link
                    .run_gripper(&gripper_line(position, speed, force), position)
                    .map(|_| ()),
            };
            if let Err(reason) = outcome {
                self.stopped = Some(reason.clone());
                return Err(Error::RobotStopped {
                    step: index,
                    label: step.label,
                    reason,
                    completed: index,
                    last_state: self.link.last_state(),
                });
            }
            if let Some(report) = self.progress {
                report(index, &step);
            }
            self.steps.push(step);
        }
        Ok(())
    }

    fn expected_duration(&self, moves: &[LinearMove]) -> f64 {
        let mut total = 0.0;
        let mut from: Option<[f64; 3]> = self.last_position();
        for m in moves {
            // From an unknown pose, assume a move across the whole envelope.
            let length = from.map_or_else(
                || {
                    let s = &self.translator.config().safety;
                    (0..3)
                        .map(|i| (s.max[i] - s.min[i]).powi(2))
                        .sum::<f64>()
                        .sqrt()
                },
                |f| blend::distance(f, m.to.position),
            );
            total += move_duration(length, m.speed, m.acceleration);
            from = Some(m.to.position);
        }
        total
    }

    /// Where the tool stood at the end of the last motion step carried out, if any.
    pub fn last_position(&self) -> Option<[f64; 3]> {
        self.steps.iter().rev().find_map(|s| match &s.action {
            Action::Move { moves } => moves.last().map(|m| m.to.position),
            Action::Gripper { .. } => None,
        })
    }
}

/// Translates every trip of a recorded plan, checks all steps against the envelope, then carries them
/// out in order (open loop: no observation between trips).
///
/// # Errors
/// [`Error::UnsafeMotion`] before anything is sent, [`Error::RobotStopped`] at the first fault.
pub fn execute_plan<L: RobotLink>(runner: &mut StepRunner<L>, plan: &Plan) -> Result<()> {
    let steps = plan_steps(runner.translator(), plan)?;
    runner.run(steps) // checks every step before sending the first
}

/// Every robot step of a recorded plan.
///
/// # Errors
/// [`Error::InvalidField`] when a trip's scene is invalid, or a trip does not fit the configured
/// gripper ([`check_trip_fits`], naming the trip and the field).
pub fn plan_steps(translator: &Translator, plan: &Plan) -> Result<Vec<Step>> {
    let mut steps = Vec::new();
    for (t, trip) in plan.trips.iter().enumerate() {
        let scene = Scene::new(trip.scene.to_spec())?;
        check_trip_fits(
            &translator.config().gripper,
            scene.gripper(),
            &trip.plan.pushes,
            Some(&trip.plan.grasp),
            t + 1,
        )?;
        let looks: Vec<usize> = trip.looks.iter().map(|look| look.after_pushes).collect();
        steps.extend(translator.trip(
            &scene,
            &trip.plan.pushes,
            &looks,
            &trip.plan.riders,
            &trip.plan.grasp,
            t + 1,
        ));
    }
    Ok(steps)
}

/// What the robot did in one trip of a closed loop, kept by [`Ur5`] as it goes so that a run that stops
/// on a fault loses nothing of what happened.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExecutedTrip {
    /// The observation the trip was planned on.
    pub scene: SceneSpec,
    /// The fork pushes completed.
    pub pushes: Vec<Push>,
    /// The riders put down on the row (`formulations/stacking.md`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub riders: Vec<Rider>,
    /// The grasp, once its trip to the bin completed (`None` when the run stopped before).
    pub grasp: Option<Grasp>,
    /// The objects the trip carried: those its grasp held (or a rider it put down) that are gone
    /// from the look after it (`tally.rs`).
    pub carried: Vec<ObjectId>,
    /// The objects gone from a look of this trip that it did not carry: lost to planning
    /// ([`Executor::lost`] gives the reason).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lost: Vec<ObjectId>,
}

/// The UR5 as an [`Executor`] for the closed loop: pushes and grasps go to the link; after each trip
/// the table is observed again. Of the objects gone from it, those the grasp held count as carried
/// and the others as lost, seen past the workspace's edge or not seen at all (`tally.rs`).
///
/// Observations must keep object ids from one to the next: a scene file or command must track them
/// itself; a camera's look keeps them with the last table, moved by the pushes since, as its prior.
#[derive(Debug)]
pub struct Ur5<L: RobotLink> {
    runner: StepRunner<L>,
    observation: Observation,
    scene: Option<Scene>,
    /// Whether the arm has pushed since the table was last read.
    pushed: bool,
    /// The pushes made since the table was last read (a camera's prior moves their objects).
    pushes: Vec<Push>,
    /// The jaws' opening when the gripper's last command was a fork push's (`None` after a grasp:
    /// the jaws are fully open at the bin).
    jaws: Option<f64>,
    /// The rise of the last fork push, held back to flow into the next action's first move (the
    /// tool waits at the push's end until then).
    rise: Option<Step>,
    record: Vec<ExecutedTrip>,
    /// What became of the objects the loop knew.
    tally: tally::Tally,
}

impl<L: RobotLink> Ur5<L> {
    /// An executor over `runner` that reads the table from `observation`.
    pub fn new(runner: StepRunner<L>, observation: Observation) -> Self {
        Self {
            runner,
            observation,
            scene: None,
            pushed: false,
            pushes: Vec::new(),
            jaws: None,
            rise: None,
            record: Vec::new(),
            tally: tally::Tally::default(),
        }
    }

    /// The step runner (steps carried out, the link).
    pub fn runner(&self) -> &StepRunner<L> {
        &self.runner
    }

    /// The trips so far; the last one may be unfinished (no grasp yet) when the run stopped in it.
    pub fn trips(&self) -> &[ExecutedTrip] {
        &self.record
    }

    /// The trip under way: the last record while its grasp is pending, else a new one.
    fn current_trip(&mut self) -> Result<&mut ExecutedTrip> {
        if self.record.last().is_none_or(|t| t.grasp.is_some()) {
            let scene = self.scene()?.to_spec();
            self.record.push(ExecutedTrip {
                scene,
                pushes: Vec::new(),
                riders: Vec::new(),
                grasp: None,
                carried: Vec::new(),
                lost: Vec::new(),
            });
        }
        let last = self.record.len() - 1;
        Ok(&mut self.record[last])
    }

    /// Carries out `steps` after the held-back rise, if any, joined with it where they flow on.
    fn run_after_rise(&mut self, steps: Vec<Step>) -> Result<()> {
        let steps: Vec<Step> = self.rise.take().into_iter().chain(steps).collect();
        let from = self.runner.last_position();
        let steps = self.runner.translator().blend(steps, from);
        self.runner.run(steps)
    }

    /// Makes the held-back rise, if any, stopping at its top (before a look, or a new run).
    fn finish_rise(&mut self) -> Result<()> {
        match self.rise.take() {
            Some(mut rise) => {
                blend::stop_at_end(std::slice::from_mut(&mut rise));
                self.runner.run(vec![rise])
            }
            None => Ok(()),
        }
    }

    fn scene(&self) -> Result<&Scene> {
        self.scene
            .as_ref()
            .ok_or_else(|| Error::misuse("ur5 executor", "act before reset(): no table was given"))
    }

    /// Looks at the table again: the tally takes what is gone (`held`, the objects a grasp made
    /// since held), the objects newly lost go to the trip's record, and the carried are returned.
    fn look(&mut self, held: &[ObjectId]) -> Result<Vec<ObjectId>> {
        let look = self
            .observation
            .look_after(self.scene.as_ref(), &self.pushes)?;
        let before = self.scene.as_ref().ok_or_else(|| {
            Error::misuse("ur5 executor", "act before reset(): no table was given")
        })?;
        let (carried, lost) = self
            .tally
            .after_look(before, &look.scene, held, &look.past_edge);
        if let Some(trip) = self.record.last_mut() {
            trip.lost.extend(lost);
        }
        self.scene = Some(look.scene);
        self.pushed = false;
        self.pushes.clear();
        Ok(carried)
    }
}

impl<L: RobotLink> Executor for Ur5<L> {
    fn name(&self) -> &'static str {
        "ur5"
    }

    /// Starts a new run on `scene` (the first observation); the trip record starts afresh.
    fn reset(&mut self, scene: &Scene) -> Result<()> {
        self.finish_rise()?;
        self.scene = Some(scene.clone());
        self.pushed = false;
        self.pushes.clear();
        self.jaws = None;
        self.record.clear();
        self.tally.clear();
        Ok(())
    }

    fn push(&mut self, push: &Push) -> Result<Option<Landing>> {
        let done = self.current_trip()?.pushes.len();
        let name = format!("trip {}, push {}", self.record.len(), done + 1);
        check_trip_fits(
            &self.runner.translator().config().gripper,
            self.scene()?.gripper(),
            std::slice::from_ref(push),
            None,
            self.record.len(),
        )?;
        let mut steps = self
            .runner
            .translator()
            .fork_push(self.scene()?, push, &name, self.jaws);
        // The rise waits for the next action, whose first move it flows into.
        let rise = steps.pop();
        self.run_after_rise(steps)?;
        self.rise = rise;
        self.pushed = true;
        self.pushes.push(push.clone());
        self.jaws = Some(push.fork.opening);
        self.current_trip()?.pushes.push(push.clone());
        Ok(None)
    }

    /// The rider's steps (`Translator::place_rider`); the rise waits for the next action, as a
    /// push's does.
    fn place(&mut self, rider: &Rider) -> Result<Option<Landing>> {
        let placed = self.current_trip()?.riders.len();
        let name = format!("trip {}, rider {}", self.record.len(), placed + 1);
        let mut steps = self
            .runner
            .translator()
            .place_rider(self.scene()?, rider, &name);
        let rise = steps.pop();
        self.run_after_rise(steps)?;
        self.rise = rise;
        self.jaws = None;
        self.current_trip()?.riders.push(rider.clone());
        Ok(None)
    }

    fn grasp(&mut self, grasp: &Grasp) -> Result<GraspResult> {
        self.current_trip()?;
        let name = format!("trip {}, grasp", self.record.len());
        check_trip_fits(
            &self.runner.translator().config().gripper,
            self.scene()?.gripper(),
            &[],
            Some(grasp),
            self.record.len(),
        )?;
        // Objects taken from past the workspace's edge are not on the table planned on; the
        // travel clears them too.
        let past: Vec<Object> = self
            .tally
            .past_edge()
            .into_iter()
            .filter(|o| grasp.objects.contains(&o.id))
            .collect();
        let steps =
            self.runner
                .translator()
                .grasp_and_trip_over(self.scene()?, &past, grasp, &name);
        self.jaws = None;
        self.run_after_rise(steps)?;
        let trip = self.current_trip()?;
        trip.grasp = Some(grasp.clone());
        let mut held = grasp.objects.clone();
        held.extend(trip.riders.iter().map(|r| r.object));
        let carried = self.look(&held)?;
        if let Some(trip) = self.record.last_mut() {
            trip.carried.clone_from(&carried);
        }
        Ok(GraspResult::carried(carried))
    }

    /// The table as last read: read again when nothing was read yet or the arm has pushed since
    /// (after a grasp the table is read anyway, to see what was carried).
    fn observe(&mut self) -> Result<Scene> {
        let rotation = self
            .rise
            .as_ref()
            .and_then(|rise| blend::last_rotation(std::slice::from_ref(rise)));
        self.finish_rise()?;
        if self.scene.is_none() || self.pushed {
            // A look during a trip: the arm leaves the camera's view first, if told where to.
            let away = rotation.filter(|_| self.pushed).and_then(|rotation| {
                let name = format!("trip {}, look", self.record.len());
                self.runner.translator().out_of_view(rotation, &name)
            });
            if let Some(step) = away {
                self.runner.run(vec![step])?;
            }
            self.look(&[])?;
        }
        Ok(self.scene()?.clone())
    }

    /// The objects gone from a look that no grasp held (`tally.rs`): seen past the workspace's
    /// edge (with a camera), or not in view.
    fn lost(&self) -> Vec<(ObjectId, &'static str)> {
        self.tally.lost()
    }

    /// The lost objects a camera saw whole past the workspace's edge at the last look, where it saw
    /// them, with their ids.
    fn past_edge(&self) -> Vec<Object> {
        self.tally.past_edge()
    }
}
