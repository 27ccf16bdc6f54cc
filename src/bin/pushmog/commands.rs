//! What each subcommand does, in terms of library calls.

use std::io::Read as _;
use std::path::Path;

use pushmog::cluster::{Clusterer, Hierarchical, HierarchicalSettings, Milp, MilpSettings};
use pushmog::error::{Error, Result};
use pushmog::exec::{ExecutorKind, SimSettings};
use pushmog::experiment::agreement::{
    AgreementSettings, agreement_markdown, agreement_svg, replay_grasps,
};
use pushmog::experiment::{
    ExperimentConfig, Log, RunnerOptions, compare_clustering as compare, comparison_markdown,
    merge_logs_into, read_log, run_experiment, write_report,
};
use pushmog::json::{self, to_json};
use pushmog::plan::{Plan, RunStatus, verify as verify_plan};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::problem::Problem;
use pushmog::render::{RenderOptions, plan_svg, replay_html, scene_svg};
use pushmog::scene::{
    GeneratorSettings, ObjectSet, Scene, Workspace, builtin_object_set, generate_scene,
};

use super::{
    AgreementArgs, ClusterArgs, CompareArgs, ComparePushingArgs, ExperimentArgs, GenerateArgs,
    PlanArgs, RenderArgs, RunArgs, SchemaFormat,
};

/// Reads a file, or standard input for `-`.
fn read_input(path: &Path) -> Result<(String, String)> {
    if path == Path::new("-") {
        let mut bytes = Vec::new();
        std::io::stdin()
            .read_to_end(&mut bytes)
            .map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        Ok((
            json::text_from_bytes(bytes, "<stdin>")?,
            "<stdin>".to_string(),
        ))
    } else {
        Ok((json::read_text(path)?, path.display().to_string()))
    }
}

pub(crate) fn read_scene(path: &Path) -> Result<Scene> {
    let (text, name) = read_input(path)?;
    json::scene_from_json(&text, &name)
}

