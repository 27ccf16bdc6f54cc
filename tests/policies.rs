//! The baselines end to end: every plan of every policy passes the independent verifier, and the
//! objects-per-trip figures behave as the policies' designs say.

use pushmog::plan::{Plan, RunStatus, verify};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::{GeneratorSettings, Scene, builtin_object_set, generate_scene};

fn scene(seed: u64) -> Scene {
    generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap()
}

fn run(kind: PolicyKind, scene: &Scene, seed: u64) -> Plan {
    let policy = Policy::new(kind, PolicySettings::default()).unwrap();
    let mut executor = policy.ideal();
    policy.run(scene, &mut executor, seed).unwrap()
}

/// Scenes for the statistical verification sweep: 200 by default (the acceptance figure); set
/// `PUSHMOG_VERIFY_SCENES` to run more or fewer.
fn sweep_size() -> u64 {
    std::env::var("PUSHMOG_VERIFY_SCENES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200)
}

/// Runs every policy on scenes `0..scenes` with plans applied exactly, one thread per policy, and
/// fails listing every plan the verifier refuses and every run that did not clear its table.
/// Returns each policy's objects per trip, scene by scene, in the order of [`PolicyKind::ALL`].
fn every_policy_verifies(scenes: u64) -> Vec<(PolicyKind, Vec<f64>)> {
    let results: Vec<(PolicyKind, Vec<String>, Vec<f64>)> = std::thread::scope(|threads| {
        let handles: Vec<_> = PolicyKind::ALL
            .into_iter()
            .map(|kind| {
                threads.spawn(move || {
                    let mut failures = Vec::new();
                    let mut per_trip = Vec::new();
                    for seed in 0..scenes {
                        let scene = scene(seed);
                        let plan = run(kind, &scene, seed);
                        let violations = verify(&plan);
                        if !violations.is_empty() {
                            failures.push(format!("seed {seed} {kind}: {}", violations[0]));
                        }
                        if plan.status != RunStatus::Cleared {
                            failures.push(format!("seed {seed} {kind}: {:?}", plan.status));
                        }
                        assert_eq!(plan.objects_carried() + remaining(&plan), scene.len());
                        per_trip.push(plan.objects_per_trip());
                    }
                    (kind, failures, per_trip)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a sweep thread panicked"))
            .collect()
    });
    let failures: Vec<String> = results.iter().flat_map(|(_, f, _)| f.clone()).collect();
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
    results
        .into_iter()
        .map(|(kind, _, per_trip)| (kind, per_trip))
        .collect()
}

/// The quick sweep of the default test run: every policy on 10 scenes.
#[test]
fn every_plan_of_every_policy_verifies_on_10_scenes() {
    every_policy_verifies(10);
}

/// The acceptance sweep, 1 200 closed-loop runs (about 9 minutes on 2 cores in the test profile):
/// statistical, so it runs with `cargo test -- --ignored`, as CI does. Its runs of the first 20
/// scenes also give the comparison of means that pushing must win: push-mog carries more objects
/// per trip than mog.
#[test]
#[ignore = "statistical: cargo test -- --ignored"]
fn every_plan_of_every_policy_verifies_on_200_scenes_and_pushing_raises_objects_per_trip() {
    let per_trip = every_policy_verifies(sweep_size().max(20));
    let mean_of_first_20 = |kind: PolicyKind| {
        let (_, values) = per_trip
            .iter()
            .find(|(k, _)| *k == kind)
            .expect("every policy ran");
        values[..20].iter().sum::<f64>() / 20.0
    };
    let (mog, push_mog) = (
        mean_of_first_20(PolicyKind::Mog),
        mean_of_first_20(PolicyKind::PushMog),
    );
    assert!(push_mog > mog, "push-mog {push_mog} vs mog {mog}");
}

fn remaining(plan: &Plan) -> usize {
    match &plan.status {
        RunStatus::Cleared => 0,
        RunStatus::Stopped { remaining, .. } => remaining.len(),
    }
}

#[test]
fn sog_carries_exactly_one_object_per_trip() {
    for seed in 0..20 {
        let plan = run(PolicyKind::Sog, &scene(seed), seed);
        assert_eq!(plan.objects_per_trip(), 1.0, "seed {seed}");
        assert!(plan.trips.iter().all(|t| t.carried.len() == 1));
    }
}

#[test]
fn runs_are_reproducible() {
    let scene = scene(4);
    assert_eq!(
        run(PolicyKind::PushMog, &scene, 9),
        run(PolicyKind::PushMog, &scene, 9)
    );
}

/// A policy keeps no state between calls (what a run remembers travels in its `TripContext`): one
/// that has cleared other tables, and planned trips of this one, plans a run and a trip exactly as a
/// fresh one does, for every policy.
#[test]
fn a_used_policy_plans_as_a_fresh_one() {
    use pushmog::policy::TripContext;
    for kind in PolicyKind::ALL {
        let used = Policy::new(kind, PolicySettings::default()).unwrap();
        let mut executor = used.ideal();
        used.run(&scene(1), &mut executor, 1).unwrap();
        let table = scene(3);
        // The table less the first trip's grasp, as the next trip finds it.
        let first = used.plan_trip(&table).unwrap().into_trip().unwrap();
        let later = table.without(&first.grasp.objects);
        used.plan_trip(&table).unwrap();
        let fresh = Policy::new(kind, PolicySettings::default()).unwrap();
        let trip = |policy: &Policy| {
            let mut context = TripContext::new(5);
            policy.plan_trip_with(&later, &mut context).unwrap().trip
        };
        assert_eq!(trip(&used), trip(&fresh), "{kind}");
        let whole = |policy: &Policy| {
            let mut executor = policy.ideal();
            policy.run(&table, &mut executor, 3).unwrap()
        };
        assert_eq!(whole(&used), whole(&fresh), "{kind}");
    }
}

/// A grasp planner of one's own plugs into push-mog-opt through the builder, and the policy grasps
/// only through it: one that hands on the built-in planner's answers plans exactly as the preset
/// does, asked only for two or more objects; one that never answers leaves single-object grasps
/// alone, and the table is still cleared by a plan the verifier accepts.
#[test]
fn a_grasp_planner_of_ones_own_plugs_into_push_mog_opt() {
    use pushmog::grasp::{Grasp, GraspPlanner, GraspRequest, MultiObject};
    use pushmog::outcome::{Outcome, Status};
    use std::sync::atomic::{AtomicUsize, Ordering};
    #[derive(Debug, Default)]
    struct Counting {
        inner: MultiObject,
        asked: AtomicUsize,
        refuse: bool,
    }
    impl GraspPlanner for Counting {
        fn name(&self) -> &'static str {
            "counting"
        }
        fn plan_request(
            &self,
            request: &GraspRequest<'_>,
        ) -> pushmog::Result<Outcome<Option<Grasp>>> {
            assert_eq!(request.min_objects, 2, "asked for one object");
            self.asked.fetch_add(1, Ordering::Relaxed);
            let mut answer = self.inner.plan_request(request)?;
            if self.refuse {
                answer.value = None;
                answer.status = Status::Failed {
                    reason: "refuses".to_string(),
                };
            }
            Ok(answer)
        }
    }
    let table = scene(2);
    let preset = Policy::new(PolicyKind::PushMogOpt, PolicySettings::default()).unwrap();
    let expected = preset.run(&table, &mut preset.ideal(), 2).unwrap();
    for refuse in [false, true] {
        let counting = std::sync::Arc::new(Counting {
            refuse,
            ..Counting::default()
        });
        #[derive(Debug)]
        struct Shared(std::sync::Arc<Counting>);
        impl GraspPlanner for Shared {
            fn name(&self) -> &'static str {
                self.0.name()
            }
            fn plan_request(
                &self,
                request: &GraspRequest<'_>,
            ) -> pushmog::Result<Outcome<Option<Grasp>>> {
                self.0.plan_request(request)
            }
        }
        let policy = Policy::builder(PolicyKind::PushMogOpt)
            .multi_object_planner(Shared(counting.clone()))
            .build()
            .unwrap();
        let plan = policy.run(&table, &mut policy.ideal(), 2).unwrap();
        assert!(counting.asked.load(Ordering::Relaxed) > 0);
        assert!(verify(&plan).is_empty(), "{:?}", verify(&plan));
        assert_eq!(plan.status, RunStatus::Cleared);
        if refuse {
            assert!(plan.trips.iter().all(|t| t.carried.len() == 1));
        } else {
            assert_eq!(plan, expected);
        }
    }
}

/// Two 7 × 50 mm bars stranded 2 mm apart and 1.5° off parallel (what pushing thin bars together can
/// leave): too close for a plate between them, and a row the grasp model may refuse. Every policy
/// that may grasp several objects clears them, with plans applied exactly and in the simulator; no
/// policy repeats a failed grasp (`sog` cannot take either bar alone, and stops saying why).
#[test]
fn stranded_bars_are_cleared_without_identical_retries() {
    use nalgebra::Point2;
    use pushmog::exec::{Executor, Sim, SimSettings};
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
    for kind in PolicyKind::ALL {
        let policy = Policy::new(kind, PolicySettings::default()).unwrap();
        let mut ideal = policy.ideal();
        let mut sim = Sim::new(SimSettings::default(), 3).unwrap();
        for executor in [&mut ideal as &mut dyn Executor, &mut sim] {
            let plan = policy.run(&scene, executor, 1).unwrap();
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
}

/// A triangle and a truncated rectangle that the paper's pushes left touching (seed 130, after a
/// push of 40 mm): no plate fits between them, so neither can be taken by itself, and the grasp
/// model refuses them together. The pushing policies clear the table, with plans applied exactly and
/// in the simulator; applied exactly, they first push one of them clear with the jaws closed. `sog`
/// and `mog`, which do not push, stop there when plans are applied exactly.
#[test]
fn objects_stuck_together_are_pushed_apart() {
    use nalgebra::Point2;
    use pushmog::exec::{Executor, Sim, SimSettings};
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
    for kind in PolicyKind::ALL {
        let policy = Policy::new(kind, PolicySettings::default()).unwrap();
        let mut ideal = policy.ideal();
        let mut sim = Sim::new(SimSettings::default(), 3).unwrap();
        for executor in [&mut ideal as &mut dyn Executor, &mut sim] {
            let plan = policy.run(&scene, executor, 1).unwrap();
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
}

/// A robot stack that owns its loop: it asks `plan_trip_with` for each trip, carries it out its own
/// way (pushes exactly, grasps as the grasp model says), and its camera sees the table again with
/// 1 mm and 0.6° of noise. The table is cleared, and every trip it was given verifies.
#[test]
fn an_outside_robot_clears_a_perturbed_table_one_trip_at_a_time() {
    use pushmog::exec::Executor;
    use pushmog::plan::{Trip, verify_trip};
    use pushmog::policy::TripContext;
    use pushmog::random::SeededRng;
    use pushmog::scene::perturb;
    let policy = Policy::new(PolicyKind::PushMogOpt, PolicySettings::default()).unwrap();
    let mut table = scene(3);
    let mut context = TripContext::new(5);
    let mut camera = SeededRng::new(9);
    let mut trips = 0;
    while !table.is_empty() {
        assert!(trips < 100, "the loop does not end");
        let trip = policy
            .plan_trip_with(&table, &mut context)
            .unwrap()
            .trip
            .expect("a trip for a non-empty table");
        let mut robot = policy.ideal();
        robot.reset(&table).unwrap();
        for push in &trip.pushes {
            robot.push(push).unwrap();
        }
        let carried = robot.grasp(&trip.grasp).unwrap().carried;
        if carried.is_empty() {
            context.failed.push(trip.grasp.jaws);
        }
        let record = Trip {
            scene: table.to_spec().into(),
            plan: trip,
            looks: Vec::new(),
            carried,
            fault: None,
            lost: Vec::new(),
        };
        assert!(
            verify_trip(&record).is_empty(),
            "{:?}",
            verify_trip(&record)
        );
        table = perturb(&robot.observe().unwrap(), &mut camera, 0.001, 0.01).unwrap();
        trips += 1;
    }
    println!("cleared in {trips} trips");
}

/// Hand-made inconsistent records are each refused by the verifier, though every trip on its own is
/// sound: trips removed, reordered, carried objects changed, duplicated or invented, impossible times
/// and statuses that do not add up.
#[test]
fn inconsistent_records_are_refused() {
    use pushmog::plan::{RunStatus, StopReason, verify};
    use pushmog::scene::{ObjectId, ObjectSpec};
    let plan = run(PolicyKind::PushMog, &scene(4), 4);
    assert!(verify(&plan).is_empty());
    assert!(plan.trips.len() > 3);
    let multi = plan
        .trips
        .iter()
        .position(|t| t.carried.len() >= 2)
        .expect("a multi-object trip");
    let mut broken: Vec<(&str, Plan)> = Vec::new();
    let mut p = plan.clone();
    p.trips.pop();
    broken.push(("last trip removed, still cleared", p));
    let mut p = plan.clone();
    p.trips.remove(1);
    broken.push(("a middle trip removed", p));
    let mut p = plan.clone();
    p.trips.swap(1, 2);
    broken.push(("two trips swapped", p));
    let mut p = plan.clone();
    p.trips[multi].carried.pop();
    broken.push(("carried less than the grasp claims", p));
    let mut p = plan.clone();
    let other = p.trips[0].carried[0];
    p.trips[1].carried.push(other);
    broken.push(("an object carried twice", p));
    let mut p = plan.clone();
    p.trips[0].carried.push(ObjectId(9999));
    broken.push(("an invented object carried", p));
    let mut p = plan.clone();
    p.seconds = -1.0;
    broken.push(("negative time", p));
    let mut p = plan.clone();
    p.seconds = f64::NAN;
    broken.push(("no time at all", p));
    let mut p = plan.clone();
    p.status = RunStatus::Stopped {
        remaining: vec![plan.trips[0].carried[0]],
        reason: StopReason::AllTooWide,
    };
    broken.push(("a carried object said to be left", p));
    let mut p = plan.clone();
    p.trips.pop();
    p.status = RunStatus::Stopped {
        remaining: Vec::new(),
        reason: StopReason::TripLimit { limit: 1 },
    };
    broken.push(("objects left unaccounted for", p));
    let mut p = plan.clone();
    let back = p.trips[0].scene.objects[0].clone();
    let carried_first = p.trips[0].carried.contains(&back.id);
    if carried_first {
        p.trips[2].scene.objects.push(back);
    } else {
        p.trips[2].scene.objects.retain(|o| o.id != back.id);
    }
    broken.push(("a table that does not follow from the last", p));
    // Looks: an ideal run looks again after every trip that pushed.
    let looked = plan
        .trips
        .iter()
        .position(|t| !t.looks.is_empty())
        .expect("a trip that looked again after its pushes");
    let mut p = plan.clone();
    std::sync::Arc::make_mut(&mut p.trips[looked].looks[0].scene.objects[0])
        .pose
        .x += 0.01;
    broken.push(("a look that is not the table after the pushes", p));
    let mut p = plan.clone();
    p.trips[looked].looks[0].after_pushes = p.trips[looked].plan.pushes.len() + 1;
    broken.push(("a look after pushes the trip does not have", p));
    let mut p = plan.clone();
    let mut stranger = ObjectSpec::clone(&p.trips[looked].scene.objects[0]);
    stranger.id = ObjectId(9999);
    stranger.pose.x += 1.0;
    p.trips[looked].looks[0].scene.objects.push(stranger.into());
    broken.push((
        "a look that sees an object the trip's table did not hold",
        p,
    ));
    let mut p = plan.clone();
    p.trips[looked].looks[0].scene.objects.clear();
    broken.push(("a look on which the grasped objects are missing", p));
    for (what, p) in &broken {
        assert!(!verify(p).is_empty(), "{what}: accepted");
    }
}

/// Plans are held and written compactly, and read back exactly:
/// - a single-object plan of 1000 objects stays small on file (it took 178 MB with a whole scene per
///   trip);
/// - in memory, an object no trip moved is one object shared by every trip's scene (a whole copy per
///   trip took 5.7 GB for 5000 objects), in the run's record and in a plan read back;
/// - `Plan::to_json`, which writes trip by trip, writes exactly what the general writer writes;
/// - for the ideal executor and for physics, with looks during trips.
#[test]
fn plan_files_are_compact_and_read_back_exactly() {
    let settings = GeneratorSettings {
        objects: 1000,
        workspace: pushmog::scene::Workspace::new(3.25, 2.44),
        ..GeneratorSettings::default()
    };
    let scene = generate_scene(&settings, &builtin_object_set(), 1).unwrap();
    let plan = run(PolicyKind::Sog, &scene, 1);
    let text = plan.to_json();
    assert!(text == pushmog::json::to_json(&plan));
    assert!(text.len() < 20_000_000, "{} bytes", text.len());
    let back: Plan = pushmog::json::from_json(&text, "plan").unwrap();
    assert!(back == plan);
    for plan in [&plan, &back] {
        let (first, last) = (
            &plan.trips[0].scene,
            &plan.trips[plan.trips.len() - 1].scene,
        );
        let shared = last.objects[0].clone();
        let in_first = first.objects.iter().find(|o| o.id == shared.id).unwrap();
        assert!(std::sync::Arc::ptr_eq(in_first, &shared));
    }

    let small = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 4).unwrap();
    let policy = Policy::new(PolicyKind::PushMog, PolicySettings::default()).unwrap();
    let mut sim = pushmog::exec::Sim::new(pushmog::exec::SimSettings::default(), 4).unwrap();
    let plan = policy.run(&small, &mut sim, 4).unwrap();
    let text = plan.to_json();
    assert!(text == pushmog::json::to_json(&plan));
    let back: Plan = pushmog::json::from_json(&text, "plan").unwrap();
    assert!(back == plan);
    assert!(text.contains("scene_change"));
    assert!(plan.trips.iter().any(|t| !t.looks.is_empty()));
}

/// Each trip records the push planner's status for each answer whose pushes it made: the SOCP's
/// `best_found` for push-mog-opt (or `heuristic` for a push that only separates two objects), the
/// paper's `heuristic` for push-mog, nothing for a trip without pushes. The statuses survive the
/// plan file, and the run's counts add them up; a plan written before they were recorded reads
/// with none.
#[test]
fn each_trip_records_the_status_of_the_pushes_it_made() {
    for (kind, allowed) in [
        (PolicyKind::PushMogOpt, &["best_found", "heuristic"][..]),
        (PolicyKind::PushMog, &["heuristic"][..]),
    ] {
        let plan = run(kind, &scene(3), 4);
        assert!(plan.trips.iter().any(|t| !t.plan.pushes.is_empty()));
        for trip in &plan.trips {
            assert_eq!(
                trip.plan.pushes.is_empty(),
                trip.plan.push_statuses.is_empty()
            );
            assert!(trip.plan.push_statuses.len() <= trip.plan.pushes.len());
            for status in &trip.plan.push_statuses {
                assert!(allowed.contains(&status.name()), "{kind:?}: {status:?}");
            }
        }
        let counts = plan.push_statuses();
        assert!(counts.get(allowed[0]).is_some_and(|&n| n > 0));
        let total: usize = plan.trips.iter().map(|t| t.plan.push_statuses.len()).sum();
        assert_eq!(counts.values().sum::<usize>(), total);
        let text = plan.to_json();
        let back: Plan = pushmog::json::from_json(&text, "plan").unwrap();
        assert!(back == plan);
        let mut old: serde_json::Value = serde_json::from_str(&text).unwrap();
        for trip in old["trips"].as_array_mut().unwrap() {
            trip.as_object_mut().unwrap().remove("push_statuses");
        }
        let old: Plan = serde_json::from_value(old).unwrap();
        assert!(old.push_statuses().is_empty());
        assert_eq!(old.trips.len(), plan.trips.len());
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

/// A test executor: the ideal executor, whose grasps go through `hook`.
struct Rigged<H> {
    table: pushmog::exec::Ideal,
    hook: H,
}

/// What a [`Rigged`] executor does in place of the ideal executor's grasp, and what it reports lost.
trait GraspHook {
    fn grasp(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult>;
    fn lost(&self) -> Vec<(pushmog::scene::ObjectId, &'static str)> {
        Vec::new()
    }
}

impl<H: GraspHook> pushmog::exec::Executor for Rigged<H> {
    fn name(&self) -> &'static str {
        "rigged"
    }
    fn reset(&mut self, scene: &Scene) -> pushmog::Result<()> {
        self.table.reset(scene)
    }
    fn push(
        &mut self,
        push: &pushmog::push::Push,
    ) -> pushmog::Result<Option<pushmog::exec::Landing>> {
        self.table.push(push)
    }
    fn grasp(
        &mut self,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult> {
        self.hook.grasp(&mut self.table, grasp)
    }
    fn observe(&mut self) -> pushmog::Result<Scene> {
        self.table.observe()
    }
    fn lost(&self) -> Vec<(pushmog::scene::ObjectId, &'static str)> {
        self.hook.lost()
    }
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
    fn lost(&self) -> Vec<(pushmog::scene::ObjectId, &'static str)> {
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

/// Four 7 × 50 mm bars side by side, 28 mm apart and a few degrees and millimetres off a row: they
/// span 91 mm, more than the jaws take, and their centroids lie within the MILP's cluster diameter.
/// The optimal clustering makes them one cluster (its size is bounded by what fits the jaws, not by
/// a count), and one trip carries all four: with plans applied exactly for the policies that push,
/// and in the simulator for push-mog-milp (the paper's pushes, which end each bar against its
/// neighbour), over several run seeds.
#[test]
fn four_bars_are_pushed_into_one_row_and_taken_in_one_trip() {
    use pushmog::exec::{Sim, SimSettings};
    use pushmog::geometry::ConvexPolygon;
    use pushmog::scene::{Gripper, Object, ObjectId, Pose, Workspace};
    let bar = ConvexPolygon::rectangle(
        &nalgebra::Point2::origin(),
        &nalgebra::Vector2::x(),
        0.0035,
        0.025,
    );
    let objects = [
        (0.10, 0.15, 0.0),
        (0.128, 0.158, 0.05),
        (0.156, 0.144, -0.03),
        (0.184, 0.153, 0.02),
    ]
    .iter()
    .enumerate()
    .map(|(k, &(x, y, yaw))| Object {
        id: ObjectId(k as u32),
        name: Some("bar-7x50".to_string()),
        polygon: bar.clone(),
        pose: Pose::new(x, y, yaw),
        height: 0.03,
        mass: None,
    })
    .collect();
    let scene = Scene::from_parts(Workspace::new(0.3, 0.3), Gripper::default(), objects).unwrap();
    let one_trip_of_four = |plan: &Plan| {
        assert!(verify(plan).is_empty(), "{:?}", verify(plan));
        plan.status == RunStatus::Cleared && plan.trips.iter().any(|t| t.carried.len() == 4)
    };
    for kind in [
        PolicyKind::PushMog,
        PolicyKind::PushMogMilp,
        PolicyKind::PushMogSocp,
        PolicyKind::PushMogOpt,
    ] {
        let policy = Policy::new(kind, PolicySettings::default()).unwrap();
        let plan = policy.run(&scene, &mut policy.ideal(), 1).unwrap();
        assert!(one_trip_of_four(&plan), "{kind}, plans applied exactly");
    }
    let policy = Policy::new(PolicyKind::PushMogMilp, PolicySettings::default()).unwrap();
    for seed in 1..=4 {
        let mut sim = Sim::new(SimSettings::default(), seed).unwrap();
        let plan = policy.run(&scene, &mut sim, seed).unwrap();
        assert!(
            one_trip_of_four(&plan),
            "push-mog-milp, simulated, seed {seed}"
        );
    }
}

/// The expected-time price against the same scene: with a far bin and grasps after pushes that always
/// carry everything, pushing saves whole trips and the policy pushes; when they never carry
/// everything, no push can pay and none is made (each skipped as not paying). Plans verify, and the
/// objects-per-trip objective pushes as it always did.
#[test]
fn the_expected_time_price_pushes_only_when_it_pays() {
    use pushmog::policy::{Pricing, SuccessBand, TripObjective};
    use pushmog::push::SkipReason;
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 3).unwrap();
    let run = |carried_all: f64, bin_distance: f64, objective: TripObjective| {
        let mut settings = PolicySettings::default();
        settings.time_model.bin_distance = bin_distance;
        let bands = vec![SuccessBand {
            judged: 0.0,
            carried_all,
        }];
        settings.pricing = Pricing {
            objective,
            success: bands.clone(),
            ahead_success: bands,
            corrections: 0.0,
            push_ahead: false,
            ahead_rows: 1,
        };
        let policy = Policy::new(PolicyKind::PushMogOpt, settings).unwrap();
        let plan = policy.run(&scene, &mut policy.ideal(), 3).unwrap();
        assert!(verify(&plan).is_empty(), "{:?}", verify(&plan));
        assert!(matches!(plan.status, RunStatus::Cleared));
        plan
    };
    let not_paying = |plan: &Plan| {
        plan.trips
            .iter()
            .flat_map(|t| &t.plan.skipped_pushes)
            .filter(|s| matches!(s.reason, SkipReason::DoesNotPay { saving } if saving <= 0.0))
            .count()
    };
    let never = run(0.0, 0.3, TripObjective::ExpectedTime);
    assert_eq!(never.push_count(), 0);
    assert!(
        not_paying(&never) > 0,
        "some pushes were planned and priced"
    );
    let far = run(1.0, 4.0, TripObjective::ExpectedTime);
    assert!(far.push_count() > 0);
    assert!(
        far.trips
            .iter()
            .any(|t| !t.plan.pushes.is_empty() && t.plan.judged.is_some())
    );
    let paper = run(0.0, 0.3, TripObjective::ObjectsPerTrip);
    assert!(paper.push_count() > 0);
    assert_eq!(not_paying(&paper), 0);
}

/// Pushing ahead: a trip's pushes prepare rows for later trips and never move what the trip's own
/// grasp takes; such a trip makes no look of its own (the next trip's look shows the rows), each row
/// pushed ahead is carried together by a later trip, and every plan verifies. With one row a trip
/// (`ahead_rows` 1) each trip pushes one cluster; with the default, some trip pushes several, and
/// only when no row pushed before still waits. With grasps after pushes that never carry
/// everything, nothing is pushed ahead.
#[test]
fn rows_pushed_ahead_are_taken_by_a_later_trip_without_a_look_of_their_own() {
    use pushmog::policy::{Pricing, SuccessBand, TripObjective};
    let run = |scene: &Scene, carried_all: f64, ahead_rows: usize| {
        let bands = vec![SuccessBand {
            judged: 0.0,
            carried_all,
        }];
        let settings = PolicySettings {
            pricing: Pricing {
                objective: TripObjective::ExpectedTime,
                success: bands.clone(),
                ahead_success: bands,
                push_ahead: true,
                ahead_rows,
                ..Pricing::default()
            },
            ..PolicySettings::default()
        };
        let policy = Policy::new(PolicyKind::PushMogOpt, settings).unwrap();
        let plan = policy.run(scene, &mut policy.ideal(), 5).unwrap();
        assert!(verify(&plan).is_empty(), "{:?}", verify(&plan));
        assert!(matches!(plan.status, RunStatus::Cleared));
        plan
    };
    let (mut rows, mut taken_later, mut batched) = (0, 0, 0);
    for (seed, ahead_rows) in [(5, 1), (6, 1), (5, 12), (6, 12)] {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        let plan = run(&scene, 1.0, ahead_rows);
        for (k, trip) in plan.trips.iter().enumerate() {
            if trip.plan.pushes.is_empty() {
                continue;
            }
            assert!(
                trip.plan
                    .pushes
                    .iter()
                    .all(|p| !trip.plan.grasp.objects.contains(&p.object))
            );
            assert!(trip.looks.is_empty());
            // The rows: the trip's clusters holding objects it pushed ahead.
            let trip_rows: Vec<Vec<_>> = trip
                .plan
                .clustering
                .clusters
                .iter()
                .map(|c| {
                    c.iter()
                        .copied()
                        .filter(|id| trip.plan.ahead.contains(id))
                        .collect()
                })
                .filter(|row: &Vec<_>| !row.is_empty())
                .collect();
            assert!(trip_rows.len() <= ahead_rows, "{trip_rows:?}");
            batched += usize::from(trip_rows.len() >= 2);
            // No row pushed before was still waiting: every object pushed ahead earlier has been
            // grasped (or pushed again) by now.
            let earlier: Vec<_> = plan.trips[..k]
                .iter()
                .flat_map(|t| t.plan.ahead.clone())
                .collect();
            assert!(earlier.iter().all(|id| {
                plan.trips[..=k]
                    .iter()
                    .any(|t| t.plan.grasp.objects.contains(id))
                    || !trip.scene.ids().any(|s| s == *id)
                    || trip.plan.pushes.iter().any(|p| p.object == *id)
            }));
            let later = &plan.trips[k + 1..];
            for row in &trip_rows {
                rows += 1;
                if later
                    .iter()
                    .any(|t| row.len() >= 2 && row.iter().all(|id| t.carried.contains(id)))
                {
                    taken_later += 1;
                }
            }
        }
        assert_eq!(run(&scene, 0.0, ahead_rows).push_count(), 0);
    }
    assert!(rows >= 8, "{rows} rows pushed ahead");
    assert!(batched >= 1, "no trip pushed two rows or more");
    // Plans applied exactly: the rows come out as planned and are taken together.
    assert_eq!(taken_later, rows);
}

/// No trip, and why, typed: an empty table; a table whose every object is wider than the jaw gap
/// (a cluster of them for the clustering policies). The closed loop does not ask on such a table:
/// it stops at once, every object too wide.
#[test]
fn no_trip_says_why_typed() {
    use crate::support::boxes;
    use pushmog::plan::StopReason;
    use pushmog::policy::NoTrip;
    let empty = boxes(0.05, 0.05, &[]);
    let wide = boxes(0.12, 0.12, &[(0.1, 0.1), (0.3, 0.25)]);
    assert!((0..wide.len()).all(|i| !wide.is_graspable(i)));
    for kind in PolicyKind::ALL {
        let policy = Policy::new(kind, PolicySettings::default()).unwrap();
        let none = policy.plan_trip(&empty).unwrap();
        assert_eq!(none.trip, Err(NoTrip::EmptyTable), "{kind}");
        let why = policy.plan_trip(&wide).unwrap().trip.unwrap_err();
        let expected = match kind {
            PolicyKind::Sog => NoTrip::NothingFitsTheJaws,
            _ => NoTrip::NoClusterFitsTheJaws,
        };
        assert_eq!(why, expected, "{kind}");
        let plan = run(kind, &wide, 1);
        assert!(
            matches!(
                plan.status,
                RunStatus::Stopped {
                    reason: StopReason::AllTooWide,
                    ..
                }
            ),
            "{kind}"
        );
        assert!(plan.failed_attempts.is_empty(), "{kind}");
    }
}

/// Riders with plans applied exactly: push-mog-opt with riders puts riders on rows, every plan
/// verifies (each rider picked clear of its neighbours, let go where its jaws carried it, standing
/// on the row's top clear of the pads), every rider rides, and the same scenes need fewer trips
/// than without riders.
#[test]
fn riders_ride_on_rows_and_save_trips() {
    use crate::support::with_riders;
    let riders = Policy::new(PolicyKind::PushMogOpt, with_riders()).unwrap();
    let plain = Policy::new(PolicyKind::PushMogOpt, PolicySettings::default()).unwrap();
    let (mut trips_with, mut trips_without, mut placed) = (0, 0, 0);
    for seed in 1..=3 {
        let table = scene(seed);
        let plan = riders.run(&table, &mut riders.ideal(), seed).unwrap();
        assert!(verify(&plan).is_empty(), "seed {seed}: {:?}", verify(&plan));
        assert!(matches!(plan.status, RunStatus::Cleared), "seed {seed}");
        assert_eq!(plan.riders_lost(), 0, "seed {seed}");
        placed += plan.riders_placed();
        trips_with += plan.trips.len();
        trips_without += plain
            .run(&table, &mut plain.ideal(), seed)
            .unwrap()
            .trips
            .len();
    }
    assert!(placed > 0);
    assert!(
        trips_with < trips_without,
        "{trips_with} against {trips_without}"
    );
}

/// Riders go only on rows whose members' centroids lie within the plates' length of their centre
/// line, inset by the support margin (`formulations/stacking.md`, "Rows held off their centre"):
/// checked on the table the riders were chosen on, the last look's after the pushes that follow it.
#[test]
fn riders_go_only_on_rows_held_near_the_plates_centre_line() {
    use pushmog::grasp::centre_line_offset;
    use pushmog::push::predict;
    let settings = crate::support::with_riders();
    let margin = settings.riders.checks.support_margin;
    let policy = Policy::new(PolicyKind::PushMogOpt, settings).unwrap();
    let mut placed = 0;
    for seed in 1..=3 {
        let table = scene(seed);
        let within = 0.5 * table.gripper().plate_length - margin;
        let plan = policy.run(&table, &mut policy.ideal(), seed).unwrap();
        assert!(verify(&plan).is_empty(), "seed {seed}: {:?}", verify(&plan));
        for trip in plan.trips.iter().filter(|t| !t.plan.riders.is_empty()) {
            let (seen, start) = trip.last_plan_scene();
            let seen = Scene::new(seen.to_spec()).unwrap();
            let predicted = predict(&seen, &trip.plan.pushes[start..]).unwrap();
            let grasp = &trip.plan.grasp;
            let members = predicted.indices_of(&grasp.objects).unwrap();
            let offset = centre_line_offset(&predicted, &grasp.jaws, &members);
            assert!(
                offset <= within,
                "seed {seed}: {offset} m off the centre line"
            );
            placed += trip.plan.riders.len();
        }
    }
    assert!(placed > 0);
}

/// Riders priced in robot time (`formulations/stacking.md`, "Riders priced"): under the
/// expected-time objective each rider placed saves, by the time model, more than its place action
/// adds to its trip; a rider that never rides (`carried = 0`) is never placed; a far bin, where a
/// saved trip is dear, takes riders, and every plan verifies.
#[test]
fn riders_are_placed_only_where_they_pay() {
    use pushmog::policy::{TripObjective, grasp_path, push_paths, rider_paths};
    let priced = |bin: f64, carried: f64| {
        let mut settings = crate::support::with_riders();
        settings.pricing.objective = TripObjective::ExpectedTime;
        settings.riders.carried = carried;
        settings.time_model.bin_distance = bin;
        Policy::new(PolicyKind::PushMogOpt, settings).unwrap()
    };
    let mut placed_far = 0;
    for seed in 1..=2 {
        let table = scene(seed);
        let never = priced(0.3, 0.0);
        let plan = never.run(&table, &mut never.ideal(), seed).unwrap();
        assert!(verify(&plan).is_empty(), "seed {seed}: {:?}", verify(&plan));
        assert_eq!(plan.riders_placed(), 0, "seed {seed}");
        for bin in [0.3, 4.0] {
            let policy = priced(bin, 0.967);
            let plan = policy.run(&table, &mut policy.ideal(), seed).unwrap();
            assert!(verify(&plan).is_empty(), "seed {seed}: {:?}", verify(&plan));
            let model = policy.problem().time_model();
            let gripper = table.gripper();
            let single = model.nominal_trip_seconds(gripper) + model.look_seconds();
            for trip in plan.trips.iter().filter(|t| !t.plan.riders.is_empty()) {
                // The riders were chosen on the last look, with the pushes planned on it.
                let start = trip.last_plan_scene().1;
                let pushes = push_paths(&trip.plan.pushes[start..]);
                let grasp = grasp_path(&trip.plan.grasp, gripper);
                let riders = rider_paths(&trip.plan.riders, gripper);
                let placing = model.trip_seconds_with_riders(gripper, &pushes, &riders, &grasp)
                    - model.trip_seconds(gripper, &pushes, &grasp);
                assert!(
                    0.967 * single > placing,
                    "seed {seed}, bin {bin}: {placing} s"
                );
            }
            if bin > 1.0 {
                placed_far += plan.riders_placed();
            }
        }
    }
    assert!(placed_far > 0);
}

/// The verifier refuses a rider put where it cannot stand, one the trip also grasps, and one let go
/// where its jaws did not carry it.
#[test]
fn the_verifier_refuses_riders_that_cannot_ride() {
    use crate::support::with_riders;
    use pushmog::plan::verify_trip;
    let policy = Policy::new(PolicyKind::PushMogOpt, with_riders()).unwrap();
    let plan = policy.run(&scene(1), &mut policy.ideal(), 1).unwrap();
    let trip = plan
        .trips
        .iter()
        .find(|t| !t.plan.riders.is_empty())
        .expect("a trip with a rider");
    assert!(verify_trip(trip).is_empty());
    let broken = |change: &dyn Fn(&mut pushmog::plan::Rider)| {
        let mut bad = trip.clone();
        change(&mut bad.plan.riders[0]);
        verify_trip(&bad)
    };
    let off_the_top = broken(&|r| r.place.y += 0.08);
    assert!(
        off_the_top.iter().any(|v| v.contains("not over the top")),
        "{off_the_top:?}"
    );
    let grasped = trip.plan.grasp.objects[0];
    let twice = broken(&|r| r.object = grasped);
    assert!(
        twice.iter().any(|v| v.contains("also grasped")),
        "{twice:?}"
    );
    let elsewhere = broken(&|r| r.release.center.x += 0.01);
    assert!(
        elsewhere.iter().any(|v| v.contains("not let go where")),
        "{elsewhere:?}"
    );
}
