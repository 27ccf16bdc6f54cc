//! Riders chosen for a trip (`formulations/stacking.md`): after the trip's pushes, objects the
//! clustering leaves to be taken by themselves are offered, nearest first, to the row the trip's
//! grasp takes. One rides when the quasi-static checks place it ([`crate::stack::place_rider`]), the
//! plates still carry the row with it, nothing beside the row stands above the row's top under it,
//! and the single-object planner has a grasp to pick it with. One rider per row, and none on a row
//! with a member's centroid farther from the plates' centre line than half the plate length less
//! the support margin: in the simulator such rows are dropped far more often
//! (`formulations/stacking.md`, "Rows held off their centre"). None on a row that still carries a
//! rider left standing there (`perched.rs`).
//!
//! Under the expected-time objective ([`super::TripObjective::ExpectedTime`]) a rider is also
//! priced: it is placed only when `q_r·(T_trip + T_obs) > ΔT_place`, with `q_r` the calibrated
//! probability that a placed rider rides its trip to the bin ([`Riders::carried`]), `T_trip + T_obs`
//! the single-object trip and look it saves, and `ΔT_place` the seconds its place action adds to the
//! trip's commands (the time model's trip with and without it). A rider its trip does not carry
//! mostly lands on the table and is taken later by itself, so it costs its place action.

use nalgebra::{Isometry2, Vector2};
use serde::{Deserialize, Serialize};

use super::{Policy, TripContext, TripPlan};
use crate::error::{Error, Result};
use crate::geometry::overlap;
use crate::grasp::{GraspRequest, JawPose, centre_line_offset, closed_motions};
use crate::plan::Rider;
use crate::scene::{ObjectId, Pose, Scene};
use crate::stack::{Row, StackSettings, place_rider, plates_carry};

/// Whether a policy puts riders on its rows, and the checks that decide where.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Riders {
    /// Put riders on rows. Default false.
    pub enabled: bool,
    /// The checks (`formulations/stacking.md`).
    pub checks: StackSettings,
    /// Probability that a placed rider rides its trip to the bin: the price's `q_r` under the
    /// expected-time objective. Default 0.967: 861 of 890 riders placed by push-mog-time with
    /// riders on training scenes 7001-7100 (simulated with noise, riders not priced) were carried
    /// by their trip (`formulations/stacking.md`).
    pub carried: f64,
    /// Let the optimal clustering choose riders with its rows (`formulations/stacking.md`, "Riders
    /// in the clustering"): a single object it puts on a row is offered to that row first, is
    /// offered to no other row, and takes no trip of its own while its row is on the table.
    /// Default false (riders chosen trip by trip among the clustering's singles, nearest first);
    /// left out of written settings when false. Only the MILP clusterer chooses riders.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub in_clustering: bool,
    /// With `in_clustering`: riders are looked for within this distance of a candidate row's mean
    /// centroid, metres (bounds the model's size). Default 0.15; left out of written settings when
    /// the default.
    #[serde(skip_serializing_if = "is_default_reach")]
    pub reach: f64,
}

const DEFAULT_REACH: f64 = 0.15;

fn is_default_reach(reach: &f64) -> bool {
    *reach == DEFAULT_REACH
}

impl Default for Riders {
    fn default() -> Self {
        Self {
            enabled: false,
            checks: StackSettings::default(),
            carried: 0.967,
            in_clustering: false,
            reach: DEFAULT_REACH,
        }
    }
}

impl Riders {
    /// Off and with the default checks: left out of written settings.
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the first field out of range.
    pub fn validate(&self) -> Result<()> {
        let c = &self.checks;
        for (name, value) in [
            ("height_tolerance", c.height_tolerance),
            ("support_margin", c.support_margin),
            ("pad_margin", c.pad_margin),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::field(
                    "riders.checks",
                    name,
                    format!("must be finite and at least 0 (metres), got {value}"),
                ));
            }
        }
        for (name, value) in [
            ("acceleration", c.acceleration),
            ("slide_factor", c.slide_factor),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::field(
                    "riders.checks",
                    name,
                    format!("must be finite and above 0, got {value}"),
                ));
            }
        }
        if c.yaws == 0 {
            return Err(Error::field("riders.checks", "yaws", "must be at least 1"));
        }
        crate::error::in_range("riders", "reach", self.reach, (1e-6, 10.0), "metres")?;
        crate::error::in_range(
            "riders",
            "carried",
            self.carried,
            (0.0, 1.0),
            "the probability that a placed rider rides its trip to the bin",
        )
    }
}

