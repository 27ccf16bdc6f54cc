//! What the UR5 closed loop counts as carried and as lost (`src/exec/ur5/tally.rs`): only what a
//! grasp held is carried; an object gone from a look otherwise is lost, and one a depth camera sees
//! past the workspace's edge can still be taken there (`run.reach_past_edge`).

use pushmog::exec::ur5::{DepthLook, NOT_IN_VIEW, Observation, Ur5};
use pushmog::exec::{Executor, SimCamera};
use pushmog::perception::{PerceptionSettings, render_depth, write_npy_f32, write_npy_u32};
use pushmog::plan::{RunStatus, StopReason};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::{ObjectId, Pose, Scene, Workspace};

use crate::support::{boxes, scratch};
use crate::ur5::{config_for, fakes, live_runner};
use pushmog::exec::ur5::fake::{ControllerFaults, GripperFaults};

/// Two boxes 30 × 40 mm, far apart on the 0.5 × 0.4 m table; box 1 near the edge at x = 0.5.
fn two_boxes() -> Scene {
    boxes(0.03, 0.04, &[(0.15, 0.2), (0.46, 0.2)])
}

/// sog with `reach` past the edge, and the object its first trip takes on `table` (plans applied
/// exactly with the same seed).
fn sog(table: &Scene, reach: f64) -> (Policy, ObjectId) {
    let mut settings = PolicySettings::default();
    settings.run.reach_past_edge = reach;
    let policy = Policy::new(PolicyKind::Sog, settings).unwrap();
    let mut ideal = policy.ideal();
    let reference = policy.run(table, &mut ideal, 5).unwrap();
    (policy, reference.trips[0].plan.grasp.objects[0])
}

/// `table` with object `id` moved to `pose`, on the workspace grown by 0.1 m on every side (so that
/// it may lie past the edge), for the renderer.
fn moved(table: &Scene, id: ObjectId, pose: Pose) -> Scene {
    let mut objects = table.objects().to_vec();
    for object in &mut objects {
        if object.id == id {
            object.pose = pose;
        }
    }
    let grown = Workspace {
        min: [-0.1, -0.1],
        max: [0.6, 0.5],
    };
    Scene::from_parts(grown, table.gripper().clone(), objects).unwrap()
}

/// A table's objects but `gone`.
fn without(table: &Scene, gone: &[ObjectId]) -> Scene {
    let kept = table
        .objects()
        .iter()
        .filter(|o| !gone.contains(&o.id))
        .cloned()
        .collect();
    table.with_objects(kept).unwrap()
}

/// An observation command that hands out `tables` as scene files, one per look.
fn replayed(name: &str, tables: &[Scene]) -> Observation {
    let dir = scratch(name);
    for (k, table) in tables.iter().enumerate() {
        std::fs::write(
            dir.join(format!("scene-{k}.json")),
            pushmog::json::to_json(table),
        )
        .unwrap();
    }
    std::fs::write(dir.join("count"), "0").unwrap();
    Observation::Command(format!(
        "cd '{}' && n=$(cat count) && echo $((n + 1)) > count && cat scene-$n.json",
        dir.display()
    ))
}

/// A depth camera over the workspace that hands out `tables` rendered (depth and labels), one per
/// look.
fn filmed(name: &str, first: &Scene, tables: &[Scene]) -> Observation {
    let dir = scratch(name);
    let camera = SimCamera::default().over(first.workspace());
    let (width, height) = (
        camera.intrinsics.width as usize,
        camera.intrinsics.height as usize,
    );
    for (k, table) in tables.iter().enumerate() {
        let frame = render_depth(table, &camera).unwrap();
        let depth = write_npy_f32(&frame.depth, height, width);
        std::fs::write(dir.join(format!("depth-{k}.npy")), depth).unwrap();
        let labels = write_npy_u32(&frame.labels, height, width);
        std::fs::write(dir.join(format!("labels-{k}.npy")), labels).unwrap();
    }
    std::fs::write(dir.join("count"), "0").unwrap();
    let command = format!(
        "cd '{}' && n=$(cat count) && echo $((n + 1)) > count && \
         cp depth-$n.npy \"$PUSHMOG_DEPTH\" && cp labels-$n.npy \"$PUSHMOG_LABELS\"",
        dir.display()
    );
    Observation::Camera(Box::new(DepthLook {
        camera,
        command,
        table: first.clone(),
        settings: PerceptionSettings::default(),
        library: None,
    }))
}

