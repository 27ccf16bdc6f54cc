//! Riders left standing on their rows (`formulations/stacking.md`, "Riders left standing"). When a
//! row's grasp carries nothing (its jaws came down on a member, say), the rider put down on it
//! mostly stays on top. A camera sees it there, not on the table, so it cannot be planned for by
//! itself; but it goes to the bin with its row if the row is grasped whole again. So before
//! anything else the next trip grasps that row again as it lies: no pushes (a push of a member
//! would tip the rider), no new rider, jaws that take every object the rider rests on, with both
//! plates at least the checks' support margin (the error in where the rider was put down) clear of
//! where the rider was put down, since the plates come down from above. A rider with no such grasp
//! waits, and the trip is planned as usual; no rider is put down on a row that carries one.

use super::context::{Perched, TripContext};
use super::{Policy, TripPlan};
use crate::cluster::Clustering;
use crate::error::Result;
use crate::geometry::distance;
use crate::grasp::{Grasp, GraspRequest};
use crate::scene::{ObjectId, Scene};

impl Policy {
    /// The grasp of the row of the first rider left standing (module docs) that `scene` and
    /// `context` allow, as a trip; `None` when there is none.
    ///
    /// # Errors
    /// Misuse only.
    pub(super) fn perched_trip(
        &self,
        scene: &Scene,
        context: &TripContext,
    ) -> Result<Option<TripPlan>> {
        for perched in &context.perched {
            if !perched.on.iter().all(|&id| scene.index_of(id).is_some()) {
                continue;
            }
            let row: Vec<ObjectId> = perched
                .row
                .iter()
                .copied()
                .filter(|&id| scene.index_of(id).is_some())
                .collect();
            let request = GraspRequest::new(scene, &row)
                .avoiding(&context.failed)
                .several();
            let Some(grasp) = self.multi.plan_request(&request)?.value else {
                continue;
            };
            if context.together(&grasp) && self.clear_of(scene, &grasp, perched) {
                return Ok(Some(TripPlan::grasping(Clustering::default(), None, grasp)));
            }
        }
        Ok(None)
    }

    /// Whether `grasp` takes every object `perched` rests on and keeps both plates clear of it.
    fn clear_of(&self, scene: &Scene, grasp: &Grasp, perched: &Perched) -> bool {
        let margin = self.settings.riders.checks.support_margin;
        perched.on.iter().all(|id| grasp.objects.contains(id))
            && grasp
                .jaws
                .plates(scene.gripper())
                .iter()
                .all(|plate| distance(plate, &perched.footprint) >= margin)
    }
}

/// Whether a rider left standing rests on one of `objects`.
pub(super) fn carries_a_rider(context: &TripContext, objects: &[ObjectId]) -> bool {
    context
        .perched
        .iter()
        .any(|p| p.on.iter().any(|id| objects.contains(id)))
}
