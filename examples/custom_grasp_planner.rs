//! A grasp planner of one's own, plugged into push-mog-opt through the public API.
//!
//! It is the built-in multi-object planner with one rule added: no grasp of several objects when
//! one of them lies within 2 cm of the workspace's edge (a failed multi-object grasp squeezes its
//! objects out along the plates, and so out of the workspace). The policy then takes such objects
//! one at a time. The plan is made with the ideal executor and checked by the verifier.
//!
//! `cargo run --release --example custom_grasp_planner -- [seed]`

use pushmog::grasp::{Grasp, GraspPlanner, GraspRequest, MultiObject};
use pushmog::outcome::{Outcome, Status};
use pushmog::plan::verify;
use pushmog::policy::{Policy, PolicyKind};
use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};

#[derive(Debug, Default)]
struct OffTheEdge {
    inner: MultiObject,
}

impl GraspPlanner for OffTheEdge {
    fn name(&self) -> &'static str {
        "multi-object, off the edge"
    }

    fn plan_request(&self, request: &GraspRequest<'_>) -> pushmog::Result<Outcome<Option<Grasp>>> {
        let mut answer = self.inner.plan_request(request)?;
        let scene = request.scene;
        let (low, high) = (
            scene.workspace().min_corner(),
            scene.workspace().max_corner(),
        );
        let near_edge = |index: usize| {
            scene.world_polygon(index).vertices().iter().any(|v| {
                let room = (v.x - low.x)
                    .min(high.x - v.x)
                    .min(v.y - low.y)
                    .min(high.y - v.y);
                room < 0.02
            })
        };
        let refused = answer.value.as_ref().is_some_and(|grasp: &Grasp| {
            grasp.objects.len() > 1
                && grasp
                    .objects
                    .iter()
                    .any(|&id| scene.index_of(id).is_some_and(near_edge))
        });
        if refused {
            answer.value = None;
            answer.status = Status::Failed {
                reason: "an object lies within 2 cm of the workspace's edge".to_string(),
            };
        }
        Ok(answer)
    }
}

fn main() -> pushmog::Result<()> {
    let seed = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed)?;
    let policy = Policy::builder(PolicyKind::PushMogOpt)
        .multi_object_planner(OffTheEdge::default())
        .build()?;
    let plan = policy.run(&scene, &mut policy.ideal(), seed)?;
    let violations = verify(&plan);
    assert!(violations.is_empty(), "{violations:?}");
    println!(
        "seed {seed}: {} objects in {} trips ({:.3} per trip), {} pushes; the plan verifies",
        plan.objects_carried(),
        plan.trips.len(),
        plan.objects_per_trip(),
        plan.push_count()
    );
    Ok(())
}
