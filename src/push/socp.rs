//! Push targets from a second-order cone program: the least total push distance that lines a cluster
//! up between the jaws (`formulations/pushing.md`).
//!
//! For a fixed closing axis and order the problem is convex ([`row`](super::row)). The planner's
//! axes are `axes` even directions over `[0, π)`, every member's edge normals (along them objects meet
//! the plates and each other flat), the directions joining the members' centroids and their principal
//! axis; axes along which the members' widths cannot fit the jaws are dropped, and the rest carry a
//! lower bound on the push distance ([`lower_bound`]). A solved row becomes pushes as follows:
//! 1. members that would move less than `min_push` are held where they are and the program is solved
//!    again with them fixed ("objects already in place are not pushed"); when every member is that
//!    close, only the one nearest its target is held, since their small offsets add up across the row;
//! 2. the pushes are sequenced: every order of the pushes is tried until one has every object's straight
//!    sweep and the fingers' footprint clear of every other object as it stands at that moment
//!    (exact separating-axis sweeps, `geometry::cast_distance`, and [`plan_fork`]); a member whose
//!    straight push is refused may take two legs, across the closing axis and along it;
//! 3. the row is judged at its intended grasp: with `robust_rows` (default) as the policy's
//!    multi-object planner judges grasps, on the predicted table and on noisy copies of it
//!    ([`MultiObject::carries`]); otherwise by the grasp model alone (held, or a member slips out).
//!
//! The search, with `prefer_held_rows` (default), looks for the cheapest held row: every axis is
//! visited, first those along which a perfect row of the members is held by the grasp model (a cheap
//! test before any program), each group in order of its bound, skipping axes whose bound cannot beat
//! the cheapest held row found. Without a held row (or without the preference), the cheapest row that
//! can be pushed into place is taken, visiting axes by bound until none can beat it. For three or more
//! members, the other orders along the chosen axis are tried too (up to `max_orders`). The answer is
//! the cheapest held row if there is one, else the cheapest row; `PushPlan::row_held` says
//! which. No row on any axis: [`Status::Infeasible`]; rows but no push sequence: a failed status.
//!
//! With `flush` (flush pushes, [`super::flush`]) every push must meet a face of its object flat:
//! each moving member's target is kept within a cone about one face's inward normal (two linear
//! rows of the program, [`row`](super::row)). A pair is tried for every face of either member that
//! faces the other, along the axis [`pair_axis`] finds (the line through both centroids once the
//! pushed one stops), with the other held and the row no longer than the two and `flush_gap`, so
//! the pushed one ends nearly touching; larger clusters are solved freely on each axis first and
//! again with each moving member's push turned to its nearest face normal. Pushes are made with
//! the jaws closed to one block facing the face.
//!
//! Objects outside the cluster are kept clear by fixed half-planes: the line of largest separation
//! between the outside object and the hull of the cluster (or, if the object reaches into that hull,
//! between it and each member), with the current gap (at most `clearance`) kept. A member's whole
//! straight sweep then stays on its side.

use std::cell::Cell;
use std::sync::Arc;
use std::time::Instant;

use clarabel::solver::SolverStatus;
use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::flush::{
    Face, PairRow, block_opening, cone_directions, flush_face, flush_faces, pair_axis,
};
use super::fork::plan_fork_facing;
use super::row::{Fence, Motion, RowProblem, RowSolution, lower_bound, solve_row};
use super::{Push, PushPlan, PushPlanner, SkipReason, SkippedPush, predict};
use crate::error::Result;
use crate::geometry::{ConvexPolygon, cast_distance, convex_hull, max_separation};
use crate::grasp::{Body, JawPose, Memory, MultiObject, Squeeze, squeeze};
use crate::outcome::{Outcome, Stats, Status};
use crate::problem::Problem;
use crate::scene::{ObjectId, Pose, Scene};

