//! Riders in the clustering (`formulations/stacking.md`, "Riders in the clustering"): which single
//! objects may ride on which candidate rows, and what each ride is worth to the objective.
//!
//! A ride `(S, r)` puts the object `r`, a cluster of its own, on the top of candidate row `S`
//! (`|S| ≥ 2`) just before `S` is grasped, so that `r` needs no trip of its own. The model gains a
//! binary `y_{S,r}` per ride (`milp/backend.rs`):
//!
//! ```text
//! Σ_r y_{S,r} ≤ x_S        one rider per row, and only on a chosen row
//! Σ_S y_{S,r} ≤ x_{r}      a rider rides one row, and stays a cluster of its own
//! ```
//!
//! with `−v_{S,r}·y_{S,r}` in the objective. The partition and the clash rows are unchanged: a rider
//! is still a cluster of its own for separability, so every clustering the model could choose
//! before is still a choice, with no rider.
//!
//! A ride is offered when `r`'s centroid lies within `reach` of the row's mean centroid and the
//! rider checks of [`crate::stack`] place it on the row as pushing is predicted to leave it: the
//! members packed along their narrowest closing axis, `ROW_GAP` apart, their centroids on one line
//! through the mean centroid (the jaws' centre line), turns unchanged. The pads are judged as that
//! row stands (not where the closing leaves it, which needs the jaws the policy plans later); the
//! policy checks the ride again on the table predicted after the real pushes. No member of a row
//! that an earlier trip pushed together and that waits for its grasp
//! ([`super::ClusterMemory::hold`]) is offered as a rider: the model would price that row's push
//! again, though it is spent.
//!
//! The worth `v`: under the time objective the seconds it is expected to save,
//! `v = q_r·(T_trip + T_look) − ΔT_place`, with `q_r` the probability that the rider rides, `T_trip`
//! the nominal single-object trip, `T_look` the look before it, and `ΔT_place` the time model's
//! place action (pick at the rider's centroid, release over the row's mean centroid) with nominal
//! grasps; only rides with `v > 0` are offered. Under the fewest-clusters objective a ride saves one
//! cluster, `v = 1 − ε·‖r − S̄‖`, the distance breaking ties as spread does.

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::ROW_GAP;
use super::objective::{ClusterObjective, CostModel};
use crate::geometry::ConvexPolygon;
use crate::problem::Problem;
use crate::scene::{ObjectId, Scene};
use crate::stack::{Row, StackSettings, place_rider, plates_carry};
use crate::time_model::{GraspPath, RiderPath, TimeModel};

/// A rider the clustering puts on a row: the object and the row's members, by id.
#[derive(
    Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, schemars::JsonSchema,
)]
pub struct Ride {
    /// The rider, a cluster of its own in the clustering.
    pub rider: ObjectId,
    /// The row it rides on, a cluster of the clustering, ids ascending.
    pub row: Vec<ObjectId>,
}

/// What the clustering needs to offer rides: the rider checks, the probability that a placed rider
/// rides, and how far from a row riders are looked for.
#[derive(Clone, Debug, PartialEq)]
pub struct RideOptions {
    /// The quasi-static checks (`stack::place_rider`).
    pub checks: StackSettings,
    /// Probability that a placed rider rides its trip to the bin (`q_r`).
    pub carried: f64,
    /// Riders are looked for within this distance of a row's mean centroid, metres.
    pub reach: f64,
}

/// One ride of the model: positions of the row and of the rider's single-object candidate among the
/// candidates, its worth (`v`, in the objective's units) and the rider's distance from the row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct RideVar {
    pub row: usize,
    pub single: usize,
    pub worth: f64,
    pub distance: f64,
}

/// The row `members` (scene indices) as pushing is predicted to leave it (module docs), or `None`
/// for fewer than two members.
pub fn predicted_row(scene: &Scene, members: &[usize]) -> Option<Row> {
    if members.len() < 2 {
        return None;
    }
    let outlines: Vec<&ConvexPolygon> = members.iter().map(|&m| scene.world_polygon(m)).collect();
    // The narrowest closing axis: the summed width is least along one of the edge normals.
    let axis = outlines
        .iter()
        .flat_map(|o| o.edges().map(|(a, b)| Vector2::new(b.y - a.y, a.x - b.x)))
        .filter(|n| n.norm() > 1e-12)
        .map(|n| n.normalize())
        .min_by(|a, b| {
            let width = |u: &Vector2<f64>| outlines.iter().map(|o| o.width(u)).sum::<f64>();
            width(a).total_cmp(&width(b))
        })?;
    let across = Vector2::new(-axis.y, axis.x);
    let mean = members
        .iter()
        .map(|&m| scene.centroid(m).coords)
        .sum::<Vector2<f64>>()
        / members.len() as f64;
    let mut order: Vec<usize> = (0..members.len()).collect();
    order.sort_by(|&a, &b| {
        axis.dot(&scene.centroid(members[a]).coords)
            .total_cmp(&axis.dot(&scene.centroid(members[b]).coords))
    });
    let total: f64 =
        outlines.iter().map(|o| o.width(&axis)).sum::<f64>() + ROW_GAP * (members.len() - 1) as f64;
    let mut start = axis.dot(&mean) - total / 2.0;
    let mut packed: Vec<Option<ConvexPolygon>> = vec![None; members.len()];
    for k in order {
        let outline = outlines[k];
        let (low, high) = outline.projection(&axis);
        let off_line = across.dot(&(scene.centroid(members[k]).coords - mean));
        packed[k] = Some(outline.translated(&(axis * (start - low) - across * off_line)));
        start += high - low + ROW_GAP;
    }
    Some(Row {
        outlines: packed.into_iter().collect::<Option<_>>()?,
        heights: members.iter().map(|&m| scene.objects()[m].height).collect(),
        axis,
        closing: None,
    })
}

