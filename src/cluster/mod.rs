//! Clustering: partition the objects into groups to be pushed together and lifted in one grasp.
//!
//! A clustering `C` of the objects `O` is valid when
//! 1. **capacity**: every cluster of two or more objects fits the jaws,
//!    `Σ_{o∈c} d*_o ≤ g` with `d*_o` the minimum grasp diameter and `g` the usable gap;
//! 2. **separability**: for any two clusters a line separates their object centroids, so each cluster
//!    can be pushed together without reaching into another.
//!
//! A single object is a valid cluster even when it is wider than the gap (it is then ungraspable,
//! which the grasp planner reports). Implementations: [`Hierarchical`] (the Push-MOG paper's
//! Algorithm 2, with pushmog's separability repair) and [`Milp`] (optimal for the model of
//! `formulations/clustering.md`, with the objectives of [`CostModel`]).

mod candidates;
mod decompose;
mod hierarchical;
mod milp;
mod objective;
mod reuse;
mod riders;
mod separability;
mod solved;
mod split;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::geometry::{ConvexPolygon, Extremes, worth_pruning};
use crate::outcome::{Abilities, Outcome};
use crate::scene::{ObjectId, Scene};

pub use candidates::{Budget, clashing_pairs, compact_candidates, compact_candidates_where};
pub use hierarchical::{Hierarchical, HierarchicalSettings, Linkage};
pub use milp::{FlushPairs, Milp, MilpBackend, MilpSettings, RowTest};
pub use objective::{ClusterObjective, CostModel, centroid_diameter, estimated_pushes, spread};
pub use reuse::ClusterMemory;
pub use riders::{Ride, RideOptions, predicted_row, ride_worth};
pub use separability::{repair_separability, separability_conflicts};
pub use split::{SplitSettings, split_until_valid};

/// A partition of a scene's objects into clusters, each a list of object ids.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Clustering {
    /// The clusters; every object of the scene is in exactly one.
    pub clusters: Vec<Vec<ObjectId>>,
    /// In a plan or run record: how good the clustering is, as its clusterer said (`optimal` only
    /// when the MILP proved it; the hierarchical heuristic's is `heuristic`). A clusterer's own
    /// answer leaves this empty and gives its status in the outcome.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub status: Option<crate::outcome::Status>,
    /// Set when the optimal clustering (the MILP) gave back the heuristic's clusters, in whole or
    /// in part, and why; absent otherwise and for other clusterers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fallback: Option<Fallback>,
    /// Riders the clustering puts on its rows ([`Milp::with_rides`]): each rider is also a cluster
    /// of its own, and rides on its row's trip instead of taking one. Empty (and left out) for
    /// clusterers that choose no riders.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub riders: Vec<Ride>,
}

/// Why the MILP's clustering is, in whole or in part, the heuristic's (which it is seeded with).
/// More reasons may come: match with a wildcard arm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Fallback {
    /// The model was not built: it would have exceeded its budget of candidates or clash rows
    /// (`what` says which). The heuristic's clustering throughout.
    OverBudget {
        /// Which budget, in words.
        what: String,
    },
    /// The solver chose no clusters (it failed, or its limit ended it before a solution). The
    /// heuristic's clustering throughout.
    NoAnswer,
    /// The solver's clusters do not cover every object exactly once. The heuristic's clustering
    /// throughout.
    NotAPartition,
    /// Two of the solver's clusters cannot be separated by a line. The heuristic's clustering
    /// throughout.
    NotSeparable,
    /// The solver's clustering costs more than the heuristic's (a limit ended it early). The
    /// heuristic's clustering throughout.
    DearerThanHeuristic,
    /// Some of the independent parts the model was solved in chose nothing; those parts keep the
    /// heuristic's clusters.
    Parts {
        /// How many parts.
        count: usize,
    },
}

impl Clustering {
    /// The clustering of `clusters` given as scene indices, by object id, with no status.
    pub fn from_indices(scene: &Scene, clusters: &[Vec<usize>]) -> Self {
        Self {
            clusters: clusters
                .iter()
                .map(|c| c.iter().map(|&i| scene.objects()[i].id).collect())
                .collect(),
            status: None,
            fallback: None,
            riders: Vec::new(),
        }
    }

    /// The number of clusters.
    pub fn len(&self) -> usize {
        self.clusters.len()
    }

    /// Whether there are no clusters (an empty table).
    pub fn is_empty(&self) -> bool {
        self.clusters.is_empty()
    }

    /// Sorts ids inside each cluster and clusters by their first id, so equal partitions compare equal.
    pub fn normalised(mut self) -> Self {
        for cluster in &mut self.clusters {
            cluster.sort_unstable();
        }
        self.clusters.sort();
        for ride in &mut self.riders {
            ride.row.sort_unstable();
        }
        self.riders.sort();
        self
    }

