//! The physics simulator: grasps that lift, grasps that cannot, pushes that land where planned.

use nalgebra::Point2;
use pushmog::exec::{Executor, FingerDrive, Sim, SimSettings};
use pushmog::geometry::ConvexPolygon;
use pushmog::grasp::{Grasp, GraspPlanner, JawPose, MultiObject, SingleObject};
use pushmog::push::{PushPlanner, TowardCentral};
use pushmog::scene::{Gripper, Object, ObjectId, Pose, Scene, Workspace};

fn polygon(points: &[(f64, f64)]) -> ConvexPolygon {
    ConvexPolygon::new(points.iter().map(|&(x, y)| Point2::new(x, y)).collect()).unwrap()
}

fn square(side: f64) -> ConvexPolygon {
    let h = side / 2.0;
    polygon(&[(-h, -h), (h, -h), (h, h), (-h, h)])
}

fn scene(objects: Vec<(ConvexPolygon, f64, f64, f64)>) -> Scene {
    let objects = objects
        .into_iter()
        .enumerate()
        .map(|(k, (outline, x, y, yaw))| Object {
            id: ObjectId(k as u32),
            name: None,
            polygon: outline,
            pose: Pose::new(x, y, yaw),
            height: 0.03,
            mass: None,
        })
        .collect();
    Scene::from_parts(Workspace::new(0.4, 0.3), Gripper::default(), objects).unwrap()
}

fn sim() -> Sim {
    Sim::new(SimSettings::noiseless(), 1).unwrap()
}

#[test]
fn a_single_object_grasp_lifts_the_object() {
    let s = scene(vec![(square(0.03), 0.2, 0.15, 0.3)]);
    let grasp = SingleObject::default()
        .plan(&s, &[ObjectId(0)])
        .unwrap()
        .value
        .unwrap();
    let mut sim = sim();
    sim.reset(&s).unwrap();
    assert_eq!(sim.grasp(&grasp).unwrap().carried, vec![ObjectId(0)]);
    assert!(sim.observe().unwrap().is_empty());
}

#[test]
fn two_cubes_side_by_side_are_lifted_together() {
    let s = scene(vec![
        (square(0.03), 0.2, 0.15, 0.0),
        (square(0.03), 0.2305, 0.15, 0.0),
    ]);
    let grasp = MultiObject::default()
        .plan(&s, &[ObjectId(0), ObjectId(1)])
        .unwrap()
        .value
        .unwrap();
    assert_eq!(grasp.objects.len(), 2);
    let mut sim = sim();
    sim.reset(&s).unwrap();
    let mut carried = sim.grasp(&grasp).unwrap().carried;
    carried.sort();
    assert_eq!(carried, vec![ObjectId(0), ObjectId(1)]);
}

/// The 2F-85 closes both fingers from one motor: a cube lying off the gripper's centre is met by one
/// finger first and pushed to the centre before the other finger arrives, then both hold it.
#[test]
fn a_finger_touching_first_pushes_a_cube_to_the_centre() {
    let s = scene(vec![(square(0.03), 0.2, 0.15, 0.0)]);
    let centre = Point2::new(0.215, 0.15);
    let grasp = Grasp {
        jaws: JawPose {
            center: centre,
            angle: 0.0,
            opening: 0.085,
        },
        objects: vec![ObjectId(0)],
        width: 0.03,
        margin: 0.0,
    };
    let mut sim = sim();
    sim.reset(&s).unwrap();
    // The cube is 15 mm left of the centre: the left plate face (at 0.1775 m) is 7.5 mm from it,
    // the right one (at 0.2525 m) 37.5 mm.
    let closing = sim.close_and_release(&grasp).unwrap();
    assert!(closing.landing.is_none());
    let cube = closing.poses[0].1;
    println!(
        "closed at {:.2} mm between plate centres; cube centre at x = {:.2} mm",
        closing.opening * 1e3,
        cube.x * 1e3
    );
    assert!(
        (cube.x - centre.x).abs() < 0.001 && (cube.y - centre.y).abs() < 0.001,
        "the cube should be held at the gripper's centre, not at {cube:?}"
    );
    assert!(
        (closing.opening - 0.04).abs() < 0.002,
        "{}",
        closing.opening
    );
    sim.reset(&s).unwrap();
    let result = sim.grasp(&grasp).unwrap();
    assert_eq!(result.carried, vec![ObjectId(0)]);
    assert!(result.landing.is_none());
}

