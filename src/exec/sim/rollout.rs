//! Grasp candidates judged by rolling them out in the simulator: the optional physics check of the
//! multi-object planner (`MultiObjectSettings` with the policy setting `rollout`).
//!
//! Each sample sets a fresh simulator to the observed table (the first sample) or to a copy moved by
//! the perception noise (the others, [`crate::scene::perturb`]), lowers and closes the jaws as planned
//! with the actuation noise, and lifts. The candidate's prediction is what the first sample carried,
//! when it carried every object caught between the plates; each other sample counts when it carries
//! the same. It costs a full grasp simulation per sample (tens of milliseconds), against well under a
//! millisecond for the planar model.

use super::{Sim, SimSettings};
use crate::exec::Executor;
use crate::grasp::{
    Grasp, GraspOutcome, JawPose, Judgement, Noise, Squeeze, caught_objects, sample_seed,
};
use crate::random::SeededRng;
use crate::scene::{Scene, perturb};

/// The rapier simulator as a grasp outcome model.
#[derive(Clone, Debug)]
pub struct Rollout {
    /// The simulator's physical settings (its own noise is replaced by `noise`).
    pub settings: SimSettings,
    /// Samples per candidate, the observed table first.
    pub samples: usize,
    /// The noise of the other samples.
    pub noise: Noise,
}

impl Rollout {
    /// Carries out the grasp of `caught` with `jaws` in sample `sample`; the scene indices carried.
    fn carried(
        &self,
        scene: &Scene,
        jaws: &JawPose,
        caught: &[usize],
        sample: usize,
    ) -> Vec<usize> {
        let seed = sample_seed(jaws, sample);
        let (world, settings) = if sample == 0 {
            (scene.clone(), SimSettings::noiseless_from(&self.settings))
        } else {
            let mut rng = SeededRng::new(seed);
            let world = perturb(
                scene,
                &mut rng,
                self.noise.perception_position,
                self.noise.perception_yaw,
            )
            .unwrap_or_else(|_| scene.clone());
            let settings = SimSettings {
                actuation_position: self.noise.actuation_position,
                actuation_yaw: self.noise.actuation_yaw,
                ..SimSettings::noiseless_from(&self.settings)
            };
            (world, settings)
        };
        let Ok(mut sim) = Sim::new(settings, seed) else {
            return Vec::new();
        };
        if sim.reset(&world).is_err() {
            return Vec::new();
        }
        let grasp = Grasp {
            jaws: *jaws,
            objects: caught.iter().map(|&i| scene.objects()[i].id).collect(),
            width: 0.0,
            margin: 0.0,
        };
        match sim.grasp(&grasp) {
            Ok(result) => result
                .carried
                .iter()
                .filter_map(|id| scene.index_of(*id))
                .collect(),
            Err(_) => Vec::new(),
        }
    }
}

impl GraspOutcome for Rollout {
    fn name(&self) -> &'static str {
        "rollout"
    }

    fn judge(
        &self,
        scene: &Scene,
        jaws: &JawPose,
        _pushed: &[usize],
        max_failures: usize,
    ) -> Judgement {
        let samples = self.samples.max(1);
        let refused = |nominal| Judgement {
            nominal,
            hits: 0,
            judged: samples,
            samples,
        };
        let Some(mut caught) = caught_objects(scene, jaws) else {
            return refused(Squeeze::PlateHits { object: 0 });
        };
        if caught.is_empty() {
            return refused(Squeeze::Empty);
        }
        caught.sort_unstable();
        let holds = |sample: usize| {
            let mut carried = self.carried(scene, jaws, &caught, sample);
            carried.sort_unstable();
            carried == caught
        };
        if !holds(0) {
            return refused(Squeeze::Turns { object: caught[0] });
        }
        let (mut hits, mut judged) = (1, 1);
        for sample in 1..samples {
            if judged - hits > max_failures {
                break;
            }
            judged += 1;
            if holds(sample) {
                hits += 1;
            }
        }
        Judgement {
            nominal: Squeeze::Held {
                objects: caught,
                width: 0.0,
            },
            hits,
            judged,
            samples,
        }
    }
}
