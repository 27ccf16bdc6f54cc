//! One suite over every executor, the same checks for each: the plans applied exactly, the
//! simulator, and the UR5 executor on loopback fakes of its controller and gripper (its
//! observations replayed from an ideal run). Acting (a grasp, putting a rider down) before a table
//! is given is misuse; a whole run passes the independent verifier and is recorded under the
//! executor's name.

use pushmog::error::Error;
use pushmog::exec::ur5::Ur5;
use pushmog::exec::ur5::fake::{ControllerFaults, GripperFaults};
use pushmog::exec::{Executor, Sim, SimSettings};
use pushmog::plan::{Rider, RunStatus, verify};
use pushmog::policy::Policy;
use pushmog::scene::{ObjectId, Pose, Scene};

use crate::support::stray_grasp;
use crate::ur5::{config_for, fakes, live_runner, replayed_observations};

/// The checks every executor passes, `name` its name, on a run of `policy` from `scene`.
fn conforms(executor: &mut dyn Executor, name: &str, policy: &Policy, scene: &Scene) -> RunStatus {
    assert_eq!(executor.name(), name);
    let early = executor.grasp(&stray_grasp());
    assert!(
        matches!(early, Err(Error::Misuse { .. })),
        "{name}: {early:?}"
    );
    let rider = Rider {
        object: ObjectId(0),
        pick: stray_grasp(),
        place: Pose::new(0.2, 0.2, 0.0),
        release: stray_grasp().jaws,
        base: 0.03,
        on: vec![ObjectId(1)],
    };
    let early = executor.place(&rider);
    assert!(
        matches!(early, Err(Error::Misuse { .. })),
        "{name}: {early:?}"
    );
    let plan = policy.run(scene, executor, 5).unwrap();
    assert_eq!(plan.executor, name);
    assert!(!plan.trips.is_empty(), "{name}");
    let problems = verify(&plan);
    assert!(problems.is_empty(), "{name}: {problems:?}");
    plan.status
}

#[test]
fn every_executor_carries_out_a_run_the_verifier_passes() {
    let (observation, reference, policy) = replayed_observations("executor-suite");
    let scene = observation.read().unwrap();
    let mut ideal = policy.ideal();
    assert_eq!(
        conforms(&mut ideal, "ideal", &policy, &scene),
        RunStatus::Cleared
    );
    let mut sim = Sim::new(SimSettings::default(), 5).unwrap();
    conforms(&mut sim, "sim", &policy, &scene);
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let config = config_for(&controller, &gripper);
    let mut robot = Ur5::new(live_runner(&config), observation);
    assert_eq!(
        conforms(&mut robot, "ur5", &policy, &scene),
        reference.status
    );
}
