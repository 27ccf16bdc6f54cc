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
//! the caught objects must slide into one row between the plates, with at least one target. With
//! `centre_along_axis` each candidate is first moved along its closing axis to the middle of what it
//! catches (`formulations/grasping.md`, "Grasps that come down on a row").
//!
//! **Judging** (the outcome model, [`GraspOutcome`], on the most promising candidates only): by
//! default the planar mechanics of `closing/` on the observed table and on `samples − 1` noisy
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
//! This is not the learned MOG-Net: it predicts with the models of `model/` and `closing/`.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

use nalgebra::Vector2;

use super::model::{Squeeze, row_in_scene, squeeze};
use super::outcome::{GraspOutcome, ModelOutcome, failures_allowed};
use super::{Grasp, GraspPlanner, GraspRequest, JawPose};
use crate::error::Result;
use crate::geometry::point_bounds;
use crate::outcome::{Outcome, Stats, Status};
use crate::problem::Problem;
use crate::scene::{ObjectId, Scene};

mod candidates;
mod settings;

pub use settings::MultiObjectSettings;

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
    /// the samples, with none of the objects it holds (two or more) within `edge_margin` of the
    /// workspace's edge: the tests a candidate must pass to be used, asked of one pose.
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
            if members.iter().all(|m| objects.contains(m))
                && !self.too_near_the_edge(scene, objects, jaws))
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
        self.search(request)
    }
}

impl MultiObject {
    /// The search behind [`GraspPlanner::plan_request`]: candidates, screening, judging and
    /// ranking, keeping only grasps predicted to carry at least `min_objects`.
    fn search(&self, request: &GraspRequest<'_>) -> Result<Outcome<Option<Grasp>>> {
        let started = Instant::now();
        let scene = request.scene;
        let indices = scene.indices_of(request.targets)?;
        let pushed = scene.indices_of(request.pushed)?;
        let mut refusals: BTreeMap<&'static str, usize> = BTreeMap::new();
        let candidates = if indices.is_empty() {
            Vec::new()
        } else {
            self.candidates(scene, &indices, request.hints)
        };
        let screened = self.screen(request, &candidates, &indices, &pushed, &mut refusals);
        let (best, judged) = self.best_judged(
            scene,
            &screened,
            &pushed,
            request.min_objects,
            &mut refusals,
        );
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

    /// The candidates worth judging, best first: caught in a row by the grasp model, holding a
    /// target and at least `min_objects`, not where a grasp failed before, no object of several
    /// near the edge, the plates clear of the rest. Ranked by most objects, then the caller's
    /// suggestions (the jaws a row was pushed for), then nearest the plates' centre line, then most
    /// clearance. A candidate counts as suggested when it stands in the same place as a hint
    /// ([`JawPose::same_place`]: within 3 mm, 5° and 3 mm of opening), so a candidate beside the
    /// hint that lies nearer the centre line, or has more clearance, ranks above the hint itself.
    fn screen(
        &self,
        request: &GraspRequest<'_>,
        candidates: &[JawPose],
        indices: &[usize],
        pushed: &[usize],
        refusals: &mut BTreeMap<&'static str, usize>,
    ) -> Vec<Screened> {
        let scene = request.scene;
        let mut screened: Vec<Screened> = Vec::new();
        for candidate in candidates {
            if request.avoid.iter().any(|a| a.same_place(candidate)) {
                *refusals.entry("failed before").or_default() += 1;
                continue;
            }
            let caught = match row_in_scene(scene, candidate, self.problem.grasp_model()) {
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
            if caught.len() < request.min_objects {
                *refusals.entry("too few objects").or_default() += 1;
                continue;
            }
            let mut sorted = caught.clone();
            sorted.sort_unstable();
            let hinted = request.hints.iter().any(|h| h.same_place(candidate));
            let centred = self
                .settings
                .centre_along_axis
                .then(|| self.centred(scene, candidate, &sorted, request.avoid, pushed))
                .flatten();
            let jaws = centred.as_ref().map_or(candidate, |(c, _)| c);
            if self.too_near_the_edge(scene, &caught, jaws) {
                *refusals.entry("near the workspace edge").or_default() += 1;
                continue;
            }
            let (clearance, enough) = match centred {
                Some((_, clearance)) => (clearance, true),
                None => self.clearance(scene, jaws, pushed),
            };
            if !enough {
                *refusals.entry("plates too close").or_default() += 1;
                continue;
            }
            screened.push(Screened {
                hinted,
                jaws: *jaws,
                offset: centre_line_offset(scene, jaws, &caught),
                caught: sorted,
                clearance,
            });
        }
        screened.sort_by(|a, b| {
            b.caught
                .len()
                .cmp(&a.caught.len())
                .then(b.hinted.cmp(&a.hinted))
                .then(a.offset.total_cmp(&b.offset))
                .then(b.clearance.total_cmp(&a.clearance))
        });
        screened
    }

    /// The best of the screened candidates by the outcome model (probability, then objects, then
    /// clearance), with its probability, and how many were judged: at most `tries_per_set` per set
    /// of caught objects and `max_judged` in all, stopping at the first that held in every sample.
    fn best_judged(
        &self,
        scene: &Scene,
        screened: &[Screened],
        pushed: &[usize],
        min_objects: usize,
        refusals: &mut BTreeMap<&'static str, usize>,
    ) -> (Option<(f64, Grasp)>, usize) {
        let settings = &self.settings;
        let mut tried: BTreeMap<Vec<usize>, usize> = BTreeMap::new();
        let mut best: Option<(f64, Grasp)> = None;
        let mut judged = 0usize;
        for candidate in screened {
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
                .judge(scene, &candidate.jaws, pushed, max_failures);
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
        (best, judged)
    }
}

/// Clearance is measured up to this, metres.
const CLEARANCE_CAP: f64 = 0.05;

impl MultiObject {
    /// Whether a grasp at `jaws` that holds `held` (scene indices) is refused for the edge: it
    /// holds two or more objects and one of them is [`MultiObject::near_edge`]. The search and the
    /// row judge ([`MultiObject::carries`]) both ask this.
    fn too_near_the_edge(&self, scene: &Scene, held: &[usize], jaws: &JawPose) -> bool {
        held.len() >= 2 && held.iter().any(|&i| self.near_edge(scene, i, jaws))
    }

    /// Whether object `index` lies within `edge_margin` of the workspace's edge (along the plates
    /// of `jaws` only, with `edge_along_plates`).
    fn near_edge(&self, scene: &Scene, index: usize, jaws: &JawPose) -> bool {
        let margin = self.settings.edge_margin;
        if margin <= 0.0 {
            return false;
        }
        let outline = scene.world_polygon(index);
        if !self.settings.edge_along_plates {
            return scene
                .workspace()
                .room(point_bounds(outline.vertices()))
                .iter()
                .any(|&room| room < margin);
        }
        let axis = jaws.axis();
        let along = Vector2::new(-axis.y, axis.x);
        let workspace = scene.workspace();
        outline.vertices().iter().any(|v| {
            [along, -along]
                .iter()
                .any(|d| workspace.room_along(v, d) < margin)
        })
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
