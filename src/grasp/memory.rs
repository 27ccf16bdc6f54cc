//! Closings already judged, remembered by their exact inputs (the robust judge's, and the SOCP's
//! perfect rows).
//!
//! A squeeze ([`squeeze_bodies`]) is a pure function of the bodies it is given (outlines and
//! masses), the gripper, the jaw pose and the grasp model. [`ModelOutcome`](super::ModelOutcome)
//! keeps one model, so it remembers each answer under the bit patterns of the other inputs and
//! gives the same answer again without simulating the closing. The same closing is asked about
//! again in a closed loop: the look after a trip's pushes plans the cluster's grasp once more, on
//! the table the pushes left, and with the ideal executor that table is exactly the predicted one.
//! Answers are identical with and without the memory; it only saves time. It holds at most
//! [`CAPACITY`] answers and forgets them all when full.

use std::collections::HashMap;
use std::sync::Mutex;

use super::jaws::JawPose;
use super::model::{Body, GraspModel, Squeeze, squeeze_bodies};
use crate::scene::Gripper;

/// Most answers remembered.
pub const CAPACITY: usize = 4096;

/// Remembered squeezes of one grasp model.
#[derive(Debug, Default)]
pub(crate) struct Memory {
    answers: Mutex<HashMap<Vec<u64>, Squeeze>>,
}

impl Clone for Memory {
    /// A copy starts with nothing remembered.
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl Memory {
    /// [`squeeze_bodies`] under `model`, from memory when these inputs were judged before.
    pub fn squeeze(
        &self,
        bodies: &[Body<'_>],
        gripper: &Gripper,
        jaws: &JawPose,
        model: &GraspModel,
    ) -> Squeeze {
        let key = key(bodies, gripper, jaws);
        if let Some(known) = self.lock().get(&key) {
            return known.clone();
        }
        let answer = squeeze_bodies(bodies, gripper, jaws, model);
        let mut answers = self.lock();
        if answers.len() >= CAPACITY {
            answers.clear();
        }
        answers.insert(key, answer.clone());
        answer
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<Vec<u64>, Squeeze>> {
        // A panic elsewhere while the lock was held leaves a usable map (answers are inserted whole).
        self.answers
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// The bit patterns of every input but the model: jaws, gripper, then each body's mass and vertices.
fn key(bodies: &[Body<'_>], gripper: &Gripper, jaws: &JawPose) -> Vec<u64> {
    let mut key = vec![
        jaws.center.x.to_bits(),
        jaws.center.y.to_bits(),
        jaws.angle.to_bits(),
        jaws.opening.to_bits(),
        gripper.stroke.to_bits(),
        gripper.plate_thickness.to_bits(),
        gripper.plate_length.to_bits(),
        gripper.fork_push_opening_fraction.to_bits(),
    ];
    for body in bodies {
        key.push(body.mass.to_bits());
        key.push(body.outline.len() as u64);
        for v in body.outline.vertices() {
            key.push(v.x.to_bits());
            key.push(v.y.to_bits());
        }
    }
    key
}
