//! The scene predicted after a sequence of pushes: each pushed object translated to its target.

use crate::error::Result;
use crate::scene::Scene;

use super::Push;

/// Moves every pushed object to its planned pose (the paper plans its grasp on this prediction rather
/// than a new image).
///
/// # Errors
/// The scene validation error when the targets overlap or leave the workspace (a planner bug that
/// `plan::verify` also catches).
pub fn predict(scene: &Scene, pushes: &[Push]) -> Result<Scene> {
    let mut objects = scene.objects().to_vec();
    for push in pushes {
        if let Some(object) = objects.iter_mut().find(|o| o.id == push.object) {
            object.pose = push.to;
        }
    }
    scene.with_objects(objects)
}
