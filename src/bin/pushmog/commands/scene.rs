//! `scene generate`, `scene check`, `library` and `demo`: scenes and the object library.

use std::path::Path;

use pushmog::error::Result;
use pushmog::experiment::tables::{Cell, Column, Table};
use pushmog::json::{self, to_json};
use pushmog::plan::verify as verify_plan;
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::render::{RenderOptions, plan_svg, scene_svg};
use pushmog::scene::{
    GeneratorSettings, ObjectSet, Scene, Workspace, builtin_object_set, generate_scene,
};

use crate::GenerateArgs;

use super::io::{read_input, read_scene, write_output};

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
    // Each policy's row is printed as soon as it has cleared the scene: the command's progress.
    let table = Table {
        columns: vec![
            Column::markdown("policy", 0).left(),
            Column::markdown("trips", 0),
            Column::markdown("objects per trip", 3),
            Column::markdown("pushes", 0),
            Column::markdown("push distance (m)", 3),
            Column::markdown("verified", 0).left(),
        ],
        rows: Vec::new(),
    };
    print!("{}", table.markdown_head());
    let mut written = Vec::new();
    for kind in PolicyKind::ALL {
        let policy = Policy::new(kind, PolicySettings::default())?;
        let plan = policy.run(&scene, &mut policy.ideal(), seed)?;
        let violations = verify_plan(&plan).len();
        print!(
            "{}",
            table.markdown_row(&[
                Cell::Text(kind.to_string()),
                Cell::Number(plan.trips.len() as f64),
                Cell::Number(plan.objects_per_trip()),
                Cell::Number(plan.push_count() as f64),
                Cell::Number(plan.push_distance()),
                Cell::Text(if violations == 0 {
                    "yes".to_string()
                } else {
                    format!("NO ({violations} violations)")
                }),
            ])
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
