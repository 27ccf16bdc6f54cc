//! Objects left past the workspace's edge (`run.reach_past_edge`, off by default;
//! `formulations/grasping.md`, "Objects past the workspace's edge"). A failed grasp or a rider
//! that falls can leave an object just over the edge of the workspace, where nothing plans for it
//! and the run ends with it left. Where the table goes on, the camera sees and the arm reaches a
//! little past that edge, such an object can still be taken by itself. Once nothing is left in the
//! workspace, each object the executor sees past the edge ([`crate::exec::Executor::past_edge`])
//! with every vertex within `reach` of the workspace is offered, nearest the workspace first, to
//! the policy's single-object planner on a table of its own: the workspace grown by `reach` on
//! every side, holding the objects seen past the edge within it (those that would overlap one
//! already held are left out), so that the plates keep clear of them as of any neighbour. No push
//! is planned there: the push planners keep objects inside the workspace, and a push out there
//! could take an object further away.

use super::{Policy, TripPlan};
use crate::cluster::Clustering;
use crate::error::Result;
use crate::grasp::{GraspRequest, JawPose};
use crate::scene::{Gripper, Object, Scene, Workspace};

/// The workspace grown by `reach` on every side.
pub(super) fn grown(workspace: &Workspace, reach: f64) -> Workspace {
    Workspace {
        min: [workspace.min[0] - reach, workspace.min[1] - reach],
        max: [workspace.max[0] + reach, workspace.max[1] + reach],
    }
}

/// How far the farthest vertex of `object` lies outside `workspace`, metres.
fn farthest_outside(object: &Object, workspace: &Workspace) -> f64 {
    object
        .world_polygon()
        .vertices()
        .iter()
        .map(|v| workspace.outside_by(v))
        .fold(0.0, f64::max)
}

impl Policy {
    /// A single-object grasp of one of `seen` (objects past the edge of `workspace`) within
    /// `run.reach_past_edge` of it, with the table it was planned on (module docs); `None` when
    /// reaching past the edge is off, nothing seen lies within reach, or no such object has a
    /// grasp that is not in the place of one of `avoid`.
    ///
    /// `avoid` are jaw poses not to try again (a closed loop's failed grasps). Closed loops of
    /// their own (another engine, a robot stack) call it once their workspace is empty but for
    /// objects they see past its edge, as [`crate::policy::Run`] does.
    ///
    /// # Errors
    /// Misuse only.
    pub fn past_edge_trip(
        &self,
        workspace: &Workspace,
        gripper: &Gripper,
        seen: &[Object],
        avoid: &[JawPose],
    ) -> Result<Option<(Scene, TripPlan)>> {
        let reach = self.settings.run.reach_past_edge;
        if reach <= 0.0 {
            return Ok(None);
        }
        let mut within: Vec<(f64, &Object)> = seen
            .iter()
            .map(|o| (farthest_outside(o, workspace), o))
            .filter(|(outside, _)| *outside <= reach)
            .collect();
        within.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.id.cmp(&b.1.id)));
        let table = grown(workspace, reach);
        // One object at a time, so that two seen overlapping (the camera's error) keep the first.
        let mut scene: Option<Scene> = None;
        for (_, object) in &within {
            let mut objects = scene.as_ref().map_or(Vec::new(), |s| s.objects().to_vec());
            objects.push((*object).clone());
            if let Ok(valid) = Scene::from_parts(table.clone(), gripper.clone(), objects) {
                scene = Some(valid);
            }
        }
        let Some(scene) = scene else {
            return Ok(None);
        };
        for object in scene.objects() {
            let target = [object.id];
            let request = GraspRequest::new(&scene, &target).avoiding(avoid);
            if let Some(grasp) = self.single.plan_request(&request)?.value {
                let trip = TripPlan::grasping(Clustering::default(), None, grasp);
                return Ok(Some((scene.clone(), trip)));
            }
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ConvexPolygon;
    use crate::policy::{PolicyKind, PolicySettings};
    use crate::scene::{ObjectId, Pose};
    use nalgebra::Point2;

    fn square(id: u32, x: f64, y: f64) -> Object {
        let h = 0.015;
        Object {
            id: ObjectId(id),
            name: None,
            polygon: ConvexPolygon::new(vec![
                Point2::new(-h, -h),
                Point2::new(h, -h),
                Point2::new(h, h),
                Point2::new(-h, h),
            ])
            .unwrap_or_else(|e| panic!("{e}")),
            pose: Pose::new(x, y, 0.1),
            height: 0.03,
            mass: None,
        }
    }

    fn policy(reach: f64) -> Policy {
        let mut settings = PolicySettings::default();
        settings.run.reach_past_edge = reach;
        Policy::new(PolicyKind::PushMog, settings).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn an_object_just_past_the_edge_is_taken_on_a_grown_table_and_one_too_far_is_not() {
        let workspace = Workspace::default();
        let gripper = Gripper::default();
        // 5 mm past the right edge at its farthest corner (a 30 mm square turned 0.1 rad), and
        // one 0.2 m beyond the far edge.
        let near = square(1, 0.5 - 0.0025, 0.2);
        let far = square(2, 0.25, 0.4 + 0.2);
        let seen = [far.clone(), near.clone()];
        let off = policy(0.0).past_edge_trip(&workspace, &gripper, &seen, &[]);
        assert!(matches!(off, Ok(None)), "off by default");
        let Ok(Some((scene, trip))) = policy(0.05).past_edge_trip(&workspace, &gripper, &seen, &[])
        else {
            panic!("no grasp of the object just past the edge")
        };
        assert_eq!(trip.grasp.objects, vec![ObjectId(1)]);
        assert!(trip.pushes.is_empty() && trip.riders.is_empty());
        assert_eq!(
            scene.len(),
            1,
            "the object out of reach is not on the grown table"
        );
        assert_eq!(scene.workspace(), &grown(&workspace, 0.05));
        // The trip passes the independent verifier on the table it was planned on.
        let record = crate::plan::Trip {
            scene: crate::plan::SharedScene::sharing(scene.to_spec(), None),
            plan: trip.clone(),
            looks: Vec::new(),
            carried: Vec::new(),
            fault: None,
            lost: Vec::new(),
        };
        assert_eq!(crate::plan::verify_trip(&record), Vec::<String>::new());
        // Where that grasp failed before, it is not planned again.
        let again = policy(0.05).past_edge_trip(&workspace, &gripper, &seen, &[trip.grasp.jaws]);
        if let Ok(Some((_, other))) = again {
            assert!(!other.grasp.jaws.same_place(&trip.grasp.jaws));
        }
    }
}