/// A plate lowered onto an object's edge comes down on top of it: the grasp stops there, the object
/// is not carried (whatever physics did to it), and the landing is reported.
#[test]
fn a_plate_placed_on_an_edge_fails_the_grasp_without_carrying() {
    let s = scene(vec![(square(0.03), 0.2, 0.15, 0.0)]);
    // The right plate (10 mm thick) is centred on the cube's right edge at x = 0.215.
    let grasp = Grasp {
        jaws: JawPose {
            center: Point2::new(0.215 - 0.0425, 0.15),
            angle: 0.0,
            opening: 0.085,
        },
        objects: vec![ObjectId(0)],
        width: 0.03,
        margin: 0.0,
    };
    for drive in [FingerDrive::Coupled, FingerDrive::Independent] {
        let mut sim = Sim::new(
            SimSettings {
                fingers: drive,
                ..SimSettings::noiseless()
            },
            1,
        )
        .unwrap();
        sim.reset(&s).unwrap();
        let result = sim.grasp(&grasp).unwrap();
        assert!(result.carried.is_empty(), "{drive:?}: {result:?}");
        assert_eq!(
            result.landing.map(|l| l.object),
            Some(ObjectId(0)),
            "{drive:?}"
        );
        // Still on the table, as physics left it.
        assert_eq!(sim.observe().unwrap().len() + sim.lost().len(), 1);
    }
}

#[test]
fn an_empty_grasp_carries_nothing_and_leaves_the_table_alone() {
    let s = scene(vec![(square(0.03), 0.1, 0.1, 0.0)]);
    let grasp = Grasp {
        jaws: JawPose {
            center: Point2::new(0.3, 0.2),
            angle: 0.0,
            opening: 0.085,
        },
        objects: Vec::new(),
        width: 0.0,
        margin: 0.0,
    };
    let mut sim = sim();
    sim.reset(&s).unwrap();
    assert!(sim.grasp(&grasp).unwrap().carried.is_empty());
    let after = sim.observe().unwrap();
    assert!((after.objects()[0].pose.x - 0.1).abs() < 1e-4);
}

/// Three equal equilateral triangles (the paper's footnote): the grasp model never proposes all three
/// together; closing the jaws on all three in the simulator is reported for information.
#[test]
fn three_equilateral_triangles_are_never_attempted_together() {
    let side = 0.028;
    let h = side * 3f64.sqrt() / 2.0;
    let up = polygon(&[(0.0, 0.0), (side, 0.0), (side / 2.0, h)]);
    let down = polygon(&[(side / 2.0, h), (side, 0.0), (3.0 * side / 2.0, h)]);
    let s = scene(vec![
        (up.clone(), 0.15, 0.15, 0.0),
        (down, 0.15, 0.15, 0.0),
        (up, 0.15 + side, 0.15, 0.0),
    ]);
    let ids = [ObjectId(0), ObjectId(1), ObjectId(2)];
    let grasp = MultiObject::default().plan(&s, &ids).unwrap().value;
    assert!(grasp.is_none_or(|g| g.objects.len() < 3));
    let forced = Grasp {
        jaws: JawPose {
            center: Point2::new(0.15 + side, 0.15 + h / 2.0),
            angle: 0.0,
            opening: 0.085,
        },
        objects: ids.to_vec(),
        width: 0.0,
        margin: 0.0,
    };
    let mut sim = sim();
    sim.reset(&s).unwrap();
    let carried = sim.grasp(&forced).unwrap().carried;
    println!(
        "physics carried {} of the three triangles when forced",
        carried.len()
    );
}

