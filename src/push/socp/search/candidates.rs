//! The rows a search tries: each closing axis with its bound, whether a perfect row along it is
//! held, the order along it and how the members may move; and how a row is solved for it.

use nalgebra::Vector2;

use super::{Candidate, SNAP, Search};
use crate::push::flush::{PairRow, cone_directions, flush_face, pair_axis};
use crate::push::row::{Motion, RowSolution, lower_bound};

impl Search<'_> {
    /// A row to try along `axis`, if one can fit the jaws there at all.
    fn candidate(
        &self,
        axis: Vector2<f64>,
        order: Vec<usize>,
        motion: Option<Motion>,
    ) -> Option<Candidate> {
        let bound = lower_bound(&self.problem(), &axis)?;
        let proxy = self.socp.settings.prefer_held_rows
            && self
                .socp
                .proxy_held(&self.outlines, &self.masses, &order, &axis, self.gripper);
        Some(Candidate {
            bound,
            axis,
            proxy,
            order,
            motion,
        })
    }

    /// Rows to try, by their bound: closing axes that can hold a row, with their lower bounds,
    /// whether a perfect row along them is held by the grasp model, the order along them and how
    /// each member may move. Flush pushes of a pair try each face of each member that faces the
    /// other, along the axis the pair then lines up on; larger clusters try every axis, each moving
    /// member's push turned to its nearest face normal once the row is solved.
    pub(super) fn candidates(&self) -> Vec<Candidate> {
        let settings = &self.socp.settings;
        let (starts, outlines) = (&self.starts, &self.outlines);
        let problem = self.problem();
        let mut axes: Vec<Candidate> = if settings.flush && self.members.len() == 2 {
            let row = PairRow {
                row_limit: problem.row_limit,
                gap: problem.gap,
                straddle: problem.straddle,
                tight: Some(settings.flush_gap),
            };
            let cone = settings.flush_cone;
            let tries: Vec<(usize, Vector2<f64>, Vector2<f64>)> = (0..2)
                .flat_map(|m| {
                    self.faces[m].iter().flat_map(move |face| {
                        cone_directions(&face.normal, cone)
                            .into_iter()
                            .map(move |direction| (m, face.normal, direction))
                    })
                })
                .collect();
            tries
                .into_iter()
                .filter_map(|(m, normal, direction)| {
                    let other = 1 - m;
                    let towards = starts[other] - starts[m];
                    let margin = settings.flush_margin;
                    if direction.dot(&towards) <= 0.0
                        || flush_face(&outlines[m], margin, &direction, cone).is_none()
                    {
                        return None;
                    }
                    let longest = towards.norm() + problem.row_limit;
                    let (axis, _) = pair_axis(
                        (starts[m], &outlines[m]),
                        (starts[other], &outlines[other]),
                        &direction,
                        row,
                        longest,
                    )?;
                    let mut motion = Motion::free(2);
                    motion.fixed[other] = true;
                    motion.along[m] = Some(normal);
                    // Tight: the pushed one goes on until it nearly touches the other.
                    let widths: f64 = [axis, -axis]
                        .iter()
                        .map(|d| outlines[0].support(d) + outlines[1].support(d))
                        .sum();
                    motion.limit = Some(problem.row_limit.min(widths + settings.flush_gap));
                    self.candidate(axis, vec![other, m], Some(motion))
                })
                .collect()
        } else {
            let free = (!settings.flush).then(|| Motion::free(self.members.len()));
            self.socp
                .axes(starts, outlines)
                .into_iter()
                .filter_map(|axis| self.candidate(axis, self.natural(&axis), free.clone()))
                .collect()
        };
        axes.sort_by(|a, b| a.bound.total_cmp(&b.bound));
        axes
    }

    /// The row along `axis` in `order`, solved with the candidate's motion; without one (flush
    /// pushes of three or more), solved freely first and then again with each moving member's
    /// push along its nearest face normal (within 45°; members without one are held).
    pub(super) fn solve_candidate(
        &self,
        axis: &Vector2<f64>,
        order: &[usize],
        motion: Option<&Motion>,
    ) -> Option<(RowSolution, Motion)> {
        if self.out_of_time() {
            return None;
        }
        if let Some(motion) = motion {
            let solution = self.solve(axis, order, motion);
            return solution.solved().then(|| (solution, motion.clone()));
        }
        let n = self.members.len();
        let free = self.solve(axis, order, &Motion::free(n));
        if !free.solved() {
            return None;
        }
        let mut motion = Motion::free(n);
        for m in 0..n {
            let moved = free.targets[m] - self.starts[m];
            let widest = SNAP + self.socp.settings.flush_cone;
            let nearest = self.faces[m]
                .iter()
                .map(|face| face.normal)
                .filter(|n| moved.norm() > 0.0 && n.dot(&moved) >= widest.cos() * moved.norm())
                .max_by(|a, b| a.dot(&moved).total_cmp(&b.dot(&moved)));
            match nearest {
                Some(direction) => motion.along[m] = Some(direction),
                None => motion.fixed[m] = true,
            }
        }
        let solution = self.solve(axis, order, &motion);
        solution.solved().then_some((solution, motion))
    }
}
