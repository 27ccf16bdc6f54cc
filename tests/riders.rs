//! Riders (`formulations/stacking.md`): placed on rows where they pay and can ride, refused by the
//! verifier where they cannot.

use pushmog::plan::{RunStatus, verify};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::Scene;

use crate::support::scene;

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

/// Riders chosen by the clustering (`riders.in_clustering`, `formulations/stacking.md`, "Riders in
/// the clustering"), plans applied exactly: every plan verifies and clears its table, no trip takes
/// by itself an object its clustering put on a row, and the riders the trips place include ones
/// the clustering chose for that row; the verifier refuses rides that are not on the clustering's
/// own rows and singles.
#[test]
fn riders_chosen_by_the_clustering_ride_their_rows() {
    let mut settings = crate::support::with_riders();
    settings.riders.in_clustering = true;
    let policy = Policy::new(PolicyKind::PushMogOpt, settings).unwrap();
    let (mut named, mut honoured) = (0, 0);
    for seed in 1..=2 {
        let table = scene(seed);
        let plan = policy.run(&table, &mut policy.ideal(), seed).unwrap();
        assert!(verify(&plan).is_empty(), "seed {seed}: {:?}", verify(&plan));
        assert!(matches!(plan.status, RunStatus::Cleared), "seed {seed}");
        for trip in &plan.trips {
            let clustering = &trip.plan.clustering;
            let grasped = &trip.plan.grasp.objects;
            assert!(
                !(grasped.len() == 1 && clustering.is_rider(grasped[0])),
                "seed {seed}: a rider of the clustering taken by itself"
            );
            if let Some(rider) = clustering.rider_on(grasped) {
                named += 1;
                honoured += usize::from(trip.plan.riders.iter().any(|r| r.object == rider));
            }
        }
    }
    println!("{honoured} of {named} rows placed the rider their clustering chose");
    assert!(honoured > 0, "{honoured} of {named}");
    // The verifier refuses a ride whose rider is a member of a row, or whose row is no cluster.
    let table = scene(1);
    let trip = policy.plan_trip(&table).unwrap().trip.unwrap();
    let mut clustering = trip.clustering.clone();
    assert!(pushmog::plan::verify_clustering(&table, &clustering).is_empty());
    let ride = clustering.riders[0].clone();
    clustering.riders[0].rider = ride.row[0];
    assert!(!pushmog::plan::verify_clustering(&table, &clustering).is_empty());
    clustering.riders[0] = pushmog::cluster::Ride {
        row: vec![ride.rider, ride.row[0]],
        ..ride
    };
    assert!(!pushmog::plan::verify_clustering(&table, &clustering).is_empty());
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

/// Fails the first grasp made with a rider aboard (one the ideal executor holds put down) as a
/// descent onto one of the row's members would: nothing lifted, the rider left standing on its
/// row. Everything else is applied exactly.
struct FirstRowLands {
    landed: bool,
}

impl crate::support::GraspHook for FirstRowLands {
    fn grasp(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult> {
        use pushmog::exec::Executor;
        if !self.landed && !table.lost().is_empty() {
            self.landed = true;
            return Ok(pushmog::exec::GraspResult {
                carried: Vec::new(),
                landing: Some(pushmog::exec::Landing {
                    object: grasp.objects[0],
                }),
            });
        }
        table.grasp(grasp)
    }
}

/// A rider left standing on its row after the row's grasp came down on a member is known to the
/// run (`formulations/stacking.md`, "Riders left standing"): the next trip grasps that row again as
/// it lies, taking every object the rider rests on, with no push, no new rider and both plates
/// clear of where the rider was put down, and carries the rider with it; the run clears and every
/// plan verifies.
#[test]
fn a_rider_left_standing_goes_with_its_row_grasped_again() {
    use pushmog::exec::RIDER_LEFT;
    let policy = Policy::new(PolicyKind::PushMogOpt, crate::support::with_riders()).unwrap();
    for seed in 1..=2 {
        let table = scene(seed);
        let mut executor = crate::support::Rigged {
            table: policy.ideal(),
            hook: FirstRowLands { landed: false },
        };
        let plan = policy.run(&table, &mut executor, seed).unwrap();
        assert!(executor.hook.landed, "seed {seed}: no rider was placed");
        assert!(verify(&plan).is_empty(), "seed {seed}: {:?}", verify(&plan));
        assert!(matches!(plan.status, RunStatus::Cleared), "seed {seed}");
        let k = plan
            .trips
            .iter()
            .position(|t| t.carried.is_empty())
            .unwrap();
        let (failed, again) = (&plan.trips[k], &plan.trips[k + 1]);
        let rider = &failed.plan.riders[0];
        assert!(
            failed
                .lost
                .iter()
                .any(|l| l.object == rider.object && l.reason == RIDER_LEFT),
            "seed {seed}: {:?}",
            failed.lost
        );
        assert!(again.plan.pushes.is_empty() && again.plan.riders.is_empty());
        assert!(
            rider
                .on
                .iter()
                .all(|id| again.plan.grasp.objects.contains(id)),
            "seed {seed}"
        );
        assert!(again.carried.contains(&rider.object), "seed {seed}");
        let before = Scene::new(failed.scene.to_spec()).unwrap();
        let footprint = before.objects()[before.index_of(rider.object).unwrap()]
            .polygon
            .transformed(&rider.place.isometry());
        for plate in again.plan.grasp.jaws.plates(before.gripper()) {
            assert!(
                pushmog::geometry::distance(&plate, &footprint)
                    >= policy.settings().riders.checks.support_margin
            );
        }
    }
}

/// Drops the first rider a grasp carries: the row goes to the bin whole and the rider falls back
/// onto the table where it was put down (the row has gone from under it).
struct FirstRiderFalls {
    table: Scene,
    placed: Vec<pushmog::plan::Rider>,
    fell: Option<pushmog::scene::ObjectId>,
}

impl crate::support::GraspHook for FirstRiderFalls {
    fn grasp(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult> {
        use pushmog::exec::Executor;
        let mut result = table.grasp(grasp)?;
        if self.fell.is_some() {
            return Ok(result);
        }
        let Some(rider) = self
            .placed
            .iter()
            .find(|r| result.carried.contains(&r.object))
            .cloned()
        else {
            return Ok(result);
        };
        self.fell = Some(rider.object);
        result.carried.retain(|&id| id != rider.object);
        let seen = table.observe()?;
        let mut objects = seen.objects().to_vec();
        let mut fallen = self.table.objects()[self.table.index_of(rider.object).unwrap()].clone();
        fallen.pose = rider.place;
        objects.push(fallen);
        table.reset(&seen.with_objects(objects)?)?;
        Ok(result)
    }

    fn place(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        rider: &pushmog::plan::Rider,
    ) -> pushmog::Result<Option<pushmog::exec::Landing>> {
        use pushmog::exec::Executor;
        self.placed.push(rider.clone());
        table.place(rider)
    }
}

/// A rider that stays behind while the row it rode on goes to the bin whole fell off a row held in
/// the jaws (`formulations/stacking.md`, "Riders that fell off"): it is not offered as a rider
/// again, the run still clears, taking it otherwise, and every plan verifies.
#[test]
fn a_rider_that_fell_off_a_row_carried_whole_does_not_ride_again() {
    let policy = Policy::new(PolicyKind::PushMogOpt, crate::support::with_riders()).unwrap();
    for seed in 1..=3 {
        let table = scene(seed);
        let mut executor = crate::support::Rigged {
            table: policy.ideal(),
            hook: FirstRiderFalls {
                table: table.clone(),
                placed: Vec::new(),
                fell: None,
            },
        };
        let plan = policy.run(&table, &mut executor, seed).unwrap();
        let fell = executor.hook.fell.unwrap();
        assert!(verify(&plan).is_empty(), "seed {seed}: {:?}", verify(&plan));
        assert!(matches!(plan.status, RunStatus::Cleared), "seed {seed}");
        let rides: Vec<usize> = (0..plan.trips.len())
            .filter(|&k| plan.trips[k].plan.riders.iter().any(|r| r.object == fell))
            .collect();
        assert_eq!(
            rides.len(),
            1,
            "seed {seed}: object {fell} rode in trips {rides:?}"
        );
        let k = rides[0];
        assert!(!plan.trips[k].carried.contains(&fell));
        assert!(
            plan.trips[k + 1..]
                .iter()
                .any(|t| t.carried.contains(&fell))
        );
        // Riders still ride after it: only the object that fell is passed over.
        assert!(
            plan.trips[k + 1..]
                .iter()
                .any(|t| !t.plan.riders.is_empty()),
            "seed {seed}"
        );
    }
}
