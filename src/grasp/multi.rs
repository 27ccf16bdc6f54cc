//! Multi-object grasps: an analytic stand-in for MOG-Net, chosen for how likely they are to hold.
//!
//! **Candidates** (after the public multi-object grasping code, `formulations/references.md`): jaw
//! centres on a `grid[0] × grid[1]` grid over the bounding box of the target objects, kept inside the
//! convex hull of their outlines, plus every target's centroid and the midpoint of every pair of
//! target centroids; closing axes at `angles` even steps over `[0, π)`, plus the direction between
//! every pair of target centroids and every target's narrowest-grasp axis. For every axis, the centre
//! that best fits the targets (the middle of their extent along the axis and of the band across it
//! they all cover) is a candidate too, and so is any pose the caller suggests (the push planner's
//! intended grasp). The jaws open to `opening_fraction` of the stroke (fully by default, as in the
//! paper).
//!
//! **Screening** (cheap, every candidate): the open plates must keep `clearance_sigmas` standard
//! deviations of the noise from every object, the ones to be grasped included (noise must not put a
//! plate on an object; a pushed object counts its push error too), and
//! the caught objects must slide into one row between the plates, with at least one target.
//!
//! **Judging** (the outcome model, [`GraspOutcome`], on the most promising candidates only): by
//! default the planar mechanics of `closing.rs` on the observed table and on `samples − 1` noisy
//! copies of it ([`Noise`]). Candidates are judged in order of how many objects they catch, then the
//! caller's suggestions first (the jaws a row was pushed for), then of how close the caught centroids
//! lie to the plates' centre line (the simulator holds rows near that line far more often), then of
//! clearance; at most `tries_per_set` per set of caught objects and `max_judged` in all.
//!
//! **Ranking**: by the estimated probability that every predicted object is carried, then by the
//! number of objects, then by clearance; a candidate below `min_probability` is not used. The search
//! stops at the first candidate that held in every sample (nothing judged later can rank above it).
//! Asked for two or more objects ([`GraspRequest::several`]), it ranks those grasps alone: the
//! policies ask so, since they take one object by itself with the single-object planner anyway.
//!
//! This is not the learned MOG-Net: it predicts with the models of `model.rs` and `closing.rs`.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::model::{Squeeze, row_in_scene, squeeze};
use super::outcome::{GraspOutcome, ModelOutcome, Noise, failures_allowed};
use super::{Grasp, GraspPlanner, GraspRequest, JawPose};
use crate::error::{Error, Result};
use crate::geometry::{ConvexPolygon, convex_hull, point_bounds};
use crate::outcome::{Outcome, Stats, Status};
use crate::problem::Problem;
use crate::scene::{ObjectId, Scene};

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
    /// as the Push-MOG paper). 0.02 took three of four losses outside the workspace away from
    /// push-mog-time on 150 training scenes, at 0.023 of its ratio to sog's picks per hour
    /// (`formulations/picks-per-hour.md`, "Objects near the edge").
    pub edge_margin: f64,
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

/// Multi-object grasps ranked by an outcome model.
#[derive(Clone, Debug)]
pub struct MultiObject {
    settings: MultiObjectSettings,
    problem: Arc<Problem>,
    outcome: Arc<dyn GraspOutcome>,
}

impl Default for MultiObject {
    fn default() -> Self {
        Self::new(MultiObjectSettings::default(), Problem::shared_default())
            .expect("the default settings are valid")
    }
}

impl MultiObject {
    /// A planner with these settings, judging candidates with the problem's grasp model (robustly
    /// when `samples > 1`).
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: MultiObjectSettings, problem: Arc<Problem>) -> Result<Self> {
        let outcome = Arc::new(ModelOutcome::new(
            problem.grasp_model().clone(),
            settings.samples,
            settings.noise.clone(),
        ));
        Self::with_outcome(settings, problem, outcome)
    }

    /// A planner with these settings judging candidates with `outcome` (a physics rollout, say);
    /// the problem's grasp model still screens them (which objects the jaws catch in a row).
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn with_outcome(
        settings: MultiObjectSettings,
        problem: Arc<Problem>,
        outcome: Arc<dyn GraspOutcome>,
    ) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            settings,
            problem,
            outcome,
        })
    }

    /// Whether the outcome model, judging `jaws` on `scene` (the objects `pushed` with their push
    /// error), carries every object of `members` (scene indices) in at least `min_probability` of
    /// the samples: the test a candidate must pass to be used, asked of one pose.
    pub fn carries(
        &self,
        scene: &Scene,
        jaws: &JawPose,
        pushed: &[usize],
        members: &[usize],
    ) -> bool {
        let samples = self.settings.samples.max(1);
        let minimum = self.settings.min_probability;
        let judgement = self
            .outcome
            .judge(scene, jaws, pushed, failures_allowed(minimum, samples));
        matches!(&judgement.nominal, Squeeze::Held { objects, .. }
            if members.iter().all(|m| objects.contains(m)))
            && judgement.probability() >= minimum
    }

    /// The outcome model's name.
    pub fn outcome_name(&self) -> &'static str {
        self.outcome.name()
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
        let (lo, hi) = point_bounds(&outline);
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

