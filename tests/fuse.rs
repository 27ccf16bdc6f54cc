//! Looks fused (`run.fuse_looks`, `policy/fuse.rs`): objects that stand still are placed at the
//! mean of their looks, measured against the simulator's ground truth; what the robot touched, or
//! what moved by more than the camera's error, starts again from its newest look.

use std::collections::HashMap;

use nalgebra::Point2;
use pushmog::exec::{Executor, Sim, SimSettings};
use pushmog::geometry::wrap_angle;
use pushmog::grasp::{GraspPlanner, GraspRequest, JawPose, SingleObject};
use pushmog::policy::{LookFusion, TOUCH_REACH};
use pushmog::scene::{Gripper, ObjectId, Pose, Scene};

use crate::support::{boxes, scene};

/// Position and yaw errors of every object in `seen` against `truth`, metres and radians.
fn errors(seen: &Scene, truth: &HashMap<ObjectId, Pose>) -> Vec<(f64, f64)> {
    seen.objects()
        .iter()
        .filter_map(|o| {
            let t = truth.get(&o.id)?;
            Some((
                (o.pose.x - t.x).hypot(o.pose.y - t.y),
                wrap_angle(o.pose.yaw - t.yaw).abs(),
            ))
        })
        .collect()
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let values: Vec<f64> = values.collect();
    values.iter().sum::<f64>() / values.len() as f64
}

#[test]
fn fused_looks_are_nearer_the_truth_than_single_looks_while_objects_are_taken_one_by_one() {
    // A table cleared one object at a time in the simulator, with its default perception noise
    // (2 mm per axis, 0.035 rad): every object not yet taken is seen at every look.
    let table = scene(3);
    let settings = SimSettings::default();
    let mut sim = Sim::new(settings.clone(), 11).unwrap();
    sim.reset(&table).unwrap();
    let mut fusion = LookFusion::new(settings.perception_position, settings.perception_yaw);
    let (mut raw, mut fused) = (Vec::new(), Vec::new());
    for _ in 0..3 * table.len() {
        let look = sim.observe().unwrap();
        if look.is_empty() {
            break;
        }
        let truth: HashMap<ObjectId, Pose> = sim.true_poses().into_iter().collect();
        raw.extend(errors(&look, &truth));
        let planned_on = fusion.fuse(look);
        fused.extend(errors(&planned_on, &truth));
        let all: Vec<ObjectId> = planned_on.objects().iter().map(|o| o.id).collect();
        let Some(grasp) = SingleObject::default()
            .plan_request(&GraspRequest::new(&planned_on, &all))
            .unwrap()
            .value
        else {
            break;
        };
        fusion.grasped(&grasp.jaws);
        sim.grasp(&grasp).unwrap();
    }
    assert!(raw.len() > 200, "{} poses seen", raw.len());
    let (raw_p, fused_p) = (
        mean(raw.iter().map(|e| e.0)),
        mean(fused.iter().map(|e| e.0)),
    );
    let (raw_y, fused_y) = (
        mean(raw.iter().map(|e| e.1)),
        mean(fused.iter().map(|e| e.1)),
    );
    // With independent errors, a mean of n looks errs as 1/√n of one; most objects here are seen
    // many times before they are taken, so the mean error falls well below one look's.
    assert!(
        fused_p < 0.6 * raw_p && fused_y < 0.6 * raw_y,
        "position {fused_p} against {raw_p}, yaw {fused_y} against {raw_y}"
    );
}

/// Two 30 mm squares, the first at (`first`, 0.1), the second at (`second`, 0.3).
fn table(first: f64, second: f64) -> Scene {
    boxes(0.03, 0.03, &[(first, 0.1), (second, 0.3)])
}

fn x_of(scene: &Scene, id: u32) -> f64 {
    scene.objects()[scene.index_of(ObjectId(id)).unwrap()]
        .pose
        .x
}

#[test]
fn an_object_left_alone_is_averaged_and_one_touched_or_moved_starts_again() {
    let mut fusion = LookFusion::new(0.002, 0.035);
    let far = 0.45;
    // Three looks of both squares standing still, 1 mm apart: the mean of the looks.
    for (k, dx) in [0.001, -0.001, 0.003].iter().enumerate() {
        let seen = fusion.fuse(table(0.1 + dx, far + dx));
        let expected = match k {
            0 => 0.101,
            1 => 0.1,
            _ => 0.101,
        };
        assert!((x_of(&seen, 0) - expected).abs() < 1e-12, "look {k}");
    }
    // Jaws come down beside the first square (within the touch reach) and far from the second:
    // the first starts again from the new look, the second goes on averaging.
    let gripper = Gripper::default();
    let jaws = JawPose {
        center: Point2::new(0.1, 0.115 + gripper.plate_length / 2.0 + TOUCH_REACH / 2.0),
        angle: 0.0,
        opening: 0.03,
    };
    fusion.grasped(&jaws);
    let seen = fusion.fuse(table(0.105, far + 0.001));
    assert!((x_of(&seen, 0) - 0.105).abs() < 1e-12);
    assert!((x_of(&seen, 1) - (far + 0.001)).abs() < 1e-12);
    // Without any action, a look 10 mm away (beyond three standard deviations of the difference)
    // is taken as a move: the newest look alone.
    let seen = fusion.fuse(table(0.105, far + 0.011));
    assert!((x_of(&seen, 1) - (far + 0.011)).abs() < 1e-12);
    assert!((x_of(&seen, 0) - 0.105).abs() < 1e-12);
}