/// Writes to a file, or to standard output when no path is given.
fn write_output(path: Option<&Path>, text: &str) -> Result<()> {
    match path {
        Some(path) => json::write_text(path, text),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

pub fn generate(args: &GenerateArgs) -> Result<()> {
    let set = match &args.object_set {
        Some(path) => {
            let (text, name) = read_input(path)?;
            json::from_json::<ObjectSet>(&text, &name)?
        }
        None => builtin_object_set(),
    };
    let settings = GeneratorSettings {
        objects: args.objects,
        workspace: Workspace::new(args.width, args.depth),
        max_samples: args.max_samples,
        ..GeneratorSettings::default()
    };
    let scene = generate_scene(&settings, &set, args.seed)?;
    write_output(args.output.as_deref(), &to_json(&scene))
}

pub fn check(path: &Path) -> Result<()> {
    let scene = read_scene(path)?;
    print!("{}", check_report(&scene, &path.display().to_string()));
    Ok(())
}

/// The per-object table printed by `scene check`.
fn check_report(scene: &Scene, name: &str) -> String {
    let gap = scene.gripper().usable_gap();
    let mut out = format!(
        "{name}: {} objects on a {:.3} m × {:.3} m workspace; usable jaw gap {:.1} mm\n\n",
        scene.len(),
        scene.workspace().width(),
        scene.workspace().depth(),
        gap * 1e3
    );
    out.push_str("   id  name                          sides  d* (mm)  graspable\n");
    for (index, object) in scene.objects().iter().enumerate() {
        let d = scene.min_grasp_diameter(index);
        let graspable = if d <= gap {
            "yes".to_string()
        } else {
            format!("NO: wider than the {:.1} mm gap", gap * 1e3)
        };
        out.push_str(&format!(
            "{:>5}  {:<28}  {:>5}  {:>7.2}  {}\n",
            object.id.to_string(),
            object.name.as_deref().unwrap_or("-"),
            object.polygon.len(),
            d * 1e3,
            graspable
        ));
    }
    let ungraspable = scene.ungraspable();
    out.push_str(&format!(
        "\nvalid scene; {} of {} objects ungraspable{}\n",
        ungraspable.len(),
        scene.len(),
        if ungraspable.is_empty() {
            String::new()
        } else {
            format!(
                " (ids {})",
                ungraspable
                    .iter()
                    .map(|id| id.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    ));
    out
}

pub(crate) fn policy(name: &str, settings: Option<&Path>) -> Result<Policy> {
    let kind: PolicyKind = name.parse()?;
    let settings = match settings {
        Some(path) => {
            let (text, source) = read_input(path)?;
            json::from_json::<PolicySettings>(&text, &source)?
        }
        None => PolicySettings::default(),
    };
    Policy::new(kind, settings)
}

pub fn grasp_agreement(args: &AgreementArgs) -> Result<()> {
    let policy = policy(&args.policy, args.settings.as_deref())?;
    let settings = AgreementSettings {
        scenes: args.scenes,
        first_seed: args.seed,
        objects: args.objects,
        policy: policy.kind(),
        policy_settings: policy.settings().clone(),
        sim: settings_or_default(args.sim_settings.as_deref())?,
        refused_per_trip: args.refused,
    };
    let replays = replay_grasps(&settings)?;
    let title = format!(
        "Grasp agreement — {} on {} scenes of {} objects (seeds {}–{}), simulator replays",
        args.policy,
        args.scenes,
        args.objects,
        args.seed,
        args.seed + args.scenes.saturating_sub(1) as u64
    );
    let text = agreement_markdown(&replays, &title);
    if let Some(path) = &args.output {
        json::write_text(path, &text)?;
    }
    if let Some(path) = &args.figure {
        let caption = format!(
            "Multi-object grasps held in the simulator ({})",
            args.policy
        );
        json::write_text(path, &agreement_svg(&replays, &caption)?)?;
    }
    print!("{text}");
    Ok(())
}

pub fn plan(args: &PlanArgs) -> Result<()> {
    let scene = read_scene(&args.scene)?;
    let policy = policy(&args.policy, args.settings.as_deref())?;
    let mut executor = policy.ideal();
    let plan = policy.run(&scene, &mut executor, args.seed)?;
    write_output(args.output.as_deref(), &plan.to_json())?;
    eprint!("{}", summary(&plan, scene.len()));
    Ok(())
}

pub fn run(args: &RunArgs) -> Result<()> {
    let scene = read_scene(&args.scene)?;
    let policy = policy(&args.policy, args.settings.as_deref())?;
    let mut sim: SimSettings = settings_or_default(args.sim_settings.as_deref())?;
    if args.noiseless {
        sim = SimSettings::noiseless_from(&sim);
    }
    let kind: ExecutorKind = args.executor.parse()?;
    let mut executor = kind.build(policy.problem(), sim, args.seed)?;
    let plan = policy.run(&scene, executor.as_mut(), args.seed)?;
    if let Some(path) = &args.plan {
        json::write_text(path, &plan.to_json())?;
    }
    if let Some(path) = &args.replay {
        json::write_text(path, &replay_html(&plan, &RenderOptions::default())?)?;
    }
    print!("{}", summary(&plan, scene.len()));
    Ok(())
}

/// The figures of a run, one per line.
pub(crate) fn summary(plan: &Plan, objects: usize) -> String {
    let mut out = format!(
        "policy {} (executor {}, seed {})\n",
        plan.policy, plan.executor, plan.seed
    );
    out.push_str(&format!(
        "objects           {} on the table, {} carried\n",
        objects,
        plan.objects_carried()
    ));
    out.push_str(&format!("trips             {}\n", plan.trips.len()));
    out.push_str(&format!(
        "objects per trip  {:.3}\n",
        plan.objects_per_trip()
    ));
    out.push_str(&format!(
        "pushes            {} ({:.3} m in total)\n",
        plan.push_count(),
        plan.push_distance()
    ));
    let skipped: usize = plan.trips.iter().map(|t| t.skipped_pushes.len()).sum();
    out.push_str(&format!("pushes skipped    {skipped}\n"));
    out.push_str(&format!("failed grasps     {}\n", plan.failed_grasps()));
    out.push_str(&format!(
        "robot time        {:.1} s ({:.0} picks per hour)\n",
        // Adding zero turns a negative zero into zero ("-0.0 s" for a run with no trips).
        plan.seconds + 0.0,
        plan.picks_per_hour() + 0.0
    ));
    out.push_str(&format!(
        "failed attempts   {}\n",
        plan.failed_attempts.len()
    ));
    if let Some(unproven) = plan.unproven_clusterings() {
        out.push_str(&format!(
            "clusterings       {} of {} trips proven optimal\n",
            plan.trips.len() - unproven,
            plan.trips.len()
        ));
    }
    // Trips counted from 1, as in the replay.
    for (k, trip) in plan.trips.iter().enumerate() {
        for lost in &trip.lost {
            out.push_str(&format!(
                "lost              object {} in trip {} ({})\n",
                lost.object,
                k + 1,
                lost.reason
            ));
        }
    }
    match &plan.status {
        RunStatus::Cleared => out.push_str("status            cleared\n"),
        RunStatus::Stopped { remaining, reason } => out.push_str(&format!(
            "status            stopped with {} objects left: {reason}\n",
            remaining.len()
        )),
    }
    out
}

fn settings_or_default<T: serde::de::DeserializeOwned + Default>(path: Option<&Path>) -> Result<T> {
    match path {
        Some(path) => {
            let (text, source) = read_input(path)?;
            json::from_json::<T>(&text, &source)
        }
        None => Ok(T::default()),
    }
}

pub fn cluster(args: &ClusterArgs) -> Result<()> {
    let scene = read_scene(&args.scene)?;
    let settings = args.settings.as_deref();
    // As a policy with these settings builds its clusterer: shared settings filled in.
    let policy = match args.policy_settings.as_deref() {
        Some(path) => {
            let settings: PolicySettings = settings_or_default(Some(path))?;
            settings.validate()?;
            Some(settings)
        }
        None => None,
    };
    let outcome = match args.method.as_str() {
        "milp" => {
            let milp = match &policy {
                Some(policy) => policy.milp_clusterer(policy.problem()?, policy.row_test())?,
                None => Milp::new(
                    settings_or_default::<MilpSettings>(settings)?,
                    Problem::shared_default(),
                )?,
            };
            milp.cluster(&scene)?
        }
        "hierarchical" => {
            let hierarchical = match &policy {
                Some(policy) => policy.clustering.clone(),
                None => settings_or_default::<HierarchicalSettings>(settings)?,
            };
            Hierarchical::new(hierarchical)?.cluster(&scene)?
        }
        other => {
            return Err(Error::field(
                "cluster",
                "--method",
                format!("unknown clusterer `{other}`; choose hierarchical or milp"),
            ));
        }
    };
    for (k, cluster) in outcome.value.clusters.iter().enumerate() {
        let ids: Vec<String> = cluster.iter().map(|id| id.to_string()).collect();
        println!("cluster {k:>3}: {}", ids.join(" "));
    }
    println!("\nstatus       {:?}", outcome.status);
    let stats = &outcome.stats;
    println!("clusters     {}", outcome.value.len());
    if let Some(objective) = stats.objective {
        println!("objective    {objective:.6}");
    }
    if let Some(bound) = stats.bound {
        println!("bound        {bound:.6}");
    }
    if let Some(gap) = stats.gap {
        println!("gap          {gap:.2e}");
    }
    println!("solve time   {:.2} ms", stats.seconds * 1e3);
    if let Some(backend) = &stats.backend_status {
        println!("backend      {backend}");
    }
    for (name, value) in &stats.counters {
        println!("{name:<12} {value}");
    }
    Ok(())
}

pub fn compare_clustering(args: &CompareArgs) -> Result<()> {
    let milp = Milp::new(
        settings_or_default::<MilpSettings>(args.settings.as_deref())?,
        Problem::shared_default(),
    )?;
    // Keep the default object density when the count changes: area grows with the count.
    let base = GeneratorSettings::default();
    let scale = (args.objects as f64 / base.objects as f64).sqrt().max(1.0);
    let generator = GeneratorSettings {
        objects: args.objects,
        workspace: Workspace::new(
            base.workspace.width() * scale,
            base.workspace.depth() * scale,
        ),
        ..base
    };
    eprintln!(
        "comparing on {} scenes of {} objects (seeds {}–{})",
        args.scenes,
        args.objects,
        args.seed,
        (args.seed + args.scenes as u64).saturating_sub(1)
    );
    let rows = compare(
        &generator,
        &builtin_object_set(),
        &milp,
        args.scenes,
        args.seed,
    )?;
    print!("{}", comparison_markdown(&rows));
    if args.per_scene {
        println!(
            "\n| seed | hierarchical trips, as taken | time (s) | milp trips | time (s) | status | solve (ms) | fewest trips | status | solve (ms) |"
        );
        println!("|---:|---:|---:|---:|---:|---|---:|---:|---|---:|");
        for r in &rows {
            println!(
                "| {} | {} | {:.1} | {} | {:.1} | {:?} | {:.2} | {} | {:?} | {:.2} |",
                r.seed,
                r.hierarchical_trips,
                r.hierarchical_seconds,
                r.milp_trips,
                r.milp_seconds,
                r.milp_status,
                r.milp_solve * 1e3,
                r.fewest_trips,
                r.fewest_status,
                r.fewest_solve * 1e3
            );
        }
    }
    for r in &rows {
        for v in &r.violations {
            eprintln!("seed {}: {v}", r.seed);
        }
    }
    Ok(())
}

pub fn compare_pushing(args: &ComparePushingArgs) -> Result<()> {
    let settings: PolicySettings = settings_or_default(args.settings.as_deref())?;
    eprintln!(
        "comparing pushes on {} scenes (seeds {}–{})",
        args.scenes,
        args.seed,
        (args.seed + args.scenes as u64).saturating_sub(1)
    );
    let rows = pushmog::experiment::compare_pushing(
        &GeneratorSettings::default(),
        &builtin_object_set(),
        &settings,
        args.seed..args.seed + args.scenes as u64,
        &mut |done| {
            if done % 10 == 0 || done == args.scenes {
                eprintln!("  {done}/{} scenes compared", args.scenes);
            }
        },
    )?;
    print!("{}", pushmog::experiment::push_comparison_markdown(&rows));
    Ok(())
}

fn parse_shard(text: &str) -> Result<(usize, usize)> {
    let bad = || {
        Error::field(
            "experiment",
            "--shard",
            format!("expected i/n with 0 ≤ i < n, got `{text}`"),
        )
    };
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

pub fn experiment(args: &ExperimentArgs) -> Result<()> {
    let config = ExperimentConfig::read(&args.config)?;
    let shard = match &args.shard {
        Some(text) => parse_shard(text)?,
        None => (0, 1),
    };
    let results = std::path::PathBuf::from("experiments/results");
    let log = args.log.clone().unwrap_or_else(|| {
        if shard.1 == 1 {
            results.join(format!("{}.jsonl", config.name))
        } else {
            results.join(format!(
                "{}.shard-{}-of-{}.jsonl",
                config.name, shard.0, shard.1
            ))
        }
    });
    let example = log.with_file_name(format!("{}-example-plan.json", config.name));
    let base = args.config.parent().unwrap_or(Path::new("."));
    let report = run_experiment(
        &config,
        base,
        &RunnerOptions {
            log: log.clone(),
            shard,
            jobs: args.jobs,
            progress: !args.quiet,
            limit: args.limit,
            example_plan: Some(example.clone()),
        },
    )?;
    eprintln!(
        "{}: {} runs in this shard, {} already logged, {} made now; log {}",
        config.name,
        report.total,
        report.resumed,
        report.made,
        log.display()
    );
    if report.resumed + report.made < report.total {
        eprintln!("stopped early: run the same command again to resume");
        return Ok(());
    }
    if shard.1 > 1 {
        eprintln!("shard done: join the shards with `pushmog merge`, then `pushmog report`");
        return Ok(());
    }
    report_files(
        &read_log(&log)?,
        &args.tables,
        &args.figures,
        Some(&example),
    )
}

fn report_files(log: &Log, tables: &Path, figures: &Path, example: Option<&Path>) -> Result<()> {
    let written = write_report(log, tables, figures)?;
    let mut files = written.files;
    if let Some(path) = example.filter(|p| p.exists()) {
        let (text, name) = read_input(path)?;
        let plan: Plan = json::from_json(&text, &name)?;
        let svg_path = figures.join(format!("{}-example.svg", log.header.config.name));
        let title = format!(
            "{}: run 0 ({}), clusters numbered in execution order",
            log.header.config.name, plan.policy
        );
        json::write_text(
            &svg_path,
            &plan_svg(&plan, &RenderOptions::default(), &title)?,
        )?;
        files.push(svg_path);
    }
    print!("{}", pushmog::experiment::tables::results_markdown(log));
    eprintln!();
    for file in &files {
        eprintln!("wrote {}", file.display());
    }
    Ok(())
}

pub fn merge(logs: &[std::path::PathBuf], output: &Path) -> Result<()> {
    let paths: Vec<&Path> = logs.iter().map(|p| p.as_path()).collect();
    let (header, rows) = merge_logs_into(&paths, output)?;
    eprintln!(
        "merged {} logs: {} of {} runs into {}",
        logs.len(),
        rows,
        header.runs,
        output.display()
    );
    Ok(())
}

pub fn report(path: &Path, tables: &Path, figures: &Path) -> Result<()> {
    let log = read_log(path)?;
    let example = path.with_file_name(format!("{}-example-plan.json", log.header.config.name));
    report_files(&log, tables, figures, Some(&example))
}

pub fn verify(path: &Path) -> Result<()> {
    let (text, name) = read_input(path)?;
    let plan: Plan = json::from_json(&text, &name)?;
    let violations = verify_plan(&plan);
    if violations.is_empty() {
        println!("{name}: {} trips verified, no violations", plan.trips.len());
        Ok(())
    } else {
        for v in &violations {
            eprintln!("{v}");
        }
        Err(Error::field(
            name,
            "trips",
            format!("{} violations", violations.len()),
        ))
    }
}

pub fn render(args: &RenderArgs) -> Result<()> {
    if !(args.scale.is_finite() && args.scale > 0.0) {
        return Err(Error::field(
            "render",
            "--scale",
            format!(
                "must be a positive number of pixels per metre, got {}",
                args.scale
            ),
        ));
    }
    let options = RenderOptions {
        pixels_per_metre: args.scale,
        show_ids: !args.no_ids,
        show_grasp_diameters: args.grasp_diameters,
        ..RenderOptions::default()
    };
    let (text, name) = read_input(&args.scene)?;
    // A plan has trips; anything else is read as a scene.
    let is_plan = serde_json::from_str::<serde_json::Value>(&text)
        .map(|v| v.get("trips").is_some())
        .unwrap_or(false);
    let svg = if is_plan {
        let plan: Plan = json::from_json(&text, &name)?;
        let title = format!("{name}: policy {}, {} trips", plan.policy, plan.trips.len());
        plan_svg(&plan, &options, &title)?
    } else {
        let scene = json::scene_from_json(&text, &name)?;
        let title = format!("{name} ({} objects)", scene.len());
        scene_svg(&scene, &options, &title)
    };
    write_output(args.output.as_deref(), &svg)
}

pub fn schema(format: SchemaFormat) -> Result<()> {
    let name = clap::ValueEnum::to_possible_value(&format)
        .map(|v| v.get_name().to_string())
        .unwrap_or_default();
    let schema = pushmog::schema::named(&name).ok_or_else(|| {
        Error::field(
            "schema",
            "format",
            format!("`{name}` is not built into this binary"),
        )
    })?;
    print!("{}", to_json(&schema));
    Ok(())
}

pub fn library(as_json: bool, output: Option<&Path>) -> Result<()> {
    let set = builtin_object_set();
    let text = if as_json {
        to_json(&set)
    } else {
        set.markdown_table()?
    };
    write_output(output, &text)
}

pub fn demo(out: &Path, seed: u64) -> Result<()> {
    let settings = GeneratorSettings::default();
    let scene = generate_scene(&settings, &builtin_object_set(), seed)?;
    let scene_path = out.join("scene.json");
    let svg_path = out.join("scene.svg");
    json::write_text(&scene_path, &to_json(&scene))?;
    let options = RenderOptions {
        show_grasp_diameters: true,
        ..RenderOptions::default()
    };
    let title = format!("pushmog demo scene, seed {seed}");
    json::write_text(&svg_path, &scene_svg(&scene, &options, &title))?;
    print!(
        "{}",
        check_report(&scene, &scene_path.display().to_string())
    );
    println!("\nclearing it with each policy (ideal executor, seed {seed}):\n");
    println!("| policy | trips | objects per trip | pushes | push distance (m) | verified |");
    println!("|---|---:|---:|---:|---:|---|");
    let mut written = Vec::new();
    for kind in PolicyKind::ALL {
        let policy = Policy::new(kind, PolicySettings::default())?;
        let plan = policy.run(&scene, &mut policy.ideal(), seed)?;
        let violations = verify_plan(&plan).len();
        println!(
            "| {kind} | {} | {:.3} | {} | {:.3} | {} |",
            plan.trips.len(),
            plan.objects_per_trip(),
            plan.push_count(),
            plan.push_distance(),
            if violations == 0 {
                "yes".to_string()
            } else {
                format!("NO ({violations} violations)")
            }
        );
        if kind == PolicyKind::PushMog {
            let plan_path = out.join("plan.json");
            let plan_svg_path = out.join("plan.svg");
            json::write_text(&plan_path, &plan.to_json())?;
            let title = format!("push-mog plan, seed {seed}");
            json::write_text(
                &plan_svg_path,
                &plan_svg(&plan, &RenderOptions::default(), &title)?,
            )?;
            written.extend([plan_path, plan_svg_path]);
        }
    }
    println!(
        "\nwrote {}, {} and {} (open the SVGs in a browser)",
        scene_path.display(),
        svg_path.display(),
        written
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}