#[test]
fn a_fork_push_leaves_the_object_near_its_target() {
    // Tolerance stated: 5 mm in position and 10° in yaw after a push of 40–75 mm that ends with the
    // object touching the other, on a table with friction 0.3, for a square, a triangle and a hexagon.
    let hexagon = polygon(
        &(0..6)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 6.0;
                (0.016 * a.cos(), 0.016 * a.sin())
            })
            .collect::<Vec<_>>(),
    );
    let triangle = polygon(&[(-0.015, -0.01), (0.015, -0.01), (0.0, 0.016)]);
    for (k, outline) in [square(0.03), triangle, hexagon].into_iter().enumerate() {
        let s = scene(vec![
            (outline, 0.12, 0.15, 0.2 * k as f64),
            (square(0.03), 0.22, 0.15, 0.0),
        ]);
        let plan = TowardCentral::default()
            .plan(&s, &[ObjectId(0), ObjectId(1)])
            .unwrap()
            .value;
        let push = plan.pushes.first().expect("one push");
        assert!(
            push.distance > 0.04 && push.distance < 0.075,
            "{}",
            push.distance
        );
        let mut sim = sim();
        sim.reset(&s).unwrap();
        sim.push(push).unwrap();
        let after = sim.observe().unwrap();
        let index = after.index_of(push.object).unwrap();
        let pose = after.objects()[index].pose;
        let miss = (pose.x - push.to.x).hypot(pose.y - push.to.y);
        let turn = (pose.yaw - push.to.yaw).sin().abs().asin();
        println!(
            "shape {k}: pushed {:.1} mm, off by {:.2} mm and {:.1}°",
            push.distance * 1e3,
            miss * 1e3,
            turn.to_degrees()
        );
        assert!(miss < 0.005, "shape {k}: {miss}");
        assert!(turn < 10f64.to_radians(), "shape {k}: {turn}");
    }
}

#[test]
fn the_same_seed_gives_the_same_run_bit_for_bit() {
    use pushmog::policy::{Policy, PolicyKind, PolicySettings};
    use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
    let settings = GeneratorSettings {
        objects: 8,
        workspace: Workspace::new(0.25, 0.2),
        ..GeneratorSettings::default()
    };
    let scene = generate_scene(&settings, &builtin_object_set(), 3).unwrap();
    let policy = Policy::new(PolicyKind::PushMog, PolicySettings::default()).unwrap();
    let run = |seed| {
        let mut sim = Sim::new(SimSettings::default(), seed).unwrap();
        policy.run(&scene, &mut sim, 5).unwrap()
    };
    let (a, b) = (run(11), run(11));
    assert_eq!(a, b);
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
    // Another noise seed observes differently.
    assert_ne!(a, run(12));
}

/// What the grasp planner calls held is held in physics: push-mog's multi-object grasps on three
/// seeded scenes, replayed in the simulator from the table the planner assumed, carry every
/// predicted object at least 90 % of the time without noise (the acceptance figure of the
/// grasp-physics work) and at least 75 % with the simulator's noise.
#[test]
fn planned_multi_object_grasps_hold_in_the_simulator() {
    use pushmog::experiment::agreement::{AgreementSettings, replay_grasps};
    let replays = replay_grasps(&AgreementSettings {
        scenes: 3,
        refused_per_trip: 0,
        ..AgreementSettings::default()
    })
    .unwrap();
    for noisy in [false, true] {
        let multi: Vec<_> = replays
            .iter()
            .filter(|r| r.noisy == noisy && r.predicted >= 2)
            .collect();
        let held = multi.iter().filter(|r| r.held()).count();
        println!("noise {noisy}: {held} of {} held", multi.len());
        assert!(multi.len() >= 5, "too few multi-object grasps to judge");
        let floor = if noisy { 0.75 } else { 0.9 };
        assert!(
            held as f64 >= floor * multi.len() as f64,
            "noise {noisy}: {held} of {}",
            multi.len()
        );
    }
}

