//! Single-object grasps: one object between the jaws, flush on an edge, jaws clear of neighbours.
//!
//! Candidates are the object's stable edge-flush grasps ([`edge_grasps`]): the closing axis is an edge
//! normal, the jaws centre on the middle of the facing contacts, and the plates open to the object's
//! width there plus `clearance` on each side (capped at the stroke; half of it when neighbours are
//! close). Candidates whose jaws catch this object alone are ordered by clearance to other objects,
//! then narrowest first, and the first the grasp model predicts held wins.

use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::model::{Squeeze, plate_clearance, row_in_scene, squeeze};
use super::{Grasp, GraspPlanner, GraspRequest, JawPose};
use crate::error::Result;
use crate::geometry::edge_grasps;
use crate::outcome::{Outcome, Stats, Status};
use crate::problem::Problem;
use crate::scene::Scene;

/// Settings of [`SingleObject`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SingleObjectSettings {
    /// Gap between each open plate and the object, metres; half of it is tried too when neighbours
    /// are close. Default 0.01.
    pub clearance: f64,
}

impl Default for SingleObjectSettings {
    fn default() -> Self {
        Self { clearance: 0.01 }
    }
}

impl SingleObjectSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        crate::error::in_range(
            "single",
            "clearance",
            self.clearance,
            (0.0, 0.05),
            "metres each side, within the stroke",
        )
    }
}

/// Single-object grasps.
#[derive(Clone, Debug)]
pub struct SingleObject {
    settings: SingleObjectSettings,
    problem: Arc<Problem>,
}

impl Default for SingleObject {
    fn default() -> Self {
        Self {
            settings: SingleObjectSettings::default(),
            problem: Problem::shared_default(),
        }
    }
}

impl SingleObject {
    /// A planner with these settings, judging grasps with the problem's grasp model.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: SingleObjectSettings, problem: Arc<Problem>) -> Result<Self> {
        settings.validate()?;
        Ok(Self { settings, problem })
    }

    /// The effective settings.
    pub fn settings(&self) -> &SingleObjectSettings {
        &self.settings
    }

    /// The best single-object grasp of object `index`, or why there is none.
    pub(super) fn grasp_object(
        &self,
        scene: &Scene,
        index: usize,
        avoid: &[JawPose],
        evaluated: &mut usize,
    ) -> std::result::Result<Grasp, String> {
        let gripper = scene.gripper();
        let object = &scene.objects()[index];
        let pose = object.pose.isometry();
        let mut last_reason = format!("object {} is wider than the jaw gap", object.id);
        // Cheap geometry first: jaws that catch this object alone, with their clearance.
        let mut candidates: Vec<(f64, f64, JawPose)> = Vec::new();
        for candidate in edge_grasps(&object.polygon) {
            if candidate.diameter > gripper.usable_gap() {
                continue;
            }
            let [near, far] = candidate.contacts(&object.polygon);
            let center = pose * nalgebra::center(&near, &far);
            let axis = pose * candidate.axis;
            for clearance in [self.settings.clearance, self.settings.clearance / 2.0] {
                let opening = (candidate.diameter + 2.0 * clearance + gripper.plate_thickness)
                    .min(gripper.stroke);
                let jaws = JawPose {
                    center,
                    angle: axis.y.atan2(axis.x),
                    opening,
                };
                *evaluated += 1;
                match row_in_scene(scene, &jaws, self.problem.grasp_model()) {
                    Ok(caught) if caught == [index] => {
                        let margin = plate_clearance(scene, &jaws, &caught, 0.05);
                        candidates.push((margin, candidate.diameter, jaws));
                        break;
                    }
                    Ok(caught) => {
                        last_reason = format!(
                            "jaws around object {} would also catch object {}",
                            object.id,
                            scene.objects()[caught
                                .iter()
                                .copied()
                                .find(|&o| o != index)
                                .unwrap_or(index)]
                            .id
                        );
                    }
                    Err(Squeeze::PlateHits { object: hit }) => {
                        last_reason =
                            format!("a plate would land on object {}", scene.objects()[hit].id);
                    }
                    Err(other) => last_reason = format!("{other:?}"),
                }
            }
        }
        // Jaws where a grasp already failed are not tried again.
        candidates.retain(|(_, _, jaws)| {
            let repeats = avoid.iter().any(|a| a.same_place(jaws));
            if repeats {
                last_reason = format!("the grasps of object {} failed before", object.id);
            }
            !repeats
        });
        // Most clearance first, then the narrowest; the first the model holds wins.
        candidates.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.total_cmp(&b.1)));
        for (margin, _, jaws) in candidates {
            match squeeze(scene, &jaws, self.problem.grasp_model()) {
                Squeeze::Held { objects, width } if objects == [index] => {
                    return Ok(Grasp {
                        jaws,
                        objects: vec![object.id],
                        width,
                        margin,
                    });
                }
                other => last_reason = format!("{other:?}"),
            }
        }
        Err(last_reason)
    }
}

impl GraspPlanner for SingleObject {
    fn name(&self) -> &'static str {
        "single-object"
    }

    /// The first target, in the order given, that has a stable grasp of its own, its jaws clear of
    /// neighbours and never in the same place as `request.avoid`. Hints and pushed objects are not
    /// used; a request for two or more objects has no answer here.
    fn plan_request(&self, request: &GraspRequest<'_>) -> Result<Outcome<Option<Grasp>>> {
        if request.min_objects > 1 {
            return Ok(Outcome {
                value: None,
                status: Status::Failed {
                    reason: "a single-object planner carries one object".to_string(),
                },
                stats: Stats::default(),
            });
        }
        let (scene, targets, avoid) = (request.scene, request.targets, request.avoid);
        let started = Instant::now();
        let indices = scene.indices_of(targets)?;
        let mut evaluated = 0;
        let mut reasons = Vec::new();
        let mut found = None;
        for index in indices {
            match self.grasp_object(scene, index, avoid, &mut evaluated) {
                Ok(grasp) => {
                    found = Some(grasp);
                    break;
                }
                Err(reason) => reasons.push(reason),
            }
        }
        let status = match &found {
            Some(_) => Status::Heuristic,
            None => Status::Failed {
                reason: if reasons.is_empty() {
                    "no target objects".to_string()
                } else {
                    reasons.join("; ")
                },
            },
        };
        Ok(Outcome {
            value: found,
            status,
            stats: Stats {
                seconds: started.elapsed().as_secs_f64(),
                counters: vec![("candidates".to_string(), evaluated as f64)],
                ..Stats::default()
            },
        })
    }
}
