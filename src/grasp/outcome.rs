//! What a grasp planner believes a closing carries: outcome models behind one trait, so experiments can
//! compare them.
//!
//! - [`ModelOutcome`] with one sample: the grasp model's own prediction ([`GraspModel`], analytic or
//!   planar mechanics) on the table as observed.
//! - [`ModelOutcome`] with several samples (the default, *robust*): the prediction repeated on copies
//!   of the table and the jaws moved by the perception and actuation noise the run assumes; the
//!   estimated probability is the share of samples in which every predicted object is carried.
//! - A physics rollout (`exec::sim::Rollout`, built by the policy): the same samples, each closed and
//!   lifted in the rapier simulator, as the multi-object grasping work that Push-MOG builds on
//!   confirmed its candidates in a physics engine.
//!
//! The first sample is always the table as observed; if the model does not predict it held, the
//! candidate is refused at once. Samples are seeded from the jaw pose, so a plan is reproducible.

use nalgebra::{Isometry2, Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::jaws::JawPose;
use super::memory::Memory;
use super::model::{Body, GraspModel, Squeeze, nearby_bodies, squeeze_reach};
use crate::error::{Error, Result};
use crate::geometry::{ConvexPolygon, overlap};
use crate::random::SeededRng;
use crate::scene::Scene;

/// The noise a grasp must survive: how far the world may be from what the camera saw, and the
/// gripper from where it was sent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Noise {
    /// Standard deviation of an object's observed position, metres, per axis. Default 0.002, as the
    /// simulator's perception noise (segmentation of an overhead RGB-D image).
    pub perception_position: f64,
    /// Standard deviation of an object's observed yaw, radians. Default 0.035 (2°).
    pub perception_yaw: f64,
    /// Standard deviation of where the gripper goes, metres, per axis. Default 0.001.
    pub actuation_position: f64,
    /// Standard deviation of the gripper's yaw, radians. Default 0.0175 (1°).
    pub actuation_yaw: f64,
    /// Further standard deviation of a pushed object's position where the push leaves it, metres,
    /// per axis. Default 0.002, measured when the simulator's friction model kept pushed objects from
    /// turning (pushes ended a median 1.1 mm, 90th percentile 3.9 mm, from their targets). With
    /// Coulomb friction at every contact, push-mog's pushes on ten scenes end a median 2.4 mm and a
    /// 90th percentile 6.1 mm away (70 pushes, actuation noise). The default stays: widening this to
    /// 4 mm and `push_yaw` to 0.05 rad cut landings but lowered simulated objects per trip on 20
    /// scenes (push-mog 1.159 to 1.115, push-mog-opt 1.158 to 1.026), because it refuses most
    /// grasps after pushes. Predicting the turn is the better remedy; the planner does not yet.
    pub push_position: f64,
    /// Further standard deviation of a pushed object's yaw, radians. Default 0.017 (1°), measured as
    /// `push_position`; the same 70 pushes now turn objects a median 4.5° and a 90th percentile 19°.
    pub push_yaw: f64,
}

impl Default for Noise {
    fn default() -> Self {
        Self {
            perception_position: 0.002,
            perception_yaw: 0.035,
            actuation_position: 0.001,
            actuation_yaw: 0.0175,
            push_position: 0.002,
            push_yaw: 0.017,
        }
    }
}

impl Noise {
    /// Standard deviation of where an open plate ends up relative to an object, metres, per axis:
    /// perception and actuation noise, and push error for a pushed object.
    pub fn position_sigma(&self, pushed: bool) -> f64 {
        let push = if pushed { self.push_position } else { 0.0 };
        (self.perception_position.powi(2) + self.actuation_position.powi(2) + push.powi(2)).sqrt()
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        for (field, value) in [
            ("perception_position", self.perception_position),
            ("perception_yaw", self.perception_yaw),
            ("actuation_position", self.actuation_position),
            ("actuation_yaw", self.actuation_yaw),
            ("push_position", self.push_position),
            ("push_yaw", self.push_yaw),
        ] {
            if !(value.is_finite() && (0.0..=0.05).contains(&value)) {
                return Err(Error::field(
                    "multi.noise",
                    field,
                    format!("must be between 0 and 0.05 (metres or radians), got {value}"),
                ));
            }
        }
        Ok(())
    }
}

