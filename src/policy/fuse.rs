//! Looks fused (`run.fuse_looks`): an object that nothing has touched since the last look keeps the
//! mean of the poses observed since it was last moved, instead of the newest look alone.
//!
//! A camera reports each pose with an error of its own at every look (the simulator: independent
//! Gaussian errors of σ_p per axis and σ_θ in yaw). An object that has not moved is seen `n` times;
//! the mean of those poses has an error of σ/√n, where a single look keeps σ. A row pushed ahead
//! in a trip's first pushes stands untouched while later trips take other rows, so by its own
//! grasp it has been seen several times.
//!
//! An object's track starts again (its newest pose alone) when
//! - its outline, as last estimated, lies within [`TOUCH_REACH`] of what the robot did since the
//!   last look: the region a push swept (the pushed object's outline at its start and its end, and
//!   the fingers at their approach and end points, in one convex hull), or the open jaws of a grasp
//!   or of a rider's pick;
//! - or the new pose is further from the mean than three standard deviations of their difference,
//!   `3·σ·√(1 + 1/n)` in position (radial) or in yaw: something the robot did not predict moved it.
//!
//! A fused pose that would overlap another object or leave the workspace is given up for the newest
//! look, so the fused table is as valid as the observed one. Yaws are averaged on the circle.
//! `formulations/perception.md`, "Looks fused".

use std::collections::HashMap;

use nalgebra::{Point2, Vector2};

use crate::geometry::{ConvexPolygon, convex_hull, distance, overlap};
use crate::grasp::JawPose;
use crate::plan::TripPlan;
use crate::push::Push;
use crate::push::fork::finger_footprints;
use crate::scene::{Gripper, OUTSIDE_TOLERANCE, OVERLAP_TOLERANCE, Object, ObjectId, Pose, Scene};

/// How close to a region the robot acted in an object's outline may lie and still count as
/// touched, metres: an object pushed there shoves its neighbours, and pushes end a few millimetres
/// from their targets (90th percentile 6.1 mm in the simulator, `grasping.md`).
pub const TOUCH_REACH: f64 = 0.02;

/// Standard deviations of a new pose from the track's mean beyond which the object is taken to have
/// moved.
const GATE: f64 = 3.0;

/// One object's poses since it was last moved.
#[derive(Clone, Debug)]
struct Track {
    looks: usize,
    sum_x: f64,
    sum_y: f64,
    sum_cos: f64,
    sum_sin: f64,
    /// The outline in the object's own frame.
    polygon: ConvexPolygon,
}

impl Track {
    fn new(object: &Object) -> Self {
        Self {
            looks: 1,
            sum_x: object.pose.x,
            sum_y: object.pose.y,
            sum_cos: object.pose.yaw.cos(),
            sum_sin: object.pose.yaw.sin(),
            polygon: object.polygon.clone(),
        }
    }

    fn mean(&self) -> Pose {
        let n = self.looks as f64;
        Pose::new(
            self.sum_x / n,
            self.sum_y / n,
            self.sum_sin.atan2(self.sum_cos),
        )
    }

    /// The outline at the mean pose.
    fn outline(&self) -> ConvexPolygon {
        self.polygon.transformed(&self.mean().isometry())
    }
}

/// The tracks of a run's objects, and what the robot touched since the last look.
#[derive(Clone, Debug, Default)]
pub struct LookFusion {
    tracks: HashMap<ObjectId, Track>,
    touched: Vec<ConvexPolygon>,
    /// Per-axis position and yaw standard deviation of one look.
    sigma: (f64, f64),
    /// The gripper of the last look, whose fingers and plates the actions are drawn with.
    gripper: Gripper,
}

impl LookFusion {
    /// Fusion for a camera whose looks err by `position` metres per axis and `yaw` radians.
    pub fn new(position: f64, yaw: f64) -> Self {
        Self {
            sigma: (position, yaw),
            ..Self::default()
        }
    }

    /// Notes that `push` was made: objects near the region it swept start their tracks again.
    pub fn pushed(&mut self, push: &Push) {
        let jaw = push.fork.jaw_angle;
        let facing = Vector2::new(jaw.sin(), -jaw.cos());
        let mut points: Vec<Point2<f64>> = Vec::new();
        // The pushed object's outline where it starts and ends (an object never seen is only the
        // fingers' path).
        if let Some(track) = self.tracks.get(&push.object) {
            let yaw = track.mean().yaw;
            for pose in [&push.from, &push.to] {
                let at = Pose::new(pose.x, pose.y, yaw).isometry();
                points.extend_from_slice(track.polygon.transformed(&at).vertices());
            }
        }
        for centre in [&push.fork.approach, &push.fork.end] {
            for finger in finger_footprints(&self.gripper, push.fork.opening, centre, &facing) {
                points.extend_from_slice(finger.vertices());
            }
        }
        self.touch(&points);
        self.tracks.remove(&push.object);
    }