/// Plans written by closed loops in the simulator pass the independent verifier, record checks
/// included: toppled objects that leave the observation and come back, objects lifted along with
/// others, looks during trips, and what is left at the end all add up. Eight closed loops in physics
/// (about 50 s on 2 cores): with the statistical checks, `cargo test -- --ignored`.
#[test]
#[ignore = "statistical: cargo test -- --ignored"]
fn simulated_runs_write_plans_that_verify() {
    use pushmog::plan::verify;
    use pushmog::policy::{Policy, PolicyKind, PolicySettings};
    use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
    let mut looks = 0;
    for seed in 0..4 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        for kind in [PolicyKind::PushMog, PolicyKind::PushMogOpt] {
            let policy = Policy::new(kind, PolicySettings::default()).unwrap();
            let mut sim = Sim::new(SimSettings::default(), seed).unwrap();
            let plan = policy.run(&scene, &mut sim, seed).unwrap();
            assert!(
                verify(&plan).is_empty(),
                "seed {seed} {kind}: {:?}",
                verify(&plan)
            );
            looks += plan.trips.iter().map(|t| t.looks.len()).sum::<usize>();
        }
    }
    // Trips that pushed looked again and planned the rest on what they saw; the verifier checked
    // those pushes and grasps on the looks.
    assert!(looks > 0);
}

/// Touching objects observed with perception noise are moved apart, never refused or dropped: a
/// row of four touching 7 mm bars is seen whole under 50 noise seeds.
#[test]
fn noisy_observations_of_touching_bars_keep_every_bar() {
    let bar = polygon(&[
        (-0.0035, -0.025),
        (0.0035, -0.025),
        (0.0035, 0.025),
        (-0.0035, 0.025),
    ]);
    let table = scene(
        (0..4)
            .map(|k| (bar.clone(), 0.15 + 0.007 * f64::from(k), 0.15, 0.0))
            .collect(),
    );
    for seed in 0..50 {
        let mut sim = Sim::new(SimSettings::default(), seed).unwrap();
        sim.reset(&table).unwrap();
        let seen = sim.observe().unwrap();
        assert_eq!(seen.len(), 4, "seed {seed}: lost {:?}", sim.lost());
    }
}

/// A square and a scalene triangle met by the plates' corners (a pair push-mog-opt planned on
/// paper-100 scene 8, in the jaws' frame, millimetres): the planar closing ends with both plate
/// contacts at the edge of their friction cones and calls the pair held, rapier squeezes the triangle
/// out, and the model that asks for friction to spare refuses the pair.
#[test]
fn a_pair_held_only_at_the_edge_of_friction_is_refused_with_friction_to_spare() {
    use pushmog::grasp::{GraspModel, Squeeze, squeeze};
    let at = |points: &[(f64, f64)]| {
        let outline = polygon(
            &points
                .iter()
                .map(|&(x, y)| (x / 1e3, y / 1e3))
                .collect::<Vec<_>>(),
        );
        let c = outline.centroid();
        let about_centroid = outline.transformed(&nalgebra::Isometry2::translation(-c.x, -c.y));
        (about_centroid, 0.2 + c.x, 0.15 + c.y, 0.0)
    };
    let s = scene(vec![
        at(&[(-26.7, -15.4), (3.1, -11.3), (-1.0, 18.4), (-30.7, 14.4)]),
        at(&[(31.9, -17.5), (13.3, 20.2), (1.5, -19.1)]),
    ]);
    let jaws = JawPose {
        center: Point2::new(0.2, 0.15),
        angle: 0.0,
        opening: 0.085,
    };
    let plain = GraspModel::default();
    assert!(
        matches!(squeeze(&s, &jaws, &plain), Squeeze::Held { ref objects, .. } if objects.len() == 2)
    );
    let spare = GraspModel {
        friction_share: Some(0.9),
        ..GraspModel::default()
    };
    assert!(!matches!(squeeze(&s, &jaws, &spare), Squeeze::Held { .. }));
    let mut sim = sim();
    sim.reset(&s).unwrap();
    let grasp = Grasp {
        jaws,
        objects: vec![ObjectId(0), ObjectId(1)],
        width: 0.0,
        margin: 0.0,
    };
    assert!(sim.grasp(&grasp).unwrap().carried.len() < 2);
}

