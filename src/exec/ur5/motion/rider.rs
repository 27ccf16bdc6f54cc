//! The place action's robot steps (`formulations/stacking.md`).

use super::{Phase, Step, Translator, tool_yaw};
use crate::plan::Rider;
use crate::scene::Scene;

impl Translator {
    /// The eight steps that put a rider on its row (`formulations/stacking.md`): move above its
    /// pick, open to the pick's opening, descend until the fingertips are at half its height, close,
    /// rise and move over the release (one blended program), lower it until its base is 2 mm above
    /// the row's top, open to let it go, rise (flowing into the next action). Travel is above the
    /// rider standing on the row.
    pub fn place_rider(&self, scene: &Scene, rider: &Rider, name: &str) -> Vec<Step> {
        let height = self.height_of(scene, rider.object);
        let grip = 0.5 * height;
        let travel = self.travel_height(scene).max(rider.base + height) + grip;
        let vertical = self.config.speeds.vertical;
        let (pick, release) = (&rider.pick.jaws, &rider.release);
        // The release is the pick turned by the rider's turn, the short way round; a linear move
        // turns the tool the short way too.
        let pick_yaw = tool_yaw(pick.angle);
        let release_yaw = pick_yaw + crate::geometry::wrap_angle(release.angle - pick.angle);
        let at_pick = |z| self.tool_pose_at_yaw(pick.center.x, pick.center.y, z, pick_yaw);
        let at_release =
            |z| self.tool_pose_at_yaw(release.center.x, release.center.y, z, release_yaw);
        let opening = self.config.gripper.count_for_opening(pick.opening);
        vec![
            Self::moves(
                Phase::AbovePick,
                format!("{name}: move above object {}", rider.object),
                vec![self.travel(at_pick(travel))],
            ),
            self.gripper(
                Phase::OpenForPick,
                format!(
                    "{name}: open to {:.1} mm between plate centres",
                    pick.opening * 1e3
                ),
                opening,
            ),
            Self::moves(
                Phase::DescendToPick,
                format!("{name}: descend to half its height ({:.1} mm)", grip * 1e3),
                vec![self.contact(at_pick(grip), vertical)],
            ),
            self.gripper(
                Phase::ClosePick,
                format!("{name}: close with limited force"),
                self.config.gripper.closed_count,
            ),
            Self::moves(
                Phase::CarryRider,
                format!("{name}: rise and move over the row"),
                vec![
                    self.flowing(self.contact(at_pick(travel), vertical)),
                    self.travel(at_release(travel)),
                ],
            ),
            Self::moves(
                Phase::LowerRider,
                format!(
                    "{name}: lower onto the row's top ({:.1} mm)",
                    rider.base * 1e3
                ),
                vec![self.contact(at_release(rider.base + 0.002 + grip), vertical)],
            ),
            self.gripper(Phase::Release, format!("{name}: open to let go"), opening),
            Self::moves(
                Phase::RiseFromRider,
                format!("{name}: rise"),
                vec![self.flowing(self.contact(at_release(travel), vertical))],
            ),
        ]
    }
}
