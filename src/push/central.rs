//! The Push-MOG paper's push planner (Algorithm 3): push every object of a cluster toward its central
//! object.
//!
//! The central object `m` is the one whose centroid is nearest the mean `M_c` of the cluster's
//! centroids. Every other object `o`, nearest first, is pushed along `u = (M_m − M_o)/‖M_m − M_o‖`
//! with the fingers behind it ([`fork`](super::fork)), so the push line runs through its centroid and
//! the contact lies on its far side. The paper pushes the cluster's objects until they touch, shortening
//! each push so the object does not run into the central object; pushmog measures the free travel `t*`
//! along `u` before the object would touch *any* object as it stands at that moment of the sequence
//! (the central object, an object of the cluster already pushed, or anything else) and pushes
//! `t* − stop_gap`, by default `t*`: the object stops where it meets the first one. When the first
//! object in the way is outside the cluster, the push is skipped with that reason; pushes shorter than
//! `min_push` are skipped as already in place.

use std::sync::Arc;
use std::time::Instant;

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::fork::plan_fork;
use super::{Push, PushPlan, PushPlanner, SkipReason, SkippedPush};
use crate::error::Result;
use crate::geometry::{ConvexPolygon, cast_distance};
use crate::outcome::{Outcome, Stats, Status};
use crate::problem::Problem;
use crate::scene::{ObjectId, Pose, Scene};

/// Settings of [`TowardCentral`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct TowardCentralSettings {
    /// Gap left between a pushed object and the first object it would touch, metres. Default 0: the
    /// objects end touching, as in the paper. On 100 simulated scenes a 2 mm gap carried 0.038 fewer
    /// objects per trip (`formulations/pushing.md`).
    pub stop_gap: f64,
}

impl Default for TowardCentralSettings {
    fn default() -> Self {
        Self { stop_gap: 0.0 }
    }
}

impl TowardCentralSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        crate::error::in_range("pushing", "stop_gap", self.stop_gap, (0.0, 0.1), "metres")
    }
}

/// Pushes toward the cluster's central object (the paper's Algorithm 3).
#[derive(Clone, Debug)]
pub struct TowardCentral {
    settings: TowardCentralSettings,
    problem: Arc<Problem>,
}

impl Default for TowardCentral {
    fn default() -> Self {
        Self {
            settings: TowardCentralSettings::default(),
            problem: Problem::shared_default(),
        }
    }
}

impl TowardCentral {
    /// A planner with these settings, making fork pushes of the problem's geometry and none
    /// shorter than its `min_push`.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: TowardCentralSettings, problem: Arc<Problem>) -> Result<Self> {
        settings.validate()?;
        Ok(Self { settings, problem })
    }

    /// The effective settings.
    pub fn settings(&self) -> &TowardCentralSettings {
        &self.settings
    }
}

impl PushPlanner for TowardCentral {
    fn name(&self) -> &'static str {
        "toward-central"
    }

    fn plan(&self, scene: &Scene, cluster: &[ObjectId]) -> Result<Outcome<PushPlan>> {
        let started = Instant::now();
        let members = scene.indices_of(cluster)?;
        let mut plan = PushPlan::default();
        if members.len() >= 2 {
            let centroids: Vec<Point2<f64>> = members.iter().map(|&i| scene.centroid(i)).collect();
            let mean = Point2::from(
                centroids.iter().map(|p| p.coords).sum::<Vector2<f64>>() / members.len() as f64,
            );
            let central = members[nearest(&centroids, &mean)];
            let target = scene.centroid(central);
            let mut order: Vec<usize> = members.iter().copied().filter(|&i| i != central).collect();
            order.sort_by(|&a, &b| {
                nalgebra::distance(&scene.centroid(a), &target)
                    .total_cmp(&nalgebra::distance(&scene.centroid(b), &target))
            });
            let ids: Vec<ObjectId> = scene.objects().iter().map(|o| o.id).collect();
            let mut world: Vec<ConvexPolygon> = (0..scene.len())
                .map(|i| scene.world_polygon(i).clone())
                .collect();
            for index in order {
                match self.push_one(scene, &world, &ids, &members, index, &target) {
                    Ok(push) => {
                        world[index] = world[index].translated(&push.displacement());
                        plan.pushes.push(push);
                    }
                    Err(reason) => plan.skipped.push(SkippedPush {
                        object: ids[index],
                        reason,
                    }),
                }
            }
        }
        let stats = Stats {
            seconds: started.elapsed().as_secs_f64(),
            objective: Some(plan.pushes.iter().map(|p| p.distance).sum()),
            counters: vec![
                ("pushes".to_string(), plan.pushes.len() as f64),
                ("skipped".to_string(), plan.skipped.len() as f64),
            ],
            ..Stats::default()
        };
        Ok(Outcome {
            value: plan,
            status: Status::Heuristic,
            stats,
        })
    }
}

impl TowardCentral {
    fn push_one(
        &self,
        scene: &Scene,
        world: &[ConvexPolygon],
        ids: &[ObjectId],
        members: &[usize],
        index: usize,
        target: &Point2<f64>,
    ) -> std::result::Result<Push, SkipReason> {
        let start = world[index].centroid();
        let offset = target - start;
        let reach = offset.norm();
        if reach <= self.problem.min_push() {
            return Err(SkipReason::AlreadyInPlace);
        }
        let direction = offset / reach;
        // First object met along the way, as objects stand now.
        let mut first: Option<(f64, usize)> = None;
        for (other, outline) in world.iter().enumerate() {
            if other == index {
                continue;
            }
            if let Some(d) = cast_distance(&world[index], &direction, reach, outline)
                && first.is_none_or(|(best, _)| d < best)
            {
                first = Some((d, other));
            }
        }
        let Some((free, blocker)) = first else {
            // The line runs into the central object's centroid, so something is always met.
            return Err(SkipReason::AlreadyInPlace);
        };
        if !members.contains(&blocker) {
            return Err(SkipReason::BlockedBy {
                object: ids[blocker],
            });
        }
        let distance = free - self.settings.stop_gap;
        if distance < self.problem.min_push() {
            return Err(SkipReason::AlreadyInPlace);
        }
        let fork = plan_fork(
            scene.gripper(),
            self.problem.fork(),
            world,
            ids,
            index,
            scene.objects()[index].height,
            &direction,
            distance,
            scene.gripper().fork_push_opening(),
        )?;
        let from = scene.objects()[index].pose;
        let moved = direction * distance;
        Ok(Push {
            object: ids[index],
            from,
            to: Pose::new(from.x + moved.x, from.y + moved.y, from.yaw),
            direction,
            distance,
            fork,
        })
    }
}

fn nearest(points: &[Point2<f64>], to: &Point2<f64>) -> usize {
    let mut best = 0;
    for (k, p) in points.iter().enumerate() {
        if nalgebra::distance(p, to) < nalgebra::distance(&points[best], to) {
            best = k;
        }
    }
    best
}
