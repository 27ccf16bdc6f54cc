//! Closed loops that meet what physics does: bars stranded or stuck together, pushes and grasps that
//! landed on other objects, grasps that failed twice, objects lost, rows that came out broken; the
//! policy recovers and says why.

use pushmog::plan::{Plan, RunStatus, verify};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::Scene;

use crate::support::{GraspHook, Rigged, scene};

/// The runs of every preset with default settings on `scene` (run seed 1): for each, its plans
/// applied exactly and then in the simulator (seed 3).
fn every_policy_exactly_and_in_the_simulator(scene: &Scene) -> Vec<(PolicyKind, Plan)> {
    use pushmog::exec::{Executor, Sim, SimSettings};
    let mut runs = Vec::new();
    for kind in PolicyKind::ALL {
        let policy = Policy::new(kind, PolicySettings::default()).unwrap();
        let mut ideal = policy.ideal();
        let mut sim = Sim::new(SimSettings::default(), 3).unwrap();
        for executor in [&mut ideal as &mut dyn Executor, &mut sim] {
            runs.push((kind, policy.run(scene, executor, 1).unwrap()));
        }
    }
    runs
}

/// Two 7 × 50 mm bars stranded 2 mm apart and 1.5° off parallel (what pushing thin bars together can
/// leave): too close for a plate between them, and a row the grasp model may refuse. Every policy
/// that may grasp several objects clears them, with plans applied exactly and in the simulator; no
/// policy repeats a failed grasp (`sog` cannot take either bar alone, and stops saying why).
#[test]
fn stranded_bars_are_cleared_without_identical_retries() {
    use nalgebra::Point2;
    use pushmog::geometry::ConvexPolygon;
    use pushmog::scene::{Gripper, Object, ObjectId, Pose, Workspace};
    let bar = ConvexPolygon::new(vec![
        Point2::new(-0.0035, -0.025),
        Point2::new(0.0035, -0.025),
        Point2::new(0.0035, 0.025),
        Point2::new(-0.0035, 0.025),
    ])
    .unwrap();
    let objects = [(0.20, 0.0), (0.209, 1.5f64.to_radians())]
        .iter()
        .enumerate()
        .map(|(k, &(x, yaw))| Object {
            id: ObjectId(k as u32),
            name: Some("bar-7x50".to_string()),
            polygon: bar.clone(),
            pose: Pose::new(x, 0.15, yaw),
            height: 0.03,
            mass: None,
        })
        .collect();
    let scene = Scene::from_parts(Workspace::new(0.4, 0.3), Gripper::default(), objects).unwrap();
    for (kind, plan) in every_policy_exactly_and_in_the_simulator(&scene) {
        if kind == PolicyKind::Sog {
            assert!(matches!(plan.status, RunStatus::Stopped { .. }));
        } else {
            assert_eq!(plan.status, RunStatus::Cleared, "{kind} {}", plan.executor);
        }
        assert!(verify(&plan).is_empty(), "{kind}: {:?}", verify(&plan));
        let failed: Vec<_> = plan
            .trips
            .iter()
            .filter(|t| t.carried.is_empty())
            .map(|t| t.plan.grasp.jaws)
            .collect();
        for (k, a) in failed.iter().enumerate() {
            assert!(
                failed[k + 1..].iter().all(|b| !a.same_place(b)),
                "{kind} {}: a failed grasp was repeated",
                plan.executor
            );
        }
    }
}

