//! The place action in the simulator: a rider picked, carried over its row and put down on its top
//! (`formulations/stacking.md`).

use rapier3d_f64::math::Vector;

use super::Sim;
use crate::error::{Error, Result};
use crate::exec::Landing;
use crate::plan::Rider;

impl Sim {
    /// The rider's pick is its single-object grasp, closed with the fingertips at half its height
    /// (not `grasp_height`) so that they stay clear of the row's top when it is put down. The jaws
    /// lift it 1 cm clear of everything within reach of the path, carry it over the release (turning
    /// with it), lower it until its base is 2 mm above the row's top, open to the pick's opening,
    /// and rise. Actuation noise offsets the pick and the release alike.
    ///
    /// # Errors
    /// Misuse: before a table was given, or for an object not on the table.
    pub(super) fn put_down(&mut self, rider: &Rider) -> Result<Option<Landing>> {
        self.table()?;
        let s = self.settings.clone();
        let Some(index) = self.prisms.iter().position(|p| p.id == rider.object) else {
            return Err(Error::misuse(
                "simulator",
                format!("no object {} on the table to place", rider.object),
            ));
        };
        let jaws = &rider.pick.jaws;
        let grip = (0.5 * self.prisms[index].height).max(s.grasp_height);
        let (mut stage, at) =
            match self.lower_and_close_at(jaws, Some(rider.release.center), Self::top_of, grip) {
                Ok(lowered) => lowered,
                Err(landing) => return Ok(Some(landing)),
            };
        stage.wait(0.05);
        // Base 1 cm above everything in reach.
        let lift = at.top + 0.01;
        stage.travel(Vector::new(0.0, 0.0, lift), s.vertical_speed);
        stage.travel_turning(
            Vector::new(at.end.0 - at.centre.0, at.end.1 - at.centre.1, 0.0),
            crate::geometry::wrap_angle(rider.release.angle - jaws.angle),
            s.vertical_speed,
        );
        stage.travel(
            Vector::new(0.0, 0.0, -(lift - rider.base - 0.002)),
            s.vertical_speed,
        );
        stage.open(jaws.opening, s.jaw_speed);
        stage.wait(0.1);
        // Up until the fingertips are 1 cm above the rider's top.
        let clear = rider.base + self.prisms[index].height + 0.01;
        let rise = (clear - stage.tip_height()).max(0.0);
        stage.travel(Vector::new(0.0, 0.0, rise), s.vertical_speed);
        stage.wait(0.05);
        stage.write_back(&mut self.prisms);
        self.placed.push(rider.object);
        Ok(None)
    }
}