    /// Notes that jaws came down open at `jaws` (a grasp, or a rider's pick).
    pub fn grasped(&mut self, jaws: &JawPose) {
        let points: Vec<Point2<f64>> = jaws
            .plates(&self.gripper)
            .iter()
            .flat_map(|plate| plate.vertices().to_vec())
            .collect();
        self.touch(&points);
    }

    /// Notes the hull of `points` as a region the robot acted in since the last look.
    fn touch(&mut self, points: &[Point2<f64>]) {
        if let Ok(region) = ConvexPolygon::new(convex_hull(points)) {
            self.touched.push(region);
        }
    }

    /// Notes that `trip`'s jaws came down open: its riders' picks, then its grasp.
    pub fn trip_grasped(&mut self, trip: &TripPlan) {
        for rider in &trip.riders {
            self.grasped(&rider.pick.jaws);
        }
        self.grasped(&trip.grasp.jaws);
    }

    /// The table of `observed` with every untouched object at the mean of its looks; starts,
    /// extends or restarts each object's track, and forgets what was touched.
    pub fn fuse(&mut self, observed: Scene) -> Scene {
        let touched = std::mem::take(&mut self.touched);
        self.gripper = observed.gripper().clone();
        let (sigma_p, sigma_yaw) = self.sigma;
        let mut tracks = HashMap::with_capacity(observed.len());
        let mut fused: Vec<Object> = observed.objects().to_vec();
        let mut averaged: Vec<usize> = Vec::new();
        for (k, object) in observed.objects().iter().enumerate() {
            let kept = self.tracks.remove(&object.id).filter(|track| {
                // The outline is drawn only when the robot acted since the last look.
                let near = !touched.is_empty() && {
                    let outline = track.outline();
                    touched
                        .iter()
                        .any(|region| distance(region, &outline) < TOUCH_REACH)
                };
                if near {
                    return false;
                }
                let mean = track.mean();
                let spread = (1.0 + 1.0 / track.looks as f64).sqrt() * GATE;
                let moved = (object.pose.x - mean.x).hypot(object.pose.y - mean.y);
                let turned = crate::geometry::wrap_angle(object.pose.yaw - mean.yaw).abs();
                moved <= spread * sigma_p && turned <= spread * sigma_yaw
            });
            let track = match kept {
                Some(mut track) => {
                    track.looks += 1;
                    track.sum_x += object.pose.x;
                    track.sum_y += object.pose.y;
                    track.sum_cos += object.pose.yaw.cos();
                    track.sum_sin += object.pose.yaw.sin();
                    fused[k].pose = track.mean();
                    averaged.push(k);
                    track
                }
                None => Track::new(object),
            };
            tracks.insert(object.id, track);
        }
        // A mean that overlaps another object or leaves the workspace gives way to the newest look;
        // each pass can only put poses back, so it ends.
        // Objects not averaged keep the observed scene's outlines.
        let mut outlines: Vec<ConvexPolygon> = (0..observed.len())
            .map(|k| observed.world_polygon(k).clone())
            .collect();
        for &k in &averaged {
            outlines[k] = fused[k].world_polygon();
        }
        loop {
            let clash = averaged.iter().position(|&k| {
                let outside = outlines[k]
                    .vertices()
                    .iter()
                    .any(|v| observed.workspace().outside_by(v) > OUTSIDE_TOLERANCE);
                outside
                    || (0..fused.len())
                        .any(|j| j != k && overlap(&outlines[j], &outlines[k], OVERLAP_TOLERANCE))
            });
            let Some(at) = clash else { break };
            let k = averaged.swap_remove(at);
            fused[k].pose = observed.objects()[k].pose;
            outlines[k] = observed.world_polygon(k).clone();
            tracks.insert(fused[k].id, Track::new(&observed.objects()[k]));
        }
        self.tracks = tracks;
        if averaged.is_empty() {
            return observed;
        }
        observed.with_objects(fused).unwrap_or(observed)
    }
}