/// Flush pushes (`push::flush`): a square pushed along a face's normal with the jaws closed to one
/// block flat against that face slides without turning, and so does one pushed 10° off the normal
/// with the block still flat against the face (inside the pads' friction cone, atan 0.4 = 21.8°);
/// the same push with the block across the push, 20° off the face, meets the square with one
/// corner and turns it until the face lies flat against the block.
#[test]
fn a_flush_push_slides_its_object_without_turning_it() {
    use nalgebra::Vector2;
    use pushmog::push::Push;
    use pushmog::push::flush::{block_opening, turned};
    use pushmog::push::fork::{ForkSettings, plan_fork_facing};
    let turn_after = |off: f64, flat: bool| {
        let s = scene(vec![(square(0.03), 0.12, 0.15, 0.0)]);
        let world = vec![s.world_polygon(0).clone()];
        let direction = turned(&Vector2::x(), off.to_radians());
        let facing = if flat { Vector2::x() } else { direction };
        let distance = 0.05;
        let fork = plan_fork_facing(
            s.gripper(),
            &ForkSettings::default(),
            &world,
            &[ObjectId(0)],
            0,
            0.03,
            (&direction, &facing),
            distance,
            block_opening(s.gripper()),
        )
        .unwrap();
        let from = s.objects()[0].pose;
        let moved = direction * distance;
        let push = Push {
            object: ObjectId(0),
            from,
            to: Pose::new(from.x + moved.x, from.y + moved.y, from.yaw),
            direction,
            distance,
            fork,
        };
        let mut sim = sim();
        sim.reset(&s).unwrap();
        sim.push(&push).unwrap();
        let pose = sim.observe().unwrap().objects()[0].pose;
        let miss = (pose.x - push.to.x).hypot(pose.y - push.to.y);
        let turn = pose.yaw.sin().abs().asin().to_degrees();
        println!(
            "{off}° off, flat {flat}: turned {turn:.2}°, {:.2} mm from target",
            miss * 1e3
        );
        (turn, miss)
    };
    let (along, miss) = turn_after(0.0, true);
    assert!(along < 1.0 && miss < 0.002, "{along}° {miss} m");
    let (oblique, miss) = turn_after(10.0, true);
    assert!(oblique < 1.0 && miss < 0.002, "{oblique}° {miss} m");
    let (across, _) = turn_after(20.0, false);
    assert!(across > 10.0, "{across}°");
}

/// A square of side `side` whose corners are arcs of radius `radius`, each traced by `segments`
/// edges: an outline as a contour tracer gives it, many vertices a millimetre apart.
fn rounded_square(side: f64, radius: f64, segments: usize) -> ConvexPolygon {
    let h = side / 2.0 - radius;
    let mut points = Vec::new();
    for (k, (cx, cy)) in [(h, h), (-h, h), (-h, -h), (h, -h)].into_iter().enumerate() {
        for j in 0..=segments {
            let angle = std::f64::consts::FRAC_PI_2 * (k as f64 + j as f64 / segments as f64);
            points.push((cx + radius * angle.cos(), cy + radius * angle.sin()));
        }
    }
    polygon(&points)
}

