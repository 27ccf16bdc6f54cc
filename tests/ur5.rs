//! The UR5 executor against loopback fakes of the controller and the Robotiq URCap socket: whole plans
//! step by step, scripted faults, calibration, the safety envelope and the golden URScript.

use std::path::Path;
use std::process::Output;

use nalgebra::{Rotation3, Vector3};
use pushmog::error::Error;
use pushmog::exec::SimCamera;
use pushmog::exec::ur5::DepthLook;
use pushmog::exec::ur5::fake::{ControllerFaults, FakeController, FakeGripper, GripperFaults};
use pushmog::exec::ur5::{
    Action, Calibration, Correspondence, DryRun, Live, LookConfig, Observation, Phase, RobotConfig,
    StepRunner, Translator, Ur5, execute_plan, gripper_command, listing, plan_steps, program,
};
use pushmog::perception::{PerceptionSettings, render_depth, write_npy_f32, write_npy_u32};
use pushmog::plan::Plan;
use pushmog::policy::{Policy, PolicyKind, PolicySettings, grasp_path, push_paths, rider_paths};
use pushmog::random::SeededRng;
use pushmog::scene::{Scene, SceneSpec};
use pushmog::time_model::{Command, TimeModel};

use crate::support::{fixture, pushmog, scratch};

fn example_config() -> RobotConfig {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("robots/ur5-example.toml");
    RobotConfig::load(&path).unwrap()
}

fn fixture_plan() -> Plan {
    let text = std::fs::read_to_string(fixture("ur5/plan.json")).unwrap();
    pushmog::json::from_json(&text, "plan.json").unwrap()
}

/// The example configuration pointed at the fakes, with short timeouts.
pub(crate) fn config_for(controller: &FakeController, gripper: &FakeGripper) -> RobotConfig {
    let mut config = example_config();
    config.controller.host = "127.0.0.1".to_string();
    config.controller.script_port = controller.script_port();
    config.controller.rtde_port = controller.rtde_port();
    config.controller.gripper_port = gripper.port();
    // Generous for the fakes (they answer in milliseconds) so a loaded CI machine does not time out.
    config.timeouts.reply = 2.0;
    config.timeouts.gripper = 2.0;
    config.timeouts.motion_margin = 2.0;
    config
}

pub(crate) fn fakes(
    controller: ControllerFaults,
    gripper: GripperFaults,
) -> (FakeController, FakeGripper) {
    (
        FakeController::start(controller).unwrap(),
        FakeGripper::start(gripper).unwrap(),
    )
}

pub(crate) fn live_runner(config: &RobotConfig) -> StepRunner<Live> {
    StepRunner::new(
        Translator::new(config.clone()).unwrap(),
        Live::connect(config).unwrap(),
    )
}

/// The move commands the fake gripper received (activation left out).
fn gripper_moves(gripper: &FakeGripper) -> Vec<String> {
    gripper
        .commands()
        .into_iter()
        .filter(|c| c.starts_with("SET POS"))
        .collect()
}

#[test]
fn a_whole_plan_reaches_the_fakes_step_by_step() {
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    controller.set_done_register(41); // left by an earlier session: tokens must start past it
    let config = config_for(&controller, &gripper);
    let plan = fixture_plan();
    let mut runner = live_runner(&config);
    execute_plan(&mut runner, &plan).unwrap();

    let translator = Translator::new(config.clone()).unwrap();
    let steps = plan_steps(&translator, &plan).unwrap();
    assert_eq!(runner.steps(), steps.as_slice());
    let mut expected_programs = Vec::new();
    let mut expected_moves = Vec::new();
    let mut token = 42;
    for (index, step) in steps.iter().enumerate() {
        match step.action {
            Action::Move { .. } => {
                expected_programs.push(program(&config, step, index, token).unwrap());
                token += 1;
            }
            Action::Gripper { .. } => expected_moves.push(gripper_command(step).unwrap()),
        }
    }
    assert_eq!(controller.programs(), expected_programs);
    assert_eq!(gripper_moves(&gripper), expected_moves);
    // Activation first, then only the moves.
    assert_eq!(gripper.commands()[0], "SET ACT 1");
    assert_eq!(gripper.commands().len(), expected_moves.len() + 1);
    // The fake ends where the last move of the last program went: over the bin.
    let end = controller.state();
    assert_eq!(end.done_register, token - 1);
    for axis in 0..3 {
        assert!((end.tcp_pose[axis] - config.bin.drop[axis]).abs() < 1e-5);
    }
    // Three steps per push (two when the jaws already stand at its opening): its move above the
    // start flows into its descent, and its rise into the next move, one program each; six per
    // grasp; one more where the rise stops for a look.
    let pushes: usize = plan.trips.iter().map(|t| t.plan.pushes.len()).sum();
    let looks: usize = plan.trips.iter().map(|t| t.looks.len()).sum();
    let jaws_kept: usize = plan
        .trips
        .iter()
        .map(|t| {
            t.plan
                .pushes
                .windows(2)
                .filter(|p| p[0].fork.opening == p[1].fork.opening)
                .count()
        })
        .sum();
    assert_eq!(
        steps.len(),
        3 * pushes - jaws_kept + looks + 6 * plan.trips.len()
    );
}

/// What a command is: a jaw command (`'J'`), an arm move that stops (`'A'`) or one that flows into
/// the next without stopping (`'T'`).
fn command_kinds(commands: &[Command]) -> String {
    commands
        .iter()
        .map(|c| match c {
            Command::Jaws(_) => 'J',
            Command::Through(_) => 'T',
            _ => 'A',
        })
        .collect()
}

/// The same for robot steps: one arm command per linear move (`'T'` when it blends into the next),
/// one jaw command per gripper step.
fn step_kinds(steps: &[pushmog::exec::ur5::Step]) -> String {
    steps
        .iter()
        .flat_map(|step| match &step.action {
            Action::Move { moves } => moves
                .iter()
                .map(|m| if m.blend > 0.0 { 'T' } else { 'A' })
                .collect(),
            Action::Gripper { .. } => vec!['J'],
        })
        .collect()
}