/// A triangle and a truncated rectangle that the paper's pushes left touching (seed 130, after a
/// push of 40 mm): no plate fits between them, so neither can be taken by itself, and the grasp
/// model refuses them together. The pushing policies clear the table, with plans applied exactly and
/// in the simulator; applied exactly, they first push one of them clear with the jaws closed. `sog`
/// and `mog`, which do not push, stop there when plans are applied exactly.
#[test]
fn objects_stuck_together_are_pushed_apart() {
    use nalgebra::Point2;
    use pushmog::geometry::ConvexPolygon;
    use pushmog::scene::{Gripper, Object, ObjectId, Pose, Workspace};
    let outline = |points: &[(f64, f64)]| {
        ConvexPolygon::new(points.iter().map(|&(x, y)| Point2::new(x, y)).collect()).unwrap()
    };
    let triangle = outline(&[
        (-0.015, -0.008660254),
        (0.015, -0.008660254),
        (0.0, 0.017320508),
    ]);
    let octagon = outline(&[
        (-0.014, -0.013),
        (0.014, -0.013),
        (0.02, -0.007),
        (0.02, 0.007),
        (0.014, 0.013),
        (-0.014, 0.013),
        (-0.02, 0.007),
        (-0.02, -0.007),
    ]);
    let object =
        |id: u32, name: &str, polygon: ConvexPolygon, (x, y, yaw): (f64, f64, f64)| Object {
            id: ObjectId(id),
            name: Some(name.to_string()),
            polygon,
            pose: Pose::new(x, y, yaw),
            height: 0.03,
            mass: None,
        };
    let objects = vec![
        object(
            3,
            "triangle-equilateral-30",
            triangle,
            (0.3418560258541743, 0.34995766131701783, -2.3556059341399953),
        ),
        object(
            28,
            "octagon-truncated-rectangle",
            octagon,
            (0.3351475195960326, 0.32233342244966756, -1.1258191577149619),
        ),
    ];
    let scene = Scene::from_parts(Workspace::new(0.6, 0.45), Gripper::default(), objects).unwrap();
    for (kind, plan) in every_policy_exactly_and_in_the_simulator(&scene) {
        assert!(verify(&plan).is_empty(), "{kind}: {:?}", verify(&plan));
        if matches!(kind, PolicyKind::Sog | PolicyKind::Mog) {
            assert!(
                !matches!(plan.status, RunStatus::Cleared) || plan.executor == "sim",
                "{kind}: cleared without pushing"
            );
            continue;
        }
        assert_eq!(plan.status, RunStatus::Cleared, "{kind} {}", plan.executor);
        let openings: Vec<f64> = plan.trips[0]
            .plan
            .pushes
            .iter()
            .map(|p| p.fork.opening)
            .collect();
        println!(
            "{kind} {}: first trip's push openings {openings:?}",
            plan.executor
        );
        if plan.executor == "ideal" {
            assert!(
                openings
                    .first()
                    .is_some_and(|&o| o < scene.gripper().fork_push_opening()),
                "{kind}: the first trip pushes nothing apart"
            );
        }
    }
}

/// A regular hexagon and an isosceles triangle pressed together 29–35 mm from the workspace's far
/// edge, as a failed pair grasp left them (paper-100 scene 80, push-mog-time with riders). Neither
/// can be taken by itself (a plate would come down on the other), there is no room between them for
/// the fingers of a push that would part them, and an edge margin of 40 mm along the plates refuses
/// the pair. Every clustering preset with that margin takes the two together as they lie, with plans
/// applied exactly and in the simulator, instead of stopping with both on the table.
#[test]
fn objects_pressed_together_near_the_edge_are_taken_together() {
    use pushmog::exec::{Executor, Sim, SimSettings};
    use pushmog::grasp::{GraspPlanner, MultiObject, MultiObjectSettings, SingleObject};
    use pushmog::scene::{Gripper, Object, ObjectId, Pose, Workspace, builtin_object_set};
    let library = builtin_object_set();
    let object = |id: u32, name: &str, (x, y, yaw): (f64, f64, f64)| {
        let shape = library.objects.iter().find(|o| o.name == name).unwrap();
        Object {
            id: ObjectId(id),
            name: Some(name.to_string()),
            polygon: shape.polygon().unwrap(),
            pose: Pose::new(x, y, yaw),
            height: shape.height,
            mass: shape.mass,
        }
    };
    let objects = vec![
        object(
            9,
            "hexagon-regular-15",
            (0.4083010931763497, 0.4002104967249667, 2.0609041621099),
        ),
        object(
            10,
            "triangle-isosceles-32x30",
            (
                0.43349137144533745,
                0.40419074985960335,
                -1.6864657879113458,
            ),
        ),
    ];
    let scene = Scene::from_parts(Workspace::new(0.6, 0.45), Gripper::default(), objects).unwrap();
    let margins = MultiObjectSettings {
        edge_margin: 0.04,
        edge_along_plates: true,
        ..MultiObjectSettings::default()
    };
    // What makes the dead end: each alone is refused, and so is the pair with the margin.
    let problem = pushmog::problem::Problem::shared_default();
    let single = SingleObject::new(Default::default(), problem.clone()).unwrap();
    for id in [ObjectId(9), ObjectId(10)] {
        assert!(
            single.plan(&scene, &[id]).unwrap().value.is_none(),
            "{id} alone"
        );
    }
    let both = [ObjectId(9), ObjectId(10)];
    let with_margin = MultiObject::new(margins.clone(), problem).unwrap();
    let pair = with_margin.plan(&scene, &both).unwrap().value;
    assert!(pair.is_none_or(|grasp| grasp.objects.len() < 2));
    let settings = PolicySettings {
        multi: margins,
        ..PolicySettings::default()
    };
    for kind in PolicyKind::ALL {
        if kind == PolicyKind::Sog {
            continue;
        }
        let policy = Policy::new(kind, settings.clone()).unwrap();
        let mut ideal = policy.ideal();
        let mut sim = Sim::new(SimSettings::default(), 3).unwrap();
        for executor in [&mut ideal as &mut dyn Executor, &mut sim] {
            let plan = policy.run(&scene, executor, 1).unwrap();
            assert_eq!(plan.status, RunStatus::Cleared, "{kind} {}", plan.executor);
            assert!(verify(&plan).is_empty(), "{kind}: {:?}", verify(&plan));
            let mut first = plan.trips[0].plan.grasp.objects.clone();
            first.sort_unstable();
            assert_eq!(first, both, "{kind} {}", plan.executor);
        }
    }
}

