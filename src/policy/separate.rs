//! The ways out of a dead end, objects standing too close for a plate between them: pushed apart
//! with the jaws closed and one of them grasped alone; failing that, grasped together as they lie
//! with the objects that stand in their plates' way, even within the policy's edge margin.

use nalgebra::Vector2;

use super::{Policy, TripContext};
use crate::error::Result;
use crate::geometry::distance;
use crate::grasp::{Grasp, GraspRequest, JawPose};
use crate::push::{Push, predict, separating_push};
use crate::scene::{ObjectId, Scene};

/// Lengths tried, shortest first, for a push that separates an object from the neighbour it is stuck
/// against, metres: a 10 mm plate and the single-object planner's clearance on either side need
/// about 20 mm; longer ones for neighbours that are not square to the push.
const SEPARATIONS: [f64; 3] = [0.02, 0.03, 0.045];

/// Directions tried for a separating push: this many around the full turn, of which those that do not
/// run into the neighbour are used.
const SEPARATION_DIRECTIONS: usize = 16;

/// Least room left between a separated object and the workspace's edge, metres (the SOCP's default
/// edge margin).
const SEPARATION_EDGE_MARGIN: f64 = 0.005;

/// Neighbours nearer than this to a member stand in the way of a plate beside it, metres: a 10 mm
/// plate and the single-object planner's clearance on either side (the shortest of
/// [`SEPARATIONS`]).
const PLATE_ROOM: f64 = 0.02;

impl Policy {
    /// A push that moves one of `members` away from the object nearest it ([`separating_push`], the
    /// shortest of [`SEPARATIONS`] that works, in the first of the directions that do not point into
    /// that object, nearest straight away first), and a grasp of that object
    /// or its neighbour by itself on the table predicted after the push; `None` when no member can
    /// be freed so. The way out when objects stand too close for a plate between them and the grasp
    /// model refuses them together (a dead end the paper's pushes, which end with objects touching,
    /// can leave).
    pub(super) fn separate(
        &self,
        observed: &Scene,
        members: &[ObjectId],
        avoid: &[JawPose],
    ) -> Result<Option<(Push, Grasp)>> {
        for &id in members {
            let Some(index) = observed.index_of(id) else {
                continue;
            };
            let outline = observed.world_polygon(index);
            let Some(neighbour) = (0..observed.len())
                .filter(|&j| j != index)
                .min_by(|&a, &b| {
                    distance(outline, observed.world_polygon(a))
                        .total_cmp(&distance(outline, observed.world_polygon(b)))
                })
            else {
                continue;
            };
            let freed = [id, observed.objects()[neighbour].id];
            let away = (observed.centroid(index) - observed.centroid(neighbour)).normalize();
            // Directions that do not run into the neighbour, nearest straight away first.
            let mut directions: Vec<(f64, Vector2<f64>)> = (0..SEPARATION_DIRECTIONS)
                .map(|k| {
                    let turn = std::f64::consts::TAU * k as f64 / SEPARATION_DIRECTIONS as f64;
                    let (sin, cos) = turn.sin_cos();
                    let direction =
                        Vector2::new(away.x * cos - away.y * sin, away.x * sin + away.y * cos);
                    (-cos, direction)
                })
                .filter(|(_, direction)| direction.dot(&away) >= -1e-9)
                .collect();
            directions.sort_by(|a, b| a.0.total_cmp(&b.0));
            for travel in SEPARATIONS {
                for (_, direction) in &directions {
                    let Ok(push) = separating_push(
                        observed,
                        self.problem.fork(),
                        (index, neighbour),
                        direction,
                        travel,
                        SEPARATION_EDGE_MARGIN,
                    ) else {
                        continue;
                    };
                    let predicted = predict(observed, std::slice::from_ref(&push))?;
                    if let Some(grasp) = self
                        .single
                        .plan_request(&GraspRequest::new(&predicted, &freed).avoiding(avoid))?
                        .value
                    {
                        return Ok(Some((push, grasp)));
                    }
                }
            }
        }
        Ok(None)
    }

    /// A multi-object grasp of `members` together with the objects that stand within
    /// [`PLATE_ROOM`] of them, on the table as it lies, planned without the edge margin
    /// (`multi.edge_margin`), avoiding grasps that failed before and sets given up; `None` when
    /// there is none. The last way out of a dead end that [`Policy::separate`] cannot free: two
    /// objects pressed together, neither with room for a plate beside the other, whose pair the
    /// margin refuses because it lies near the workspace's edge. There is no room between them for
    /// the fingers of a push that would part them, so without this the run stops with both on the
    /// table. The margin says where a failed pair grasp is more likely to squeeze an object out
    /// (`formulations/picks-per-hour.md`, "The margins"), not where a pair cannot be held.
    pub(super) fn take_with_neighbours(
        &self,
        observed: &Scene,
        members: &[ObjectId],
        context: &TripContext,
    ) -> Result<Option<Grasp>> {
        let mut targets = members.to_vec();
        for &id in members {
            let Some(index) = observed.index_of(id) else {
                continue;
            };
            let outline = observed.world_polygon(index);
            for (j, other) in observed.objects().iter().enumerate() {
                if !targets.contains(&other.id)
                    && distance(outline, observed.world_polygon(j)) < PLATE_ROOM
                {
                    targets.push(other.id);
                }
            }
        }
        if targets.len() < 2 {
            return Ok(None);
        }
        let planner = self.at_edges.as_deref().unwrap_or(&*self.multi);
        let outcome = planner.plan_request(
            &GraspRequest::new(observed, &targets)
                .avoiding(&context.failed)
                .several(),
        )?;
        Ok(outcome.value.filter(|grasp| context.together(grasp)))
    }
}
