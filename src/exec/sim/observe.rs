//! What the simulator's camera reports: each prism's pose seen from above with perception noise,
//! or why it cannot be planned for (toppled, outside the workspace, lying on another object, a
//! rider left on another object); noise that would make outlines overlap undone. Objects outside
//! the workspace are also kept as seen there (`Executor::past_edge`).

use super::Sim;
use crate::error::Result;
use crate::exec::RIDER_LEFT;
use crate::geometry::overlap;
use crate::scene::{Object, Pose, Scene, Workspace};

impl Sim {
    /// The table as the camera sees it now (see the module docs of `sim`), and what it cannot plan
    /// for in `self.lost`.
    ///
    /// # Errors
    /// Misuse before a table was given.
    pub(super) fn observation(&mut self) -> Result<Scene> {
        let workspace = self.table()?.clone();
        let s = &self.settings;
        let mut objects: Vec<Object> = Vec::new();
        let mut truth: Vec<Object> = Vec::new();
        self.lost.clear();
        for prism in &self.prisms {
            if self.rider_left_standing(prism) {
                self.lost.push((prism.id, RIDER_LEFT));
                continue;
            }
            // Upright, it is its own prism; toppled flat on a face, the camera sees a new one.
            let (polygon, pose, height) = if prism.tilt() <= s.topple_angle {
                (prism.polygon.clone(), prism.planar_pose(), prism.height)
            } else if let Some(seen) = prism.lying_flat() {
                seen
            } else {
                self.lost.push((prism.id, "toppled"));
                continue;
            };
            let outside = polygon
                .transformed(&pose.isometry())
                .vertices()
                .iter()
                .any(|v| workspace.outside_by(v) > crate::scene::OUTSIDE_TOLERANCE);
            let object = Object {
                id: prism.id,
                name: prism.name.clone(),
                polygon,
                pose,
                height,
                mass: Some(prism.mass),
            };
            if outside {
                self.lost.push((prism.id, "outside the workspace"));
                let rng = &mut self.past_edge_rng;
                let seen = Pose::new(
                    pose.x + s.perception_position * rng.normal(),
                    pose.y + s.perception_position * rng.normal(),
                    pose.yaw + s.perception_yaw * rng.normal(),
                );
                self.past_edge.push(Object {
                    pose: seen,
                    ..object
                });
                continue;
            }
            truth.push(object.clone());
            let noisy = Pose::new(
                pose.x + s.perception_position * self.rng.normal(),
                pose.y + s.perception_position * self.rng.normal(),
                pose.yaw + s.perception_yaw * self.rng.normal(),
            );
            objects.push(Object {
                pose: noisy,
                ..object
            });
        }
        // Undo noise that made outlines overlap each other or leave the workspace; physics may also
        // leave contacts a fraction of a millimetre deep, which a camera would not report either.
        for k in 0..objects.len() {
            let outline = objects[k].world_polygon();
            let clashes = objects[..k].iter().any(|o| {
                overlap(
                    &o.world_polygon(),
                    &outline,
                    crate::scene::OVERLAP_TOLERANCE,
                )
            }) || outline
                .vertices()
                .iter()
                .any(|v| workspace.outside_by(v) > crate::scene::OUTSIDE_TOLERANCE);
            if clashes {
                objects[k].pose = truth[k].pose;
            }
        }
        separate(&mut objects, &workspace);
        // What still overlaps after that rests on another object (a toppled object lying across a
        // neighbour): the camera cannot give it a place on the table, so it is left out.
        let mut kept: Vec<Object> = Vec::with_capacity(objects.len());
        for object in objects {
            let outline = object.world_polygon();
            let on_another = kept.iter().any(|o| {
                overlap(
                    &o.world_polygon(),
                    &outline,
                    crate::scene::OVERLAP_TOLERANCE,
                )
            });
            if on_another {
                self.lost.push((object.id, "lying on another object"));
            } else {
                kept.push(object);
            }
        }
        Scene::from_parts(workspace, self.gripper.clone(), kept)
    }
}

/// Pushes apart observed outlines that still interpenetrate (physics contacts), each pair along the
/// axis of largest separation, a little past touching; a bounded number of passes.
fn separate(objects: &mut [Object], workspace: &Workspace) {
    for _ in 0..20 {
        let mut moved = false;
        for a in 0..objects.len() {
            for b in a + 1..objects.len() {
                let (pa, pb) = (objects[a].world_polygon(), objects[b].world_polygon());
                let (normal, separation) = crate::geometry::max_separation(&pa, &pb);
                if separation < -crate::scene::OVERLAP_TOLERANCE / 2.0 {
                    let shift = normal * (-separation / 2.0 + 1e-6);
                    objects[a].pose.x -= shift.x;
                    objects[a].pose.y -= shift.y;
                    objects[b].pose.x += shift.x;
                    objects[b].pose.y += shift.y;
                    moved = true;
                }
            }
        }
        // Keep everything inside after the shifts.
        for object in objects.iter_mut() {
            let (lo, hi) = object.world_polygon().bounding_box();
            let dx = (workspace.min[0] - lo.x).max(0.0) - (hi.x - workspace.max[0]).max(0.0);
            let dy = (workspace.min[1] - lo.y).max(0.0) - (hi.y - workspace.max[1]).max(0.0);
            object.pose.x += dx;
            object.pose.y += dy;
        }
        if !moved {
            return;
        }
    }
}