impl Policy {
    /// Riders for `trip`, on `predicted`, the table after its pushes; none when riders are off, the
    /// grasp takes fewer than two objects, a rider left standing rests on one of them, or no object
    /// passes (see the module docs). An object that fell off a row carried whole before
    /// (`context.fell_off`) is not offered. Jaws where grasps failed before (`context.failed`) are not
    /// proposed for a pick.
    pub(super) fn riders_for(
        &self,
        predicted: &Scene,
        trip: &TripPlan,
        context: &TripContext,
    ) -> Result<Vec<Rider>> {
        let settings = &self.settings.riders;
        if !settings.enabled
            || trip.grasp.objects.len() < 2
            || super::perched::carries_a_rider(context, &trip.grasp.objects)
        {
            return Ok(Vec::new());
        }
        let avoid = context.failed.as_slice();
        let members: Vec<usize> = trip
            .grasp
            .objects
            .iter()
            .filter_map(|&id| predicted.index_of(id))
            .collect();
        let jaws = &trip.grasp.jaws;
        // A member gripped with its centroid off the plates' centre line turns about the closing
        // axis as the row is lifted, and tilts what rests on it: riders only on rows whose members'
        // centroids lie within the plates' length, inset by the support margin.
        let within = 0.5 * predicted.gripper().plate_length - settings.checks.support_margin;
        if centre_line_offset(predicted, jaws, &members) > within {
            return Ok(Vec::new());
        }
        let model = self.problem.grasp_model();
        let mut row = row_of(predicted, &members, jaws);
        let row_masses: Vec<f64> = members
            .iter()
            .map(|&i| model.mass_of(&predicted.objects()[i]))
            .collect();
        let busy: Vec<ObjectId> = trip
            .grasp
            .objects
            .iter()
            .chain(&trip.ahead)
            .copied()
            .chain(trip.pushes.iter().map(|p| p.object))
            .collect();
        // The rider the clustering chose for this row goes first, then the singles it chose for no
        // row, then those it chose for other rows (a row may never form), each nearest first.
        let clustering = &trip.clustering;
        let chosen = clustering.rider_on(&trip.grasp.objects);
        let mut offered: Vec<((u8, f64), usize)> = clustering
            .clusters
            .iter()
            .filter(|cluster| cluster.len() == 1 && !busy.contains(&cluster[0]))
            .filter(|cluster| !context.fell_off.contains(&cluster[0]))
            .filter_map(|cluster| predicted.index_of(cluster[0]))
            .map(|i| {
                let object = &predicted.objects()[i];
                let rank = if Some(object.id) == chosen {
                    0
                } else if clustering.is_rider(object.id) {
                    2
                } else {
                    1
                };
                let at = object.world_centroid();
                ((rank, nalgebra::distance(&at, &jaws.center)), i)
            })
            .collect();
        offered.sort_by(|a, b| a.0.0.cmp(&b.0.0).then(a.0.1.total_cmp(&b.0.1)));
        // Where the closing leaves the row, simulated only when some object is offered.
        if settings.checks.pads_after_closing && !offered.is_empty() {
            row.closing = closed_motions(predicted, jaws, model, &members);
        }
        for (_, index) in offered {
            let object = &predicted.objects()[index];
            if !plates_carry(
                model.friction_jaw,
                model.grip_force,
                &row_masses,
                &[model.mass_of(object)],
            ) {
                continue;
            }
            let Ok(placed) = place_rider(
                &row,
                &object.polygon,
                object.height,
                model.friction_object,
                &settings.checks,
            ) else {
                continue;
            };
            // Nothing but the row and the rider itself may stand above the row's top under it.
            let footprint = object.polygon.transformed(&placed.pose.isometry());
            let clash = predicted.objects().iter().enumerate().any(|(i, other)| {
                i != index
                    && !members.contains(&i)
                    && other.height > placed.base
                    && overlap(predicted.world_polygon(i), &footprint, 0.0)
            });
            if clash {
                continue;
            }
            let Some(pick) = self
                .single
                .plan_request(&GraspRequest::new(predicted, &[object.id]).avoiding(avoid))?
                .value
            else {
                continue;
            };
            let release = moved_with(&pick.jaws, &object.pose, &placed.pose);
            let rider = Rider {
                object: object.id,
                pick,
                place: placed.pose,
                release,
                base: placed.base,
                on: placed
                    .resting_on
                    .iter()
                    .map(|&k| predicted.objects()[members[k]].id)
                    .collect(),
            };
            if self
                .rider_saving(predicted, trip, &rider)
                .is_some_and(|s| s <= 0.0)
            {
                continue;
            }
            return Ok(vec![rider]);
        }
        Ok(Vec::new())
    }

    /// Under the expected-time objective, the expected seconds `rider` saves on `trip` (module
    /// docs); `None` under the objects-per-trip objective, which places every rider that passes
    /// the checks.
    fn rider_saving(&self, predicted: &Scene, trip: &TripPlan, rider: &Rider) -> Option<f64> {
        if self.settings.pricing.objective != super::TripObjective::ExpectedTime {
            return None;
        }
        let model = self.problem.time_model();
        let gripper = predicted.gripper();
        let pushes = super::push_paths(&trip.pushes);
        let grasp = super::grasp_path(&trip.grasp, gripper);
        let riders = super::rider_paths(std::slice::from_ref(rider), gripper);
        let placing = model.trip_seconds_with_riders(gripper, &pushes, &riders, &grasp)
            - model.trip_seconds(gripper, &pushes, &grasp);
        let single = model.nominal_trip_seconds(gripper) + model.look_seconds();
        Some(self.settings.riders.carried * single - placing)
    }
}

/// The row that `jaws` close on: the outlines and heights of `members` (indices in `scene`) and the
/// closing axis.
fn row_of(scene: &Scene, members: &[usize], jaws: &JawPose) -> Row {
    Row {
        outlines: members
            .iter()
            .map(|&i| scene.world_polygon(i).clone())
            .collect(),
        heights: members.iter().map(|&i| scene.objects()[i].height).collect(),
        axis: Vector2::new(jaws.angle.cos(), jaws.angle.sin()),
        closing: None,
    }
}

/// The jaws `jaws`, holding an object at `from`, once the object has been carried to `to` without
/// slipping in them.
pub(super) fn moved_with(jaws: &JawPose, from: &Pose, to: &Pose) -> JawPose {
    let held = Isometry2::new(jaws.center.coords, jaws.angle);
    let relative = from.isometry().inverse() * held;
    let moved = to.isometry() * relative;
    let turn = crate::geometry::wrap_angle(to.yaw - from.yaw);
    JawPose {
        center: moved.translation.vector.into(),
        angle: jaws.angle + turn,
        opening: jaws.opening,
    }
}