/// Settings of [`Socp`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SocpSettings {
    /// Evenly spaced closing axes tried over `[0, π)`. Default 12 (15° apart).
    pub axes: usize,
    /// Orders tried along the chosen axis, the natural one included, for clusters of three or more.
    /// Default 6 (every order of three objects).
    pub max_orders: usize,

    /// Room left between the row and the usable jaw gap, metres. Default 0.010: on each side, the
    /// 4.5 mm the grasp planner keeps between an open plate and a pushed object, rounded up.
    pub margin: f64,
    /// Gap kept between neighbours in the row, metres. Default 0.001.
    pub gap: f64,
    /// How far every object must reach past the plates' centre line on each side, metres. Default
    /// 0.003: every object is caught by the plates and touches its neighbours when squeezed.
    pub straddle: f64,
    /// How far a target centroid may lie from the plates' centre line, metres. Default 0.002: in
    /// the simulator, rows whose centroids lie near that line are held far more often than rows
    /// whose centroids lie 10 mm or more off it (`pushmog grasp-agreement`). Against 0.004 (the
    /// default before), push-mog-opt carried 0.020 more objects per trip in the simulator on
    /// paper-100 and on 60 held-out scenes, and in MuJoCo (30 scenes, with noise) lost objects in
    /// 21 multi-object grasps instead of 35, at up to 5.5 % more push distance
    /// (`formulations/pushing.md`).
    pub centring: f64,
    /// How far inside the workspace's edges targets stay (or their start's distance from the edge,
    /// if smaller), metres. Default 0.005: pushes end a median 2.4 mm and a 90th percentile 6.1 mm
    /// from their targets in the simulator, and an object whose outline leaves the workspace can no
    /// longer be planned for (targets 1 µm inside left one object outside in 5 of 100 paper-100
    /// runs of push-mog-opt).
    pub edge_margin: f64,
    /// Gap kept to objects outside the cluster (or the current gap, if smaller), metres. Default 0.002.
    pub clearance: f64,
    /// Outside objects further than this from every member are ignored, metres. Default 0.15.
    pub neighbourhood: f64,
    /// Among rows that can be pushed into place, take the cheapest one the grasp model predicts held
    /// (the cheapest of all when none is). Default true.
    pub prefer_held_rows: bool,
    /// Judge a row's intended grasp as the policy's multi-object planner judges its grasps: on the
    /// table predicted after the pushes and on copies moved by the noise the run assumes (a pushed
    /// object's push error included), held when at least its `min_probability` of the samples
    /// carry every member. Default true. False, or a planner built without that judge
    /// ([`Socp::with_judge`]): the grasp model's prediction alone.
    pub robust_rows: bool,
    /// Push every object flush (`push::flush`): the jaws closed to one block that meets one face
    /// of the object flat and pushes within `flush_cone` of that face's inward normal, so the
    /// object slides without turning. A pair lines up along the line through both centroids once
    /// the pushed one stops, tight against the other (`flush_gap`); in larger clusters each moving
    /// member's push is turned to its nearest face normal. The clustering then proposes only pairs
    /// a flush push lines up. Default false (the paper's fork, jaw line across the push, any
    /// direction). In the simulator, pushes within 5° of a face normal turned their object a
    /// median 3.8° and the pair was carried together 91 % of the time, against 12–15° and 73–76 %
    /// for pushes 10–30° off; flush pushes turned it a median 1.5° (`formulations/pushing.md`).
    pub flush: bool,
    /// How far the face a flush push meets must reach past the line of the push through the
    /// centroid on each side, beyond 2 mm of placement error, metres. Default 0.002.
    pub flush_margin: f64,
    /// Largest angle between a flush push and its face's normal, radians. Default 0.19 (10.9°): half
    /// the friction cone of the pads on the objects at μ 0.4 (atan 0.4 = 21.8°), within which the
    /// contact holds the object without slipping along the face. In the simulator, pushes 10° off
    /// the normal turned their object a median 1.4–2.0° (p90 3.7–4.4°), as pushes along it; 20°
    /// off, a p90 of 16°. 0: along the normal only.
    pub flush_cone: f64,
    /// How far from its neighbour a flush push of a pair leaves the pushed object along the row,
    /// at most, metres (and at least `gap`). Default 0.003, about 1.4 standard deviations of where
    /// flush pushes end along the push (2.2 mm in the simulator): the row is then as short as
    /// the two allow and the jaws have room on both sides, instead of the row just fitting the
    /// jaws less the margin, as the least push would leave it.
    pub flush_gap: f64,
}

impl Default for SocpSettings {
    fn default() -> Self {
        Self {
            axes: 12,
            max_orders: 6,
            margin: 0.010,
            gap: 0.001,
            straddle: 0.003,
            centring: 0.002,
            edge_margin: 0.005,
            clearance: 0.002,
            neighbourhood: 0.15,
            prefer_held_rows: true,
            robust_rows: true,
            flush: false,
            flush_margin: 0.002,
            flush_cone: 0.19,
            flush_gap: 0.003,
        }
    }
}

impl SocpSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let counts: [(&str, usize, (usize, usize), &str); 2] = [
            ("axes", self.axes, (1, 360), "each axis is a solve"),
            (
                "max_orders",
                self.max_orders,
                (1, 720),
                "each order is a solve (720 = every order of six)",
            ),
        ];
        for (field, value, range, why) in counts {
            crate::error::count_in_range("socp", field, value, range, why)?;
        }
        let lengths: [(&str, f64, (f64, f64)); 9] = [
            ("margin", self.margin, (0.0, 0.05)),
            ("gap", self.gap, (0.0, 0.02)),
            ("straddle", self.straddle, (0.0, 0.05)),
            ("centring", self.centring, (0.0, 0.05)),
            ("edge_margin", self.edge_margin, (0.0, 0.05)),
            ("clearance", self.clearance, (0.0, 0.05)),
            ("neighbourhood", self.neighbourhood, (0.0, 2.0)),
            ("flush_margin", self.flush_margin, (0.0, 0.02)),
            ("flush_gap", self.flush_gap, (0.0, 0.05)),
        ];
        for (field, value, range) in lengths {
            crate::error::in_range("socp", field, value, range, "metres, within a jaw's reach")?;
        }
        crate::error::in_range(
            "socp",
            "flush_cone",
            self.flush_cone,
            (0.0, 0.6),
            "radians off a face's normal; beyond atan 0.6 (31°) the pads slip on any known surface",
        )
    }
}

/// Push targets from the row SOCP.
#[derive(Clone, Debug)]
pub struct Socp {
    settings: SocpSettings,
    /// What every stage agrees on: the grasp model, the fork, `min_push` and the time model.
    problem: Arc<Problem>,
    /// Closings of perfect rows already judged (`grasp/memory.rs`): the same cluster is planned
    /// again on later trips.
    memory: Memory,
    /// The policy's multi-object planner, judging rows under noise when `robust_rows` is set.
    judge: Option<MultiObject>,
}

