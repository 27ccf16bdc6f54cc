//! Scenes as a camera might see them: every pose moved by seeded Gaussian noise, never into another
//! object or out of the workspace.

use super::{OUTSIDE_TOLERANCE, OVERLAP_TOLERANCE, Object, Pose, Scene};
use crate::error::Result;
use crate::geometry::overlap;
use crate::random::SeededRng;

/// Draws of one object's noise before it is left where it was.
const DRAWS: usize = 10;

/// `scene` with each object's position moved by Gaussian noise of standard deviation `position`
/// (metres, per axis) and its yaw by `yaw` (radians). Objects are moved in order; a draw that would
/// overlap an object already placed or leave the workspace is drawn again, up to ten times, and the
/// object keeps its pose if none fits (so touching objects stay valid).
///
/// # Errors
/// Only if the result is not a valid scene, which the draws rule out.
pub fn perturb(scene: &Scene, rng: &mut SeededRng, position: f64, yaw: f64) -> Result<Scene> {
    let workspace = scene.workspace();
    let mut placed: Vec<Object> = Vec::with_capacity(scene.len());
    for object in scene.objects() {
        let mut chosen = object.clone();
        for _ in 0..DRAWS {
            let candidate = Object {
                pose: Pose::new(
                    object.pose.x + position * rng.normal(),
                    object.pose.y + position * rng.normal(),
                    object.pose.yaw + yaw * rng.normal(),
                ),
                ..object.clone()
            };
            let outline = candidate.world_polygon();
            let inside = outline
                .vertices()
                .iter()
                .all(|v| workspace.outside_by(v) <= OUTSIDE_TOLERANCE);
            // Objects not yet placed keep their poses, so a draw must clear them too.
            let clear = placed
                .iter()
                .chain(scene.objects()[placed.len() + 1..].iter())
                .all(|other| !overlap(&other.world_polygon(), &outline, OVERLAP_TOLERANCE));
            if inside && clear {
                chosen = candidate;
                break;
            }
        }
        placed.push(chosen);
    }
    scene.with_objects(placed)
}
