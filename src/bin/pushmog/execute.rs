//! `pushmog execute`: a plan on the UR5, as a dry run (the default) or for real with `--execute`.

use std::path::Path;

use pushmog::error::{Error, Result};
use pushmog::exec::ur5::{
    DepthLook, DryRun, Live, Observation, RobotConfig, Step, StepRunner, Translator, Ur5,
    execute_plan, listing, plan_steps, step_list,
};
use pushmog::json;
use pushmog::perception::PerceptionSettings;
use pushmog::plan::{Plan, verify};
use pushmog::policy::Run;
use pushmog::scene::Scene;

use super::ExecuteArgs;
use super::commands::{policy, read_camera, read_library, read_scene, summary};

fn print_step(index: usize, step: &Step) {
    eprintln!("done {index:4}  {}", step.label);
}

fn read_plan(path: &Path) -> Result<Plan> {
    let text = json::read_text(path)?;
    json::from_json(&text, &path.display().to_string())
}

/// Writes the three dry-run files for `steps` and says what they hold.
fn write_dry_run(
    translator: &Translator,
    scene: Option<&Scene>,
    steps: &[Step],
    out: &Path,
) -> Result<()> {
    let script = out.join("program.script");
    let list = out.join("steps.txt");
    json::write_text(&script, &listing(translator.config(), steps))?;
    json::write_text(&list, &step_list(steps))?;
    let mut written = vec![script.display().to_string(), list.display().to_string()];
    if let Some(scene) = scene {
        let drawing = out.join("tool-path.svg");
        json::write_text(
            &drawing,
            &pushmog::render::tool_path_svg(translator, scene, steps),
        )?;
        written.push(drawing.display().to_string());
    }
    let motions = steps
        .iter()
        .filter(|s| matches!(s.action, pushmog::exec::ur5::Action::Move { .. }))
        .count();
    println!(
        "dry run: {} steps ({motions} motion programs, {} gripper commands), all inside the \
         safety envelope; nothing was sent",
        steps.len(),
        steps.len() - motions
    );
    println!("wrote {}", written.join(", "));
    println!("add --execute to drive the robot");
    Ok(())
}

/// Writes `executed.txt`: every step the robot completed and, when it stopped, why — so a stopped run
/// loses nothing of what is known about it.
fn write_record(steps: &[Step], error: Option<&Error>, out: &Path) -> Result<()> {
    let path = out.join("executed.txt");
    let mut text = step_list(steps);
    if let Some(error) = error {
        text.push_str(&format!("\nstopped: {error}\n"));
    }
    json::write_text(&path, &text)?;
    eprintln!("wrote {} ({} steps completed)", path.display(), steps.len());
    Ok(())
}

fn connect(config: &RobotConfig) -> Result<Live> {
    eprintln!(
        "connecting to {} (script {}, RTDE {}, gripper {})",
        config.controller.host,
        config.controller.script_port,
        config.controller.rtde_port,
        config.controller.gripper_port
    );
    Live::connect(config).map_err(|reason| Error::RobotStopped {
        step: 0,
        label: "connect and activate the gripper".to_string(),
        reason,
        completed: 0,
        last_state: "not connected".to_string(),
    })
}

pub fn execute(args: &ExecuteArgs) -> Result<()> {
    let config = RobotConfig::load(&args.robot)?;
    let translator = Translator::new(config.clone())?;
    let calibration = translator.calibration();
    eprintln!(
        "calibration: {} points, RMS residual {:.2} mm, largest {:.2} mm (point {})",
        config.calibration.points.len(),
        calibration.rms_residual * 1e3,
        calibration.max_residual * 1e3,
        calibration.worst_point
    );
    let observation = match (&args.observe_file, &args.observe_command, &args.camera) {
        (Some(path), _, _) => Some(Observation::File(path.clone())),
        (None, Some(command), Some(camera)) => Some(Observation::Camera(Box::new(DepthLook {
            camera: read_camera(camera)?,
            command: command.clone(),
            table: read_scene(args.state.as_deref().unwrap_or(Path::new("-")))?,
            settings: PerceptionSettings::default(),
            library: args.library.as_deref().map(read_library).transpose()?,
        }))),
        (None, Some(command), None) => Some(Observation::Command(command.clone())),
        (None, None, _) => None,
    };
    match (&args.plan, observation) {
        (Some(path), None) => {
            let plan = read_plan(path)?;
            // Refuse a plan the verifier rejects before writing or connecting anything.
            if let Some(violation) = verify(&plan).first() {
                return Err(Error::field(
                    path.display().to_string(),
                    "plan",
                    format!("refused: the verifier says {violation}"),
                ));
            }
            let scene = plan
                .trips
                .first()
                .map(|t| Scene::new(t.scene.to_spec()))
                .transpose()?;
            let steps = plan_steps(&translator, &plan)?;
            // Refuse an unsafe plan before writing or connecting anything.
            translator.check(&steps, 0)?;
            if args.execute {
                let mut runner =
                    StepRunner::new(translator, connect(&config)?).with_progress(print_step);
                let outcome = runner.run(steps);
                write_record(runner.steps(), outcome.as_ref().err(), &args.out)?;
                outcome?;
                println!(
                    "executed {} steps of {} trips",
                    runner.steps().len(),
                    plan.trips.len()
                );
                Ok(())
            } else {
                write_dry_run(&translator, scene.as_ref(), &steps, &args.out)
            }
        }
        (None, Some(observation)) => {
            let policy = policy(&args.policy, args.settings.as_deref())?;
            let scene = observation.read()?;
            if args.execute {
                let runner =
                    StepRunner::new(translator, connect(&config)?).with_progress(print_step);
                let mut robot = Ur5::new(runner, observation);
                // The run's own record is kept whatever happens: after a fault, run.json holds
                // every trip completed, stopped as interrupted.
                let (plan, stepped) = match Run::start(&policy, &scene, &mut robot, args.seed) {
                    Err(e) => (None, Err(e)),
                    Ok(run) => {
                        let mut run = run.verify_before_acting();
                        let stepped = loop {
                            match run.step(&mut robot) {
                                Ok(Some(_)) => break Ok(()),
                                Ok(None) => {}
                                Err(e) => break Err(e),
                            }
                        };
                        (Some(run.record()), stepped)
                    }
                };
                write_record(robot.runner().steps(), stepped.as_ref().err(), &args.out)?;
                json::write_text(
                    &args.out.join("executed-trips.json"),
                    &json::to_json(&robot.trips()),
                )?;
                if let Some(plan) = &plan {
                    json::write_text(&args.out.join("run.json"), &plan.to_json())?;
                }
                stepped?;
                if let Some(plan) = &plan {
                    print!("{}", summary(plan, scene.len()));
                }
                Ok(())
            } else {
                // Nothing moves in a dry run, so the table would never change: plan the whole run
                // with the ideal executor and show what the robot would be sent.
                let mut ideal = policy.ideal();
                let plan = policy.run(&scene, &mut ideal, args.seed)?;
                let mut runner = StepRunner::new(translator, DryRun::default());
                execute_plan(&mut runner, &plan)?;
                eprintln!(
                    "closed loop shown open: the first observation planned with the ideal executor \
                     ({} trips)",
                    plan.trips.len()
                );
                write_dry_run(runner.translator(), Some(&scene), runner.steps(), &args.out)
            }
        }
        (plan, _) => Err(Error::field(
            "execute",
            "plan",
            if plan.is_some() {
                "give either a plan file or an observation, not both"
            } else {
                "give a plan file (open loop) or --observe-file / --observe-command (closed loop)"
            },
        )),
    }
}
