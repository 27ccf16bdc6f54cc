//! A drawing of one scene, built in layers: workspace, objects, then whatever a planner adds (clusters,
//! push arrows, jaw outlines), then ids, a scale bar and a legend on top.

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use super::svg::{Canvas, Style};
use crate::scene::Scene;

/// Drawing settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderOptions {
    /// Pixels per metre. Default 1500 (a 0.6 m workspace is 900 px wide).
    pub pixels_per_metre: f64,
    /// Blank border around the workspace, pixels. Default 24.
    pub margin: f64,
    /// Write each object's id at its centroid. Default true.
    pub show_ids: bool,
    /// Draw each object's narrowest grasp (the minimum-grasp-diameter segment). Default false.
    pub show_grasp_diameters: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            pixels_per_metre: 1500.0,
            margin: 24.0,
            show_ids: true,
            show_grasp_diameters: false,
        }
    }
}

/// Fill of an object no layer has coloured.
pub const OBJECT_FILL: &str = "#d9d9d9";
/// Outline of every object.
pub const OBJECT_STROKE: &str = "#404040";
/// Outline of objects wider than the usable jaw gap.
pub const UNGRASPABLE_STROKE: &str = "#c0392b";

/// Space below the workspace for the scale bar and legend, pixels.
const FOOTER: f64 = 36.0;

/// A scene drawing in progress.
pub struct Figure<'a> {
    scene: &'a Scene,
    options: RenderOptions,
    canvas: Canvas,
    legend: Vec<(String, String)>,
}

impl<'a> Figure<'a> {
    /// Starts a drawing with the workspace outline.
    pub fn new(scene: &'a Scene, options: &RenderOptions) -> Self {
        let workspace = scene.workspace();
        let mut canvas = Canvas::new(
            workspace.min_corner(),
            workspace.max_corner(),
            options.pixels_per_metre,
            options.margin,
            FOOTER,
        );
        canvas.begin_group("workspace");
        let (lo, hi) = (workspace.min_corner(), workspace.max_corner());
        canvas.polygon(
            &[lo, Point2::new(hi.x, lo.y), hi, Point2::new(lo.x, hi.y)],
            &Style::filled("#fbfaf5", "#808080"),
        );
        canvas.end_group();
        Self {
            scene,
            options: options.clone(),
            canvas,
            legend: Vec::new(),
        }
    }

    /// Draws the objects; `fills[i]` overrides the colour of object `i` (missing entries or `None`
    /// keep the default grey).
    pub fn objects(&mut self, fills: &[Option<String>]) {
        self.canvas.begin_group("objects");
        let usable_gap = self.scene.gripper().usable_gap();
        let mut any_ungraspable = false;
        for index in 0..self.scene.len() {
            let fill = fills
                .get(index)
                .and_then(|f| f.clone())
                .unwrap_or_else(|| OBJECT_FILL.to_string());
            let graspable = self.scene.min_grasp_diameter(index) <= usable_gap;
            let mut style = Style::filled(&fill, OBJECT_STROKE);
            if !graspable {
                style.stroke = UNGRASPABLE_STROKE.to_string();
                style.stroke_width = 2.5;
                style.dash = "5 3".to_string();
                any_ungraspable = true;
            }
            self.canvas
                .polygon(self.scene.world_polygon(index).vertices(), &style);
        }
        self.canvas.end_group();
        if any_ungraspable {
            self.legend_entry(UNGRASPABLE_STROKE, "wider than the jaw gap");
        }
        if self.options.show_grasp_diameters {
            self.grasp_diameters();
        }
    }

    fn grasp_diameters(&mut self) {
        self.canvas.begin_group("grasp-diameters");
        let style = Style::outline("#1f6fb2", 1.5);
        for index in 0..self.scene.len() {
            let object = &self.scene.objects()[index];
            let grasp = self.scene.grasp_diameter(index);
            let pose = object.pose.isometry();
            let [near, far] = grasp.contacts(&object.polygon);
            self.canvas.line(&(pose * near), &(pose * far), &style);
        }
        self.canvas.end_group();
    }

    /// The canvas, for layers of other modules (clusters, pushes, jaws), in table coordinates.
    pub fn canvas(&mut self) -> &mut Canvas {
        &mut self.canvas
    }

    /// Adds a legend line: a colour swatch and its meaning.
    pub fn legend_entry(&mut self, colour: &str, text: &str) {
        self.legend.push((colour.to_string(), text.to_string()));
    }

    /// Draws ids, the scale bar and the legend, and returns the SVG document.
    pub fn finish(mut self, title: &str) -> String {
        if self.options.show_ids {
            self.canvas.begin_group("ids");
            let size = (self.options.pixels_per_metre * 0.009).clamp(7.0, 16.0);
            for index in 0..self.scene.len() {
                let text = self.scene.objects()[index].id.to_string();
                let at = self.scene.centroid(index);
                self.canvas.label(&at, &text, size, "#202020");
            }
            self.canvas.end_group();
        }
        self.scale_bar();
        self.draw_legend();
        self.canvas.finish(title)
    }

    fn scale_bar(&mut self) {
        // The longest of 1, 2, 5 × 10^k metres that fits a quarter of the workspace width.
        let width = self.scene.workspace().width();
        let mut length = 10f64.powf((width / 4.0).log10().floor());
        for factor in [5.0, 2.0] {
            if length * factor <= width / 4.0 {
                length *= factor;
                break;
            }
        }
        let y = self.canvas.height() - FOOTER / 2.0;
        let x0 = self.options.margin;
        let x1 = x0 + length * self.canvas.scale();
        let style = Style::outline("#202020", 2.0);
        self.canvas.begin_group("scale-bar");
        self.canvas.page_line((x0, y), (x1, y), &style);
        self.canvas.page_line((x0, y - 4.0), (x0, y + 4.0), &style);
        self.canvas.page_line((x1, y - 4.0), (x1, y + 4.0), &style);
        let text = if length >= 1.0 {
            format!("{length} m")
        } else if length >= 0.01 {
            format!("{} cm", (length * 100.0).round())
        } else {
            format!("{} mm", (length * 1000.0).round())
        };
        self.canvas
            .page_text(x1 + 6.0, y, &text, 12.0, "#202020", "start");
        self.canvas.end_group();
    }

    fn draw_legend(&mut self) {
        if self.legend.is_empty() {
            return;
        }
        let y = self.canvas.height() - FOOTER / 2.0;
        let mut x = self.canvas.width() - self.options.margin;
        self.canvas.begin_group("legend");
        for (colour, text) in self.legend.clone().iter().rev() {
            self.canvas.page_text(x, y, text, 12.0, "#202020", "end");
            x -= 7.0 * text.chars().count() as f64 + 8.0;
            let style = Style::outline(colour, 3.0);
            self.canvas.page_line((x - 14.0, y), (x, y), &style);
            x -= 30.0;
        }
        self.canvas.end_group();
    }
}
