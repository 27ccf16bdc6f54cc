//! SVG drawings of scenes (and, as planners land, of their plans).
//!
//! A [`Figure`] draws in layers on a [`Canvas`] that works in table coordinates (metres, y up):
//! the workspace, the objects (colour per object, ungraspable ones outlined in red and dashed), layers
//! added by other modules, then ids, a scale bar and a legend. [`scene_svg`] is the whole drawing of a
//! bare scene; [`plan_svg`] draws a plan: clusters numbered in execution order, push arrows with their
//! targets, and jaw plates.

mod figure;
mod plan;
mod svg;
#[cfg(feature = "robot")]
mod tool_path;

pub use figure::{Figure, OBJECT_FILL, OBJECT_STROKE, RenderOptions, UNGRASPABLE_STROKE};
pub use plan::{plan_svg, replay_html, trip_colour, trip_svg};
pub use svg::{Canvas, Style};
#[cfg(feature = "robot")]
pub use tool_path::tool_path_svg;

use crate::scene::Scene;

/// The SVG drawing of a scene: workspace, objects with ids, a scale bar.
pub fn scene_svg(scene: &Scene, options: &RenderOptions, title: &str) -> String {
    let mut figure = Figure::new(scene, options);
    figure.objects(&[]);
    figure.finish(title)
}