/// The first of seeds 0–19 whose scene's first trip (context seeded alike) is `wanted`: its table,
/// seed and trip.
fn first_trip_where(
    policy: &Policy,
    wanted: impl Fn(&pushmog::policy::TripPlan) -> bool,
) -> Option<(Scene, u64, pushmog::policy::TripPlan)> {
    (0..20).find_map(|seed| {
        let table = scene(seed);
        let trip = policy
            .plan_trip_with(&table, &mut pushmog::policy::TripContext::new(seed))
            .unwrap()
            .into_trip()?;
        wanted(&trip).then_some((table, seed, trip))
    })
}

/// After a finger came down during a push on an object the camera does not see (outside the
/// workspace), that object is not pushed again with its fingers lowered near there: the trip planned
/// again with the landing remembered makes no such push, says why, and still grasps something.
#[test]
fn a_push_that_landed_on_an_unseen_object_is_not_repeated() {
    use pushmog::policy::{Landing, TripContext};
    use pushmog::push::SkipReason;
    use pushmog::scene::ObjectId;
    let policy = Policy::new(PolicyKind::PushMogOpt, PolicySettings::default()).unwrap();
    let (table, seed, first) = first_trip_where(&policy, |trip| !trip.pushes.is_empty())
        .expect("a first trip with pushes on one of 20 scenes");
    let landed = first.pushes[0].clone();
    let unseen = ObjectId(1000);
    assert!(table.index_of(unseen).is_none());
    let mut context = TripContext::new(seed);
    context.landed.push(Landing {
        push: landed.clone(),
        on: unseen,
    });
    let again = policy
        .plan_trip_with(&table, &mut context)
        .unwrap()
        .trip
        .expect("a trip without the push");
    assert!(again.pushes.iter().all(|p| p.object != landed.object));
    assert!(
        again
            .skipped_pushes
            .iter()
            .any(|s| s.reason == SkipReason::LandedBefore { object: unseen })
    );
    assert!(!again.grasp.objects.is_empty());
    // Landing on an object that is seen teaches nothing new: the fingers keep clear of it anyway.
    let mut context = TripContext::new(seed);
    context.landed.push(Landing {
        push: landed.clone(),
        on: table.objects()[0].id,
    });
    let same = policy.plan_trip_with(&table, &mut context).unwrap().trip;
    assert_eq!(same, Ok(first));
}

