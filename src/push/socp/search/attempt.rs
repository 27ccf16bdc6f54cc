//! A solved row made into pushes: members that barely move held in place, the pushes sequenced,
//! fewer pushes where that is faster, and the row judged at its intended grasp.

use nalgebra::{Point2, Vector2};

use super::{Attempt, EQUAL_TIME, Realised, Refusal, Search};
use crate::push::row::{Motion, RowSolution};
use crate::push::socp::rows::intended_grasp;
use crate::push::{Push, PushPlan, SkipReason, SkippedPush};
use crate::scene::ObjectId;

impl Search<'_> {
    /// Turns a solved row into pushes: targets held where members barely move (solving again with
    /// them fixed when `refine`), then pushes sequenced. A member that cannot be pushed (its path
    /// is blocked, or there is no room for the fingers) is held where it is and the row solved
    /// again around it, while another member is left to move.
    fn realise(
        &self,
        (axis, order): (&Vector2<f64>, &[usize]),
        base: &Motion,
        mut fixed: Vec<bool>,
        (mut targets, mut centre_line): (Vec<Point2<f64>>, f64),
        mut refine: bool,
    ) -> std::result::Result<Realised, Refusal> {
        let (scene, members, starts) = (self.scene, &self.members, &self.starts);
        loop {
            if refine {
                let refined = self.solve(axis, order, &base.holding(&fixed));
                if refined.solved() {
                    targets = refined.targets;
                    centre_line = refined.centre_line;
                }
            }
            for (m, &hold) in fixed.iter().enumerate() {
                if hold
                    || nalgebra::distance(&targets[m], &starts[m]) < self.socp.problem.min_push()
                {
                    targets[m] = starts[m];
                }
            }
            match self.socp.sequence(scene, members, &targets, axis) {
                Ok(pushes) => return Ok((pushes, targets, centre_line)),
                Err((object, reason)) => {
                    let stuck = members
                        .iter()
                        .position(|&i| scene.objects()[i].id == object)
                        .filter(|&m| !fixed[m]);
                    let Some(m) = stuck else {
                        return Err((object, reason));
                    };
                    fixed[m] = true;
                    if fixed.iter().all(|&f| f) {
                        return Err((object, reason));
                    }
                    let refined = self.solve(axis, order, &base.holding(&fixed));
                    if !refined.solved() {
                        return Err((object, reason));
                    }
                    targets = refined.targets;
                    centre_line = refined.centre_line;
                    refine = false;
                }
            }
        }
    }

    /// The row `solution` along `axis` in `order` as pushes, judged at its intended grasp.
    pub(super) fn attempt(
        &self,
        axis: &Vector2<f64>,
        order: &[usize],
        solution: &RowSolution,
        base: &Motion,
    ) -> std::result::Result<Attempt, Refusal> {
        let (scene, members, starts) = (self.scene, &self.members, &self.starts);
        let moves: Vec<f64> = (0..members.len())
            .map(|m| nalgebra::distance(&solution.targets[m], &starts[m]))
            .collect();
        let mut fixed: Vec<bool> = moves
            .iter()
            .zip(&base.fixed)
            .map(|(&d, &held)| held || d < self.socp.problem.min_push())
            .collect();
        // Every member within `min_push` of its target does not make the row: their small
        // offsets add up across it. Only the member nearest its target is held then (with
        // those the row holds anyway), and the row solved again around it says whether the
        // others must still move.
        if fixed.iter().all(|&f| f) {
            let nearest = (0..moves.len())
                .filter(|&m| !base.fixed[m])
                .min_by(|&a, &b| moves[a].total_cmp(&moves[b]))
                .unwrap_or(0);
            fixed = (0..moves.len())
                .map(|m| m == nearest || base.fixed[m])
                .collect();
        }
        let refine = fixed.iter().any(|&f| f);
        let realised = self.realise(
            (axis, order),
            base,
            fixed.clone(),
            (solution.targets.clone(), solution.centre_line),
            refine,
        )?;
        let (pushes, targets, centre_line) =
            self.fewer_pushes((axis, order), base, &fixed, realised);
        if let Some((pushed, held)) = self.shoves_out(&pushes, &targets) {
            return Err((pushed, SkipReason::WouldShoveOut { object: held }));
        }
        let skipped = (0..members.len())
            .filter(|&m| targets[m] == starts[m])
            .map(|m| SkippedPush {
                object: scene.objects()[members[m]].id,
                reason: SkipReason::AlreadyInPlace,
            })
            .collect();
        let jaws = intended_grasp(
            axis,
            &targets,
            &self.outlines,
            centre_line,
            self.gripper.stroke,
        );
        let held = self.socp.row_is_held(scene, members, &pushes, &jaws);
        let objective = pushes.iter().map(|p| p.distance).sum();
        Ok(Attempt {
            plan: PushPlan {
                pushes,
                skipped,
                intended_grasp: Some(jaws),
                row_held: Some(held),
            },
            held,
            objective,
            axis: *axis,
            status: solution.status,
        })
    }

    /// Fewer pushes: a push costs a fixed time (lowering and raising the fork) that many
    /// centimetres of pushing take; the row with one more member held where it is may take less
    /// time, though not less distance. Returns the fastest of `realised` and those rows.
    fn fewer_pushes(
        &self,
        (axis, order): (&Vector2<f64>, &[usize]),
        base: &Motion,
        fixed: &[bool],
        realised: Realised,
    ) -> Realised {
        let (pushes, targets, centre_line) = realised;
        if pushes.len() < 2 {
            return (pushes, targets, centre_line);
        }
        let (scene, members, starts) = (self.scene, &self.members, &self.starts);
        let seconds = |pushes: &[Push]| -> f64 {
            pushes
                .iter()
                .map(|p| {
                    self.socp
                        .problem
                        .time_model()
                        .nominal_push_seconds(self.gripper, p.distance)
                })
                .sum()
        };
        // A member pushed up to one held in place can shove it; near the workspace edge, out of
        // the workspace. Of pushes that take about as long, those that hold the members furthest
        // from the edge are kept (the nearer member moves, inward).
        let held_room = |targets: &[Point2<f64>]| {
            (0..members.len())
                .filter(|&m| targets[m] == starts[m])
                .flat_map(|m| {
                    scene
                        .workspace()
                        .room(scene.world_polygon(members[m]).bounding_box())
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut best = seconds(&pushes);
        let mut best_room = held_room(&targets);
        let mut best_shoves = self.shoves_out(&pushes, &targets).is_some();
        let mut chosen = (pushes, targets, centre_line);
        for m in 0..members.len() {
            if fixed[m] || chosen.1[m] == starts[m] {
                continue;
            }
            let mut held = fixed.to_vec();
            held[m] = true;
            let refined = self.solve(axis, order, &base.holding(&held));
            if !refined.solved() {
                continue;
            }
            let Ok(fewer) = self.realise(
                (axis, order),
                base,
                held,
                (refined.targets, refined.centre_line),
                false,
            ) else {
                continue;
            };
            let time = seconds(&fewer.0);
            let room = held_room(&fewer.1);
            let shoves = self.shoves_out(&fewer.0, &fewer.1).is_some();
            let as_fast = (time - best).abs() <= EQUAL_TIME;
            let better = time < best - EQUAL_TIME
                || (as_fast && room > best_room + 1e-9)
                || (as_fast && (room - best_room).abs() <= 1e-9 && time < best - 1e-9);
            // A row that shoves no held member out comes first, then the fastest.
            if (best_shoves && !shoves) || (shoves == best_shoves && better) {
                best = time;
                best_room = room;
                best_shoves = shoves;
                chosen = fewer;
            }
        }
        chosen
    }

    /// A push of the row and a member held in place ahead of it (its centroid further along the
    /// push than the pushed one's start) with less than `held_edge_margin` between its outline
    /// and the workspace's edge along that push: the ids of the pushed and the held object.
    fn shoves_out(&self, pushes: &[Push], targets: &[Point2<f64>]) -> Option<(ObjectId, ObjectId)> {
        let margin = self.socp.settings.held_edge_margin;
        if margin <= 0.0 {
            return None;
        }
        let (scene, members, starts) = (self.scene, &self.members, &self.starts);
        let workspace = scene.workspace();
        let id = |m: usize| scene.objects()[members[m]].id;
        pushes.iter().find_map(|push| {
            let pushed = (0..members.len()).find(|&m| id(m) == push.object)?;
            (0..members.len())
                .filter(|&m| targets[m] == starts[m])
                .find(|&m| {
                    (starts[m] - starts[pushed]).dot(&push.direction) > 0.0
                        && scene
                            .world_polygon(members[m])
                            .vertices()
                            .iter()
                            .any(|v| workspace.room_along(v, &push.direction) < margin)
                })
                .map(|held| (push.object, id(held)))
        })
    }
}