/// The rides offered on `candidates` (scene indices; the single-object candidates are the riders'
/// own clusters), by the module docs' rule; no member of a row in `held` (rows already pushed
/// together, waiting for their grasps) is offered as a rider.
pub(super) fn ride_vars(
    scene: &Scene,
    candidates: &[Vec<usize>],
    costs: &CostModel<'_>,
    problem: &Problem,
    options: &RideOptions,
    held: &[Vec<ObjectId>],
) -> Vec<RideVar> {
    let mut single_of = vec![None; scene.len()];
    for (k, candidate) in candidates.iter().enumerate() {
        if let [only] = candidate[..]
            && !held
                .iter()
                .flatten()
                .any(|&id| id == scene.objects()[only].id)
        {
            single_of[only] = Some(k);
        }
    }
    let mut rides = Vec::new();
    for (k, members) in candidates.iter().enumerate() {
        if members.len() < 2 {
            continue;
        }
        let row = RowToRide::new(scene, members, problem);
        for (r, single) in single_of.iter().enumerate() {
            let Some(single) = *single else { continue };
            if let Some((worth, distance)) = row.worth(scene, r, costs, problem, options) {
                rides.push(RideVar {
                    row: k,
                    single,
                    worth,
                    distance,
                });
            }
        }
    }
    rides
}

/// What the clustering's objective gains when object `rider` (a scene index) rides on the row
/// `members` (scene indices), and the rider's distance from the row's mean centroid; `None` when
/// the ride is not offered (module docs: out of reach, a member of the row, the checks refuse it on
/// the predicted row, or it is worth nothing).
pub fn ride_worth(
    scene: &Scene,
    members: &[usize],
    rider: usize,
    costs: &CostModel<'_>,
    problem: &Problem,
    options: &RideOptions,
) -> Option<(f64, f64)> {
    RowToRide::new(scene, members, problem).worth(scene, rider, costs, problem, options)
}

/// A candidate row as every rider offered to it is judged against: its members, mean centroid,
/// predicted row and masses, computed once.
struct RowToRide<'a> {
    members: &'a [usize],
    mean: Point2<f64>,
    row: Option<Row>,
    masses: Vec<f64>,
}

impl<'a> RowToRide<'a> {
    fn new(scene: &Scene, members: &'a [usize], problem: &Problem) -> Self {
        let model = problem.grasp_model();
        Self {
            members,
            mean: Point2::from(
                members
                    .iter()
                    .map(|&m| scene.centroid(m).coords)
                    .sum::<Vector2<f64>>()
                    / members.len().max(1) as f64,
            ),
            row: predicted_row(scene, members),
            masses: members
                .iter()
                .map(|&m| model.mass_of(&scene.objects()[m]))
                .collect(),
        }
    }

    /// [`ride_worth`] of `rider` on this row.
    fn worth(
        &self,
        scene: &Scene,
        rider: usize,
        costs: &CostModel<'_>,
        problem: &Problem,
        options: &RideOptions,
    ) -> Option<(f64, f64)> {
        if self.members.contains(&rider) {
            return None;
        }
        let distance = nalgebra::distance(&scene.centroid(rider), &self.mean);
        if distance > options.reach {
            return None;
        }
        let row = self.row.as_ref()?;
        let model = problem.grasp_model();
        let object = &scene.objects()[rider];
        let mass = model.mass_of(object);
        if !plates_carry(model.friction_jaw, model.grip_force, &self.masses, &[mass]) {
            return None;
        }
        place_rider(
            row,
            &object.polygon,
            object.height,
            model.friction_object,
            &options.checks,
        )
        .ok()?;
        let worth = match costs.objective() {
            ClusterObjective::Time => {
                let time = problem.time_model();
                let gripper = scene.gripper();
                let saved =
                    options.carried * (time.nominal_trip_seconds(gripper) + time.look_seconds());
                saved - place_seconds(time, scene, scene.centroid(rider), self.mean)
            }
            ClusterObjective::FewestClusters => 1.0 - costs.epsilon() * distance,
        };
        (worth > 0.0).then_some((worth, distance))
    }
}

/// The seconds a place action adds to a trip without pushes whose grasp is at `row`: the rider
/// picked at `rider` and let go over `row`, nominal grasps throughout.
fn place_seconds(time: &TimeModel, scene: &Scene, rider: Point2<f64>, row: Point2<f64>) -> f64 {
    let gripper = scene.gripper();
    let nominal = TimeModel::nominal_grasp(gripper);
    let grasp = GraspPath {
        center: row,
        ..nominal
    };
    let ride = RiderPath {
        pick: GraspPath {
            center: rider,
            ..nominal
        },
        release: row,
    };
    time.trip_seconds_with_riders(gripper, &[], &[ride], &grasp)
        - time.trip_seconds(gripper, &[], &grasp)
}