/// Objects whose multi-object grasps carried nothing twice are taken one at a time: the trip planned
/// again with two such failures remembered grasps no set of exactly those objects, yet still grasps
/// something. One failure alone does not give them up.
#[test]
fn objects_grasped_together_twice_in_vain_are_not_grasped_together_again() {
    use pushmog::policy::{GIVE_UP_AFTER, TripContext};
    let policy = Policy::new(PolicyKind::PushMogOpt, PolicySettings::default()).unwrap();
    let (table, seed, first) = first_trip_where(&policy, |trip| trip.grasp.objects.len() >= 2)
        .expect("a first trip with a multi-object grasp on one of 20 scenes");
    let mut together = first.grasp.objects.clone();
    together.sort_unstable();
    let mut context = TripContext::new(seed);
    for failures in 1..=GIVE_UP_AFTER {
        let mut grasp = first.grasp.clone();
        // The same objects, grasped elsewhere: the failed jaws themselves are avoided anyway.
        grasp.jaws.center.x += 0.05 * failures as f64;
        grasp.objects.reverse();
        context.record_failure(&grasp);
        assert_eq!(context.given_up(&together), failures >= GIVE_UP_AFTER);
    }
    let again = policy
        .plan_trip_with(&table, &mut context)
        .unwrap()
        .trip
        .expect("a trip without that multi-object grasp");
    let mut objects = again.grasp.objects.clone();
    objects.sort_unstable();
    assert_ne!(objects, together);
    assert!(!again.grasp.objects.is_empty());
    // A single-object grasp that carried nothing gives up no set.
    let mut context = TripContext::new(seed);
    for _ in 0..GIVE_UP_AFTER {
        let mut single = first.grasp.clone();
        single.objects.truncate(1);
        context.record_failure(&single);
    }
    assert!(context.failed_together.is_empty());
}

/// After its first grasp, loses one object the grasp left (as if pushed out of the workspace): the
/// object is no longer seen, and `lost` names it.
struct LosesOne {
    lost: Option<pushmog::scene::ObjectId>,
}