impl Default for Socp {
    fn default() -> Self {
        Self {
            settings: SocpSettings::default(),
            problem: Problem::shared_default(),
            memory: Memory::default(),
            judge: None,
        }
    }
}

/// A solved row turned into pushes.
struct Attempt {
    plan: PushPlan,
    held: bool,
    objective: f64,
    axis: Vector2<f64>,
    status: SolverStatus,
}

impl Socp {
    /// A planner with these settings, judging rows with the problem's grasp model, making fork pushes
    /// of its geometry, none shorter than its `min_push`, and choosing which members move by its
    /// time model.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: SocpSettings, problem: Arc<Problem>) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            settings,
            problem,
            memory: Memory::default(),
            judge: None,
        })
    }

    /// The same planner judging rows as `judge` judges its grasps ([`MultiObject::carries`]) when
    /// `robust_rows` is set (the policies give it their multi-object planner).
    pub fn with_judge(mut self, judge: MultiObject) -> Self {
        self.judge = Some(judge);
        self
    }

    /// The effective settings.
    pub fn settings(&self) -> &SocpSettings {
        &self.settings
    }

    fn axes(&self, starts: &[Point2<f64>], outlines: &[ConvexPolygon]) -> Vec<Vector2<f64>> {
        let n = self.settings.axes;
        let mut axes: Vec<Vector2<f64>> = (0..n)
            .map(|k| {
                let angle = std::f64::consts::PI * k as f64 / n as f64;
                Vector2::new(angle.cos(), angle.sin())
            })
            .collect();
        // Edge normals: along them an object meets the plates and its neighbours flat.
        for outline in outlines {
            for (a, b) in outline.edges() {
                let edge = b - a;
                axes.push(Vector2::new(edge.y, -edge.x).normalize());
            }
        }
        for (a, p) in starts.iter().enumerate() {
            for q in &starts[a + 1..] {
                let joining = q - p;
                if joining.norm() > 0.0 {
                    axes.push(joining.normalize());
                }
            }
        }
        // Principal axis of the centroids.
        let mean = starts.iter().map(|p| p.coords).sum::<Vector2<f64>>() / starts.len() as f64;
        let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
        for p in starts {
            let d = p.coords - mean;
            xx += d.x * d.x;
            xy += d.x * d.y;
            yy += d.y * d.y;
        }
        let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
        axes.push(Vector2::new(angle.cos(), angle.sin()));
        axes
    }

    /// Half-planes keeping each member clear of the outside objects near the cluster.
    ///
    /// When a line separates an outside object from the hull of the whole cluster, that line (the
    /// axis of largest separation) fences every member: members may move anywhere on the cluster's
    /// side. An object reaching into the cluster's hull is fenced off from each member separately,
    /// along the axis of largest separation between the two.
    fn fences(&self, scene: &Scene, members: &[usize], outlines: &[ConvexPolygon]) -> Vec<Fence> {
        let points: Vec<Point2<f64>> = members
            .iter()
            .flat_map(|&i| scene.world_polygon(i).vertices().to_vec())
            .collect();
        let hull = ConvexPolygon::new(convex_hull(&points)).ok();
        let mut fences = Vec::new();
        for other in (0..scene.len()).filter(|o| !members.contains(o)) {
            let outline = scene.world_polygon(other);
            let whole = hull
                .as_ref()
                .map(|h| max_separation(outline, h))
                .filter(|&(_, separation)| separation > 0.0);
            for (m, &index) in members.iter().enumerate() {
                let own = scene.world_polygon(index);
                let (normal, separation) = match whole {
                    Some((normal, _)) => {
                        // The member's own gap along the cluster's fence.
                        let gap = own.projection(&normal).0 - outline.projection(&normal).1;
                        (normal, gap)
                    }
                    None => max_separation(outline, own),
                };
                if separation > self.settings.neighbourhood {
                    continue;
                }
                // n·p − h(−n) ≥ max_q n·x + kept gap, with h about the centroid.
                let kept = self.settings.clearance.min(separation.max(0.0));
                let far_side = outline.projection(&normal).1;
                let offset = far_side + kept + outlines[m].support(&-normal);
                // Never demand more than the member already has (rounding).
                let offset = offset.min(normal.dot(&scene.centroid(index).coords));
                fences.push(Fence {
                    member: m,
                    normal,
                    offset,
                });
            }
        }
        fences
    }

    /// Whether the grasp model holds a perfect row along `axis`: the members in `order`, centroids on
    /// one line, neighbours `gap` apart, jaws centred on it. A cheap stand-in, solved before any
    /// program, for whether rows along `axis` can be held.
    fn proxy_held(
        &self,
        outlines: &[ConvexPolygon],
        masses: &[f64],
        order: &[usize],
        axis: &Vector2<f64>,
        gripper: &crate::scene::Gripper,
    ) -> bool {
        let mut placed = Vec::with_capacity(order.len());
        let mut at = 0.0;
        for (j, &m) in order.iter().enumerate() {
            if j > 0 {
                at += outlines[order[j - 1]].support(axis)
                    + outlines[m].support(&-axis)
                    + self.settings.gap;
            }
            placed.push(outlines[m].translated(&(axis * at)));
        }
        let (Some(&first), Some(&last)) = (order.first(), order.last()) else {
            return false;
        };
        let low = -outlines[first].support(&-axis);
        let high = at + outlines[last].support(axis);
        let jaws = JawPose {
            center: Point2::from(axis * ((low + high) / 2.0)),
            angle: axis.y.atan2(axis.x),
            opening: gripper.stroke,
        };
        let bodies: Vec<Body<'_>> = placed
            .iter()
            .zip(order)
            .map(|(outline, &m)| Body {
                outline,
                mass: masses[m],
            })
            .collect();
        matches!(
            self.memory.squeeze(&bodies, gripper, &jaws, self.problem.grasp_model()),
            Squeeze::Held { objects, .. } if objects.len() == order.len()
        )
    }

    /// Whether every member is carried when the jaws close at `jaws` after the pushes: by the grasp
    /// model alone, or under noise by the judge (`robust_rows`).
    fn row_is_held(
        &self,
        scene: &Scene,
        members: &[usize],
        pushes: &[Push],
        jaws: &JawPose,
    ) -> bool {
        let Ok(after) = predict(scene, pushes) else {
            return false;
        };
        match self.judge.as_ref().filter(|_| self.settings.robust_rows) {
            Some(judge) => {
                let pushed: Vec<usize> = pushes
                    .iter()
                    .filter_map(|p| after.index_of(p.object))
                    .collect();
                judge.carries(&after, jaws, &pushed, members)
            }
            None => matches!(squeeze(&after, jaws, self.problem.grasp_model()),
                Squeeze::Held { objects, .. } if members.iter().all(|m| objects.contains(m))),
        }
    }

    /// Pushes that reach `targets` in some order with every sweep and finger path clear. Straight
    /// pushes first, in every order; only when no order works may a member whose straight push is
    /// refused take two legs instead, across the closing axis `axis` and along it
    /// ([`Socp::two_legs`]). The failure reported is that of the straight pushes.
    fn sequence(
        &self,
        scene: &Scene,
        members: &[usize],
        targets: &[Point2<f64>],
        axis: &Vector2<f64>,
    ) -> std::result::Result<Vec<Push>, (ObjectId, SkipReason)> {
        let moves: Vec<usize> = (0..members.len())
            .filter(|&m| nalgebra::distance(&targets[m], &scene.centroid(members[m])) > 0.0)
            .collect();
        let ids: Vec<ObjectId> = scene.objects().iter().map(|o| o.id).collect();
        let mut straight_failure = None;
        for with_legs in [false, true] {
            for order in permutations(&moves, 120) {
                let mut world: Vec<ConvexPolygon> = (0..scene.len())
                    .map(|i| scene.world_polygon(i).clone())
                    .collect();
                let mut pushes = Vec::new();
                let mut failed = None;
                for &m in &order {
                    let index = members[m];
                    let offset = targets[m] - scene.centroid(index);
                    let from = scene.objects()[index].pose;
                    let legs = match self.leg(scene, &world, &ids, index, from, offset) {
                        Ok(push) => Ok(vec![(push, offset)]),
                        Err(straight) if with_legs => self
                            .two_legs(scene, &world, &ids, index, offset, axis)
                            .ok_or(straight),
                        Err(straight) => Err(straight),
                    };
                    match legs {
                        Ok(legs) => {
                            for (push, moved) in legs {
                                world[index] = world[index].translated(&moved);
                                pushes.push(push);
                            }
                        }
                        Err(reason) => {
                            failed = Some((ids[index], reason));
                            break;
                        }
                    }
                }
                match failed {
                    None => return Ok(pushes),
                    Some(failure) if !with_legs => straight_failure = Some(failure),
                    Some(_) => {}
                }
            }
        }
        match straight_failure {
            Some(failure) => Err(failure),
            None => Ok(Vec::new()),
        }
    }

    /// One straight push by `offset` of the object `index`, at pose `from` on the table `world` as
    /// it stands: its sweep must touch no other object and the fingers must find room
    /// ([`plan_fork`]).
    fn leg(
        &self,
        scene: &Scene,
        world: &[ConvexPolygon],
        ids: &[ObjectId],
        index: usize,
        from: Pose,
        offset: Vector2<f64>,
    ) -> std::result::Result<Push, SkipReason> {
        let distance = offset.norm();
        let direction = offset / distance;
        let swept = world[index].swept_box(&offset);
        if let Some(blocker) = (0..world.len())
            .filter(|&o| o != index && world[o].box_meets(swept))
            .find(|&o| {
                cast_distance(&world[index], &direction, distance, &world[o])
                    .is_some_and(|hit| hit < distance - 1e-9)
            })
        {
            return Err(SkipReason::BlockedBy {
                object: ids[blocker],
            });
        }
        let gripper = scene.gripper();
        let (opening, facing) = if self.settings.flush {
            let settings = &self.settings;
            let face = flush_face(
                &world[index],
                settings.flush_margin,
                &direction,
                settings.flush_cone,
            )
            .ok_or(SkipReason::NotFlush)?;
            (block_opening(gripper), face.normal)
        } else {
            (gripper.fork_push_opening(), direction)
        };
        let fork = plan_fork_facing(
            gripper,
            self.problem.fork(),
            world,
            ids,
            index,
            scene.objects()[index].height,
            (&direction, &facing),
            distance,
            opening,
        )?;
        Ok(Push {
            object: ids[index],
            from,
            to: Pose::new(from.x + offset.x, from.y + offset.y, from.yaw),
            direction,
            distance,
            fork,
        })
    }

    /// The push by `offset` as two legs, one across `axis` and one along it, in either order, when
    /// both are at least `min_push` long and each is clear. Two objects whose extents along some
    /// line are apart cannot meet while one slides across that line, so a member that a straight
    /// push would drag past a neighbour's corner reaches its slot this way: along the axis first when
    /// it lies beside the neighbour across the axis, across first when it lies in line with it.
    fn two_legs(
        &self,
        scene: &Scene,
        world: &[ConvexPolygon],
        ids: &[ObjectId],
        index: usize,
        offset: Vector2<f64>,
        axis: &Vector2<f64>,
    ) -> Option<Vec<(Push, Vector2<f64>)>> {
        let along = axis * offset.dot(axis);
        let across = offset - along;
        if along.norm() < self.problem.min_push() || across.norm() < self.problem.min_push() {
            return None;
        }
        let from = scene.objects()[index].pose;
        // The corner of the path keeps inside the workspace as targets do: `edge_margin` from every
        // edge, or the start's own distance from it if smaller (both legs then stay inside too).
        let workspace = scene.workspace();
        let start_room = workspace.room(world[index].bounding_box());
        [[across, along], [along, across]]
            .into_iter()
            .find_map(|[a, b]| {
                let corner = world[index].translated(&a);
                let inside = workspace
                    .room(corner.bounding_box())
                    .iter()
                    .zip(start_room)
                    .all(|(&r, start)| r >= self.settings.edge_margin.min(start));
                if !inside {
                    return None;
                }
                let first = self.leg(scene, world, ids, index, from, a).ok()?;
                let mut moved = world.to_vec();
                moved[index] = corner;
                let second = self.leg(scene, &moved, ids, index, first.to, b).ok()?;
                Some(vec![(first, a), (second, b)])
            })
    }
}