/// Objects traced by many vertices stand still while the gripper works beside them: such an outline
/// rests on its whole base, not on four vertices of one rounded corner (which let them rock and
/// creep by centimetres), and is still lifted by its outline.
#[test]
fn outlines_of_many_vertices_stand_still_beside_a_grasp() {
    let rounded = rounded_square(0.03, 0.003, 5);
    assert_eq!(rounded.vertices().len(), 24);
    let s = scene(vec![
        (square(0.03), 0.2, 0.15, 0.3),
        (rounded.clone(), 0.27, 0.15, 0.2),
        (rounded, 0.2, 0.08, -0.4),
    ]);
    let grasp = SingleObject::default()
        .plan(&s, &[ObjectId(0)])
        .unwrap()
        .value
        .unwrap();
    let mut sim = sim();
    sim.reset(&s).unwrap();
    assert_eq!(sim.grasp(&grasp).unwrap().carried, vec![ObjectId(0)]);
    let after = sim.observe().unwrap();
    assert_eq!(after.len(), 2);
    for object in after.objects() {
        let before = s.objects()[object.id.0 as usize].pose;
        let moved = (object.pose.x - before.x).hypot(object.pose.y - before.y);
        // Resting on four vertices of a corner they moved 0.3 and 0.6 mm in this one grasp.
        assert!(moved < 5e-5, "object {} moved {moved} m", object.id.0);
    }
    // The base touches only the table: the fingers still lift the object by its outline.
    let grasp = SingleObject::default()
        .plan(&after, &[ObjectId(1)])
        .unwrap()
        .value
        .unwrap();
    assert_eq!(sim.grasp(&grasp).unwrap().carried, vec![ObjectId(1)]);
}

/// Riders in physics: push-mog-opt with riders on one scene puts riders on rows in the simulator,
/// the plan passes the verifier (riders included), and the riders that their trips did not carry
/// are counted. Whether riders ride is measured over many scenes (`experiments/stacking.toml`).
#[test]
fn riders_are_placed_in_the_simulator_and_the_plan_verifies() {
    use pushmog::plan::verify;
    use pushmog::policy::{Policy, PolicyKind};
    use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 3).unwrap();
    let policy = Policy::new(PolicyKind::PushMogOpt, crate::support::with_riders()).unwrap();
    let mut sim = Sim::new(SimSettings::default(), 3).unwrap();
    let plan = policy.run(&scene, &mut sim, 3).unwrap();
    assert!(verify(&plan).is_empty(), "{:?}", verify(&plan));
    assert!(plan.riders_placed() > 0);
    assert!(plan.riders_lost() <= plan.riders_placed());
}

/// The simulator's depth camera: a generated table rendered, given depth noise and perceived is seen
/// whole, each object under its own id where it lies (footprint IoU with the truth at least 0.9,
/// the floor measured for isolated objects under this noise being 0.915).
#[test]
fn the_depth_camera_sees_every_object_of_a_generated_table_where_it_lies() {
    use pushmog::exec::SimCamera;
    use pushmog::geometry::intersection_over_union;
    use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
    let truth = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 2).unwrap();
    let settings = SimSettings {
        camera: Some(SimCamera::default()),
        ..SimSettings::default()
    };
    let mut sim = Sim::new(settings, 2).unwrap();
    sim.reset(&truth).unwrap();
    let seen = sim.observe().unwrap();
    assert!(sim.lost().is_empty(), "{:?}", sim.lost());
    assert_eq!(seen.len(), truth.len());
    for (k, object) in truth.objects().iter().enumerate() {
        let j = seen.index_of(object.id).expect("seen under its own id");
        let iou = intersection_over_union(seen.world_polygon(j), truth.world_polygon(k));
        assert!(iou >= 0.9, "object {}: IoU {iou}", object.id.0);
        // The mass a library lookup by the tracked id would give: the one the physics uses.
        assert!(seen.objects()[j].mass.is_some());
        if let Some(mass) = object.mass {
            assert_eq!(seen.objects()[j].mass, Some(mass));
        }
    }
}