impl GraspHook for LosesOne {
    fn grasp(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult> {
        use pushmog::exec::Executor;
        let result = table.grasp(grasp)?;
        if self.lost.is_none() {
            let left = table.observe()?;
            let gone = left.objects()[0].id;
            let kept = left.objects()[1..].to_vec();
            table.reset(&left.with_objects(kept)?)?;
            self.lost = Some(gone);
        }
        Ok(result)
    }
    fn lost(&self, _table: &pushmog::exec::Ideal) -> Vec<(pushmog::scene::ObjectId, &'static str)> {
        self.lost
            .iter()
            .map(|&id| (id, "outside the workspace"))
            .collect()
    }
}

/// The trip after which an object was lost names it, once; the plan file keeps it and the replay
/// shows it.
#[test]
fn the_trip_that_lost_an_object_names_it() {
    use pushmog::plan::{LostObject, StopReason};
    let policy = Policy::new(PolicyKind::PushMog, PolicySettings::default()).unwrap();
    let table = scene(2);
    let mut executor = Rigged {
        table: policy.ideal(),
        hook: LosesOne { lost: None },
    };
    let plan = policy.run(&table, &mut executor, 3).unwrap();
    let gone = executor.hook.lost.expect("the first grasp was made");
    assert_eq!(
        plan.trips[0].lost,
        vec![LostObject {
            object: gone,
            reason: "outside the workspace".to_string(),
        }]
    );
    assert!(plan.trips[1..].iter().all(|t| t.lost.is_empty()));
    match &plan.status {
        RunStatus::Stopped {
            remaining,
            reason: StopReason::NothingPlannable { .. },
        } => assert_eq!(remaining, &vec![gone]),
        other => panic!("{other:?}"),
    }
    assert!(verify(&plan).is_empty(), "{:?}", verify(&plan));
    let text = serde_json::to_string(&plan).unwrap();
    let read: Plan = serde_json::from_str(&text).unwrap();
    assert_eq!(read, plan);
    let replay =
        pushmog::render::replay_html(&plan, &pushmog::render::RenderOptions::default()).unwrap();
    assert!(replay.contains(&format!("lost {gone} (outside the workspace)")));
}

/// After its first grasp, moves one object the grasp left to lie 5 mm past the workspace's right
/// edge (as a grasp that nudged it there would): the object is reported lost outside the
/// workspace and seen there ([`pushmog::exec::Executor::past_edge`]); a grasp of it carries it.
struct PushedPastEdge {
    out: Option<pushmog::scene::Object>,
    moved: bool,
}

impl GraspHook for PushedPastEdge {
    fn grasp(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult> {
        use pushmog::exec::Executor;
        if let Some(out) = &self.out
            && grasp.objects == [out.id]
        {
            self.out = None;
            return Ok(pushmog::exec::GraspResult::carried(grasp.objects.clone()));
        }
        let result = table.grasp(grasp)?;
        if !self.moved {
            self.moved = true;
            let left = table.observe()?;
            let mut object = left.objects()[0].clone();
            let right = object
                .world_polygon()
                .vertices()
                .iter()
                .map(|v| v.x)
                .fold(f64::MIN, f64::max);
            object.pose.x += left.workspace().max[0] + 0.005 - right;
            table.reset(&left.with_objects(left.objects()[1..].to_vec())?)?;
            self.out = Some(object);
        }
        Ok(result)
    }
    fn lost(&self, _table: &pushmog::exec::Ideal) -> Vec<(pushmog::scene::ObjectId, &'static str)> {
        self.out
            .iter()
            .map(|o| (o.id, "outside the workspace"))
            .collect()
    }
    fn past_edge(&self) -> Vec<pushmog::scene::Object> {
        self.out.iter().cloned().collect()
    }
}

/// An object left 5 mm past the workspace's edge ends the run with it left, unless the policy may
/// reach that far (`run.reach_past_edge`): then, once the workspace is clear, one trip takes it by
/// itself, planned on the workspace grown by the reach, and the whole run passes the verifier and
/// reads back from its file.
#[test]
fn an_object_just_past_the_edge_is_taken_once_the_workspace_is_clear() {
    use pushmog::plan::StopReason;
    let table = scene(2);
    let run = |reach: f64| {
        let mut settings = PolicySettings::default();
        settings.run.reach_past_edge = reach;
        let policy = Policy::new(PolicyKind::PushMog, settings).unwrap();
        let mut executor = Rigged {
            table: policy.ideal(),
            hook: PushedPastEdge {
                out: None,
                moved: false,
            },
        };
        policy.run(&table, &mut executor, 3).unwrap()
    };
    let stopped = run(0.0);
    assert!(
        matches!(
            &stopped.status,
            RunStatus::Stopped {
                reason: StopReason::NothingPlannable { .. },
                ..
            }
        ),
        "{:?}",
        stopped.status
    );
    assert_eq!(stopped.trips_past_edge(), 0);
    let reached = run(0.02);
    assert_eq!(reached.status, RunStatus::Cleared);
    assert_eq!(reached.trips_past_edge(), 1);
    assert_eq!(reached.trips.len(), stopped.trips.len() + 1);
    // The trips before are the same: nothing changes until the workspace is clear.
    assert_eq!(reached.trips[..stopped.trips.len()], stopped.trips[..]);
    let last = reached.trips.last().unwrap();
    assert!(last.plan.pushes.is_empty() && last.plan.grasp.objects.len() == 1);
    assert_eq!(last.scene.workspace.max[0], table.workspace().max[0] + 0.02);
    assert!(verify(&reached).is_empty(), "{:?}", verify(&reached));
    let text = serde_json::to_string(&reached).unwrap();
    let read: Plan = serde_json::from_str(&text).unwrap();
    assert_eq!(read, reached);
    // The replay says so and outlines the workspace inside the grown table.
    let replay =
        pushmog::render::replay_html(&reached, &pushmog::render::RenderOptions::default()).unwrap();
    assert!(replay.contains("taken from past the workspace's edge"));
    assert!(replay.contains("workspace (dashed)"));
    // Too far for a reach of 4 mm: the run stops as without it.
    assert_eq!(run(0.004).status, stopped.status);
}

/// Grasps of `object` come down on `blocker` (as a grasp does when the table seen is a little
/// off) for as long as `blocker` is on the table.
struct InTheWay {
    object: pushmog::scene::ObjectId,
    blocker: pushmog::scene::ObjectId,
    landings: usize,
}

impl GraspHook for InTheWay {
    fn grasp(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult> {
        use pushmog::exec::Executor;
        let there = table.observe()?.index_of(self.blocker).is_some();
        if there && grasp.objects.contains(&self.object) {
            self.landings += 1;
            return Ok(pushmog::exec::GraspResult {
                carried: Vec::new(),
                landing: Some(pushmog::exec::Landing {
                    object: self.blocker,
                }),
            });
        }
        table.grasp(grasp)
    }
}

/// A grasp that came down on a neighbour is not repeated in the same place while other grasps
/// remain, but once the neighbour has gone and nothing else can be planned, its place is tried
/// again. Two bars 10 × 100 mm: each has one grasp place (across its width; its length is wider
/// than the jaws open). Every grasp of the first lands on the second while the second lies there,
/// so the first's only place has failed before; without forgetting that failure the run would stop
/// after ten attempts with the first bar left.
#[test]
fn a_grasp_that_landed_on_an_object_now_gone_is_tried_again() {
    use crate::support::boxes;
    use pushmog::scene::ObjectId;
    let table = boxes(0.01, 0.1, &[(0.2, 0.2), (0.26, 0.2)]);
    let policy = Policy::new(PolicyKind::Sog, PolicySettings::default()).unwrap();
    let mut blocked_first = 0;
    for seed in 0..4 {
        let mut executor = Rigged {
            table: policy.ideal(),
            hook: InTheWay {
                object: ObjectId(0),
                blocker: ObjectId(1),
                landings: 0,
            },
        };
        let plan = policy.run(&table, &mut executor, seed).unwrap();
        assert_eq!(plan.status, RunStatus::Cleared, "seed {seed}");
        assert!(verify(&plan).is_empty(), "{:?}", verify(&plan));
        let first = &plan.trips[0].plan.grasp;
        if first.objects == [ObjectId(0)] {
            // The first trip went for the bar that cannot be carried yet: one landing, then the
            // other bar, then the first again in the place that failed.
            assert_eq!(executor.hook.landings, 1, "seed {seed}");
            assert_eq!(plan.trips.len(), 3);
            assert!(plan.trips[2].plan.grasp.jaws.same_place(&first.jaws));
            blocked_first += 1;
        }
    }
    assert!(blocked_first > 0, "no seed went for the blocked bar first");
}

/// A row of three bars (7 × 50 mm) that pushes left broken: two stand 20 mm apart, the third 50 mm
/// beyond, so the three span 77 mm, more than the 75 mm the jaws take. As it lies, a grasp takes
/// the two; a corrective push lets one grasp take all three, and when pushes are allowed it comes
/// first. Without pushes, the two are taken.
#[test]
fn a_broken_row_is_pushed_whole_before_part_of_it_is_taken() {
    use crate::support::boxes;
    use pushmog::policy::TripContext;
    let row = boxes(0.007, 0.05, &[(0.15, 0.2), (0.17, 0.2), (0.19, 0.2)]);
    let policy = Policy::new(PolicyKind::PushMogOpt, PolicySettings::default()).unwrap();
    let trip = policy.plan_trip(&row).unwrap().trip.unwrap();
    let cluster = &trip.clustering.clusters[trip.cluster.unwrap()];
    assert_eq!(cluster.len(), 3, "the three bars form one cluster");
    assert_eq!(
        trip.grasp.objects.len(),
        3,
        "and are taken together as they stand"
    );
    let broken = boxes(0.007, 0.05, &[(0.15, 0.2), (0.17, 0.2), (0.22, 0.2)]);
    let context = TripContext::new(0);
    let corrected = policy
        .correct_trip(&broken, &trip, &context, true)
        .unwrap()
        .unwrap();
    assert!(
        !corrected.pushes.is_empty(),
        "a corrective push comes first"
    );
    assert_eq!(corrected.grasp.objects.len(), 3, "{:?}", corrected.grasp);
    let as_it_lies = policy
        .correct_trip(&broken, &trip, &context, false)
        .unwrap()
        .unwrap();
    assert!(as_it_lies.pushes.is_empty());
    let mut taken = as_it_lies.grasp.objects.clone();
    taken.sort();
    assert_eq!(
        taken,
        [pushmog::scene::ObjectId(0), pushmog::scene::ObjectId(1)]
    );
}