    /// The rider this clustering puts on `row` (its members, in any order), if any.
    pub fn rider_on(&self, row: &[ObjectId]) -> Option<ObjectId> {
        let mut sorted = row.to_vec();
        sorted.sort_unstable();
        self.riders
            .iter()
            .find(|ride| ride.row == sorted)
            .map(|ride| ride.rider)
    }

    /// Whether this clustering puts `object` on a row as a rider.
    pub fn is_rider(&self, object: ObjectId) -> bool {
        self.riders.iter().any(|ride| ride.rider == object)
    }
}

/// Summed minimum grasp diameter of a group of objects given by scene index, metres.
pub fn summed_diameter(scene: &Scene, members: &[usize]) -> f64 {
    members.iter().map(|&i| scene.min_grasp_diameter(i)).sum()
}

/// Whether a group of objects (scene indices) fits the jaws: one object always does (it may be
/// ungraspable, which is the grasp planner's business), more must have `Σ d* ≤ usable gap`.
pub fn fits_jaws(scene: &Scene, members: &[usize]) -> bool {
    members.len() <= 1 || summed_diameter(scene, members) <= scene.gripper().usable_gap()
}

/// Gap between neighbours in a candidate's row, metres (the SOCP push planner's default `gap`): the
/// row test of the MILP's candidates and of the heuristic's clusters as taken.
pub const ROW_GAP: f64 = 0.001;

/// Whether a group of objects (scene indices) can stand in one row of at most `limit` metres along
/// some closing axis, neighbours `gap` apart, at their current yaws. The summed width along an axis
/// is concave between the members' edge normals, so its minimum is at one of them: those are the
/// axes tried, and the answer is exact. It is monotone: adding an object never makes a row fit.
pub fn admits_row(scene: &Scene, members: &[usize], limit: f64, gap: f64) -> bool {
    if members.len() <= 1 {
        return true;
    }
    let spacing = gap * (members.len() - 1) as f64;
    let outlines: Vec<&ConvexPolygon> = members.iter().map(|&m| scene.world_polygon(m)).collect();
    // On outlines of many vertices, widths are bounded from below first (extreme vertices climbed
    // from the last axis's) and measured in full only on axes where the bounds still leave room:
    // the same answer, cheaper there.
    let most = outlines.iter().map(|o| o.len()).max().unwrap_or(0);
    let mut extremes: Vec<Extremes<'_>> = if worth_pruning(most, most) {
        outlines.iter().map(|o| Extremes::new(o)).collect()
    } else {
        Vec::new()
    };
    outlines.iter().any(|outline| {
        outline.edges().any(|(a, b)| {
            let edge = b - a;
            let axis = nalgebra::Vector2::new(edge.y, -edge.x).normalize();
            // `width` measures along the axis normalised once more; the bounds use the same.
            let unit = axis.normalize();
            let least: f64 = if extremes.is_empty() {
                f64::NEG_INFINITY
            } else {
                extremes
                    .iter_mut()
                    .map(|e| {
                        let (low, high) = e.bounds(&unit);
                        high - low
                    })
                    .sum()
            };
            if least + spacing > limit {
                return false;
            }
            let widths: f64 = outlines.iter().map(|o| o.width(&axis)).sum();
            widths + spacing <= limit
        })
    })
}

/// `clusters` (scene indices) with every cluster that cannot stand in one row of at most `limit`
/// ([`admits_row`]) split into single objects, as a planner that pushes rows would take them.
pub fn split_unrowable(
    scene: &Scene,
    clusters: Vec<Vec<usize>>,
    limit: f64,
    gap: f64,
) -> Vec<Vec<usize>> {
    clusters
        .into_iter()
        .flat_map(|members| {
            if admits_row(scene, &members, limit, gap) {
                vec![members]
            } else {
                members.into_iter().map(|i| vec![i]).collect()
            }
        })
        .collect()
}

/// A way to cluster a scene.
pub trait Clusterer {
    /// A short name for logs and tables (`hierarchical`, `milp`).
    fn name(&self) -> &'static str;

    /// What its answers can claim ([`Abilities`]); by default, none.
    fn abilities(&self) -> Abilities {
        Abilities::heuristic(self.name())
    }

    /// Partitions the scene's objects into valid clusters.
    ///
    /// # Errors
    /// Only for misuse (invalid settings); a clustering problem with no good answer is reported in
    /// the outcome's status.
    fn cluster(&self, scene: &Scene) -> Result<Outcome<Clustering>>;

    /// As [`Clusterer::cluster`], with what earlier calls of the same run left in `memory` (the
    /// MILP's last proven optimum, [`ClusterMemory`]); a clusterer that remembers nothing ignores
    /// it. The closed loop calls this with the memory in the run's `policy::TripContext`.
    ///
    /// # Errors
    /// As [`Clusterer::cluster`].
    fn cluster_remembering(
        &self,
        scene: &Scene,
        memory: &mut ClusterMemory,
    ) -> Result<Outcome<Clustering>> {
        let _ = memory;
        self.cluster(scene)
    }
}