#[test]
fn the_dry_run_sends_exactly_the_commands_the_time_model_charges() {
    let translator = Translator::new(example_config()).unwrap();
    let model = TimeModel::default();
    // The fixture, and a push-mog-opt run whose trips push up to three objects.
    let scene = pushmog::scene::generate_scene(
        &pushmog::scene::GeneratorSettings::default(),
        &pushmog::scene::builtin_object_set(),
        4,
    )
    .unwrap();
    let policy = Policy::new(PolicyKind::PushMogOpt, PolicySettings::default()).unwrap();
    let run = policy.run(&scene, &mut policy.ideal(), 4).unwrap();
    assert!(
        run.trips.iter().any(|t| t.plan.pushes.len() >= 2),
        "a trip with two pushes or more"
    );
    // push-mog-time: flush pushes with the jaws closed to one block, several rows pushed ahead in
    // one trip.
    let mut settings = PolicySettings::default();
    settings.socp.flush = true;
    settings.pricing.objective = pushmog::policy::TripObjective::ExpectedTime;
    settings.pricing.push_ahead = true;
    let time = Policy::new(PolicyKind::PushMogOpt, settings).unwrap();
    let ahead = time.run(&scene, &mut time.ideal(), 4).unwrap();
    assert!(
        ahead.trips.iter().any(|t| t.plan.pushes.len() >= 2),
        "a trip pushing two rows ahead or more"
    );
    // Riders: each put on its row by the place action's steps.
    let stacking = Policy::new(PolicyKind::PushMogOpt, crate::support::with_riders()).unwrap();
    let riding = stacking.run(&scene, &mut stacking.ideal(), 4).unwrap();
    assert!(riding.riders_placed() > 0, "a trip with a rider");
    let mut jaws_left_out = 0;
    let mut blended = 0;
    for plan in [fixture_plan(), run.clone(), ahead, riding] {
        for (t, trip) in plan.trips.iter().enumerate() {
            let scene = pushmog::scene::Scene::new(trip.scene.to_spec()).unwrap();
            let gripper = scene.gripper();
            let looks: Vec<usize> = trip.looks.iter().map(|l| l.after_pushes).collect();
            let steps = translator.trip(
                &scene,
                &trip.plan.pushes,
                &looks,
                &trip.plan.riders,
                &trip.plan.grasp,
                t + 1,
            );
            let mut paths = push_paths(&trip.plan.pushes);
            for &after in &looks {
                paths[after - 1].look_after = true;
            }
            let riders = rider_paths(&trip.plan.riders, gripper);
            let charged = model.trip_commands_with_riders(
                gripper,
                &paths,
                &riders,
                &grasp_path(&trip.plan.grasp, gripper),
            );
            assert_eq!(step_kinds(&steps), command_kinds(&charged), "trip {t}");
            // Each rider is put down turned as planned: the tool turns from its pick to where it
            // lowers it by the rider's turn, the short way round.
            let orientation = |phase: Phase| -> Vec<Rotation3<f64>> {
                steps
                    .iter()
                    .filter(|s| s.phase == phase)
                    .filter_map(|s| match &s.action {
                        Action::Move { moves } => moves.last(),
                        Action::Gripper { .. } => None,
                    })
                    .map(|m| Rotation3::from_scaled_axis(Vector3::from(m.to.rotation)))
                    .collect()
            };
            let (picks, lowers) = (
                orientation(Phase::DescendToPick),
                orientation(Phase::LowerRider),
            );
            assert_eq!(picks.len(), trip.plan.riders.len());
            for ((pick, lower), rider) in picks.iter().zip(&lowers).zip(&trip.plan.riders) {
                let planned =
                    pushmog::geometry::wrap_angle(rider.release.angle - rider.pick.jaws.angle);
                let turned = (lower * pick.inverse()).angle();
                assert!(
                    (turned - planned.abs()).abs() < 1e-6,
                    "{turned} against {planned}"
                );
            }
            jaws_left_out += 5 * trip.plan.pushes.len() + 9 * riders.len() + 7 - charged.len();
            blended += charged
                .iter()
                .filter(|c| matches!(c, Command::Through(_)))
                .count();
        }
    }
    assert!(jaws_left_out > 0, "some push found the jaws at its opening");
    assert!(blended > 0, "some move flowed into the next");
    // With a waiting pose out of the camera's view, each look during a trip adds the move there,
    // and the model set to charge it charges exactly that.
    let mut config = example_config();
    config.look = Some(waiting_pose());
    let away = Translator::new(config).unwrap();
    let model = TimeModel {
        look_away: 0.3,
        ..TimeModel::default()
    };
    let mut waits = 0;
    for (t, trip) in run.trips.iter().enumerate() {
        let scene = pushmog::scene::Scene::new(trip.scene.to_spec()).unwrap();
        let looks: Vec<usize> = trip.looks.iter().map(|l| l.after_pushes).collect();
        let steps = away.trip(
            &scene,
            &trip.plan.pushes,
            &looks,
            &[],
            &trip.plan.grasp,
            t + 1,
        );
        let mut paths = push_paths(&trip.plan.pushes);
        for &after in &looks {
            paths[after - 1].look_after = true;
        }
        let charged = model.trip_commands(
            scene.gripper(),
            &paths,
            &grasp_path(&trip.plan.grasp, scene.gripper()),
        );
        assert_eq!(step_kinds(&steps), command_kinds(&charged), "trip {t}");
        waits += steps.iter().filter(|s| s.phase == Phase::OutOfView).count();
        assert_eq!(
            waits,
            run.trips[..=t].iter().map(|t| t.looks.len()).sum::<usize>()
        );
    }
    assert!(waits > 0, "a look during a trip");
}

/// A waiting pose beside the bin, out of an overhead camera's view of the example cell's table.
fn waiting_pose() -> LookConfig {
    LookConfig {
        wait: [-0.40, 0.50, 0.30],
    }
}