/// An outcome model's verdict on one candidate.
#[derive(Clone, Debug, PartialEq)]
pub struct Judgement {
    /// The prediction on the table as observed (scene indices).
    pub nominal: Squeeze,
    /// Samples in which every object of the nominal prediction was carried.
    pub hits: usize,
    /// Samples judged (fewer than asked when judging stopped early).
    pub judged: usize,
    /// Samples asked for.
    pub samples: usize,
}

impl Judgement {
    /// The estimated probability that every predicted object is carried (0 when the nominal
    /// prediction is not held, or judging stopped early).
    pub fn probability(&self) -> f64 {
        if self.judged < self.samples {
            0.0
        } else {
            self.hits as f64 / self.samples.max(1) as f64
        }
    }
}

/// Something that judges candidate grasps.
pub trait GraspOutcome: Send + Sync + std::fmt::Debug {
    /// A short name for logs (`analytic`, `planar`, `robust`, `rollout`).
    fn name(&self) -> &'static str;

    /// Judges `jaws` on `scene`, where the objects `pushed` (scene indices) stand where pushes are
    /// predicted to leave them; stops once more than `max_failures` samples have failed (the caller
    /// can no longer use the candidate then).
    fn judge(
        &self,
        scene: &Scene,
        jaws: &JawPose,
        pushed: &[usize],
        max_failures: usize,
    ) -> Judgement;
}

/// The grasp model, on the observed table and on noisy copies of it. Closings it has judged are
/// remembered by their exact inputs (`memory.rs`), so asking again costs nothing and answers the same.
#[derive(Clone, Debug)]
pub struct ModelOutcome {
    model: GraspModel,
    samples: usize,
    noise: Noise,
    memory: Memory,
}

impl ModelOutcome {
    /// Judges with `model` on the observed table and `samples − 1` copies moved by `noise` (one
    /// sample or none: the model's prediction alone).
    pub fn new(model: GraspModel, samples: usize, noise: Noise) -> Self {
        Self {
            model,
            samples,
            noise,
            memory: Memory::default(),
        }
    }

    /// The model.
    pub fn model(&self) -> &GraspModel {
        &self.model
    }

    /// Samples per candidate, the observed table first.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// The noise of the samples after the first.
    pub fn noise(&self) -> &Noise {
        &self.noise
    }
}

impl GraspOutcome for ModelOutcome {
    fn name(&self) -> &'static str {
        match (self.samples, self.model.mechanics) {
            (0 | 1, super::model::Mechanics::Analytic) => "analytic",
            (0 | 1, super::model::Mechanics::Planar) => "planar",
            _ => "robust",
        }
    }

    fn judge(
        &self,
        scene: &Scene,
        jaws: &JawPose,
        pushed: &[usize],
        max_failures: usize,
    ) -> Judgement {
        let samples = self.samples.max(1);
        let gripper = scene.gripper();
        let (near, bodies) = nearby_bodies(
            scene,
            &self.model,
            &jaws.center,
            squeeze_reach(jaws, gripper),
        );
        let nominal = self
            .memory
            .squeeze(&bodies, gripper, jaws, &self.model)
            .map_objects(|k| near[k]);
        let Squeeze::Held { objects, .. } = &nominal else {
            return Judgement {
                nominal,
                hits: 0,
                judged: samples,
                samples,
            };
        };
        let mut expected = objects.clone();
        expected.sort_unstable();
        let (mut hits, mut judged) = (1, 1);
        for k in 1..samples {
            if judged - hits > max_failures {
                break;
            }
            judged += 1;
            let copy = noisy_copy(scene, jaws, &self.noise, pushed, k);
            // The moved objects, and every other object the moved jaws can reach: the jaws moved
            // by `shift`, so those within `reach + shift` of the planned centre (and a hair for rounding).
            let shift = nalgebra::distance(&copy.jaws.center, &jaws.center);
            let mut local = scene.near(
                &jaws.center,
                squeeze_reach(&copy.jaws, gripper) + shift + 1e-9,
            );
            local.extend(&copy.objects);
            local.sort_unstable();
            local.dedup();
            let bodies: Vec<Body<'_>> = local
                .iter()
                .map(|&i| Body {
                    outline: copy
                        .objects
                        .binary_search(&i)
                        .map_or(scene.world_polygon(i), |k| &copy.outlines[k]),
                    mass: self.model.mass_of(&scene.objects()[i]),
                })
                .collect();
            if let Squeeze::Held { objects, .. } =
                self.memory
                    .squeeze(&bodies, gripper, &copy.jaws, &self.model)
            {
                let mut objects: Vec<usize> = objects.into_iter().map(|k| local[k]).collect();
                objects.sort_unstable();
                if objects == expected {
                    hits += 1;
                }
            }
        }
        Judgement {
            nominal,
            hits,
            judged,
            samples,
        }
    }
}