/// An object that vanishes from the look after a grasp that did not hold it was not carried: the
/// trip records it lost, the executor reports it not in view, and the run stops with it left
/// (before, everything gone from the look counted as carried, and the run was called cleared).
#[test]
fn an_object_gone_from_the_look_that_no_grasp_held_is_lost() {
    let table = two_boxes();
    let (policy, first) = sog(&table, 0.0);
    let other = table.objects().iter().map(|o| o.id).find(|&id| id != first);
    let other = other.unwrap();
    let observation = replayed(
        "ur5-lost",
        &[table.clone(), without(&table, &[first, other])],
    );
    // The first look is the table the run starts from.
    assert_eq!(observation.read().unwrap(), table);
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let config = config_for(&controller, &gripper);
    let mut robot = Ur5::new(live_runner(&config), observation);
    let run = policy.run(&table, &mut robot, 5).unwrap();
    assert_eq!(run.trips.len(), 1);
    assert_eq!(run.trips[0].carried, vec![first]);
    assert_eq!(robot.trips()[0].carried, vec![first]);
    assert_eq!(robot.trips()[0].lost, vec![other]);
    assert_eq!(robot.lost(), vec![(other, NOT_IN_VIEW)]);
    match &run.status {
        RunStatus::Stopped {
            remaining,
            reason: StopReason::NothingPlannable { lost },
        } => {
            assert_eq!(remaining, &vec![other]);
            assert_eq!(lost, &vec![(NOT_IN_VIEW.to_string(), 1)]);
        }
        status => panic!("the run must stop with the object lost: {status:?}"),
    }
}

/// Through a depth camera: the first trip's grasp leaves the other box lying 2 mm past the
/// workspace's edge. Without a reach past the edge the run stops with it outside the workspace;
/// with a 5 cm reach the loop takes it there under its own id, the travel clears it, and the look
/// after (nothing past the edge any more) counts it carried.
#[test]
fn an_object_a_camera_sees_past_the_edge_keeps_its_id_and_is_taken_there() {
    let table = two_boxes();
    let (_, first) = sog(&table, 0.05);
    let other = table.objects().iter().map(|o| o.id).find(|&id| id != first);
    let other = other.unwrap();
    // 0.5 + 0.002 + 0.015: the box's near side 2 mm past the edge; its top, nearer the camera and
    // so seen farther out, ends 4 px inside the image (5 cm round the workspace).
    let outside = moved(
        &without(&table, &[first]),
        other,
        Pose::new(0.517, 0.2, 0.0),
    );
    let empty = table.with_objects(Vec::new()).unwrap();
    for (reach, name) in [(0.0, "ur5-past-edge-off"), (0.05, "ur5-past-edge")] {
        let (policy, _) = sog(&table, reach);
        let looks = [table.clone(), outside.clone(), empty.clone()];
        let observation = filmed(name, &table, &looks);
        // The first look sees the table the run starts from (ids from the labels: 1 and 2).
        assert_eq!(observation.read().unwrap().len(), 2);
        let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
        let config = config_for(&controller, &gripper);
        let mut robot = Ur5::new(live_runner(&config), observation);
        let run = policy.run(&table, &mut robot, 5).unwrap();
        assert_eq!(run.trips[0].carried, vec![first]);
        assert_eq!(robot.trips()[0].lost, vec![other]);
        if reach == 0.0 {
            assert_eq!(run.trips.len(), 1);
            assert_eq!(robot.lost(), vec![(other, pushmog::exec::ur5::OUTSIDE)]);
            let seen = robot.past_edge();
            assert_eq!(seen.len(), 1);
            assert_eq!(seen[0].id, other);
            assert!((seen[0].world_centroid().x - 0.517).abs() < 0.002);
            assert!(matches!(run.status, RunStatus::Stopped { .. }));
            continue;
        }
        assert_eq!(run.status, RunStatus::Cleared, "{:?}", run.status);
        assert_eq!(run.trips.len(), 2);
        assert_eq!(run.trips_past_edge(), 1);
        let taken = &run.trips[1];
        assert_eq!(taken.plan.grasp.objects, vec![other]);
        assert_eq!(taken.carried, vec![other]);
        assert!(taken.plan.grasp.jaws.center.x > 0.5);
        assert_eq!(robot.trips()[1].carried, vec![other]);
        assert!(robot.trips()[1].lost.is_empty() && robot.lost().is_empty());
        let violations = pushmog::plan::verify(&run);
        assert!(violations.is_empty(), "{violations:?}");
    }
}