/// With labels that stop short of each outline (`label_erosion`, a segmenter's masks), the camera
/// still sees each object whole where it lies: the depth gives the outline, the eroded label only
/// which object it is. Two boxes pressed flush together, whose union is one convex blob in depth,
/// are seen as two, and so is a generated table (IoU with the truth at least 0.9 for every object).
#[test]
fn eroded_labels_still_part_touching_objects_and_see_each_whole() {
    use pushmog::exec::SimCamera;
    use pushmog::geometry::intersection_over_union;
    let pressed = crate::support::boxes(0.03, 0.04, &[(0.2, 0.2), (0.23, 0.2)]);
    let generated = crate::support::scene(2);
    for erosion in [2, 4] {
        let settings = SimSettings {
            camera: Some(SimCamera {
                label_erosion: erosion,
                ..SimCamera::default()
            }),
            ..SimSettings::default()
        };
        for truth in [&pressed, &generated] {
            let mut sim = Sim::new(settings.clone(), 2).unwrap();
            sim.reset(truth).unwrap();
            let seen = sim.observe().unwrap();
            assert!(sim.lost().is_empty(), "{erosion} px: {:?}", sim.lost());
            assert_eq!(seen.len(), truth.len());
            for (k, object) in truth.objects().iter().enumerate() {
                let j = seen.index_of(object.id).expect("seen under its own id");
                let iou = intersection_over_union(seen.world_polygon(j), truth.world_polygon(k));
                assert!(
                    iou >= 0.9,
                    "{erosion} px, object {}: IoU {iou}",
                    object.id.0
                );
            }
        }
    }
}

/// A calibration error moves what the camera sees as the error says: an offset of the calibrated
/// optical centre moves every object by its horizontal part (the table's fit takes the vertical
/// part up), and a turn about the vertical turns them about the camera's nadir, to within 10 µm for
/// the turn and 50 µm for the offset, a 25th of a pixel (the table's fit picks its pixels near the
/// calibrated table, so a few of them change, and the outline's sides are fitted to every pixel
/// near the edge, so a pixel that changes side there moves a side a little: 21 µm at most here,
/// against 10 µm before that fit). The same frame is perceived each time (the same seed draws the
/// same noise).
#[test]
fn a_calibration_error_moves_what_the_camera_sees_by_that_error() {
    use nalgebra::{Point2, Rotation2, Vector2};
    use pushmog::exec::{CalibrationError, SimCamera};
    use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
    let truth = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 3).unwrap();
    let look = |calibration: CalibrationError| {
        let settings = SimSettings {
            camera: Some(SimCamera {
                calibration,
                ..SimCamera::default()
            }),
            ..SimSettings::default()
        };
        let mut sim = Sim::new(settings, 3).unwrap();
        sim.reset(&truth).unwrap();
        let seen = sim.observe().unwrap();
        assert!(sim.lost().is_empty(), "{:?}", sim.lost());
        seen
    };
    let exact = look(CalibrationError::default());
    let shifted = look(CalibrationError {
        offset: [0.01, -0.005, 0.01],
        turn: [0.0; 3],
    });
    let turned = look(CalibrationError {
        offset: [0.0; 3],
        turn: [0.0, 0.0, 0.01],
    });
    let workspace = truth.workspace();
    let nadir = Point2::new(
        0.5 * (workspace.min[0] + workspace.max[0]),
        0.5 * (workspace.min[1] + workspace.max[1]),
    );
    for object in exact.objects() {
        let at = object.world_centroid();
        let find = |scene: &pushmog::scene::Scene| {
            let j = scene.index_of(object.id).expect("seen under its own id");
            scene.objects()[j].world_centroid()
        };
        let moved = find(&shifted) - at;
        assert!(
            (moved - Vector2::new(0.01, -0.005)).norm() < 5e-5,
            "{moved}"
        );
        let expected = nadir + Rotation2::new(0.01) * (at - nadir);
        assert!(
            (find(&turned) - expected).norm() < 1e-5,
            "{}",
            find(&turned) - expected
        );
        let j = shifted.index_of(object.id).unwrap();
        let dh = shifted.objects()[j].height - object.height;
        assert!(dh.abs() < 1e-4, "{dh}");
    }
}