#[test]
fn a_disconnect_mid_plan_stops_with_the_step_and_sends_nothing_more() {
    let (controller, gripper) = fakes(
        ControllerFaults {
            disconnect_after_programs: Some(3),
            ..ControllerFaults::default()
        },
        GripperFaults::default(),
    );
    let config = config_for(&controller, &gripper);
    let plan = fixture_plan();
    let steps = plan_steps(&Translator::new(config.clone()).unwrap(), &plan).unwrap();
    let third_motion = steps
        .iter()
        .enumerate()
        .filter(|(_, s)| matches!(s.action, Action::Move { .. }))
        .nth(2)
        .unwrap()
        .0;
    let mut runner = live_runner(&config);
    let error = execute_plan(&mut runner, &plan).unwrap_err();
    match &error {
        Error::RobotStopped {
            step,
            completed,
            reason,
            ..
        } => {
            assert_eq!(*step, third_motion);
            assert_eq!(*completed, third_motion);
            assert!(reason.contains("RTDE connection lost"), "{reason}");
        }
        other => panic!("expected RobotStopped, got {other}"),
    }
    assert!(error.to_string().contains("last known state"));
    std::thread::sleep(std::time::Duration::from_millis(50));
    assert_eq!(controller.programs().len(), 3);
    let grippers_before = steps[..third_motion]
        .iter()
        .filter(|s| matches!(s.action, Action::Gripper { .. }))
        .count();
    assert_eq!(gripper_moves(&gripper).len(), grippers_before);
    // A later call sends nothing either.
    let again = execute_plan(&mut runner, &plan).unwrap_err();
    assert!(matches!(again, Error::RobotStopped { .. }));
    assert_eq!(controller.programs().len(), 3);
    assert_eq!(gripper_moves(&gripper).len(), grippers_before);
}

/// What a scripted fault left behind: the step the run stopped at, the reason, and how many programs
/// and gripper moves the fakes had received (checked after a pause, so late sends would show).
struct Stopped {
    step: usize,
    reason: String,
    programs: usize,
    gripper_moves: usize,
}

/// Runs the fixture plan against fakes with the given faults (and gripper timeout) until it stops.
fn run_until_stopped(
    controller_faults: ControllerFaults,
    gripper_faults: GripperFaults,
    gripper_timeout: f64,
) -> Stopped {
    let (controller, gripper) = fakes(controller_faults, gripper_faults);
    let mut config = config_for(&controller, &gripper);
    config.timeouts.gripper = gripper_timeout;
    let mut runner = live_runner(&config);
    let error = execute_plan(&mut runner, &fixture_plan()).unwrap_err();
    std::thread::sleep(std::time::Duration::from_millis(50));
    match error {
        Error::RobotStopped { step, reason, .. } => Stopped {
            step,
            reason,
            programs: controller.programs().len(),
            gripper_moves: gripper_moves(&gripper).len(),
        },
        other => panic!("expected RobotStopped, got {other}"),
    }
}

// The fixture plan's first trip has no push: step 0 moves above the grasp, 1 opens the jaws, 2
// descends (the second program), 3 closes (the second gripper move).

#[test]
fn a_protective_stop_stops_the_run_at_its_step() {
    let faults = ControllerFaults {
        protective_stop_at_program: Some(2),
        ..ControllerFaults::default()
    };
    let stopped = run_until_stopped(faults, GripperFaults::default(), 2.0);
    assert_eq!(stopped.step, 2);
    assert!(
        stopped.reason.contains("safety mode 3"),
        "{}",
        stopped.reason
    );
    assert_eq!((stopped.programs, stopped.gripper_moves), (2, 1));
}

#[test]
fn a_gripper_that_never_finishes_times_out_at_its_step() {
    let faults = GripperFaults {
        never_done: true,
        ..GripperFaults::default()
    };
    let stopped = run_until_stopped(ControllerFaults::default(), faults, 0.3);
    assert_eq!(stopped.step, 1);
    assert!(
        stopped.reason.contains("did not finish"),
        "{}",
        stopped.reason
    );
    assert_eq!((stopped.programs, stopped.gripper_moves), (1, 1));
}

#[test]
fn a_gripper_fault_stops_at_once() {
    let faults = GripperFaults {
        fault_at_move: Some((2, 7)),
        ..GripperFaults::default()
    };
    let stopped = run_until_stopped(ControllerFaults::default(), faults, 2.0);
    assert_eq!(stopped.step, 3);
    assert!(stopped.reason.contains("FLT 7"), "{}", stopped.reason);
    assert_eq!((stopped.programs, stopped.gripper_moves), (2, 2));
}

#[test]
fn the_envelope_refuses_before_any_byte_is_sent() {
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let mut config = config_for(&controller, &gripper);
    config.safety.min[0] = -0.40; // the bin at x = −0.45 is now outside
    let translator = Translator::new(config.clone()).unwrap();
    let steps = plan_steps(&translator, &fixture_plan()).unwrap();
    let refused = translator.check(&steps, 0).unwrap_err();
    match &refused {
        Error::UnsafeMotion {
            step,
            label,
            reason,
        } => {
            assert_eq!(*step, 4, "{label}");
            assert!(label.contains("move to the bin"));
            assert!(reason.contains("along x"), "{reason}");
        }
        other => panic!("expected UnsafeMotion, got {other}"),
    }
    // Through a live link: refused before the first step, so no program and no gripper move.
    let mut runner = live_runner(&config);
    let error = execute_plan(&mut runner, &fixture_plan()).unwrap_err();
    assert!(matches!(error, Error::UnsafeMotion { step: 4, .. }));
    std::thread::sleep(std::time::Duration::from_millis(30));
    assert!(controller.programs().is_empty());
    assert!(gripper_moves(&gripper).is_empty());

    // A speed over the limit is refused too, already in the robot file.
    let mut fast = config.clone();
    fast.safety.min[0] = -0.55;
    fast.speeds.travel = 0.5;
    let error = Translator::new(fast).unwrap_err();
    assert!(
        error.to_string().contains("speeds.travel") && error.to_string().contains("max_speed"),
        "{error}"
    );
}

