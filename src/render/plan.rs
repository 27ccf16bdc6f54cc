//! Drawing a plan over its first scene: objects coloured by the trip that carries them, each trip's
//! cluster outlined and numbered in execution order, push arrows with dashed targets, and the jaw
//! plates of every grasp.

use nalgebra::Point2;

use super::figure::{Figure, RenderOptions};
use super::svg::{Canvas, Style};
use crate::error::{Error, Result};
use crate::geometry::{ConvexPolygon, convex_hull};
use crate::plan::{Plan, Trip};
use crate::scene::Scene;

/// Colours of trips, cycled (Tableau 10).
const PALETTE: [&str; 10] = [
    "#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7",
    "#9c755f", "#bab0ac",
];

/// The colour of trip `k` (0-based).
pub fn trip_colour(k: usize) -> &'static str {
    PALETTE[k % PALETTE.len()]
}

/// The SVG drawing of a plan over the scene of its first trip.
///
/// # Errors
/// [`Error::InvalidField`] for a plan without trips; scene validation errors for a corrupt plan.
pub fn plan_svg(plan: &Plan, options: &RenderOptions, title: &str) -> Result<String> {
    let first = plan
        .trips
        .first()
        .ok_or_else(|| Error::field("plan", "trips", "the plan has no trips to draw"))?;
    let scene = Scene::new(first.scene.to_spec())?;
    let mut fills: Vec<Option<String>> = vec![None; scene.len()];
    for (k, trip) in plan.trips.iter().enumerate() {
        for id in &trip.carried {
            if let Some(i) = scene.index_of(*id) {
                fills[i] = Some(light(trip_colour(k)));
            }
        }
    }
    let mut figure = Figure::new(&scene, options);
    figure.objects(&fills);
    for (k, trip) in plan.trips.iter().enumerate() {
        let table = Scene::new(trip.scene.to_spec())?;
        draw_trip(
            figure.canvas(),
            trip,
            k,
            &table,
            0..trip.plan.pushes.len(),
            true,
        );
    }
    figure.legend_entry("#202020", "jaw plates");
    figure.legend_entry("#808080", "push (dashed: target)");
    Ok(figure.finish(title))
}

/// The tables a trip was planned on, each with the numbers of the pushes made from it: the trip's
/// own scene, then every look during the trip. The grasp follows the last.
fn stages(trip: &Trip) -> Result<Vec<(Scene, std::ops::Range<usize>)>> {
    let mut tables = vec![(Scene::new(trip.scene.to_spec())?, 0)];
    for look in &trip.looks {
        tables.push((Scene::new(look.scene.to_spec())?, look.after_pushes));
    }
    let ends: Vec<usize> = tables
        .iter()
        .skip(1)
        .map(|t| t.1)
        .chain([trip.plan.pushes.len()])
        .collect();
    Ok(tables
        .into_iter()
        .zip(ends)
        .map(|((table, start), end)| (table, start..end.max(start)))
        .collect())
}

/// One trip's layer on `table`: its cluster outlined and numbered, the pushes numbered `pushes`
/// as arrows from where each started with dashed targets, and, with `jaws`, the jaw plates.
fn draw_trip(
    canvas: &mut Canvas,
    trip: &Trip,
    k: usize,
    table: &Scene,
    pushes: std::ops::Range<usize>,
    jaws: bool,
) {
    let colour = trip_colour(k);
    let cluster = match trip
        .plan
        .cluster
        .and_then(|c| trip.plan.clustering.clusters.get(c))
    {
        Some(cluster) => cluster,
        None => &trip.plan.grasp.objects,
    };
    let members: Vec<usize> = cluster
        .iter()
        .filter_map(|&id| table.index_of(id))
        .collect();
    canvas.begin_group(&format!("trip-{}", k + 1));
    // The cluster's outline, slightly enlarged around its objects.
    let points: Vec<Point2<f64>> = members
        .iter()
        .flat_map(|&i| table.world_polygon(i).vertices().to_vec())
        .collect();
    let hull = convex_hull(&points);
    if hull.len() >= 3 {
        let mut style = Style::outline(colour, 1.5);
        style.dash = "6 3".to_string();
        canvas.polygon(&grow(&hull, 0.006), &style);
    }
    for push in trip.plan.pushes.get(pushes).unwrap_or_default() {
        let Some(i) = table.index_of(push.object) else {
            continue;
        };
        let polygon = &table.objects()[i].polygon;
        let target = polygon.transformed(&push.to.isometry());
        let mut ghost = Style::outline(colour, 1.2);
        ghost.dash = "3 2".to_string();
        canvas.polygon(target.vertices(), &ghost);
        canvas.arrow(
            &polygon.transformed(&push.from.isometry()).centroid(),
            &target.centroid(),
            8.0,
            &Style::outline(colour, 2.0),
        );
    }
    if jaws {
        for plate in trip.plan.grasp.jaws.plates(table.gripper()) {
            let mut style = Style::filled(colour, "#202020");
            style.fill_opacity = 0.85;
            canvas.polygon(plate.vertices(), &style);
        }
    }
    // The trip number beside the cluster.
    if let Some(top) = points.iter().copied().max_by(|a, b| a.y.total_cmp(&b.y)) {
        let at = Point2::new(top.x, top.y + 0.012);
        canvas.dot(&at, 8.0, &Style::filled(colour, "white"));
        canvas.label(&at, &(k + 1).to_string(), 10.0, "white");
    }
    canvas.end_group();
}