/// How many of `samples` may fail while the share carried still reaches `probability`.
pub fn failures_allowed(probability: f64, samples: usize) -> usize {
    ((1.0 - probability) * samples as f64 + 1e-9).floor() as usize
}

/// A seed from a jaw pose and a sample number (SplitMix64 over the pose's bits).
pub fn sample_seed(jaws: &JawPose, sample: usize) -> u64 {
    let mut state = jaws.center.x.to_bits()
        ^ jaws.center.y.to_bits().rotate_left(21)
        ^ jaws.angle.to_bits().rotate_left(42)
        ^ jaws.opening.to_bits().rotate_left(7)
        ^ (sample as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    state = (state ^ (state >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    state = (state ^ (state >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    state ^ (state >> 31)
}

/// One noisy sample of the table around a grasp ([`noisy_copy`]).
#[derive(Clone, Debug, PartialEq)]
pub struct NoisyCopy {
    /// Scene indices, ascending, of the objects within reach of the jaws (the ones the noise moves;
    /// every other object keeps its outline).
    pub objects: Vec<usize>,
    /// Their outlines in this sample, in the same order.
    pub outlines: Vec<ConvexPolygon>,
    /// The jaws moved by the actuation noise.
    pub jaws: JawPose,
}

/// Sample `sample` of the noisy world around `jaws`: every object within reach moved by the
/// perception noise, and the objects `pushed` (scene indices) by the push error too (a draw that
/// would overlap another object is drawn again, up to five times, and the object stays put if none
/// fits), and the jaws moved by the actuation noise. Objects out of reach keep their outlines and
/// are not listed.
pub fn noisy_copy(
    scene: &Scene,
    jaws: &JawPose,
    noise: &Noise,
    pushed: &[usize],
    sample: usize,
) -> NoisyCopy {
    let mut rng = SeededRng::new(sample_seed(jaws, sample));
    let reach = jaws.opening / 2.0 + scene.gripper().plate_length + 0.03;
    let near = scene.near(&jaws.center, reach);
    let mut outlines: Vec<ConvexPolygon> = near
        .iter()
        .map(|&i| scene.world_polygon(i).clone())
        .collect();
    for (k, &i) in near.iter().enumerate() {
        let centroid = scene.centroid(i);
        let (position, yaw) = if pushed.contains(&i) {
            (
                noise.perception_position.hypot(noise.push_position),
                noise.perception_yaw.hypot(noise.push_yaw),
            )
        } else {
            (noise.perception_position, noise.perception_yaw)
        };
        for _ in 0..5 {
            let shift = Vector2::new(position * rng.normal(), position * rng.normal());
            let turn = yaw * rng.normal();
            let about = Isometry2::translation(centroid.x, centroid.y)
                * Isometry2::new(shift, turn)
                * Isometry2::translation(-centroid.x, -centroid.y);
            let candidate = scene.world_polygon(i).transformed(&about);
            let clear = outlines
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != k)
                .all(|(_, other)| !overlap(other, &candidate, crate::scene::OVERLAP_TOLERANCE));
            if clear {
                outlines[k] = candidate;
                break;
            }
        }
    }
    let moved = JawPose {
        center: Point2::new(
            jaws.center.x + noise.actuation_position * rng.normal(),
            jaws.center.y + noise.actuation_position * rng.normal(),
        ),
        angle: jaws.angle + noise.actuation_yaw * rng.normal(),
        opening: jaws.opening,
    };
    NoisyCopy {
        objects: near,
        outlines,
        jaws: moved,
    }
}