/// Writes `config` as `dir/robot.toml` and runs `pushmog execute <fixture plan> --robot robot.toml`
/// with `extra` arguments.
fn execute_fixture_plan(config: &RobotConfig, dir: &Path, extra: &[&str]) -> Output {
    let robot = dir.join("robot.toml");
    std::fs::write(&robot, toml::to_string(config).unwrap()).unwrap();
    let plan = fixture("ur5/plan.json");
    let mut args = vec![
        "execute",
        plan.to_str().unwrap(),
        "--robot",
        robot.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    pushmog(&args)
}

#[test]
fn the_cli_refuses_an_unsafe_plan_without_connecting() {
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let mut config = config_for(&controller, &gripper);
    config.safety.max[2] = 0.15; // the bin at z = 0.2 is now outside
    let out = execute_fixture_plan(&config, &scratch("ur5-cli-refuse"), &["--execute"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("refused before sending anything"),
        "{stderr}"
    );
    assert_eq!(gripper.connections(), 0);
    assert!(controller.programs().is_empty());
}

#[test]
fn the_cli_executes_a_plan_on_the_fakes_and_dry_runs_by_default() {
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let config = config_for(&controller, &gripper);
    let dir = scratch("ur5-cli");
    let out_dir = dir.join("dry");
    let dry = execute_fixture_plan(&config, &dir, &["--out", out_dir.to_str().unwrap()]);
    assert!(
        dry.status.success(),
        "{}",
        String::from_utf8_lossy(&dry.stderr)
    );
    for file in ["program.script", "steps.txt", "tool-path.svg"] {
        assert!(out_dir.join(file).is_file(), "{file}");
    }
    assert!(controller.programs().is_empty(), "a dry run sends nothing");
    assert_eq!(gripper.connections(), 0);

    let live_dir = dir.join("live");
    let live = execute_fixture_plan(
        &config,
        &dir,
        &["--execute", "--out", live_dir.to_str().unwrap()],
    );
    assert!(
        live.status.success(),
        "{}",
        String::from_utf8_lossy(&live.stderr)
    );
    let script = std::fs::read_to_string(out_dir.join("program.script")).unwrap();
    assert_eq!(
        controller.programs().len(),
        script.matches("def pushmog_step_").count()
    );
    // The record of what was done is the dry run's step list, all of it.
    let done = std::fs::read_to_string(live_dir.join("executed.txt")).unwrap();
    let listed = std::fs::read_to_string(out_dir.join("steps.txt")).unwrap();
    assert_eq!(done, listed);
}

#[test]
fn the_cli_reports_a_fault_and_keeps_the_record_of_completed_steps() {
    let (controller, gripper) = fakes(
        ControllerFaults::default(),
        GripperFaults {
            fault_at_move: Some((2, 5)),
            ..GripperFaults::default()
        },
    );
    let config = config_for(&controller, &gripper);
    let dir = scratch("ur5-cli-fault");
    let out = execute_fixture_plan(
        &config,
        &dir,
        &["--execute", "--out", dir.to_str().unwrap()],
    );
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("robot stopped at step 3"), "{stderr}");
    assert!(stderr.contains("FLT 5"), "{stderr}");
    let record = std::fs::read_to_string(dir.join("executed.txt")).unwrap();
    assert!(
        record.contains("stopped: robot stopped at step 3"),
        "{record}"
    );
    // Steps 0–2 are recorded as done; step 3 is not.
    assert!(record.contains("   2  trip 1, grasp: descend"));
    assert!(!record.contains("   3  trip 1"));
}

/// The observations an ideal run of push-mog on the fixture scene sees, replayed one per call by a
/// shell command; returns the command and the ideal run.
pub(crate) fn replayed_observations(name: &str) -> (Observation, Plan, Policy) {
    let scene = pushmog::json::read_scene(&fixture("ur5/scene.json")).unwrap();
    let policy = Policy::new(PolicyKind::PushMog, PolicySettings::default()).unwrap();
    let mut ideal = policy.ideal();
    let reference = policy.run(&scene, &mut ideal, 5).unwrap();
    let dir = scratch(name);
    // Every trip's table, then every look during the trip.
    let mut observations: Vec<SceneSpec> = reference
        .trips
        .iter()
        .flat_map(|t| std::iter::once(&t.scene).chain(t.looks.iter().map(|l| &l.scene)))
        .map(|scene| scene.to_spec())
        .collect();
    let mut empty = scene.to_spec();
    empty.objects.clear();
    observations.push(empty);
    for (k, spec) in observations.iter().enumerate() {
        std::fs::write(
            dir.join(format!("scene-{k}.json")),
            pushmog::json::to_json(spec),
        )
        .unwrap();
    }
    std::fs::write(dir.join("count"), "0").unwrap();
    let command = format!(
        "cd '{}' && n=$(cat count) && echo $((n + 1)) > count && cat scene-$n.json",
        dir.display()
    );
    (Observation::Command(command), reference, policy)
}

#[test]
fn the_closed_loop_replans_on_each_observation() {
    // Replay the observations of an ideal run while the fakes carry the steps out: the robot's run
    // must make the same trips.
    let (observation, reference, policy) = replayed_observations("ur5-closed-loop");
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    // The arm leaves the camera's view for each look during a trip.
    let mut config = config_for(&controller, &gripper);
    config.look = Some(waiting_pose());
    let first = observation.read().unwrap();
    let mut robot = Ur5::new(live_runner(&config), observation);
    let run = policy.run(&first, &mut robot, 5).unwrap();
    assert_eq!(run.trips.len(), reference.trips.len());
    for (a, b) in run.trips.iter().zip(&reference.trips) {
        assert_eq!(a.plan.grasp, b.plan.grasp);
        assert_eq!(a.plan.pushes, b.plan.pushes);
        let (mut x, mut y) = (a.carried.clone(), b.carried.clone());
        x.sort_unstable();
        y.sort_unstable();
        assert_eq!(x, y);
    }
    assert_eq!(run.status, pushmog::plan::RunStatus::Cleared);
    // The executor's own record agrees with the run.
    assert_eq!(robot.trips().len(), run.trips.len());
    for (done, trip) in robot.trips().iter().zip(&run.trips) {
        assert_eq!(done.scene, trip.scene.to_spec());
        assert_eq!(done.pushes, trip.plan.pushes);
        assert_eq!(done.grasp.as_ref(), Some(&trip.plan.grasp));
        assert_eq!(done.carried, trip.carried);
    }
    let motions = robot
        .runner()
        .steps()
        .iter()
        .filter(|s| matches!(s.action, Action::Move { .. }))
        .count();
    assert_eq!(controller.programs().len(), motions);
    // The closed loop holds each push's rise back for the next action (or stops it for a look and
    // moves out of the camera's view): the moves it sent stop and blend exactly where the time
    // model, charging the way out of view, charges a stop or none.
    let model = TimeModel {
        look_away: 0.3,
        ..TimeModel::default()
    };
    let charged: String = run
        .trips
        .iter()
        .map(|trip| {
            let gripper = trip.scene.gripper.clone();
            let mut paths = push_paths(&trip.plan.pushes);
            for look in &trip.looks {
                paths[look.after_pushes - 1].look_after = true;
            }
            command_kinds(&model.trip_commands(
                &gripper,
                &paths,
                &grasp_path(&trip.plan.grasp, &gripper),
            ))
        })
        .collect();
    assert_eq!(step_kinds(robot.runner().steps()), charged);
    let looks: usize = run.trips.iter().map(|t| t.looks.len()).sum();
    assert!(looks > 0 && charged.contains('T'), "looks and blends");
    // Each look waited at the pose: a stopping move there right after a push's rise.
    let steps = robot.runner().steps();
    let waits: Vec<usize> = (0..steps.len())
        .filter(|&k| steps[k].phase == Phase::OutOfView)
        .collect();
    assert_eq!(waits.len(), looks);
    for k in waits {
        assert_eq!(steps[k - 1].phase, Phase::RiseFromPush);
        let Action::Move { moves } = &steps[k].action else {
            panic!("a move out of view");
        };
        assert_eq!(moves.len(), 1);
        assert_eq!(
            (moves[0].to.position, moves[0].blend),
            (waiting_pose().wait, 0.0)
        );
    }
}

/// The tables an ideal run of push-mog on the fixture scene saw, rendered as depth and labels by a
/// camera over the workspace and handed out one per look by a shell command (as a camera driver
/// would write them): the look, the ideal run and its policy.
fn camera_replay(name: &str) -> (DepthLook, Plan, Policy) {
    let (_, reference, policy) = replayed_observations(&format!("{name}-scenes"));
    let dir = scratch(name);
    let first = Scene::try_from(reference.trips[0].scene.to_spec()).unwrap();
    let camera = SimCamera::default().over(first.workspace());
    let (width, height) = (
        camera.intrinsics.width as usize,
        camera.intrinsics.height as usize,
    );
    let mut tables: Vec<Scene> = reference
        .trips
        .iter()
        .flat_map(|t| std::iter::once(&t.scene).chain(t.looks.iter().map(|l| &l.scene)))
        .map(|scene| Scene::try_from(scene.to_spec()).unwrap())
        .collect();
    tables.push(first.with_objects(Vec::new()).unwrap());
    for (k, table) in tables.iter().enumerate() {
        let frame = render_depth(table, &camera).unwrap();
        let write = |file: String, bytes: Vec<u8>| std::fs::write(dir.join(file), bytes).unwrap();
        write(
            format!("depth-{k}.npy"),
            write_npy_f32(&frame.depth, height, width),
        );
        write(
            format!("labels-{k}.npy"),
            write_npy_u32(&frame.labels, height, width),
        );
    }
    std::fs::write(dir.join("count"), "0").unwrap();
    let command = format!(
        "cd '{}' && n=$(cat count) && echo $((n + 1)) > count && \
         cp depth-$n.npy \"$PUSHMOG_DEPTH\" && cp labels-$n.npy \"$PUSHMOG_LABELS\"",
        dir.display()
    );
    // The frames are the ideal run's tables, so the loop must plan the trips that run planned. With
    // the fitted outline (`PerceptionSettings::fit_outline`) the second trip's single grasp takes
    // another of its near-tied jaw angles (traced: the same object, the jaws turned by 36°), the
    // table then differs from the next frame and the ids no longer match; the hull alone gives the
    // ideal run's plans here.
    let look = DepthLook {
        camera,
        command,
        table: first,
        settings: PerceptionSettings {
            fit_outline: false,
            ..PerceptionSettings::default()
        },
        library: Some(pushmog::scene::builtin_object_set()),
    };
    (look, reference, policy)
}

/// The closed loop looking through a depth camera (`camera_replay`), each look perceived with the
/// last table moved by the pushes since as the prior: the robot's trips take the same objects as
/// the ideal run's, every object keeps its id, and the table is cleared. Without the prior, ids
/// change after pushes and the trips no longer match.
#[test]
fn the_closed_loop_sees_through_a_depth_camera_and_keeps_the_ids() {
    let (look, reference, policy) = camera_replay("ur5-camera");
    let first = look.table.clone();
    let observation = Observation::Camera(Box::new(look));
    // The first look has no prior: the ids are the labels, one object per object, each named from
    // the library as the table's own object is.
    let seen = observation.read().unwrap();
    assert_eq!(seen.len(), first.len());
    let mut names: Vec<_> = seen.objects().iter().map(|o| o.name.clone()).collect();
    let mut truth: Vec<_> = first.objects().iter().map(|o| o.name.clone()).collect();
    names.sort();
    truth.sort();
    assert_eq!(names, truth);
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let config = config_for(&controller, &gripper);
    let mut robot = Ur5::new(live_runner(&config), observation);
    let run = policy.run(&first, &mut robot, 5).unwrap();
    assert_eq!(run.status, pushmog::plan::RunStatus::Cleared);
    assert_eq!(run.trips.len(), reference.trips.len());
    let sorted = |ids: &mut dyn Iterator<Item = pushmog::scene::ObjectId>| {
        let mut ids: Vec<_> = ids.collect();
        ids.sort_unstable();
        ids
    };
    for (a, b) in run.trips.iter().zip(&reference.trips) {
        assert_eq!(sorted(&mut a.scene.ids()), sorted(&mut b.scene.ids()));
        assert_eq!(a.plan.grasp.objects, b.plan.grasp.objects);
        assert_eq!(
            sorted(&mut a.carried.iter().copied()),
            sorted(&mut b.carried.iter().copied())
        );
    }
}

/// An observation command learns the table expected after the pushes from `$PUSHMOG_PRIOR`: the
/// last table with each pushed object where its push was planned to leave it; the first look, with
/// no table known, gets none.
#[test]
fn an_observation_command_is_given_the_expected_table() {
    let plan = fixture_plan();
    let trip = plan
        .trips
        .iter()
        .find(|t| !t.plan.pushes.is_empty())
        .unwrap();
    let table = Scene::try_from(trip.scene.to_spec()).unwrap();
    let dir = scratch("ur5-prior");
    std::fs::write(dir.join("table.json"), pushmog::json::to_json(&table)).unwrap();
    let command = format!(
        "cd '{}' && if [ -n \"$PUSHMOG_PRIOR\" ]; then cp \"$PUSHMOG_PRIOR\" prior.json; fi && cat table.json",
        dir.display()
    );
    let observation = Observation::Command(command);
    observation.read().unwrap();
    assert!(!dir.join("prior.json").exists());
    observation
        .read_after(Some(&table), &trip.plan.pushes)
        .unwrap();
    let text = std::fs::read_to_string(dir.join("prior.json")).unwrap();
    let expected = pushmog::json::scene_from_json(&text, "prior.json").unwrap();
    // Each pushed object where its last push was planned to leave it.
    let mut checked = Vec::new();
    for push in trip.plan.pushes.iter().rev() {
        if !checked.contains(&push.object) {
            let k = expected.index_of(push.object).unwrap();
            assert_eq!(expected.objects()[k].pose, push.to);
            checked.push(push.object);
        }
    }
    assert_eq!(expected.len(), table.len());
}

/// `pushmog execute --camera … --state … --observe-command …` runs the same closed loop.
#[test]
fn the_cli_runs_a_closed_loop_through_a_depth_camera() {
    let (look, reference, _) = camera_replay("ur5-cli-camera");
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let config = config_for(&controller, &gripper);
    let dir = scratch("ur5-cli-camera-out");
    let path = |name: &str| dir.join(name).display().to_string();
    std::fs::write(path("robot.toml"), toml::to_string(&config).unwrap()).unwrap();
    std::fs::write(path("camera.toml"), toml::to_string(&look.camera).unwrap()).unwrap();
    std::fs::write(path("state.json"), pushmog::json::to_json(&look.table)).unwrap();
    let out = pushmog(&[
        "execute",
        "--robot",
        &path("robot.toml"),
        "--camera",
        &path("camera.toml"),
        "--state",
        &path("state.json"),
        "--observe-command",
        &look.command,
        "--library",
        "builtin",
        "--seed",
        "5",
        "--execute",
        "--out",
        &path("out"),
    ]);
    let run = cleared_run(&out, &dir.join("out"));
    assert_eq!(run.trips.len(), reference.trips.len());
    // The objects of the first look were named from the library, as the table's own are.
    let names = |scene: &SceneSpec| {
        let mut names: Vec<_> = scene.objects.iter().map(|o| o.name.clone()).collect();
        names.sort();
        names
    };
    assert_eq!(
        names(&run.trips[0].scene.to_spec()),
        names(&look.table.to_spec())
    );
}

#[test]
fn calibration_recovers_a_known_transform_within_the_noise() {
    let rotation = Rotation3::from_euler_angles(0.01, -0.02, 0.7);
    let translation = Vector3::new(-0.31, 0.27, 0.012);
    let mut rng = SeededRng::new(11);
    let sigma = 0.0005;
    let table: Vec<[f64; 2]> = (0..12)
        .map(|i| [0.6 * f64::from(i % 4) / 3.0, 0.45 * f64::from(i / 4) / 2.0])
        .collect();
    let points: Vec<Correspondence> = table
        .iter()
        .map(|t| {
            let exact = rotation * Vector3::new(t[0], t[1], 0.0) + translation;
            let noise = Vector3::new(rng.normal(), rng.normal(), rng.normal()) * sigma;
            let b = exact + noise;
            Correspondence {
                table: *t,
                base: [b.x, b.y, b.z],
            }
        })
        .collect();
    let fit = Calibration::fit(&points).unwrap();
    let angle_error = (fit.rotation * rotation.inverse()).angle();
    let offset_error = (fit.translation - translation).norm();
    // With 12 points spread over 0.6 m × 0.45 m, a 0.5 mm noise moves the fit by well under a
    // milliradian and a millimetre.
    assert!(angle_error < 2e-3, "rotation off by {angle_error} rad");
    assert!(offset_error < 1e-3, "translation off by {offset_error} m");
    // Residuals are of the noise's size (3 axes of σ each).
    assert!(fit.rms_residual > 0.2 * sigma && fit.rms_residual < 3.0 * sigma);

    // Exact points give the transform back exactly.
    let exact: Vec<Correspondence> = [table[0], table[3], table[11]]
        .iter()
        .map(|t| {
            let b = rotation * Vector3::new(t[0], t[1], 0.0) + translation;
            Correspondence {
                table: *t,
                base: [b.x, b.y, b.z],
            }
        })
        .collect();
    let fit = Calibration::fit(&exact).unwrap();
    // (Compared as matrices: `angle()` goes through acos, which is only good to ~1e-8 near zero.)
    let difference = (fit.rotation.matrix() - rotation.matrix()).norm();
    assert!(difference < 1e-9, "rotation differs by {difference}");
    assert!((fit.translation - translation).norm() < 1e-9);
    assert!(fit.rms_residual < 1e-9);
}

#[test]
fn calibration_rejects_too_few_or_collinear_points() {
    let on_a_line: Vec<Correspondence> = (0..4)
        .map(|i| Correspondence {
            table: [0.1 * f64::from(i), 0.0],
            base: [0.1 * f64::from(i), 0.3, 0.0],
        })
        .collect();
    let error = Calibration::fit(&on_a_line).unwrap_err();
    assert!(error.to_string().contains("one line"), "{error}");
    let error = Calibration::fit(&on_a_line[..2]).unwrap_err();
    assert!(error.to_string().contains("at least 3"), "{error}");

    // A configuration whose points disagree by centimetres is refused with the residual named.
    let mut config = example_config();
    config.calibration.points[2].base[0] += 0.02;
    let error = config.validate().unwrap_err();
    assert!(error.to_string().contains("RMS residual"), "{error}");
}

#[test]
fn the_tool_points_down_with_the_jaws_along_the_plan() {
    let translator = Translator::new(example_config()).unwrap();
    for angle in [0.0, 0.4, 1.2, 2.0, 3.0] {
        let pose = translator.tool_pose(0.3, 0.2, 0.05, angle);
        let rv = Vector3::from(pose.rotation);
        let r = Rotation3::new(rv);
        // The tool's z axis points down, its y axis (the closing axis) along the jaw angle.
        assert!((r * Vector3::z() + Vector3::z()).norm() < 1e-9);
        let closing = r * Vector3::y();
        let along = closing.x * angle.cos() + closing.y * angle.sin();
        assert!((along.abs() - 1.0).abs() < 1e-9, "angle {angle}");
    }
}

#[test]
fn the_urscript_of_the_fixture_plan_matches_the_reviewed_golden_file() {
    let config = example_config();
    let translator = Translator::new(config.clone()).unwrap();
    let steps = plan_steps(&translator, &fixture_plan()).unwrap();
    let text = listing(&config, &steps);
    let golden = fixture("ur5/program.script");
    if std::env::var_os("PUSHMOG_UPDATE_GOLDEN").is_some() {
        std::fs::write(&golden, &text).unwrap();
    }
    let expected = std::fs::read_to_string(&golden).unwrap();
    assert_eq!(
        text, expected,
        "URScript changed: review the difference, then rerun with PUSHMOG_UPDATE_GOLDEN=1"
    );
    // A dry run through the runner records the same programs.
    let mut runner = StepRunner::new(translator, DryRun::default());
    runner.run(steps.clone()).unwrap();
    assert_eq!(
        runner.link().programs.len(),
        text.matches("def pushmog_step_").count()
    );
}

/// Each `(from, to, named)`: the example robot file with `from` replaced by `to` is refused, and the
/// error names `named`.
fn each_edit_is_refused_naming(cases: &[(&str, &str, &str)]) {
    let example = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/ur5-example.toml"),
    )
    .unwrap();
    for &(from, to, named) in cases {
        assert!(example.contains(from), "{from}");
        let text = example.replacen(from, to, 1);
        let error = RobotConfig::from_toml(&text, "cell.toml")
            .unwrap_err()
            .to_string();
        assert!(error.contains(named), "{to}: {error}");
    }
}

