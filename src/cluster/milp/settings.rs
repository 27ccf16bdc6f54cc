//! Settings of the optimal clustering ([`super::Milp`]) and the row test its candidates pass.

use serde::{Deserialize, Serialize};

use crate::cluster::objective::ClusterObjective;
use crate::error::{Error, Result};

/// The push planner's flush-push settings, for the clustering's pair test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlushPairs {
    /// How far each member must reach past the plates' centre line on both sides, metres.
    pub straddle: f64,
    /// How far a finger must overlap the face it pushes, metres.
    pub margin: f64,
    /// Largest angle between a flush push and its face's normal, radians.
    pub cone: f64,
    /// Gap a flush push leaves between a pair, at most, metres.
    pub tight: f64,
}

/// Which MILP solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum MilpBackend {
    /// microlp, pure Rust (always available).
    Microlp,
    /// HiGHS (needs the `highs` feature: cmake and libclang at build time).
    Highs,
}

/// Largest finite `max_diameter`, metres: the diagonal of a ±1000 m workspace (2000·√2 ≈ 2829 m), so
/// any larger value would mean the same as no limit.
const NO_DIAMETER_LIMIT: f64 = 2830.0;

/// Settings of [`Milp`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MilpSettings {
    /// What to minimise. Default `time`.
    pub objective: ClusterObjective,
    /// Largest number of objects in a candidate cluster. Default 12: capacity decides (the summed
    /// minimum grasp diameters fit the gap and the members stand in one row within it), and this
    /// only bounds the enumeration (ten 7 mm bars fill the 75 mm gap).
    pub max_cluster_size: usize,
    /// Largest distance between two centroids of a candidate cluster (push reach), metres. Default
    /// 0.10, the hierarchical clustering's default cut height.
    pub max_diameter: f64,
    /// Wall-clock limit of one clustering (enumeration and every solve), seconds. Default 10.
    pub time_limit: f64,
    /// Most candidate clusters the model may hold; beyond it (tightly packed small objects) the
    /// heuristic's clustering is returned with status `heuristic`. Default 20 000 (paper scenes of
    /// 34 objects give a few hundred; each candidate is a variable and a list of members).
    pub max_candidates: usize,
    /// Most clash rows the model may hold, with the same fallback. Default 200 000.
    pub max_clash_rows: usize,
    /// Relative gap at which the solver may stop. Default 0 (prove optimality).
    pub mip_gap: f64,
    /// The solver. Default `microlp`.
    pub backend: MilpBackend,
    /// Solve the fewest-clusters objective in two stages (count, then spread among clusterings with
    /// that count) rather than as one weighted sum. Default true: the weighted sum's near-ties slow
    /// the proof by orders of magnitude (`formulations/clustering.md`).
    pub two_stage_fewest_clusters: bool,
}

impl Default for MilpSettings {
    fn default() -> Self {
        Self {
            objective: ClusterObjective::Time,
            max_cluster_size: 12,
            max_diameter: 0.10,
            time_limit: 10.0,
            max_candidates: 20_000,
            max_clash_rows: 200_000,
            mip_gap: 0.0,
            backend: MilpBackend::Microlp,
            two_stage_fewest_clusters: true,
        }
    }
}

impl MilpSettings {
    /// Checks every field, and that the chosen backend is compiled in.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        if !(1..=20).contains(&self.max_cluster_size) {
            return Err(Error::field(
                "milp",
                "max_cluster_size",
                format!(
                    "must be between 1 and 20 (candidates grow combinatorially with it), got {}",
                    self.max_cluster_size
                ),
            ));
        }
        // The diameter may be infinite: no compactness limit (small instances, brute-force checks).
        // From a file, the workspace's longest diagonal already means no limit.
        if self.max_diameter.is_nan()
            || self.max_diameter < 0.0
            || (self.max_diameter.is_finite() && self.max_diameter > NO_DIAMETER_LIMIT)
        {
            return Err(Error::field(
                "milp",
                "max_diameter",
                format!(
                    "must be between 0 and {NO_DIAMETER_LIMIT} m (the diagonal of the largest \
                     workspace, ±1000 m, which already means no limit), got {}",
                    self.max_diameter
                ),
            ));
        }
        crate::error::in_range(
            "milp",
            "mip_gap",
            self.mip_gap,
            (0.0, 1.0),
            "a relative gap",
        )?;
        crate::error::in_range(
            "milp",
            "time_limit",
            self.time_limit,
            (0.001, 3600.0),
            "seconds; under a millisecond not even the candidates are enumerated",
        )?;
        for (field, value, high) in [
            ("max_candidates", self.max_candidates, 5_000_000),
            ("max_clash_rows", self.max_clash_rows, 50_000_000),
        ] {
            crate::error::count_in_range(
                "milp",
                field,
                value,
                (1, high),
                "each is a model row or column held in memory",
            )?;
        }
        if self.backend == MilpBackend::Highs && !cfg!(feature = "highs") {
            return Err(Error::NotCompiled {
                component: "milp".to_string(),
                field: "backend".to_string(),
                feature: "highs",
                reason: "HiGHS is not compiled in: build with `--features highs` (needs cmake and \
                         libclang)"
                    .to_string(),
            });
        }
        Ok(())
    }
}

/// Which clusters may be candidates: those whose members stand in a row the push planner can make.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowTest {
    /// Room a candidate cluster's row must leave in the usable jaw gap, metres: a cluster of two or
    /// more is a candidate only if its members can stand in a row (1 mm apart) of at most the gap
    /// less this, along some axis at their current yaws. Default 0.010; in a policy, the push
    /// planner's (`socp.margin`).
    pub margin: f64,
    /// With flush pushes (`socp.flush`), pairs are candidates only when a flush push of one member
    /// lines them up ([`crate::push::flush::admits_flush_pair`]), with the push planner's straddle
    /// and face margin. `None` (default): any pair that stands in a row.
    pub flush_pairs: Option<FlushPairs>,
}

impl Default for RowTest {
    fn default() -> Self {
        Self {
            margin: 0.010,
            flush_pairs: None,
        }
    }
}
