//! What each subcommand does, in terms of library calls.

use std::io::Read as _;
use std::path::Path;

use pushmog::error::{Error, Result};
use pushmog::json::{self, to_json};
use pushmog::render::{RenderOptions, scene_svg};
use pushmog::scene::{
    GeneratorSettings, ObjectSet, Scene, Workspace, builtin_object_set, generate_scene,
};

use super::{GenerateArgs, RenderArgs, SchemaFormat};

/// Reads a file, or standard input for `-`.
fn read_input(path: &Path) -> Result<(String, String)> {
    if path == Path::new("-") {
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        Ok((text, "<stdin>".to_string()))
    } else {
        Ok((json::read_text(path)?, path.display().to_string()))
    }
}

fn read_scene(path: &Path) -> Result<Scene> {
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
    let scene = read_scene(&args.scene)?;
    let options = RenderOptions {
        pixels_per_metre: args.scale,
        show_ids: !args.no_ids,
        show_grasp_diameters: args.grasp_diameters,
        ..RenderOptions::default()
    };
    let title = format!("{} ({} objects)", args.scene.display(), scene.len());
    write_output(args.output.as_deref(), &scene_svg(&scene, &options, &title))
}

pub fn schema(format: SchemaFormat) -> Result<()> {
    let schema = match format {
        SchemaFormat::Scene => json::scene_schema(),
        SchemaFormat::ObjectSet => json::object_set_schema(),
    };
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
    println!(
        "\nwrote {} and {} (open the SVG in a browser)",
        scene_path.display(),
        svg_path.display()
    );
    Ok(())
}
