//! Settings of the multi-object planner: the candidate grid, the noise it judges under, the least
//! probability it uses, and how far from the workspace's edge it holds objects.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::grasp::Noise;

/// Settings of [`MultiObject`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MultiObjectSettings {
    /// Grid of jaw centres over the targets' bounding box, `[along x, along y]`. Default `[7, 10]`.
    pub grid: [usize; 2],
    /// Evenly spaced closing axes over `[0, π)`. Default 24 (7.5° apart). With 12 axes and 8 tries
    /// per set (the defaults before), simulated push-mog carried 0.021 ± 0.007 fewer objects per trip
    /// on paper-100 and 0.026 ± 0.008 fewer on 60 other scenes, push-mog-opt 0.016 ± 0.008 fewer
    /// (`formulations/grasping.md`).
    pub angles: usize,
    /// Jaw opening as a fraction of the stroke. Default 1.0 (fully open, as in the paper).
    pub opening_fraction: f64,
    /// Samples per judged candidate, the observed table first; 1 judges the observed table alone.
    /// Default 8: with `min_probability` 0.75 a grasp may fail in at most two of them. With 4 (one
    /// failure allowed) and the policies choosing pairs over single objects (`GraspRequest::several`),
    /// push-mog's two-object grasps held in 65 of 84 noisy replays (77 %); with 8, 61 of 71 (86 %),
    /// at the same simulated objects per trip (20 scenes).
    pub samples: usize,
    /// The noise of the other samples. Defaults: the simulator's.
    pub noise: Noise,
    /// Least gap between an open plate and any object, in standard deviations of where the plate
    /// ends up relative to that object (`Noise::position_sigma`). Default 1.5: 3.4 mm from an object
    /// as observed, 4.5 mm from a pushed one.
    pub clearance_sigmas: f64,
    /// Least estimated probability of a grasp to be used. Default 0.75.
    pub min_probability: f64,
    /// Candidates judged per set of caught objects. Default 32.
    pub tries_per_set: usize,
    /// Candidates judged per call. Default 40.
    pub max_judged: usize,
    /// Least distance, metres, between the workspace's edge and every object a multi-object grasp
    /// holds, on the table the grasp is planned for. A multi-object grasp that fails squeezes its
    /// objects along the plates or shoves them a few millimetres, and an object that close to the
    /// edge then leaves the workspace: such objects are taken one at a time. Default 0 (no margin,
    /// as the Push-MOG paper); push-mog-time (`experiments/push-mog-time.json`) sets 0.02 with
    /// `edge_along_plates` (`formulations/picks-per-hour.md`, "The margins").
    pub edge_margin: f64,
    /// Measure `edge_margin` along the plates only (the way a failed grasp squeezes objects out, a
    /// median 20 mm in the simulator), from each caught object's outline to the edge, both ways.
    /// Default false: every direction. With 0.02 (and `socp.held_edge_margin`), push-mog-time
    /// cleared 295 of 300 training scenes against 284 without margins, at 0.006 of its ratio to
    /// sog's picks per hour and 0.015 objects per trip.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub edge_along_plates: bool,
    /// Move each candidate along its closing axis to the middle of the objects it catches, so that
    /// the open plates stand as far from them on one side as on the other (when the move catches the
    /// same objects and keeps the plates clear of the rest; otherwise the candidate stays where it
    /// was). Default false: replayed on push-mog-time's 600 runs of `stacking-unseen` and
    /// `stacking` it took a quarter of the grasps out of the 3-4 mm band, where most grasps that
    /// come down on their row are, but as many came down (`formulations/grasping.md`, "Grasps that
    /// come down on a row").
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub centre_along_axis: bool,
}

impl Default for MultiObjectSettings {
    fn default() -> Self {
        Self {
            grid: [7, 10],
            angles: 24,
            opening_fraction: 1.0,
            samples: 8,
            noise: Noise::default(),
            clearance_sigmas: 1.5,
            min_probability: 0.75,
            tries_per_set: 32,
            max_judged: 40,
            edge_margin: 0.0,
            edge_along_plates: false,
            centre_along_axis: false,
        }
    }
}

impl MultiObjectSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        for (field, value, high) in [
            ("grid[0]", self.grid[0], 100),
            ("grid[1]", self.grid[1], 100),
            ("angles", self.angles, 360),
        ] {
            crate::error::count_in_range(
                "multi",
                field,
                value,
                (1, high),
                "every grid point × angle is a candidate the model judges",
            )?;
        }
        if !(self.opening_fraction > 0.0 && self.opening_fraction <= 1.0) {
            return Err(Error::field(
                "multi",
                "opening_fraction",
                format!("must be in (0, 1], got {}", self.opening_fraction),
            ));
        }
        if !(1..=64).contains(&self.samples) {
            return Err(Error::field(
                "multi",
                "samples",
                format!("must be between 1 and 64, got {}", self.samples),
            ));
        }
        if !(self.clearance_sigmas.is_finite() && (0.0..=5.0).contains(&self.clearance_sigmas)) {
            return Err(Error::field(
                "multi",
                "clearance_sigmas",
                format!("must be between 0 and 5, got {}", self.clearance_sigmas),
            ));
        }
        if !(self.edge_margin.is_finite() && (0.0..=0.2).contains(&self.edge_margin)) {
            return Err(Error::field(
                "multi",
                "edge_margin",
                format!(
                    "must be between 0 and 0.2 m (a margin wider than a third of a workspace \
                     leaves few objects to grasp together), got {}",
                    self.edge_margin
                ),
            ));
        }
        if !(self.min_probability.is_finite() && (0.0..=1.0).contains(&self.min_probability)) {
            return Err(Error::field(
                "multi",
                "min_probability",
                format!("must be in [0, 1], got {}", self.min_probability),
            ));
        }
        for (field, value) in [
            ("tries_per_set", self.tries_per_set),
            ("max_judged", self.max_judged),
        ] {
            crate::error::count_in_range(
                "multi",
                field,
                value,
                (1, 1000),
                "judged candidates: at least one, and at most 1000 per call (each is a judgement)",
            )?;
        }
        self.noise.validate()
    }
}
