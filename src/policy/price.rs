//! The expected-time price of pushing: whether a trip's pushes are expected to save more robot
//! seconds than they cost (`formulations/picks-per-hour.md`).
//!
//! A cluster whose pushes are planned, with a multi-object grasp of `k` objects on the table
//! predicted after them, can instead be taken as it lies: `t` objects now (one, or the grasp as it
//! lies), the rest one trip each later. Pushing saves
//!
//! `S = q(p)·(k − t)·(T_trip + T_obs) − (ΔT_push + T_look) − c·(T_push,later + T_look)`
//!
//! seconds, with:
//! - `q(p)` the probability that the grasp after the pushes carries all `k`, read from a calibration
//!   table of the grasp judge's own probability `p` ([`SuccessBand`]), fitted to simulated outcomes;
//! - `T_trip + T_obs` a single-object trip and the look before it (the time model's nominal trip);
//! - `ΔT_push` the seconds the planned pushes add to the trip (the time model's commands for this
//!   trip with and without them) and `T_look` the look after them (`run.observe_after_pushes`);
//! - `c` the expected rounds of corrective pushes after them, each a later push of the mean planned
//!   length and a look.
//!
//! Under [`TripObjective::ExpectedTime`] the pushes are made only when `S > 0`; under
//! [`TripObjective::ObjectsPerTrip`] (the Push-MOG paper's aim) whenever a multi-object grasp
//! follows them.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::grasp::Grasp;
use crate::plan::Rider;
use crate::push::Push;
use crate::scene::Gripper;
use crate::time_model::{GraspPath, PushPath, RiderPath, TimeModel};

/// What a policy's decisions to push aim at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TripObjective {
    /// Push whenever a multi-object grasp follows (the Push-MOG paper's aim: objects per trip).
    ObjectsPerTrip,
    /// Push only when the expected robot seconds saved exceed those spent (picks per hour).
    ExpectedTime,
}

/// One row of the calibration table: grasps judged at least `judged` carry all their objects after
/// the pushes with probability `carried_all`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SuccessBand {
    /// Least probability the grasp judge gave the grasp on the predicted table.
    pub judged: f64,
    /// Observed probability that such a grasp carried every object it was planned for.
    pub carried_all: f64,
}

/// How the policy prices pushes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Pricing {
    /// What decisions to push aim at. Default `objects_per_trip`.
    pub objective: TripObjective,
    /// Calibration of the grasp judge after pushes made in the trip of their grasp, by increasing
    /// `judged`. Default, fitted in the simulator with noise on training scenes no experiment uses,
    /// for flush pushes (`socp.flush`) and the default judge (`formulations/picks-per-hour.md`):
    /// judged below 1, 0.784 (37 clusters), judged 1, 0.923 (678), of push-mog-opt pushing every
    /// cluster it can in the trip (scenes 5001-5100; the priced policy pushing ahead makes no
    /// pushes in the trip there, so its own runs cannot fit these).
    pub success: Vec<SuccessBand>,
    /// Expected rounds of corrective pushes after a trip's pushes. Default 0.041, from the same
    /// 715 clusters.
    pub corrections: f64,
    /// Calibration for rows pushed ahead (`push_ahead`): the probability that the trip that next
    /// grasps or pushes a row's objects takes the whole row, by judged probability. Default, fitted
    /// on the rows push-mog-time (flush pushes, default judge, pushing ahead) itself pushed on
    /// scenes 5001-5100 and 7001-7100, each row by its own judged probability: judged below 1,
    /// 0.605 (86 rows); judged 1, 0.854 (2085). push-mog-time's settings file
    /// (`experiments/push-mog-time.json`), whose grasp model has the friction margin, carries its
    /// own bands, refitted the same way with the margin: 0.633 and 0.880.
    pub ahead_success: Vec<SuccessBand>,
    /// Push clusters ahead: each trip grasps one cluster as it lies and, before that grasp, pushes
    /// another into a row for a later trip, whose look shows the row (`policy/ahead.rs`). Default
    /// false.
    pub push_ahead: bool,
    /// Most rows one trip pushes ahead (`push_ahead`), each only when it pays with what it adds to
    /// the trip's commands; a trip pushes ahead only when no row pushed before still waits. Rows
    /// pushed together share the jaw commands and the travel to and from the table, so with flush
    /// pushes a further row in a trip costs about 8.0 s against 9.5 s for the first
    /// (`formulations/picks-per-hour.md`).
    /// Default 12: no trip on tables of 34 objects has more rows worth pushing.
    pub ahead_rows: usize,
}