#[test]
fn bad_robot_configurations_name_the_field() {
    let cases = [
        ("speed = 128", "speed = 999", "speed = 999"), // the parser quotes the line
        ("max_speed = 0.30", "max_speed = -1.0", "safety.max_speed"),
        (
            "closed_count = 230",
            "closed_count = 2",
            "gripper.closed_count",
        ),
        ("[heights]", "[heights]\nbogus = 1.0", "bogus"),
        (
            "# [look]\n# wait = [-0.40, 0.50, 0.30]",
            "[look]\nwait = [-0.40, 2.50, 0.30]",
            "look.wait[1]",
        ),
        (
            "min = [-0.55, 0.20, 0.000]",
            "min = [0.55, 0.20, 0.000]",
            "safety",
        ),
    ];
    each_edit_is_refused_naming(&cases);
    // The example's waiting pose, uncommented, reads.
    let example = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/ur5-example.toml"),
    )
    .unwrap()
    .replacen("# [look]\n# wait", "[look]\nwait", 1);
    let config = RobotConfig::from_toml(&example, "cell.toml").unwrap();
    assert_eq!(config.look, Some(waiting_pose()));
}

/// Issue 38, defect 4: values the UR5 and the 2F-85 cannot take, each refused naming its field.
#[test]
fn robot_files_outside_the_arms_and_grippers_ranges_are_refused() {
    let cases = [
        ("travel = 0.25", "travel = 1e-300", "speeds.travel"),
        ("push = 0.05", "push = 0.5", "speeds.push"), // above max_speed 0.30
        ("max_speed = 0.30", "max_speed = 300.0", "safety.max_speed"),
        ("max_speed = 0.30", "max_speed = 1e308", "safety.max_speed"),
        ("connect = 3.0", "connect = 1e308", "timeouts.connect"),
        (
            "motion_margin = 5.0",
            "motion_margin = 1e308",
            "timeouts.motion_margin",
        ),
        (
            "script_port = 30002",
            "script_port = 0",
            "controller.script_port",
        ),
        (
            "tcp = [0.0, 0.0, 0.175, 0.0, 0.0, 0.0]",
            "tcp = [0.0, 0.0, 100.0, 0.0, 0.0, 0.0]",
            "tcp[2]",
        ),
        (
            "tcp = [0.0, 0.0, 0.175, 0.0, 0.0, 0.0]",
            "tcp = [0.0, 0.0, 0.175, 0.0, 0.0, 1e300]",
            "tcp",
        ),
        ("host = \"192.168.1.10\"", "host = \"\"", "controller.host"),
        ("open_gap = 0.085", "open_gap = 1e-300", "gripper.open_gap"),
        (
            "plate_thickness = 0.010",
            "plate_thickness = 300.0",
            "gripper.plate_thickness",
        ),
        (
            "drop = [-0.45, 0.50, 0.20]",
            "drop = [-0.45, 0.50, 200.0]",
            "bin.drop[2]",
        ),
    ];
    each_edit_is_refused_naming(&cases);
}