/// A row to try: its closing axis, its lower bound on the pushes, whether a perfect row along it is
/// held by the grasp model, the members' order along it, and how they may move (`None`: flush
/// pushes turned to the nearest face normal once solved).
struct Candidate {
    bound: f64,
    axis: Vector2<f64>,
    proxy: bool,
    order: Vec<usize>,
    motion: Option<Motion>,
}

/// Largest angle through which a flush push of a larger cluster turns a member's planned push to
/// its nearest face normal, radians (45°).
const SNAP: f64 = std::f64::consts::FRAC_PI_4;

/// Push plans whose times differ by at most this are taken as equally fast, seconds: 2.5 mm of
/// pushing at the time model's default push speed (0.05 m/s).
const EQUAL_TIME: f64 = 0.05;

/// Pushes in order, the targets they reach and the plates' centre line across the axis.
type Realised = (Vec<Push>, Vec<Point2<f64>>, f64);

/// The jaws the row was built for: closing along `axis`, centred on the row's extent along it and on
/// its centre line across, fully open.
fn intended_grasp(
    axis: &Vector2<f64>,
    targets: &[Point2<f64>],
    outlines: &[ConvexPolygon],
    centre_line: f64,
    stroke: f64,
) -> JawPose {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for (target, outline) in targets.iter().zip(outlines) {
        let at = target.coords.dot(axis);
        low = low.min(at - outline.support(&-axis));
        high = high.max(at + outline.support(axis));
    }
    let across = Vector2::new(-axis.y, axis.x);
    JawPose {
        center: Point2::from(axis * ((low + high) / 2.0) + across * centre_line),
        angle: axis.y.atan2(axis.x),
        opening: stroke,
    }
}

