//! The `pushmog` command line: a thin layer over the library.
//!
//! Exit codes: 0 on success, 1 when the input is invalid (the message names the culprit), 2 on a usage
//! error (clap's convention).

mod commands;
mod execute;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use pushmog::exec::ExecutorKind;

/// Plans fork pushes and multi-object grasps that clear a table of convex polygons in few trips.
#[derive(Parser, Debug)]
#[command(name = "pushmog", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Generate and check scenes.
    #[command(subcommand)]
    Scene(SceneCommand),
    /// Plan how to clear a scene (closed loop with the ideal executor) and write the plan as JSON.
    Plan(PlanArgs),
    /// Clear a scene with a policy and print trips, objects per trip and failures.
    Run(RunArgs),
    /// Cluster one scene and print the clusters with the solver's status and statistics.
    Cluster(ClusterArgs),
    /// Compare hierarchical against optimal (MILP) clustering over seeded scenes; prints a Markdown table.
    CompareClustering(CompareArgs),
    /// Compare the paper's pushes against SOCP push targets on the same clusters; prints a Markdown table.
    ComparePushing(ComparePushingArgs),
    /// Replay every grasp a policy plans on seeded scenes in the simulator, from the scene the
    /// planner assumed, without and with noise; prints how often physics carried what was predicted.
    GraspAgreement(AgreementArgs),
    /// Run an experiment configuration: every run logged, then its tables and figures.
    Experiment(ExperimentArgs),
    /// Join the logs of the shards of one experiment.
    Merge {
        /// Shard logs.
        #[arg(required = true)]
        logs: Vec<PathBuf>,
        /// The merged log.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Rebuild the tables and figures of an experiment log.
    Report(ReportArgs),
    /// Carry a plan out on a UR5 with a Robotiq 2F-85: a dry run by default (URScript, step list and
    /// tool-path drawing written, nothing sent); `--execute` drives the robot.
    Execute(ExecuteArgs),
    /// Check a plan file with the independent verifier.
    Verify {
        /// Plan file written by `pushmog plan`.
        plan: PathBuf,
    },
    /// Turn an overhead depth image (and instance labels) into a scene file: every blob reported,
    /// ids kept from a prior scene; refuses, listing them, when blobs block planning.
    Perceive(PerceiveArgs),
    /// Draw a scene, or a plan (clusters numbered in execution order, push arrows, jaw outlines), as SVG.
    Render(RenderArgs),
    /// Print the JSON Schema of a file format.
    Schema {
        /// Which format.
        #[arg(value_enum)]
        format: SchemaFormat,
    },
    /// Print the built-in object library as a Markdown table (or as an object-set JSON file).
    Library {
        /// Write the object set as JSON instead of the table.
        #[arg(long)]
        json: bool,
        /// Output file (default: standard output).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Generate a seeded scene, check it and draw it: the quick tour of what pushmog does today.
    Demo {
        /// Folder for scene.json and scene.svg.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Seed of the scene.
        #[arg(long, default_value_t = 7)]
        seed: u64,
    },
}

#[derive(Subcommand, Debug)]
enum SceneCommand {
    /// Generate a seeded random scene as the Push-MOG paper did (same seed, same bytes).
    Generate(GenerateArgs),
    /// Validate a scene and print each object's minimum grasp diameter.
    Check {
        /// Scene file (`-` for standard input).
        scene: PathBuf,
    },
}

#[derive(Args, Debug)]
struct GenerateArgs {
    /// Number of objects.
    #[arg(long, default_value_t = 34)]
    objects: usize,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Workspace width (x extent) in metres.
    #[arg(long, default_value_t = 0.6)]
    width: f64,
    /// Workspace depth (y extent) in metres.
    #[arg(long, default_value_t = 0.45)]
    depth: f64,
    /// Object set JSON file (default: the built-in 34 objects).
    #[arg(long)]
    object_set: Option<PathBuf>,
    /// Position samples to draw before giving up.
    #[arg(long, default_value_t = 100_000)]
    max_samples: usize,
    /// Output file (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct PlanArgs {
    /// Scene file (`-` for standard input).
    scene: PathBuf,
    /// Policy: one of the six, or a named preset (`push-mog-time`, `push-mog-time-riders`,
    /// `push-mog-opt-riders`: a policy with settings of its own, `--settings` laid over them).
    #[arg(long, default_value = "push-mog", value_parser = policy_names())]
    policy: String,
    /// Seed of the policy's random choices.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Policy settings as JSON (fields not given keep their defaults, or a preset's;
    /// `pushmog schema policy`).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Output file (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct RunArgs {
    /// Scene file (`-` for standard input).
    scene: PathBuf,
    /// Policy: one of the six, or a named preset (`push-mog-time`, `push-mog-time-riders`,
    /// `push-mog-opt-riders`: a policy with settings of its own, `--settings` laid over them).
    #[arg(long, default_value = "push-mog", value_parser = policy_names())]
    policy: String,
    /// Executor.
    #[arg(long, value_enum, default_value_t = ExecutorKind::Ideal)]
    executor: ExecutorKind,
    /// Simulator settings as JSON (fields not given keep their defaults; `pushmog schema sim`).
    #[arg(long)]
    sim_settings: Option<PathBuf>,
    /// Turn off the simulator's perception and actuation noise.
    #[arg(long)]
    noiseless: bool,
    /// Write an HTML page that steps through the run trip by trip.
    #[arg(long)]
    replay: Option<PathBuf>,
    /// Seed of the policy's random choices.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Policy settings as JSON (fields not given keep their defaults, or a preset's).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Also write the run's plan as JSON here.
    #[arg(long)]
    plan: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct ExecuteArgs {
    /// Plan file written by `pushmog plan` or `pushmog run --plan` (open loop: every trip in turn).
    /// Without it, `--observe-file` or `--observe-command` gives the table and the run is closed-loop.
    plan: Option<PathBuf>,
    /// Robot configuration (TOML; see `robots/ur5-example.toml`, `pushmog schema robot`).
    #[arg(long)]
    robot: PathBuf,
    /// Only write what would be sent (the default).
    #[arg(long, conflicts_with = "execute")]
    dry_run: bool,
    /// Send it to the robot. Without this flag nothing moves.
    #[arg(long)]
    execute: bool,
    /// Folder for what is written: a dry run's program.script, steps.txt and tool-path.svg; an
    /// executed run's executed.txt (the steps completed, and why it stopped); a closed loop's
    /// executed-trips.json (what each trip did, the last one possibly unfinished) and run.json.
    #[arg(long, default_value = "out/ur5")]
    out: PathBuf,
    /// Closed loop: a scene JSON file read again after every trip.
    #[arg(long, conflicts_with_all = ["plan", "observe_command"])]
    observe_file: Option<PathBuf>,
    /// Closed loop: a shell command that prints a scene JSON document, run after every trip.
    #[arg(long, conflicts_with = "plan")]
    observe_command: Option<String>,
    /// Closed loop through a depth camera (TOML, `pushmog schema camera`): `--observe-command` then
    /// writes each frame as `.npy` to `$PUSHMOG_DEPTH` (labels, if any, to `$PUSHMOG_LABELS`)
    /// instead of printing a scene, and the frame is perceived here with the last table, moved by
    /// the pushes since, as the prior.
    #[arg(long, requires_all = ["observe_command", "state"])]
    camera: Option<PathBuf>,
    /// With `--camera`: a scene file whose workspace and gripper the looks are for.
    #[arg(long, requires = "camera")]
    state: Option<PathBuf>,
    /// With `--camera`: the cell's object set (a JSON file, or `builtin`), from which objects seen
    /// without a prior (the first look's) are named, as `pushmog perceive --library` does.
    #[arg(long, requires = "camera")]
    library: Option<PathBuf>,
    /// Policy of the closed loop.
    #[arg(long, default_value = "push-mog", value_parser = policy_names())]
    policy: String,
    /// Policy settings as JSON (fields not given keep their defaults, or a preset's).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Seed of the policy's random choices.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

#[derive(Args, Debug)]
struct ClusterArgs {
    /// Scene file (`-` for standard input).
    scene: PathBuf,
    /// Clusterer.
    #[arg(long, value_enum, default_value_t = ClusterMethod::Milp)]
    method: ClusterMethod,
    /// Settings of the clusterer as JSON (fields not given keep their defaults).
    #[arg(long, conflicts_with = "policy_settings")]
    settings: Option<PathBuf>,
    /// Policy settings as JSON (`pushmog schema policy`): the clusterer as a policy with them builds
    /// it, with the policy's `time_model`, `min_push`, `socp.margin` and `clustering` shared in.
    #[arg(long)]
    policy_settings: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct CompareArgs {
    /// Number of scenes.
    #[arg(long, default_value_t = 100)]
    scenes: usize,
    /// Seed of the first scene (the others follow).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Objects per scene.
    #[arg(long, default_value_t = 34)]
    objects: usize,
    /// MILP settings as JSON (fields not given keep their defaults).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Also print one row per scene.
    #[arg(long)]
    per_scene: bool,
}

#[derive(Args, Debug)]
struct ComparePushingArgs {
    /// Number of scenes.
    #[arg(long, default_value_t = 200)]
    scenes: usize,
    /// Seed of the first scene (the others follow).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Policy settings as JSON, for the clustering, both push planners and the grasp model.
    #[arg(long)]
    settings: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct AgreementArgs {
    /// Number of scenes.
    #[arg(long, default_value_t = 10)]
    scenes: usize,
    /// Seed of the first scene (the others follow).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Objects per scene.
    #[arg(long, default_value_t = 34)]
    objects: usize,
    /// Policy whose grasps are replayed.
    #[arg(long, default_value = "push-mog", value_parser = policy_names())]
    policy: String,
    /// Policy settings as JSON (fields not given keep their defaults, or a preset's).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Simulator settings as JSON (its noise is used for the noisy replays).
    #[arg(long)]
    sim_settings: Option<PathBuf>,
    /// Refused candidates replayed per trip, to count false refusals.
    #[arg(long, default_value_t = 2)]
    refused: usize,
    /// Also write the tables here (Markdown).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also draw hold rate against centre-line offset here (SVG).
    #[arg(long)]
    figure: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct ExperimentArgs {
    /// The configuration (`experiments/<name>.toml`).
    config: PathBuf,
    /// Run only shard i of n (`--shard 0/4`): runs with number % n == i.
    #[arg(long)]
    shard: Option<String>,
    /// Worker threads (default: one per core).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// The log (default: experiments/results/<name>.jsonl, or <name>.shard-i-of-n.jsonl).
    #[arg(long)]
    log: Option<PathBuf>,
    /// Folder for the tables.
    #[arg(long, default_value = "paper/tables")]
    tables: PathBuf,
    /// Folder for the figures.
    #[arg(long, default_value = "paper/figures")]
    figures: PathBuf,
    /// Stop after this many new runs (the log resumes later).
    #[arg(long)]
    limit: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

#[derive(Args, Debug)]
struct ReportArgs {
    /// The log.
    log: PathBuf,
    /// Folder for the tables.
    #[arg(long, default_value = "paper/tables")]
    tables: PathBuf,
    /// Folder for the figures.
    #[arg(long, default_value = "paper/figures")]
    figures: PathBuf,
}

#[derive(Args, Debug)]
struct RenderArgs {
    /// Scene or plan file (`-` for standard input).
    scene: PathBuf,
    /// Output SVG file (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Pixels per metre (100 to 100 000).
    #[arg(long, default_value_t = 1500.0, value_parser = pixels_per_metre)]
    scale: f64,
    /// Leave out the object ids.
    #[arg(long)]
    no_ids: bool,
    /// Draw each object's narrowest grasp.
    #[arg(long)]
    grasp_diameters: bool,
}

#[derive(clap::Args, Debug)]
struct PerceiveArgs {
    /// The camera: TOML (or JSON by extension), `pushmog schema camera`.
    #[arg(long)]
    camera: PathBuf,
    /// Depth image: `.npy` of float32/float64 metres or uint16 units, or a 16-bit grey PNG in the
    /// camera's `depth.scale` units.
    #[arg(long)]
    depth: Option<PathBuf>,
    /// Instance labels: `.npy` of integers or an 8/16-bit grey PNG, one id per pixel, 0 for none.
    #[arg(long)]
    labels: Option<PathBuf>,
    /// Top heights above the table, metres, of labelled objects, for labels without depth: a JSON
    /// object from label to height, e.g. `{"1": 0.03, "2": 0.045}`.
    #[arg(long)]
    heights: Option<PathBuf>,
    /// The scene expected: the last look, or better the scene predicted after the pushes; its ids
    /// are kept, and its workspace and gripper used unless `--state` is given.
    #[arg(long)]
    prior: Option<PathBuf>,
    /// A scene file whose workspace and gripper the look is for (its objects are not used).
    #[arg(long)]
    state: Option<PathBuf>,
    /// Perception settings as JSON (`pushmog schema perception-settings`).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Names objects seen without a prior from an object set (a JSON file, `pushmog schema
    /// object-set`, or `builtin` for the built-in 34 shapes): each takes the name, mass and frame,
    /// so the yaw, of the set's shape that fits its outline best, when one fits (IoU ≥ 0.85, height
    /// within 5 mm); the report's adjustments say which.
    #[arg(long)]
    library: Option<PathBuf>,
    /// The scene file to write (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// The report of every blob, the table fit and the adjustments, as JSON.
    #[arg(long)]
    report: Option<PathBuf>,
    /// The blobs drawn over the image, as SVG: rejected ones in red with their reasons.
    #[arg(long)]
    overlay: Option<PathBuf>,
}

/// The clusterers `pushmog cluster --method` offers.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum ClusterMethod {
    /// The clustering MILP (proven optimal unless a time limit or gap stops it).
    Milp,
    /// The paper's hierarchical clustering (a heuristic).
    Hierarchical,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum SchemaFormat {
    /// A scene file.
    Scene,
    /// An object-set file.
    ObjectSet,
    /// Policy settings (`--settings` of `plan` and `run`).
    Policy,
    /// Simulator settings (`--sim-settings` of `run`).
    Sim,
    /// Experiment configurations (TOML, same fields).
    Experiment,
    /// Robot configurations of `execute` (TOML, same fields).
    Robot,
    /// Plans and run records (`plan`, `run --plan`, `execute`'s run.json).
    Plan,
    /// One trip as a planner plans it (the Python package's `TripPlan.to_dict()`).
    Trip,
    /// A depth camera's calibration (`pushmog::perception::Camera`).
    Camera,
    /// What a look found besides its objects (`perceive --report`).
    PerceptionReport,
    /// Perception thresholds (`pushmog::perception::PerceptionSettings`).
    PerceptionSettings,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Scene(SceneCommand::Generate(args)) => commands::generate(&args),
        Command::Scene(SceneCommand::Check { scene }) => commands::check(&scene),
        Command::Plan(args) => commands::plan(&args),
        Command::Run(args) => commands::run(&args),
        Command::Verify { plan } => commands::verify(&plan),
        Command::Execute(args) => execute::execute(&args),
        Command::CompareClustering(args) => commands::compare_clustering(&args),
        Command::Cluster(args) => commands::cluster(&args),
        Command::GraspAgreement(args) => commands::grasp_agreement(&args),
        Command::Experiment(args) => commands::experiment(&args),
        Command::Merge { logs, output } => commands::merge(&logs, &output),
        Command::Report(args) => commands::report(&args.log, &args.tables, &args.figures),
        Command::ComparePushing(args) => commands::compare_pushing(&args),
        Command::Render(args) => commands::render(&args),
        Command::Perceive(args) => commands::perceive(&args),
        Command::Schema { format } => commands::schema(format),
        Command::Library { json, output } => commands::library(json, output.as_deref()),
        Command::Demo { out, seed } => commands::demo(&out, seed),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(1)
        }
    }
}

/// The policy names `--policy` accepts, the six policies and the named presets (a usage error,
/// exit 2, for any other).
fn policy_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(pushmog::policy::preset::policy_names())
}

/// `--scale`: a finite number of pixels per metre in a range that gives a drawing a viewer opens.
fn pixels_per_metre(text: &str) -> Result<f64, String> {
    let scale: f64 = text.parse().map_err(|e| format!("{e}"))?;
    if scale.is_finite() && (100.0..=100_000.0).contains(&scale) {
        Ok(scale)
    } else {
        Err(format!(
            "must be between 100 and 100000 pixels per metre, got {text}"
        ))
    }
}
