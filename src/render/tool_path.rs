//! A top view of a dry run in the robot's base frame: the safety envelope, the bin, the objects of
//! the first observation and the tool's path (travel grey, pushes red, descents and grasps as dots).

use nalgebra::Point2;

use super::{Canvas, Style};
use crate::exec::ur5::{Action, Phase, Step, Translator};
use crate::scene::Scene;

/// The SVG drawing of `steps` over `scene` (its objects drawn through the calibration).
pub fn tool_path_svg(translator: &Translator, scene: &Scene, steps: &[Step]) -> String {
    let config = translator.config();
    let calibration = translator.calibration();
    let safety = &config.safety;
    let margin = 0.02;
    let mut canvas = Canvas::new(
        Point2::new(safety.min[0] - margin, safety.min[1] - margin),
        Point2::new(safety.max[0] + margin, safety.max[1] + margin),
        800.0,
        20.0,
        30.0,
    );
    let (lo, hi) = (safety.min, safety.max);
    canvas.polygon(
        &[
            Point2::new(lo[0], lo[1]),
            Point2::new(hi[0], lo[1]),
            Point2::new(hi[0], hi[1]),
            Point2::new(lo[0], hi[1]),
        ],
        &Style::outline("#999999", 1.0),
    );
    let to_base = |p: &Point2<f64>| {
        let b = calibration.to_base(p.x, p.y, 0.0);
        Point2::new(b.x, b.y)
    };
    let workspace = scene.workspace();
    let corners = [
        Point2::new(workspace.min[0], workspace.min[1]),
        Point2::new(workspace.max[0], workspace.min[1]),
        Point2::new(workspace.max[0], workspace.max[1]),
        Point2::new(workspace.min[0], workspace.max[1]),
    ];
    canvas.polygon(
        &corners.iter().map(to_base).collect::<Vec<_>>(),
        &Style::outline("#555555", 1.5),
    );
    for object in scene.objects() {
        let outline: Vec<_> = object
            .world_polygon()
            .vertices()
            .iter()
            .map(to_base)
            .collect();
        canvas.polygon(&outline, &Style::filled("#d9d9d9", "#666666"));
    }
    let bin = Point2::new(config.bin.drop[0], config.bin.drop[1]);
    canvas.dot(&bin, 10.0, &Style::filled("#8fbc8f", "#2e8b57"));
    canvas.label(&bin, "bin", 12.0, "#2e8b57");

    let mut from: Option<Point2<f64>> = None;
    for step in steps {
        let Action::Move { moves } = &step.action else {
            continue;
        };
        let is_push = step.phase == Phase::Push;
        for m in moves {
            let to = Point2::new(m.to.position[0], m.to.position[1]);
            if let Some(f) = from {
                if (to - f).norm() < 1e-6 {
                    canvas.dot(&to, 2.5, &Style::filled("#1f77b4", "none"));
                } else if is_push {
                    canvas.arrow(&f, &to, 9.0, &Style::outline("#d62728", 2.0));
                } else {
                    canvas.line(&f, &to, &Style::outline("#aaaaaa", 0.8));
                }
            }
            from = Some(to);
        }
    }
    canvas.page_text(
        20.0,
        canvas.height() - 10.0,
        "base frame, top view: envelope (grey box), workspace (dark), travel (grey), pushes (red), \
         descents (blue dots)",
        11.0,
        "#333333",
        "start",
    );
    canvas.finish("pushmog dry run: tool path")
}