/// Closed loops that look through the depth camera write plans that pass the independent verifier
/// (two scenes, push-mog and push-mog-opt): with the statistical checks, `cargo test -- --ignored`.
#[test]
#[ignore = "statistical: cargo test -- --ignored"]
fn closed_loops_that_see_through_the_depth_camera_write_plans_that_verify() {
    use pushmog::exec::SimCamera;
    use pushmog::plan::verify;
    use pushmog::policy::{Policy, PolicyKind, PolicySettings};
    use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
    for seed in 0..2 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        for kind in [PolicyKind::PushMog, PolicyKind::PushMogOpt] {
            let policy = Policy::new(kind, PolicySettings::default()).unwrap();
            let settings = SimSettings {
                camera: Some(SimCamera::default()),
                ..SimSettings::default()
            };
            let mut sim = Sim::new(settings, seed).unwrap();
            let plan = policy.run(&scene, &mut sim, seed).unwrap();
            assert!(
                verify(&plan).is_empty(),
                "seed {seed} {kind}: {:?}",
                verify(&plan)
            );
            assert!(plan.trips.len() >= scene.len() / 3, "seed {seed} {kind}");
        }
    }
}

/// The camera's settings are checked by field, and the noise-free settings silence its depth noise.
#[test]
fn camera_settings_are_checked_and_noiseless_silences_the_depth_noise() {
    use pushmog::exec::SimCamera;
    let with_camera = |camera: SimCamera| SimSettings {
        camera: Some(camera),
        ..SimSettings::default()
    };
    let coarse = with_camera(SimCamera {
        pixel: 0.0,
        ..SimCamera::default()
    });
    let Err(refusal) = Sim::new(coarse, 1) else {
        panic!("a zero pixel is refused")
    };
    assert!(refusal.to_string().contains("camera.pixel"), "{refusal}");
    let mut miscalibrated = SimCamera::default();
    miscalibrated.calibration.turn[0] = 0.2;
    let Err(refusal) = Sim::new(with_camera(miscalibrated), 1) else {
        panic!("a 0.2 rad calibration error is refused")
    };
    assert!(
        refusal.to_string().contains("camera.calibration.turn[0]"),
        "{refusal}"
    );
    let Err(refusal) = Sim::new(
        with_camera(SimCamera {
            label_erosion: 11,
            ..SimCamera::default()
        }),
        1,
    ) else {
        panic!("labels eroded by 11 px are refused")
    };
    assert!(
        refusal.to_string().contains("camera.label_erosion"),
        "{refusal}"
    );
    let quiet = SimSettings::noiseless_from(&with_camera(SimCamera::default()));
    let noise = quiet.camera.expect("the camera stays").noise;
    assert_eq!(
        (noise.sigma_per_square_metre, noise.dropped, noise.flying),
        (0.0, 0.0, 0.0)
    );
}

/// `experiments/data/rows-with-riders.json` (read by `examples/rows_with_riders.rs` and the MuJoCo
/// example `mujoco_rows.py`): every entry is a valid scene, the rider is an object of it outside the
/// row, and the rider's row is the grasp's.
#[test]
fn the_rows_with_riders_file_holds_valid_scenes_riders_and_grasps() {
    #[derive(serde::Deserialize)]
    struct Entry {
        scene: Scene,
        rider: pushmog::plan::Rider,
        grasp: Grasp,
    }
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/experiments/data/rows-with-riders.json"
    );
    let entries: Vec<Entry> =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert!(!entries.is_empty());
    for entry in &entries {
        let ids: Vec<ObjectId> = entry.scene.objects().iter().map(|o| o.id).collect();
        assert!(ids.contains(&entry.rider.object));
        assert!(!entry.grasp.objects.contains(&entry.rider.object));
        assert!(entry.grasp.objects.iter().all(|id| ids.contains(id)));
        assert_eq!(entry.rider.on, entry.grasp.objects);
        assert_eq!(entry.rider.pick.objects, vec![entry.rider.object]);
    }
}
