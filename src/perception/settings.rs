//! The thresholds of `perceive`, each with the reason for its default.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Result, in_range};

/// Thresholds of a look (`formulations/perception.md`, "Thresholds").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct PerceptionSettings {
    /// Height above the fitted table above which a pixel belongs to an object, metres (5 mm: four
    /// standard deviations of the default noise at 0.7 m, and a sixth of the library's 30 mm).
    pub cut_height: f64,
    /// Smallest footprint that is an object, m² (1 cm²; the library's smallest shape is about 6 cm²).
    pub min_area: f64,
    /// Largest footprint extent (its longest chord) that is an object, metres.
    pub max_extent: f64,
    /// Tallest object, metres.
    pub max_height: f64,
    /// Smallest solidity of a blob that is one object (0.97: single objects measured 0.994 or more
    /// under every noise setting, merged pairs of touching objects 0.68–0.94 unless they meet flush;
    /// `formulations/perception.md`).
    pub min_solidity: f64,
    /// Largest distance from a prior object's centroid at which a blob keeps its id, metres.
    pub track_gate: f64,
    /// Distance from the calibrated table `z = 0` within which pixels start the table fit, metres
    /// (as far as the fit may lie from it, `max_table_offset`).
    pub table_start: f64,
    /// Largest height of the fitted table above or below the calibrated one, metres.
    pub max_table_offset: f64,
    /// Largest angle between the fitted and the calibrated table, radians.
    pub max_table_tilt: f64,
    /// Smallest fraction of a labelled blob's pixels with depth, when no height is given.
    pub min_depth_fraction: f64,
    /// Smallest drop from the top plateau to a second one that makes a blob stacked, metres.
    pub stacked_step: f64,
    /// Smallest share of a blob's pixels on a second plateau that makes it stacked.
    pub stacked_fraction: f64,
    /// Largest overlap of two footprints that is cut apart at its middle rather than reported,
    /// metres (2 mm: the error of two touching objects' edges measured with the default noise).
    pub overlap_repair: f64,
    /// Largest reach of a footprint beyond the workspace that is trimmed rather than reported, metres.
    pub edge_trim: f64,
    /// Fit a line to each side of a blob and put back the corner tips that the 3×3 median cut,
    /// instead of taking the hull of its pixels (`formulations/perception.md`, "Sides fitted, tips
    /// put back"). Off by default: it makes outlines more accurate on average but not in the worst
    /// case, its yaw errors are larger, and it moves near-limit plans. Left out of written settings
    /// when off.
    #[serde(skip_serializing_if = "is_false")]
    pub fit_sides: bool,
    /// Fit each side of a blob's image outline to the pixels on both sides of its edge, starting from
    /// the hull (`formulations/perception.md`, "The outline fitted to both sides of the edge"). On by
    /// default; off gives the hull moved by the area-matching offset alone, as before this option.
    /// Depth only: labels without depth keep the hull. Left out of written settings when on.
    #[serde(skip_serializing_if = "is_true")]
    pub fit_outline: bool,
}

fn is_true(value: &bool) -> bool {
    *value
}

fn is_false(value: &bool) -> bool {
    !*value
}

impl Default for PerceptionSettings {
    fn default() -> Self {
        Self {
            cut_height: 0.005,
            min_area: 1e-4,
            max_extent: 0.3,
            max_height: 0.3,
            min_solidity: 0.97,
            track_gate: 0.02,
            table_start: 0.02,
            max_table_offset: 0.02,
            max_table_tilt: 0.035,
            min_depth_fraction: 0.5,
            stacked_step: 0.008,
            stacked_fraction: 0.15,
            overlap_repair: 0.002,
            edge_trim: 0.001,
            fit_sides: false,
            fit_outline: true,
        }
    }
}

impl PerceptionSettings {
    /// Checks every threshold's range.
    ///
    /// # Errors
    /// An [`Error::InvalidField`](crate::Error::InvalidField) naming the field.
    pub fn validate(&self) -> Result<()> {
        let c = "perception settings";
        in_range(c, "cut_height", self.cut_height, (1e-4, 0.1), "metres")?;
        in_range(c, "min_area", self.min_area, (0.0, 1.0), "square metres")?;
        in_range(c, "max_extent", self.max_extent, (1e-3, 10.0), "metres")?;
        in_range(c, "max_height", self.max_height, (1e-3, 10.0), "metres")?;
        in_range(
            c,
            "min_solidity",
            self.min_solidity,
            (0.0, 1.0),
            "a fraction",
        )?;
        in_range(c, "track_gate", self.track_gate, (0.0, 1.0), "metres")?;
        in_range(c, "table_start", self.table_start, (1e-4, 0.5), "metres")?;
        in_range(
            c,
            "max_table_offset",
            self.max_table_offset,
            (0.0, 1.0),
            "metres",
        )?;
        in_range(
            c,
            "max_table_tilt",
            self.max_table_tilt,
            (0.0, 0.5),
            "radians",
        )?;
        in_range(
            c,
            "min_depth_fraction",
            self.min_depth_fraction,
            (0.0, 1.0),
            "a fraction",
        )?;
        in_range(c, "stacked_step", self.stacked_step, (1e-3, 1.0), "metres")?;
        in_range(
            c,
            "stacked_fraction",
            self.stacked_fraction,
            (0.0, 1.0),
            "a fraction",
        )?;
        in_range(
            c,
            "overlap_repair",
            self.overlap_repair,
            (0.0, 0.05),
            "metres",
        )?;
        in_range(c, "edge_trim", self.edge_trim, (0.0, 0.05), "metres")?;
        Ok(())
    }
}