/// Issue 38, defect 5: a plan made for wider jaws or other plates than the robot's is refused by
/// `execute`, naming the trip and the field, and no program is written.
#[test]
fn execute_refuses_a_plan_that_does_not_fit_the_configured_gripper() {
    for (field, narrow) in [
        ("gripper.open_gap", 0.04),
        ("gripper.plate_thickness", 0.02),
    ] {
        let mut config = example_config();
        match field {
            "gripper.open_gap" => config.gripper.open_gap = narrow,
            _ => config.gripper.plate_thickness = narrow,
        }
        config.validate().unwrap();
        let dir = scratch(&format!("ur5-fit-{}", field.replace('.', "-")));
        let folder = dir.join("out");
        let out = execute_fixture_plan(&config, &dir, &["--out", folder.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(1), "{field}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains(field) && stderr.contains("trip 1"),
            "{stderr}"
        );
        let written = std::fs::read_dir(&folder).map_or(0, |d| d.count());
        assert_eq!(written, 0, "{field}: wrote {written} files");
    }
}

#[test]
fn a_closed_loop_that_stops_keeps_its_trips() {
    let (observation, reference, policy) = replayed_observations("ur5-closed-loop-fault");
    let faults = GripperFaults {
        fault_at_move: Some((6, 4)),
        ..GripperFaults::default()
    };
    let (controller, gripper) = fakes(ControllerFaults::default(), faults);
    let config = config_for(&controller, &gripper);
    let first = observation.read().unwrap();
    let mut robot = Ur5::new(live_runner(&config), observation);
    let error = policy.run(&first, &mut robot, 5).unwrap_err();
    assert!(error.to_string().contains("FLT 4"), "{error}");
    let trips = robot.trips();
    let (last, finished) = trips.split_last().unwrap();
    // Every trip before the fault is whole and as the ideal run made it; the last one stopped
    // before its grasp was done.
    assert!(last.grasp.is_none());
    for (done, trip) in finished.iter().zip(&reference.trips) {
        assert_eq!(done.grasp.as_ref(), Some(&trip.plan.grasp));
        assert_eq!(done.pushes, trip.plan.pushes);
    }
    assert_eq!(gripper_moves(&gripper).len(), 6);
}

/// The run a closed-loop `pushmog execute` wrote to `folder`, after checking that it exited well and
/// printed a cleared table.
fn cleared_run(out: &Output, folder: &Path) -> Plan {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("status            cleared"), "{stdout}");
    let text = std::fs::read_to_string(folder.join("run.json")).unwrap();
    pushmog::json::from_json(&text, "run").unwrap()
}