impl Default for Pricing {
    fn default() -> Self {
        let band = |judged, carried_all| SuccessBand {
            judged,
            carried_all,
        };
        Self {
            objective: TripObjective::ObjectsPerTrip,
            success: vec![band(0.0, 0.784), band(0.999, 0.923)],
            corrections: 0.041,
            ahead_success: vec![band(0.0, 0.605), band(0.999, 0.854)],
            push_ahead: false,
            ahead_rows: 12,
        }
    }
}

impl Pricing {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        validate_bands("success", &self.success)?;
        validate_bands("ahead_success", &self.ahead_success)?;
        crate::error::count_in_range(
            "pricing",
            "ahead_rows",
            self.ahead_rows,
            (1, 20),
            "each row is a push plan and a grasp judged in the trip's planning",
        )?;
        crate::error::in_range(
            "pricing",
            "corrections",
            self.corrections,
            (0.0, 10.0),
            "expected rounds of corrective pushes per trip",
        )
    }

    /// The calibrated probability that a grasp the judge gave `judged` carries all its objects: in
    /// the trip of the pushes, or (`ahead`) in the trip after pushes ahead.
    pub fn carried_all(&self, judged: f64, ahead: bool) -> f64 {
        let bands = if ahead {
            &self.ahead_success
        } else {
            &self.success
        };
        bands
            .iter()
            .rev()
            .find(|band| judged >= band.judged)
            .or(bands.first())
            .map_or(0.0, |band| band.carried_all)
    }

    /// Expected robot seconds saved by making `pushes` for `grasp` (judged `judged` by the grasp
    /// planner) instead of taking `taken` objects as they lie (module docs); `ahead` is the grasp
    /// the trip makes after pushes ahead (another cluster's; `None`: the trip makes `grasp`
    /// itself), `earlier` the pushes ahead of other rows the trip makes before these (their
    /// seconds are not charged again: only what `pushes` add to the trip), and `look` whether the
    /// loop looks at the table after pushing (never after pushes ahead).
    pub fn saving(
        &self,
        model: &TimeModel,
        gripper: &Gripper,
        (pushes, earlier, grasp, ahead): (&[Push], &[Push], &Grasp, Option<&Grasp>),
        judged: f64,
        taken: usize,
        look: bool,
    ) -> f64 {
        let jaws = grasp_path(ahead.unwrap_or(grasp), gripper);
        let before = push_paths(earlier);
        let mut paths = before.clone();
        paths.extend(push_paths(pushes));
        if let Some(last) = paths.last_mut() {
            // The arm stops out of the rise for the look.
            last.look_after = look;
        }
        // The moves out of the camera's view and back for that look are in `pushing`, and in a
        // corrective round's estimate.
        let (look, away) = if look {
            (model.look_seconds(), model.look_away_seconds())
        } else {
            (0.0, 0.0)
        };
        let pushing = model.trip_seconds(gripper, &paths, &jaws)
            - model.trip_seconds(gripper, &before, &jaws);
        let mean = pushes.iter().map(|p| p.distance).sum::<f64>() / pushes.len().max(1) as f64;
        let correcting = model.nominal_later_push_seconds(mean) + look + away;
        let single = model.nominal_trip_seconds(gripper) + model.look_seconds();
        let gained = grasp.objects.len().saturating_sub(taken) as f64;
        self.carried_all(judged, ahead.is_some()) * gained * single
            - (pushing + look)
            - self.corrections * correcting
    }
}

/// Checks a calibration table: at least one band, probabilities, increasing `judged`.
fn validate_bands(name: &str, bands: &[SuccessBand]) -> Result<()> {
    if bands.is_empty() {
        return Err(Error::field("pricing", name, "needs at least one band"));
    }
    for (k, band) in bands.iter().enumerate() {
        let field = format!("{name}[{k}]");
        for (part, value) in [("judged", band.judged), ("carried_all", band.carried_all)] {
            crate::error::in_range(
                "pricing",
                &format!("{field}.{part}"),
                value,
                (0.0, 1.0),
                "a probability",
            )?;
        }
        if k > 0 && band.judged <= bands[k - 1].judged {
            return Err(Error::field(
                "pricing",
                field,
                "bands must be in increasing order of `judged`",
            ));
        }
    }
    Ok(())
}

