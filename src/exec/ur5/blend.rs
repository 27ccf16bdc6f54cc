//! A trip as robot steps ([`Translator::trip`]), and blended moves: a motion step whose last move
//! flows into the next (a blend radius at its end) is joined with the step after it into one
//! URScript program, so the controller turns that corner without stopping (`formulations/ur5.md`,
//! "Blends").

use super::motion::{Action, LinearMove, Step, Translator};
use crate::grasp::Grasp;
use crate::plan::Rider;
use crate::push::Push;
use crate::scene::Scene;

/// Blends narrower than this are not made: the move stops instead, metres.
const MIN_BLEND: f64 = 0.0005;

impl Translator {
    /// All steps of one trip: its pushes in order, then its grasp and the trip to the bin, moves
    /// that flow into the next joined into one program ([`Translator::blend`]). `looks` lists after
    /// how many pushes the loop looked at the table (a plan's `looks`): the rise before a look stops,
    /// and the arm moves out of the camera's view when the configuration says where
    /// ([`Translator::out_of_view`]).
    pub fn trip(
        &self,
        scene: &Scene,
        pushes: &[Push],
        looks: &[usize],
        riders: &[Rider],
        grasp: &Grasp,
        trip: usize,
    ) -> Vec<Step> {
        let mut steps = Vec::new();
        let mut jaws = None;
        for (k, push) in pushes.iter().enumerate() {
            let name = format!("trip {trip}, push {} of {}", k + 1, pushes.len());
            let mut push_steps = self.fork_push(scene, push, &name, jaws);
            let look = looks.contains(&(k + 1));
            if look {
                stop_at_end(&mut push_steps);
            }
            let away = look
                .then(|| last_rotation(&push_steps))
                .flatten()
                .and_then(|rotation| self.out_of_view(rotation, &name));
            steps.extend(push_steps);
            steps.extend(away);
            jaws = Some(push.fork.opening);
        }
        for (k, rider) in riders.iter().enumerate() {
            let name = format!("trip {trip}, rider {} of {}", k + 1, riders.len());
            steps.extend(self.place_rider(scene, rider, &name));
        }
        steps.extend(self.grasp_and_trip(scene, grasp, &format!("trip {trip}, grasp")));
        self.blend(steps, None)
    }

    /// Joins every motion step whose last move flows on ([`LinearMove::blend`] > 0) with the motion
    /// step after it into one program, so the controller turns that corner without stopping. Each
    /// blend is narrowed to half of either move it joins (UR blends may not overlap), moves shorter
    /// than `MIN_BLEND` (0.5 mm) inside a program are left out, and a move that flows into nothing (a
    /// gripper step or the end) stops. `from` is where the tool stands before `steps` (`None`:
    /// unknown, the first move's length does not narrow its blend).
    pub fn blend(&self, steps: Vec<Step>, from: Option<[f64; 3]>) -> Vec<Step> {
        join_flowing(steps, from)
    }
}

/// As [`Translator::blend`].
fn join_flowing(steps: Vec<Step>, from: Option<[f64; 3]>) -> Vec<Step> {
    let flows_on = |step: &Step| match &step.action {
        Action::Move { moves } => moves.last().is_some_and(|m| m.blend > 0.0),
        Action::Gripper { .. } => false,
    };
    let mut joined: Vec<Step> = Vec::with_capacity(steps.len());
    for step in steps {
        match (joined.last_mut(), step.action) {
            (Some(last), Action::Move { moves }) if flows_on(last) => {
                if let Action::Move { moves: before } = &mut last.action {
                    before.extend(moves);
                }
                last.label = joined_label(&last.label, &step.label);
                last.phase = step.phase;
            }
            (_, action) => joined.push(Step { action, ..step }),
        }
    }
    let mut at = from;
    for step in &mut joined {
        let Action::Move { moves } = &mut step.action else {
            continue;
        };
        let start = at;
        let count = moves.len();
        let mut kept: Vec<LinearMove> = Vec::with_capacity(count);
        for (k, m) in moves.drain(..).enumerate() {
            if k + 1 < count && at.is_some_and(|a| distance(a, m.to.position) < MIN_BLEND) {
                continue; // a move to where the tool stands already
            }
            at = Some(m.to.position);
            kept.push(m);
        }
        let mut previous = start;
        for k in 0..kept.len() {
            let here = kept[k].to.position;
            let radius = kept.get(k + 1).map_or(0.0, |next| {
                let into = previous.map_or(f64::INFINITY, |p| distance(p, here));
                kept[k]
                    .blend
                    .min(0.5 * distance(here, next.to.position))
                    .min(0.5 * into)
            });
            kept[k].blend = if radius >= MIN_BLEND { radius } else { 0.0 };
            previous = Some(here);
        }
        *moves = kept;
    }
    joined
}

/// Two step labels as one: `trip 2, push 1: rise, then trip 2, grasp: move above …`, the second's
/// name left out when the two share it.
fn joined_label(first: &str, second: &str) -> String {
    match (first.split_once(": "), second.split_once(": ")) {
        (Some((name, _)), Some((same, what))) if name == same => format!("{first}, then {what}"),
        _ => format!("{first}, then {second}"),
    }
}

/// Distance between two points, metres.
pub(super) fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

/// The tool's rotation at the end of the last move of `steps`.
pub fn last_rotation(steps: &[Step]) -> Option<[f64; 3]> {
    steps.iter().rev().find_map(|step| match &step.action {
        Action::Move { moves } => moves.last().map(|m| m.to.rotation),
        Action::Gripper { .. } => None,
    })
}

/// Makes the last move of `steps` stop at its end (the arm waits there, for a look).
pub fn stop_at_end(steps: &mut [Step]) {
    if let Some(Step {
        action: Action::Move { moves },
        ..
    }) = steps.last_mut()
        && let Some(m) = moves.last_mut()
    {
        m.blend = 0.0;
    }
}