#[test]
fn the_cli_runs_a_closed_loop_on_the_fakes() {
    let (observation, reference, _) = replayed_observations("ur5-cli-closed-loop");
    let Observation::Command(command) = observation else {
        unreachable!("replayed observations come from a command")
    };
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let config = config_for(&controller, &gripper);
    let dir = scratch("ur5-cli-closed-loop-out");
    let robot = dir.join("robot.toml");
    std::fs::write(&robot, toml::to_string(&config).unwrap()).unwrap();
    let out = pushmog(&[
        "execute",
        "--robot",
        robot.to_str().unwrap(),
        "--observe-command",
        &command,
        "--policy",
        "push-mog",
        "--seed",
        "5",
        "--execute",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let run = cleared_run(&out, &dir);
    assert_eq!(run.trips.len(), reference.trips.len());
    assert_eq!(run.executor, "ur5");
    assert!(dir.join("executed-trips.json").is_file());
    assert!(!controller.programs().is_empty());
}

/// A plan the verifier rejects never reaches the robot: `execute` refuses it (exit 1, naming the trip
/// and the rule) before writing a dry run or connecting, with `--execute` too.
#[test]
fn the_cli_refuses_a_plan_the_verifier_rejects() {
    let (controller, gripper) = fakes(ControllerFaults::default(), GripperFaults::default());
    let config = config_for(&controller, &gripper);
    let dir = scratch("ur5-cli-unverified");
    // The fixture plan with its first trip's grasp claiming an object twice.
    let mut plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("ur5/plan.json")).unwrap()).unwrap();
    let first = plan["trips"][0]["carried"][0].clone();
    plan["trips"][0]["carried"]
        .as_array_mut()
        .unwrap()
        .push(first);
    let bad = dir.join("bad-plan.json");
    std::fs::write(&bad, serde_json::to_string(&plan).unwrap()).unwrap();
    let robot = dir.join("robot.toml");
    std::fs::write(&robot, toml::to_string(&config).unwrap()).unwrap();
    for extra in [&[][..], &["--execute"][..]] {
        let out_dir = dir.join(if extra.is_empty() { "dry" } else { "live" });
        let mut args = vec![
            "execute",
            bad.to_str().unwrap(),
            "--robot",
            robot.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = pushmog(&args);
        assert_eq!(out.status.code(), Some(1), "{extra:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("verifier") && stderr.contains("trip 0"),
            "{stderr}"
        );
        assert!(!out_dir.exists(), "{extra:?}: something was written");
    }
    assert_eq!(gripper.connections(), 0);
    assert!(controller.programs().is_empty());
}

#[test]
fn fixed_length_arrays_refuse_extra_or_missing_elements() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/ur5-example.toml"),
    )
    .unwrap();
    assert!(RobotConfig::from_toml(&text, "example").is_ok());
    for (from, to) in [
        (
            "max = [0.40, 0.85, 0.400]",
            "max = [0.40, 0.85, 0.400, 99.0]",
        ),
        ("max = [0.40, 0.85, 0.400]", "max = [0.40, 0.85]"),
        (
            "tcp = [0.0, 0.0, 0.175, 0.0, 0.0, 0.0]",
            "tcp = [0.0, 0.0, 0.175, 0.0, 0.0, 0.0, 1.0]",
        ),
        (
            "drop = [-0.45, 0.50, 0.20]",
            "drop = [-0.45, 0.50, 0.20, 0.0]",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let err = RobotConfig::from_toml(&text.replacen(from, to, 1), "bad").unwrap_err();
        assert!(err.to_string().contains("exactly"), "{err}");
    }
}