impl GraspPlanner for MultiObject {
    fn name(&self) -> &'static str {
        "multi-object"
    }

    /// Candidates screened, judged and ranked, keeping only grasps predicted to carry at least
    /// `request.min_objects`. Objects in `request.pushed` stand where the pushes are meant to leave
    /// them, so the plates keep further from them and the samples move them by the push error too.
    /// With `min_objects` 2 (what a policy asks when it would otherwise push nothing or take one
    /// object by itself), a pair held in three samples of four is chosen where the search from 1
    /// would prefer one object held in all four.
    fn plan_request(&self, request: &GraspRequest<'_>) -> Result<Outcome<Option<Grasp>>> {
        self.search(
            request.scene,
            request.targets,
            request.hints,
            request.pushed,
            request.avoid,
            request.min_objects,
        )
    }
}

impl MultiObject {
    /// The search behind [`GraspPlanner::plan_request`]: candidates, screening, judging and
    /// ranking, keeping only grasps predicted to carry at least `min_objects`.
    fn search(
        &self,
        scene: &Scene,
        targets: &[ObjectId],
        hints: &[JawPose],
        pushed: &[ObjectId],
        avoid: &[JawPose],
        min_objects: usize,
    ) -> Result<Outcome<Option<Grasp>>> {
        let started = Instant::now();
        let indices = scene.indices_of(targets)?;
        let pushed = scene.indices_of(pushed)?;
        let settings = &self.settings;
        let mut refusals: BTreeMap<&'static str, usize> = BTreeMap::new();
        let mut screened: Vec<Screened> = Vec::new();
        let candidates = if indices.is_empty() {
            Vec::new()
        } else {
            self.candidates(scene, &indices, hints)
        };
        for jaws in &candidates {
            if avoid.iter().any(|a| a.same_place(jaws)) {
                *refusals.entry("failed before").or_default() += 1;
                continue;
            }
            let caught = match row_in_scene(scene, jaws, self.problem.grasp_model()) {
                Ok(caught) => caught,
                Err(refusal) => {
                    *refusals.entry(refusal_name(&refusal)).or_default() += 1;
                    continue;
                }
            };
            if !caught.iter().any(|o| indices.contains(o)) {
                *refusals.entry("holds no target").or_default() += 1;
                continue;
            }
            if caught.len() < min_objects {
                *refusals.entry("too few objects").or_default() += 1;
                continue;
            }
            if caught.len() >= 2 && caught.iter().any(|&i| self.near_edge(scene, i)) {
                *refusals.entry("near the workspace edge").or_default() += 1;
                continue;
            }
            let mut sorted = caught.clone();
            sorted.sort_unstable();
            let (clearance, enough) = self.clearance(scene, jaws, &pushed);
            if !enough {
                *refusals.entry("plates too close").or_default() += 1;
                continue;
            }
            screened.push(Screened {
                hinted: hints.iter().any(|h| h.same_place(jaws)),
                jaws: *jaws,
                offset: centre_line_offset(scene, jaws, &caught),
                caught: sorted,
                clearance,
            });
        }
        // Most objects first, then the caller's suggestions (the jaws a row was pushed for), then
        // nearest the plates' centre line, then most clearance.
        screened.sort_by(|a, b| {
            b.caught
                .len()
                .cmp(&a.caught.len())
                .then(b.hinted.cmp(&a.hinted))
                .then(a.offset.total_cmp(&b.offset))
                .then(b.clearance.total_cmp(&a.clearance))
        });
        let mut tried: BTreeMap<Vec<usize>, usize> = BTreeMap::new();
        let mut best: Option<(f64, Grasp)> = None;
        let mut judged = 0usize;
        for candidate in &screened {
            if judged >= settings.max_judged {
                break;
            }
            let count = candidate.caught.len();
            // Nothing judged from here on can rank above a candidate that held in every sample with
            // as many objects.
            if best
                .as_ref()
                .is_some_and(|(p, g)| *p >= 1.0 && g.objects.len() >= count)
            {
                break;
            }
            let tries = tried.entry(candidate.caught.clone()).or_default();
            if *tries >= settings.tries_per_set {
                continue;
            }
            *tries += 1;
            judged += 1;
            // A candidate must beat the best so far: fewer failures than it allowed.
            let samples = settings.samples;
            let floor = best.as_ref().map_or(settings.min_probability, |(p, _)| {
                settings.min_probability.max(*p)
            });
            let max_failures = failures_allowed(floor, samples);
            let judgement = self
                .outcome
                .judge(scene, &candidate.jaws, &pushed, max_failures);
            let Squeeze::Held { objects, width } = &judgement.nominal else {
                *refusals
                    .entry(refusal_name(&judgement.nominal))
                    .or_default() += 1;
                continue;
            };
            if objects.len() < min_objects {
                *refusals.entry("too few objects").or_default() += 1;
                continue;
            }
            let probability = judgement.probability();
            if probability < settings.min_probability {
                *refusals.entry("not robust to noise").or_default() += 1;
                continue;
            }
            let better = best.as_ref().is_none_or(|(p, g)| {
                probability > *p + 1e-12
                    || (probability >= *p - 1e-12
                        && (objects.len() > g.objects.len()
                            || (objects.len() == g.objects.len()
                                && candidate.clearance > g.margin + 1e-12)))
            });
            if better {
                best = Some((
                    probability,
                    Grasp {
                        jaws: candidate.jaws,
                        objects: objects.iter().map(|&i| scene.objects()[i].id).collect(),
                        width: *width,
                        margin: candidate.clearance,
                    },
                ));
            }
        }
        let status = match &best {
            Some(_) => Status::Heuristic,
            None => Status::Failed {
                reason: format!(
                    "no candidate holds a target ({} tried, {judged} judged by the {} model: {})",
                    candidates.len(),
                    self.outcome.name(),
                    refusals
                        .iter()
                        .map(|(k, v)| format!("{k} {v}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            },
        };
        let probability = best.as_ref().map_or(0.0, |(p, _)| *p);
        Ok(Outcome {
            value: best.map(|(_, grasp)| grasp),
            status,
            stats: Stats {
                seconds: started.elapsed().as_secs_f64(),
                counters: [
                    ("candidates".to_string(), candidates.len() as f64),
                    ("screened".to_string(), screened.len() as f64),
                    ("judged".to_string(), judged as f64),
                    ("probability".to_string(), probability),
                ]
                .into_iter()
                .chain(
                    refusals
                        .iter()
                        .map(|(why, n)| (format!("refused: {why}"), *n as f64)),
                )
                .collect(),
                ..Stats::default()
            },
        })
    }
}

/// Clearance is measured up to this, metres.
const CLEARANCE_CAP: f64 = 0.05;

impl MultiObject {
    /// Whether object `index` lies within `edge_margin` of the workspace's edge.
    fn near_edge(&self, scene: &Scene, index: usize) -> bool {
        let margin = self.settings.edge_margin;
        margin > 0.0
            && scene
                .workspace()
                .room(point_bounds(scene.world_polygon(index).vertices()))
                .iter()
                .any(|&room| room < margin)
    }

    /// The gap between the open plates and the nearest object (capped), and whether every object
    /// is at least `clearance_sigmas` of its noise away.
    fn clearance(&self, scene: &Scene, jaws: &JawPose, pushed: &[usize]) -> (f64, bool) {
        let noise = &self.settings.noise;
        let plates = jaws.plates(scene.gripper());
        let mut nearest = CLEARANCE_CAP;
        let mut enough = true;
        for index in scene.near(&jaws.center, jaws.opening / 2.0 + CLEARANCE_CAP) {
            let outline = scene.world_polygon(index);
            let gap = plates
                .iter()
                .map(|p| crate::geometry::distance(p, outline))
                .fold(f64::INFINITY, f64::min);
            nearest = nearest.min(gap);
            let sigma = noise.position_sigma(pushed.contains(&index));
            enough &= gap >= self.settings.clearance_sigmas * sigma;
        }
        (nearest, enough)
    }
}

/// A candidate that passed the screening.
#[derive(Clone, Debug)]
struct Screened {
    /// Whether the caller suggested these jaws.
    hinted: bool,
    jaws: JawPose,
    /// Scene indices of the caught objects, sorted.
    caught: Vec<usize>,
    /// Furthest caught centroid from the plates' centre line, metres.
    offset: f64,
    /// Gap between the open plates and the nearest object, metres.
    clearance: f64,
}

/// Furthest distance of these objects' centroids from the line through the jaw centre along the
/// closing axis, metres.
pub fn centre_line_offset(scene: &Scene, jaws: &JawPose, indices: &[usize]) -> f64 {
    let axis = jaws.axis();
    let across = Vector2::new(-axis.y, axis.x);
    indices
        .iter()
        .map(|&i| (scene.centroid(i) - jaws.center).dot(&across).abs())
        .fold(0.0, f64::max)
}

impl MultiObject {
    /// Candidate grasps of `targets` that the model refuses although their open plates land on
    /// nothing and they catch two or more objects, each with the caught objects as its `objects`;
    /// in candidate order. For measuring how often the model refuses what physics would hold.
    ///
    /// # Errors
    /// An id that is not in the scene.
    pub fn refused(&self, scene: &Scene, targets: &[ObjectId]) -> Result<Vec<Grasp>> {
        let indices = scene.indices_of(targets)?;
        let mut refused = Vec::new();
        for jaws in self.candidates(scene, &indices, &[]) {
            let Some(caught) = super::model::caught_objects(scene, &jaws) else {
                continue;
            };
            if caught.len() < 2 {
                continue;
            }
            let held = matches!(
                squeeze(scene, &jaws, self.problem.grasp_model()),
                Squeeze::Held { ref objects, .. } if objects.len() == caught.len()
            );
            if !held {
                refused.push(Grasp {
                    jaws,
                    objects: caught.iter().map(|&i| scene.objects()[i].id).collect(),
                    width: 0.0,
                    margin: 0.0,
                });
            }
        }
        Ok(refused)
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
        Squeeze::Turns { .. } => "turns out",
        Squeeze::TooHeavy => "too heavy",
    }
}
