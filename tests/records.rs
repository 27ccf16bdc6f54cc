//! The plan file as a record: inconsistent records refused by the verifier, compact files read back
//! exactly, and the status of every push a trip made.

use pushmog::plan::Plan;
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};

use crate::support::{run, scene};

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