/// The SVG drawing of trip `k` of a run over the scene it was planned on: the objects it carried
/// filled, its cluster, pushes and jaws. Of a trip that looked again (`Trip::looks`), stage `s` is
/// its `s`-th table: 0 the trip's scene, then each look, with the pushes made from it; the jaws are
/// drawn on the last.
///
/// # Errors
/// Scene validation errors for a corrupt trip; [`Error::InvalidField`] for a stage the trip does
/// not have.
pub fn trip_svg(
    trip: &Trip,
    k: usize,
    stage: usize,
    options: &RenderOptions,
    title: &str,
) -> Result<String> {
    let mut stages = stages(trip)?;
    let last = stages.len() - 1;
    if stage > last {
        return Err(Error::field(
            format!("trip {k}"),
            "stage",
            format!("the trip has stages 0 to {last}, not {stage}"),
        ));
    }
    let (scene, pushes) = stages.swap_remove(stage);
    Ok(stage_svg(
        trip,
        k,
        &scene,
        pushes,
        stage == last,
        options,
        title,
    ))
}

/// One stage of trip `k` drawn on `table`: the objects it carried filled, its cluster, the pushes
/// numbered `pushes` and, with `jaws`, the jaw plates.
fn stage_svg(
    trip: &Trip,
    k: usize,
    table: &Scene,
    pushes: std::ops::Range<usize>,
    jaws: bool,
    options: &RenderOptions,
    title: &str,
) -> String {
    stage_svg_within(trip, k, table, (pushes, jaws), None, options, title)
}

/// As [`stage_svg`], with `workspace`, when the trip was planned on a table grown past it (an
/// object taken from past its edge, `run.reach_past_edge`), outlined dashed.
fn stage_svg_within(
    trip: &Trip,
    k: usize,
    table: &Scene,
    (pushes, jaws): (std::ops::Range<usize>, bool),
    workspace: Option<&crate::scene::Workspace>,
    options: &RenderOptions,
    title: &str,
) -> String {
    let fills: Vec<Option<String>> = table
        .objects()
        .iter()
        .map(|o| trip.carried.contains(&o.id).then(|| light(trip_colour(k))))
        .collect();
    let mut figure = Figure::new(table, options);
    if let Some(w) = workspace {
        let mut style = Style::outline("#606060", 1.5);
        style.dash = "6 4".to_string();
        let corners = [
            Point2::new(w.min[0], w.min[1]),
            Point2::new(w.max[0], w.min[1]),
            Point2::new(w.max[0], w.max[1]),
            Point2::new(w.min[0], w.max[1]),
        ];
        figure.canvas().polygon(&corners, &style);
        figure.legend_entry("#606060", "workspace (dashed), the table grown past it");
    }
    figure.objects(&fills);
    draw_trip(figure.canvas(), trip, k, table, pushes, jaws);
    figure.legend_entry("#202020", "jaw plates");
    figure.finish(title)
}

