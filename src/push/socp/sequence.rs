//! The pushes that bring a solved row about: an order in which every sweep and finger path is
//! clear, with two legs for a member whose straight push is refused.

use nalgebra::{Point2, Vector2};

use super::Socp;
use super::rows::permutations;
use crate::geometry::{ConvexPolygon, cast_distance};
use crate::push::flush::{block_opening, flush_face};
use crate::push::fork::plan_fork_facing;
use crate::push::{Push, SkipReason};
use crate::scene::{ObjectId, Pose, Scene};

impl Socp {
    /// Pushes that reach `targets` in some order with every sweep and finger path clear. Straight
    /// pushes first, in every order; only when no order works may a member whose straight push is
    /// refused take two legs instead, across the closing axis `axis` and along it
    /// ([`Socp::two_legs`]). The failure reported is that of the straight pushes.
    pub(super) fn sequence(
        &self,
        scene: &Scene,
        members: &[usize],
        targets: &[Point2<f64>],
        axis: &Vector2<f64>,
    ) -> std::result::Result<Vec<Push>, (ObjectId, SkipReason)> {
        let moves: Vec<usize> = (0..members.len())
            .filter(|&m| nalgebra::distance(&targets[m], &scene.centroid(members[m])) > 0.0)
            .collect();
        let ids: Vec<ObjectId> = scene.objects().iter().map(|o| o.id).collect();
        let mut straight_failure = None;
        for with_legs in [false, true] {
            for order in permutations(&moves, 120) {
                let mut world: Vec<ConvexPolygon> = (0..scene.len())
                    .map(|i| scene.world_polygon(i).clone())
                    .collect();
                let mut pushes = Vec::new();
                let mut failed = None;
                for &m in &order {
                    let index = members[m];
                    let offset = targets[m] - scene.centroid(index);
                    let from = scene.objects()[index].pose;
                    let legs = match self.leg(scene, &world, &ids, index, from, offset) {
                        Ok(push) => Ok(vec![(push, offset)]),
                        Err(straight) if with_legs => self
                            .two_legs(scene, &world, &ids, index, offset, axis)
                            .ok_or(straight),
                        Err(straight) => Err(straight),
                    };
                    match legs {
                        Ok(legs) => {
                            for (push, moved) in legs {
                                world[index] = world[index].translated(&moved);
                                pushes.push(push);
                            }
                        }
                        Err(reason) => {
                            failed = Some((ids[index], reason));
                            break;
                        }
                    }
                }
                match failed {
                    None => return Ok(pushes),
                    Some(failure) if !with_legs => straight_failure = Some(failure),
                    Some(_) => {}
                }
            }
        }
        match straight_failure {
            Some(failure) => Err(failure),
            None => Ok(Vec::new()),
        }
    }

    /// One straight push by `offset` of the object `index`, at pose `from` on the table `world` as
    /// it stands: its sweep must touch no other object and the fingers must find room
    /// ([`plan_fork`]).
    fn leg(
        &self,
        scene: &Scene,
        world: &[ConvexPolygon],
        ids: &[ObjectId],
        index: usize,
        from: Pose,
        offset: Vector2<f64>,
    ) -> std::result::Result<Push, SkipReason> {
        let distance = offset.norm();
        let direction = offset / distance;
        let swept = world[index].swept_box(&offset);
        if let Some(blocker) = (0..world.len())
            .filter(|&o| o != index && world[o].box_meets(swept))
            .find(|&o| {
                cast_distance(&world[index], &direction, distance, &world[o])
                    .is_some_and(|hit| hit < distance - 1e-9)
            })
        {
            return Err(SkipReason::BlockedBy {
                object: ids[blocker],
            });
        }
        let gripper = scene.gripper();
        let (opening, facing) = if self.settings.flush {
            let settings = &self.settings;
            let face = flush_face(
                &world[index],
                settings.flush_margin,
                &direction,
                settings.flush_cone,
            )
            .ok_or(SkipReason::NotFlush)?;
            (block_opening(gripper), face.normal)
        } else {
            (gripper.fork_push_opening(), direction)
        };
        let fork = plan_fork_facing(
            gripper,
            self.problem.fork(),
            world,
            ids,
            index,
            scene.objects()[index].height,
            (&direction, &facing),
            distance,
            opening,
        )?;
        Ok(Push {
            object: ids[index],
            from,
            to: Pose::new(from.x + offset.x, from.y + offset.y, from.yaw),
            direction,
            distance,
            fork,
        })
    }

    /// The push by `offset` as two legs, one across `axis` and one along it, in either order, when
    /// both are at least `min_push` long and each is clear. Two objects whose extents along some
    /// line are apart cannot meet while one slides across that line, so a member that a straight
    /// push would drag past a neighbour's corner reaches its slot this way: along the axis first when
    /// it lies beside the neighbour across the axis, across first when it lies in line with it.
    fn two_legs(
        &self,
        scene: &Scene,
        world: &[ConvexPolygon],
        ids: &[ObjectId],
        index: usize,
        offset: Vector2<f64>,
        axis: &Vector2<f64>,
    ) -> Option<Vec<(Push, Vector2<f64>)>> {
        let along = axis * offset.dot(axis);
        let across = offset - along;
        if along.norm() < self.problem.min_push() || across.norm() < self.problem.min_push() {
            return None;
        }
        let from = scene.objects()[index].pose;
        // The corner of the path keeps inside the workspace as targets do: `edge_margin` from every
        // edge, or the start's own distance from it if smaller (both legs then stay inside too).
        let workspace = scene.workspace();
        let start_room = workspace.room(world[index].bounding_box());
        [[across, along], [along, across]]
            .into_iter()
            .find_map(|[a, b]| {
                let corner = world[index].translated(&a);
                let inside = workspace
                    .room(corner.bounding_box())
                    .iter()
                    .zip(start_room)
                    .all(|(&r, start)| r >= self.settings.edge_margin.min(start));
                if !inside {
                    return None;
                }
                let first = self.leg(scene, world, ids, index, from, a).ok()?;
                let mut moved = world.to_vec();
                moved[index] = corner;
                let second = self.leg(scene, &moved, ids, index, first.to, b).ok()?;
                Some(vec![(first, a), (second, b)])
            })
    }
}
