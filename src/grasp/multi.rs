//! Multi-object grasps: an analytic stand-in for MOG-Net.
//!
//! Candidates (after the public multi-object grasping code, `formulations/references.md`): jaw centres on a
//! `grid[0] × grid[1]` grid over the bounding box of the target objects, kept inside the convex hull of
//! their outlines, plus every target's centroid and the midpoint of every pair of target centroids;
//! closing axes at `angles` even steps over `[0, π)`, plus the direction between every pair of target
//! centroids and every target's narrowest-grasp axis. For every axis, the centre that best fits the
//! targets (the middle of their extent along the axis and of the band across it they all cover) is a
//! candidate too, and so is any pose the caller suggests (the push planner's intended grasp). The jaws
//! open to `opening_fraction` of the stroke (fully by default, as in the paper). Each candidate is scored by [`GraspModel`]: the most
//! objects predicted held wins, ties go to the larger clearance between the open plates and the other
//! objects, then to the narrower row. A candidate must hold at least one target.
//!
//! This is not the learned MOG-Net: it predicts with the rigid-contact model of `model.rs`.

use std::collections::BTreeMap;
use std::time::Instant;

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::model::{GraspModel, Squeeze, plate_clearance, squeeze};
use super::{Grasp, GraspPlanner, JawPose};
use crate::error::{Error, Result};
use crate::geometry::{ConvexPolygon, convex_hull};
use crate::plan::{Outcome, Stats, Status};
use crate::scene::{ObjectId, Scene};

/// Settings of [`MultiObject`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MultiObjectSettings {
    /// Grid of jaw centres over the targets' bounding box, `[along x, along y]`. Default `[7, 10]`.
    pub grid: [usize; 2],
    /// Evenly spaced closing axes over `[0, π)`. Default 12 (15° apart).
    pub angles: usize,
    /// Jaw opening as a fraction of the stroke. Default 1.0 (fully open, as in the paper).
    pub opening_fraction: f64,
    /// The grasp model.
    pub model: GraspModel,
}

impl Default for MultiObjectSettings {
    fn default() -> Self {
        Self {
            grid: [7, 10],
            angles: 12,
            opening_fraction: 1.0,
            model: GraspModel::default(),
        }
    }
}

impl MultiObjectSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        if self.grid[0] == 0 || self.grid[1] == 0 || self.angles == 0 {
            return Err(Error::field(
                "multi_object",
                "grid/angles",
                "need at least one grid point and one angle",
            ));
        }
        if !(self.opening_fraction > 0.0 && self.opening_fraction <= 1.0) {
            return Err(Error::field(
                "multi_object",
                "opening_fraction",
                format!("must be in (0, 1], got {}", self.opening_fraction),
            ));
        }
        self.model.validate()
    }
}

/// Multi-object grasps ranked by the analytic grasp model.
#[derive(Clone, Debug, Default)]
pub struct MultiObject {
    settings: MultiObjectSettings,
}

impl MultiObject {
    /// A planner with these settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: MultiObjectSettings) -> Result<Self> {
        settings.validate()?;
        Ok(Self { settings })
    }

    /// The effective settings.
    pub fn settings(&self) -> &MultiObjectSettings {
        &self.settings
    }

    fn centres(&self, scene: &Scene, targets: &[usize]) -> Vec<Point2<f64>> {
        let outline: Vec<Point2<f64>> = targets
            .iter()
            .flat_map(|&i| scene.world_polygon(i).vertices().to_vec())
            .collect();
        let hull = ConvexPolygon::new(convex_hull(&outline)).ok();
        let (lo, hi) = bounds(&outline);
        let [nx, ny] = self.settings.grid;
        let mut centres = Vec::new();
        for ix in 0..nx {
            for iy in 0..ny {
                let p = Point2::new(
                    lo.x + (hi.x - lo.x) * (ix as f64 + 0.5) / nx as f64,
                    lo.y + (hi.y - lo.y) * (iy as f64 + 0.5) / ny as f64,
                );
                if hull.as_ref().is_none_or(|h| h.contains_point(&p, 0.0)) {
                    centres.push(p);
                }
            }
        }
        for (k, &a) in targets.iter().enumerate() {
            centres.push(scene.centroid(a));
            for &b in &targets[k + 1..] {
                centres.push(nalgebra::center(&scene.centroid(a), &scene.centroid(b)));
            }
        }
        centres
    }

    /// Every jaw pose to evaluate: grid centres × angles, the centre aligned with the targets for
    /// every angle, and the caller's hints.
    fn candidates(&self, scene: &Scene, targets: &[usize], hints: &[JawPose]) -> Vec<JawPose> {
        let opening = self.settings.opening_fraction * scene.gripper().stroke;
        let angles = self.angles(scene, targets);
        let mut poses: Vec<JawPose> = hints.to_vec();
        for &angle in &angles {
            poses.push(JawPose {
                center: aligned_centre(scene, targets, angle),
                angle,
                opening,
            });
        }
        for center in self.centres(scene, targets) {
            for &angle in &angles {
                poses.push(JawPose {
                    center,
                    angle,
                    opening,
                });
            }
        }
        poses
    }

    fn angles(&self, scene: &Scene, targets: &[usize]) -> Vec<f64> {
        let n = self.settings.angles;
        let mut angles: Vec<f64> = (0..n)
            .map(|k| std::f64::consts::PI * k as f64 / n as f64)
            .collect();
        let half_turn = |v: Vector2<f64>| v.y.atan2(v.x).rem_euclid(std::f64::consts::PI);
        for (k, &a) in targets.iter().enumerate() {
            let object = &scene.objects()[a];
            angles.push(half_turn(
                object.pose.isometry() * scene.grasp_diameter(a).axis,
            ));
            for &b in &targets[k + 1..] {
                let joining = scene.centroid(b) - scene.centroid(a);
                if joining.norm() > 0.0 {
                    angles.push(half_turn(joining));
                }
            }
        }
        angles
    }
}