/// A self-contained HTML page to step through a run trip by trip (buttons or arrow keys), each frame
/// the observation the trip was planned on with its pushes and grasp, and what it carried; a trip
/// that looked again during its pushes has a frame for every look.
///
/// # Errors
/// As [`trip_svg`].
pub fn replay_html(plan: &Plan, options: &RenderOptions) -> Result<String> {
    let mut frames = Vec::with_capacity(plan.trips.len());
    let workspace = plan.trips.first().map(|t| t.scene.workspace.clone());
    for (k, trip) in plan.trips.iter().enumerate() {
        let past_edge = workspace.as_ref().filter(|w| **w != trip.scene.workspace);
        let carried: Vec<String> = trip.carried.iter().map(|id| id.to_string()).collect();
        let mut carried = format!(
            "carried {} ({})",
            trip.carried.len(),
            if carried.is_empty() {
                "nothing".to_string()
            } else {
                carried.join(", ")
            }
        );
        if !trip.lost.is_empty() {
            let lost: Vec<String> = trip
                .lost
                .iter()
                .map(|l| format!("{} ({})", l.object, l.reason))
                .collect();
            carried.push_str(&format!("; lost {}", lost.join(", ")));
        }
        let stages = stages(trip)?;
        for (stage, (table, pushes)) in stages.iter().enumerate() {
            let look = match stage {
                0 => String::new(),
                _ => format!(", look {} after {} pushes", stage, pushes.start),
            };
            let last = stage + 1 == stages.len();
            let next = if last {
                format!("{} pushes, then the grasp; {carried}", pushes.len())
            } else {
                format!("{} pushes, then a new look", pushes.len())
            };
            let past = if past_edge.is_some() {
                ", taken from past the workspace's edge"
            } else {
                ""
            };
            let title = format!("trip {} of {}{look}{past}: {next}", k + 1, plan.trips.len());
            let stage = (pushes.clone(), last);
            let svg = stage_svg_within(trip, k, table, stage, past_edge, options, &title);
            frames.push((title, svg));
        }
    }
    let mut html = String::from(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>pushmog replay</title>\n\
         <style>body{font-family:sans-serif;margin:16px} .frame{display:none} .frame.on{display:block}\
         button{font-size:16px;margin-right:8px}</style></head><body>\n",
    );
    html.push_str(&format!(
        "<h2>policy {}, executor {}, seed {}: {} trips, {} objects carried, {:.3} objects per trip</h2>\n",
        escape(&plan.policy),
        escape(&plan.executor),
        plan.seed,
        plan.trips.len(),
        plan.objects_carried(),
        plan.objects_per_trip()
    ));
    html.push_str("<p><button onclick=\"show(-1)\">previous</button><button onclick=\"show(1)\">next</button><span id=\"caption\"></span></p>\n");
    for (k, (title, svg)) in frames.iter().enumerate() {
        html.push_str(&format!(
            "<div class=\"frame{}\" data-title=\"{}\">{}</div>\n",
            if k == 0 { " on" } else { "" },
            escape(title),
            svg
        ));
    }
    html.push_str(
        "<script>let k=0;const f=document.querySelectorAll('.frame');\n\
         function show(d){if(!f.length)return;f[k].classList.remove('on');k=(k+d+f.length)%f.length;\
         f[k].classList.add('on');document.getElementById('caption').textContent=f[k].dataset.title;}\n\
         document.addEventListener('keydown',e=>{if(e.key==='ArrowRight')show(1);if(e.key==='ArrowLeft')show(-1);});\n\
         show(0);</script></body></html>\n",
    );
    Ok(html)
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A colour mixed halfway with white, for fills under outlines.
fn light(hex: &str) -> String {
    let channel = |k: usize| u8::from_str_radix(&hex[k..k + 2], 16).unwrap_or(128);
    let mix = |c: u8| (u16::from(c) + 255) / 2;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(channel(1)),
        mix(channel(3)),
        mix(channel(5))
    )
}

/// The hull pushed outward by `by` metres from its centroid (for drawing only).
fn grow(hull: &[Point2<f64>], by: f64) -> Vec<Point2<f64>> {
    let centre = ConvexPolygon::new(hull.to_vec())
        .map(|p| p.centroid())
        .unwrap_or(hull[0]);
    hull.iter()
        .map(|p| {
            let out = p - centre;
            let length = out.norm();
            if length > 0.0 {
                p + out / length * by
            } else {
                *p
            }
        })
        .collect()
}
