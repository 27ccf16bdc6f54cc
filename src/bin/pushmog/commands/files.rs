//! `verify`, `render` and `schema`: plan files checked and drawn, formats described.

use std::path::Path;

use pushmog::error::{Error, Result};
use pushmog::json::{self, to_json};
use pushmog::plan::{Plan, verify as verify_plan};
use pushmog::render::{RenderOptions, plan_svg, scene_svg};

use crate::{RenderArgs, SchemaFormat};

use super::io::{read_input, write_output};

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