/// The jaw centre that fits the targets best for closing along `angle`: the middle of their extent
/// along the axis, and the middle of the band across it that all of them cover (or the mean of their
/// middles when there is none).
fn aligned_centre(scene: &Scene, targets: &[usize], angle: f64) -> Point2<f64> {
    let axis = Vector2::new(angle.cos(), angle.sin());
    let across = Vector2::new(-axis.y, axis.x);
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut band_low, mut band_high) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut middles = 0.0;
    for &i in targets {
        let outline = scene.world_polygon(i);
        let (a, b) = outline.projection(&axis);
        low = low.min(a);
        high = high.max(b);
        let (c, d) = outline.projection(&across);
        band_low = band_low.max(c);
        band_high = band_high.min(d);
        middles += (c + d) / 2.0;
    }
    let along = (low + high) / 2.0;
    let side = if band_low <= band_high {
        (band_low + band_high) / 2.0
    } else {
        middles / targets.len() as f64
    };
    Point2::from(axis * along + across * side)
}

fn bounds(points: &[Point2<f64>]) -> (Point2<f64>, Point2<f64>) {
    points.iter().fold(
        (
            Point2::new(f64::INFINITY, f64::INFINITY),
            Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        ),
        |(lo, hi), p| {
            (
                Point2::new(lo.x.min(p.x), lo.y.min(p.y)),
                Point2::new(hi.x.max(p.x), hi.y.max(p.y)),
            )
        },
    )
}

impl GraspPlanner for MultiObject {
    fn name(&self) -> &'static str {
        "multi-object"
    }

    fn plan(&self, scene: &Scene, targets: &[ObjectId]) -> Result<Outcome<Option<Grasp>>> {
        self.plan_with_hints(scene, targets, &[])
    }

    fn plan_with_hints(
        &self,
        scene: &Scene,
        targets: &[ObjectId],
        hints: &[JawPose],
    ) -> Result<Outcome<Option<Grasp>>> {
        let started = Instant::now();
        let indices = scene.indices_of(targets)?;
        let mut best: Option<(usize, Grasp)> = None;
        let mut evaluated = 0usize;
        let mut refusals: BTreeMap<&'static str, usize> = BTreeMap::new();
        if !indices.is_empty() {
            for jaws in self.candidates(scene, &indices, hints) {
                {
                    evaluated += 1;
                    let outcome = squeeze(scene, &jaws, &self.settings.model);
                    let Squeeze::Held { objects, width } = outcome else {
                        *refusals.entry(refusal_name(&outcome)).or_default() += 1;
                        continue;
                    };
                    if !objects.iter().any(|o| indices.contains(o)) {
                        *refusals.entry("holds no target").or_default() += 1;
                        continue;
                    }
                    let count = objects.len();
                    // Cheap pre-check before the clearance query.
                    if best.as_ref().is_some_and(|(c, _)| count < *c) {
                        continue;
                    }
                    let margin = plate_clearance(scene, &jaws, &objects, 0.05);
                    let better = best.as_ref().is_none_or(|(c, b)| {
                        count > *c
                            || margin > b.margin + 1e-12
                            || (margin >= b.margin - 1e-12 && width < b.width - 1e-12)
                    });
                    if better {
                        let ids = objects.iter().map(|&i| scene.objects()[i].id).collect();
                        best = Some((
                            count,
                            Grasp {
                                jaws,
                                objects: ids,
                                width,
                                margin,
                            },
                        ));
                    }
                }
            }
        }
        let status = match &best {
            Some(_) => Status::Heuristic,
            None => Status::Failed {
                reason: format!(
                    "no candidate holds a target ({evaluated} tried: {})",
                    refusals
                        .iter()
                        .map(|(k, v)| format!("{k} {v}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            },
        };
        Ok(Outcome {
            value: best.map(|(_, grasp)| grasp),
            status,
            stats: Stats {
                seconds: started.elapsed().as_secs_f64(),
                counters: vec![("candidates".to_string(), evaluated as f64)],
                ..Stats::default()
            },
        })
    }
}

fn refusal_name(squeeze: &Squeeze) -> &'static str {
    match squeeze {
        Squeeze::Held { .. } => "held",
        Squeeze::Empty => "empty",
        Squeeze::PlateHits { .. } => "plate hits an object",
        Squeeze::Straddles { .. } => "object reaches past a plate",
        Squeeze::NotARow { .. } => "not a row",
        Squeeze::Slips { .. } => "slips",
        Squeeze::TooHeavy => "too heavy",
    }
}
