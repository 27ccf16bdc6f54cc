//! The expected-time price on built and generated tables: bars pushed into one row and taken in one
//! trip, pushes made only where they pay, rows pushed ahead and taken by a later trip.

use pushmog::plan::{Plan, RunStatus, verify};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::{GeneratorSettings, Scene, builtin_object_set, generate_scene};

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