/// The time model's view of fork pushes.
pub fn push_paths(pushes: &[Push]) -> Vec<PushPath> {
    pushes
        .iter()
        .map(|p| PushPath {
            approach: p.fork.approach,
            end: p.fork.end,
            opening: p.fork.opening,
            look_after: false,
        })
        .collect()
}

/// The time model's view of a grasp: its jaws, closed on the row it was planned for.
pub fn grasp_path(grasp: &Grasp, gripper: &Gripper) -> GraspPath {
    GraspPath {
        center: grasp.jaws.center,
        opening: grasp.jaws.opening,
        closed: (grasp.width + gripper.plate_thickness).min(grasp.jaws.opening),
    }
}

/// The time model's view of riders: each one's pick, and where the jaws let it go.
pub fn rider_paths(riders: &[Rider], gripper: &Gripper) -> Vec<RiderPath> {
    riders
        .iter()
        .map(|rider| RiderPath {
            pick: grasp_path(&rider.pick, gripper),
            release: rider.release.center,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grasp::JawPose;
    use crate::push::ForkPush;
    use crate::scene::{ObjectId, Pose};
    use nalgebra::{Point2, Vector2};

    /// A flush push (jaws closed to one block) of 30 mm along +x of an object at (x, y).
    fn push(id: u32, x: f64, y: f64) -> Push {
        Push {
            object: ObjectId(id),
            from: Pose::new(x, y, 0.0),
            to: Pose::new(x + 0.03, y, 0.0),
            direction: Vector2::x(),
            distance: 0.03,
            fork: ForkPush {
                approach: Point2::new(x - 0.03, y),
                contact: Point2::new(x - 0.02, y),
                end: Point2::new(x + 0.01, y),
                jaw_angle: std::f64::consts::FRAC_PI_2,
                opening: 0.011,
                height: Some(0.015),
            },
        }
    }

    fn grasp(ids: &[u32], x: f64, y: f64) -> Grasp {
        Grasp {
            jaws: JawPose {
                center: Point2::new(x, y),
                angle: 0.0,
                opening: 0.085,
            },
            objects: ids.iter().copied().map(ObjectId).collect(),
            width: 0.06,
            margin: 0.01,
        }
    }

    #[test]
    fn a_second_row_pushed_in_the_same_trip_costs_less_than_the_first() {
        let (model, gripper) = (TimeModel::default(), Gripper::default());
        let pricing = Pricing::default();
        let trip_grasp = grasp(&[9], 0.3, 0.3);
        let (first, second) = (push(0, 0.2, 0.2), push(2, 0.2, 0.1));
        let (row_a, row_b) = (grasp(&[0, 1], 0.25, 0.2), grasp(&[2, 3], 0.25, 0.1));
        let alone = pricing.saving(
            &model,
            &gripper,
            (std::slice::from_ref(&first), &[], &row_a, Some(&trip_grasp)),
            1.0,
            1,
            false,
        );
        let after = pricing.saving(
            &model,
            &gripper,
            (
                std::slice::from_ref(&second),
                std::slice::from_ref(&first),
                &row_b,
                Some(&trip_grasp),
            ),
            1.0,
            1,
            false,
        );
        // Both gain one trip with the same probability; the second sends no jaw command of its own
        // (the jaws stand at the block already) and its travel replaces part of the first's.
        let jaw = (gripper.stroke - 0.011) / model.jaw_speed + model.gripper_settle;
        assert!(after - alone > 0.5 * jaw, "{alone} then {after}");
        let expected = pricing.carried_all(1.0, true)
            * (model.nominal_trip_seconds(&gripper) + model.look_seconds());
        assert!(alone < expected && after < expected);
    }

    #[test]
    fn the_calibration_reads_the_highest_band_reached() {
        let band = |judged, carried_all| SuccessBand {
            judged,
            carried_all,
        };
        let pricing = Pricing {
            success: vec![band(0.0, 0.5), band(0.999, 0.75)],
            ahead_success: vec![band(0.0, 0.6)],
            ..Pricing::default()
        };
        assert_eq!(pricing.carried_all(0.5, false), 0.5);
        assert_eq!(pricing.carried_all(0.875, false), 0.5);
        assert_eq!(pricing.carried_all(1.0, false), 0.75);
        assert_eq!(pricing.carried_all(1.0, true), 0.6);
        assert!(pricing.validate().is_ok());
        assert!(Pricing::default().validate().is_ok());
        let unordered = Pricing {
            success: pricing.success.iter().rev().cloned().collect(),
            ..pricing
        };
        assert!(unordered.validate().is_err());
    }
}