/// Up to `limit` orderings of `items`, the given order first (Heap's algorithm).
fn permutations(items: &[usize], limit: usize) -> Vec<Vec<usize>> {
    let mut current = items.to_vec();
    let mut out = vec![current.clone()];
    let n = current.len();
    let mut counters = vec![0usize; n];
    let mut i = 0;
    while i < n && out.len() < limit {
        if counters[i] < i {
            if i % 2 == 0 {
                current.swap(0, i);
            } else {
                current.swap(counters[i], i);
            }
            out.push(current.clone());
            counters[i] += 1;
            i = 0;
        } else {
            counters[i] = 0;
            i += 1;
        }
    }
    out
}

impl PushPlanner for Socp {
    fn name(&self) -> &'static str {
        "socp"
    }

    fn plan(&self, scene: &Scene, cluster: &[ObjectId]) -> Result<Outcome<PushPlan>> {
        let started = Instant::now();
        let members = scene.indices_of(cluster)?;
        let finish = |plan: PushPlan,
                      status: Status,
                      backend: Option<String>,
                      counters: Vec<(String, f64)>| {
            let objective = plan.pushes.iter().map(|p| p.distance).sum::<f64>() + 0.0;
            Outcome {
                value: plan,
                status,
                stats: Stats {
                    seconds: started.elapsed().as_secs_f64(),
                    objective: Some(objective),
                    backend_status: backend,
                    counters,
                    ..Stats::default()
                },
            }
        };
        if members.len() < 2 {
            return Ok(finish(
                PushPlan::default(),
                Status::Optimal,
                None,
                Vec::new(),
            ));
        }
        let starts: Vec<Point2<f64>> = members.iter().map(|&i| scene.centroid(i)).collect();
        let outlines: Vec<ConvexPolygon> = members
            .iter()
            .map(|&i| {
                scene
                    .world_polygon(i)
                    .translated(&-scene.centroid(i).coords)
            })
            .collect();
        let masses: Vec<f64> = members
            .iter()
            .map(|&i| self.problem.grasp_model().mass_of(&scene.objects()[i]))
            .collect();
        let fences = self.fences(scene, &members, &outlines);
        let gripper = scene.gripper();
        let problem = RowProblem {
            starts: &starts,
            outlines: &outlines,
            fences: &fences,
            workspace: scene.workspace(),
            edge: self.settings.edge_margin,
            row_limit: gripper.usable_gap() - self.settings.margin,
            gap: self.settings.gap,
            straddle: self.settings.straddle,
            centring: self.settings.centring,
        };
        let solves = Cell::new(0usize);
        let solver_seconds = Cell::new(0.0f64);
        let iterations = Cell::new(0u64);
        let last_status = Cell::new(SolverStatus::Unsolved);
        let solve = |axis: &Vector2<f64>, order: &[usize], motion: &Motion| {
            let solution = solve_row(&problem, axis, order, motion, self.settings.flush_cone);
            solves.set(solves.get() + 1);
            solver_seconds.set(solver_seconds.get() + solution.seconds);
            iterations.set(iterations.get() + u64::from(solution.iterations));
            last_status.set(solution.status);
            solution
        };
        let natural = |axis: &Vector2<f64>| {
            let mut order: Vec<usize> = (0..members.len()).collect();
            order.sort_by(|&a, &b| {
                starts[a]
                    .coords
                    .dot(axis)
                    .total_cmp(&starts[b].coords.dot(axis))
            });
            order
        };
        // Turns a solved row into pushes: hold members that would barely move (solving again with
        // them fixed), sequence the pushes, and judge the row with the grasp model.
        // Targets held where members barely move, then pushes sequenced. A member that cannot be
        // pushed (its path is blocked, or there is no room for the fingers) is held where it is
        // and the row solved again around it, while another member is left to move.
        let realise = |axis: &Vector2<f64>,
                       order: &[usize],
                       base: &Motion,
                       mut fixed: Vec<bool>,
                       mut targets: Vec<Point2<f64>>,
                       mut centre_line: f64,
                       mut refine: bool|
         -> std::result::Result<Realised, (ObjectId, SkipReason)> {
            loop {
                if refine {
                    let refined = solve(axis, order, &base.holding(&fixed));
                    if refined.solved() {
                        targets = refined.targets;
                        centre_line = refined.centre_line;
                    }
                }
                for (m, &hold) in fixed.iter().enumerate() {
                    if hold || nalgebra::distance(&targets[m], &starts[m]) < self.problem.min_push()
                    {
                        targets[m] = starts[m];
                    }
                }
                match self.sequence(scene, &members, &targets, axis) {
                    Ok(pushes) => return Ok((pushes, targets, centre_line)),
                    Err((object, reason)) => {
                        let stuck = members
                            .iter()
                            .position(|&i| scene.objects()[i].id == object)
                            .filter(|&m| !fixed[m]);
                        let Some(m) = stuck else {
                            return Err((object, reason));
                        };
                        fixed[m] = true;
                        if fixed.iter().all(|&f| f) {
                            return Err((object, reason));
                        }
                        let refined = solve(axis, order, &base.holding(&fixed));
                        if !refined.solved() {
                            return Err((object, reason));
                        }
                        targets = refined.targets;
                        centre_line = refined.centre_line;
                        refine = false;
                    }
                }
            }
        };
        let attempt = |axis: &Vector2<f64>,
                       order: &[usize],
                       solution: &RowSolution,
                       base: &Motion|
         -> std::result::Result<Attempt, (ObjectId, SkipReason)> {
            let moves: Vec<f64> = (0..members.len())
                .map(|m| nalgebra::distance(&solution.targets[m], &starts[m]))
                .collect();
            let mut fixed: Vec<bool> = moves
                .iter()
                .zip(&base.fixed)
                .map(|(&d, &held)| held || d < self.problem.min_push())
                .collect();
            // Every member within `min_push` of its target does not make the row: their small
            // offsets add up across it. Only the member nearest its target is held then (with
            // those the row holds anyway), and the row solved again around it says whether the
            // others must still move.
            if fixed.iter().all(|&f| f) {
                let nearest = (0..moves.len())
                    .filter(|&m| !base.fixed[m])
                    .min_by(|&a, &b| moves[a].total_cmp(&moves[b]))
                    .unwrap_or(0);
                fixed = (0..moves.len())
                    .map(|m| m == nearest || base.fixed[m])
                    .collect();
            }
            let refine = fixed.iter().any(|&f| f);
            let (mut pushes, mut targets, mut centre_line) = realise(
                axis,
                order,
                base,
                fixed.clone(),
                solution.targets.clone(),
                solution.centre_line,
                refine,
            )?;
            // Fewer pushes: a push costs a fixed time (lowering and raising the fork) that many
            // centimetres of pushing take; the row with one more member held where it is may take
            // less time, though not less distance.
            if pushes.len() >= 2 {
                let seconds = |pushes: &[Push]| -> f64 {
                    pushes
                        .iter()
                        .map(|p| {
                            self.problem
                                .time_model()
                                .nominal_push_seconds(gripper, p.distance)
                        })
                        .sum()
                };
                // A member pushed up to one held in place can shove it; near the workspace edge,
                // out of the workspace. Of pushes that take about as long, those that hold the
                // members furthest from the edge are kept (the nearer member moves, inward).
                let held_room = |targets: &[Point2<f64>]| {
                    (0..members.len())
                        .filter(|&m| targets[m] == starts[m])
                        .flat_map(|m| {
                            scene
                                .workspace()
                                .room(scene.world_polygon(members[m]).bounding_box())
                        })
                        .fold(f64::INFINITY, f64::min)
                };
                let mut best = seconds(&pushes);
                let mut best_room = held_room(&targets);
                for m in 0..members.len() {
                    if fixed[m] || targets[m] == starts[m] {
                        continue;
                    }
                    let mut held = fixed.clone();
                    held[m] = true;
                    let refined = solve(axis, order, &base.holding(&held));
                    if !refined.solved() {
                        continue;
                    }
                    let Ok(fewer) = realise(
                        axis,
                        order,
                        base,
                        held,
                        refined.targets,
                        refined.centre_line,
                        false,
                    ) else {
                        continue;
                    };
                    let time = seconds(&fewer.0);
                    let room = held_room(&fewer.1);
                    let as_fast = (time - best).abs() <= EQUAL_TIME;
                    let better = time < best - EQUAL_TIME
                        || (as_fast && room > best_room + 1e-9)
                        || (as_fast && (room - best_room).abs() <= 1e-9 && time < best - 1e-9);
                    if better {
                        best = time;
                        best_room = room;
                        (pushes, targets, centre_line) = fewer;
                    }
                }
            }
            let skipped = (0..members.len())
                .filter(|&m| targets[m] == starts[m])
                .map(|m| SkippedPush {
                    object: scene.objects()[members[m]].id,
                    reason: SkipReason::AlreadyInPlace,
                })
                .collect();
            let jaws = intended_grasp(axis, &targets, &outlines, centre_line, gripper.stroke);
            let held = self.row_is_held(scene, &members, &pushes, &jaws);
            let objective = pushes.iter().map(|p| p.distance).sum();
            Ok(Attempt {
                plan: PushPlan {
                    pushes,
                    skipped,
                    intended_grasp: Some(jaws),
                    row_held: Some(held),
                },
                held,
                objective,
                axis: *axis,
                status: solution.status,
            })
        };

        // Rows to try: closing axes that can hold a row, with their lower bounds, whether a perfect
        // row along them is held by the grasp model, the order along them and how each member may
        // move. Flush pushes of a pair try each face of each member that faces the other, along
        // the axis the pair then lines up on; larger clusters try every axis, each moving member's
        // push turned to its nearest face normal once the row is solved.
        let faces: Vec<Vec<Face>> = outlines
            .iter()
            .map(|o| flush_faces(o, self.settings.flush_margin))
            .collect();
        let candidate = |axis: Vector2<f64>, order: Vec<usize>, motion: Option<Motion>| {
            let bound = lower_bound(&problem, &axis)?;
            let proxy = self.settings.prefer_held_rows
                && self.proxy_held(&outlines, &masses, &order, &axis, gripper);
            Some(Candidate {
                bound,
                axis,
                proxy,
                order,
                motion,
            })
        };
        let mut axes: Vec<Candidate> = if self.settings.flush && members.len() == 2 {
            let row = PairRow {
                row_limit: problem.row_limit,
                gap: problem.gap,
                straddle: problem.straddle,
                tight: Some(self.settings.flush_gap),
            };
            let cone = self.settings.flush_cone;
            let tries: Vec<(usize, Vector2<f64>, Vector2<f64>)> = (0..2)
                .flat_map(|m| {
                    faces[m].iter().flat_map(move |face| {
                        cone_directions(&face.normal, cone)
                            .into_iter()
                            .map(move |direction| (m, face.normal, direction))
                    })
                })
                .collect();
            tries
                .into_iter()
                .filter_map(|(m, normal, direction)| {
                    let other = 1 - m;
                    let towards = starts[other] - starts[m];
                    let margin = self.settings.flush_margin;
                    if direction.dot(&towards) <= 0.0
                        || flush_face(&outlines[m], margin, &direction, cone).is_none()
                    {
                        return None;
                    }
                    let longest = towards.norm() + problem.row_limit;
                    let axis = pair_axis(
                        (starts[m], &outlines[m]),
                        (starts[other], &outlines[other]),
                        &direction,
                        row,
                        longest,
                    )?;
                    let mut motion = Motion::free(2);
                    motion.fixed[other] = true;
                    motion.along[m] = Some(normal);
                    // Tight: the pushed one goes on until it nearly touches the other.
                    let widths: f64 = [axis, -axis]
                        .iter()
                        .map(|d| outlines[0].support(d) + outlines[1].support(d))
                        .sum();
                    motion.limit = Some(problem.row_limit.min(widths + self.settings.flush_gap));
                    candidate(axis, vec![other, m], Some(motion))
                })
                .collect()
        } else {
            let free = (!self.settings.flush).then(|| Motion::free(members.len()));
            self.axes(&starts, &outlines)
                .into_iter()
                .filter_map(|axis| candidate(axis, natural(&axis), free.clone()))
                .collect()
        };
        axes.sort_by(|a, b| a.bound.total_cmp(&b.bound));
        // The row along `axis` in `order`, solved with the candidate's motion; without one (flush
        // pushes of three or more), solved freely first and then again with each moving member's
        // push along its nearest face normal (within 45°; members without one are held).
        let solve_candidate = |axis: &Vector2<f64>, order: &[usize], motion: Option<&Motion>| {
            if let Some(motion) = motion {
                let solution = solve(axis, order, motion);
                return solution.solved().then(|| (solution, motion.clone()));
            }
            let free = solve(axis, order, &Motion::free(members.len()));
            if !free.solved() {
                return None;
            }
            let mut motion = Motion::free(members.len());
            for m in 0..members.len() {
                let moved = free.targets[m] - starts[m];
                let widest = SNAP + self.settings.flush_cone;
                let nearest = faces[m]
                    .iter()
                    .map(|face| face.normal)
                    .filter(|n| moved.norm() > 0.0 && n.dot(&moved) >= widest.cos() * moved.norm())
                    .max_by(|a, b| a.dot(&moved).total_cmp(&b.dot(&moved)));
                match nearest {
                    Some(direction) => motion.along[m] = Some(direction),
                    None => motion.fixed[m] = true,
                }
            }
            let solution = solve(axis, order, &motion);
            solution.solved().then_some((solution, motion))
        };
        let mut attempts: Vec<Attempt> = Vec::new();
        let mut failure: Option<(ObjectId, SkipReason)> = None;
        let mut tried = vec![false; axes.len()];
        let mut solved_any = false;
        let cheapest = |attempts: &[Attempt], held_only: bool| {
            attempts
                .iter()
                .enumerate()
                .filter(|(_, a)| a.held || !held_only)
                .min_by(|a, b| a.1.objective.total_cmp(&b.1.objective))
                .map(|(k, a)| (k, a.objective))
        };
        // Phase 1: every axis, those whose perfect row is held first, each in order of its bound,
        // skipping any whose bound cannot beat the cheapest held row found.
        // Phase 2 (no held row found, or held rows not preferred): the axes not yet solved, in order
        // of their bound, until none can beat the cheapest row that can be pushed into place.
        let mut held_first: Vec<usize> = (0..axes.len()).collect();
        held_first.sort_by_key(|&k| !axes[k].proxy);
        for held_phase in [true, false] {
            if held_phase && !self.settings.prefer_held_rows {
                continue;
            }
            let visit: Vec<usize> = if held_phase {
                held_first.clone()
            } else {
                (0..axes.len()).collect()
            };
            for k in visit {
                let (bound, axis) = (axes[k].bound, axes[k].axis);
                if tried[k] {
                    continue;
                }
                if cheapest(&attempts, held_phase).is_some_and(|(_, best)| bound >= best - 1e-12) {
                    if held_phase {
                        continue;
                    }
                    break;
                }
                tried[k] = true;
                let order = &axes[k].order;
                let Some((solution, motion)) =
                    solve_candidate(&axis, order, axes[k].motion.as_ref())
                else {
                    continue;
                };
                solved_any = true;
                match attempt(&axis, order, &solution, &motion) {
                    Ok(found) => attempts.push(found),
                    Err(reason) => failure = Some(reason),
                }
            }
            if held_phase && cheapest(&attempts, true).is_some() {
                break;
            }
        }
        // Other orders along the chosen axis (two objects can only swap by passing each other,
        // which never shortens the pushes, so pairs keep their natural order).
        let held_found = cheapest(&attempts, true).is_some();
        if members.len() >= 3
            && let Some((k, _)) = cheapest(&attempts, held_found)
        {
            let axis = attempts[k].axis;
            let free = (!self.settings.flush).then(|| Motion::free(members.len()));
            for order in permutations(&natural(&axis), self.settings.max_orders)
                .into_iter()
                .skip(1)
            {
                if let Some((solution, motion)) = solve_candidate(&axis, &order, free.as_ref())
                    && let Ok(found) = attempt(&axis, &order, &solution, &motion)
                {
                    attempts.push(found);
                }
            }
        }
        let held_found = cheapest(&attempts, true).is_some();
        let mut counters = vec![
            ("socp_solves".to_string(), solves.get() as f64),
            ("solver_seconds".to_string(), solver_seconds.get()),
            ("iterations".to_string(), iterations.get() as f64),
            ("axes".to_string(), axes.len() as f64),
            (
                "held_axes".to_string(),
                axes.iter().filter(|a| a.proxy).count() as f64,
            ),
            ("fences".to_string(), fences.len() as f64),
        ];
        if let Some((k, _)) = cheapest(&attempts, held_found) {
            let chosen = attempts.swap_remove(k);
            counters.push(("axis".to_string(), chosen.axis.y.atan2(chosen.axis.x)));
            let plan = chosen.plan;
            // Each row is optimal for its axis and order; over the axes and orders sampled, the
            // cheapest is the best found.
            return Ok(finish(
                plan,
                Status::BestFound,
                Some(format!("clarabel: {:?}", chosen.status)),
                counters,
            ));
        }
        let ids: Vec<ObjectId> = members.iter().map(|&i| scene.objects()[i].id).collect();
        let (status, skipped) = match failure {
            Some((object, reason)) if solved_any => (
                Status::Failed {
                    reason: format!("no push sequence for any row: object {object}: {reason}"),
                },
                vec![SkippedPush { object, reason }],
            ),
            _ => (
                Status::Infeasible,
                ids.iter()
                    .map(|&object| SkippedPush {
                        object,
                        reason: SkipReason::NoRow,
                    })
                    .collect(),
            ),
        };
        Ok(finish(
            PushPlan {
                pushes: Vec::new(),
                skipped,
                intended_grasp: None,
                row_held: None,
            },
            status,
            Some(format!("clarabel: {:?}", last_status.get())),
            counters,
        ))
    }
}
