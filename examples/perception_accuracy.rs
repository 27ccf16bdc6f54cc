//! Measures `perceive` on generated scenes rendered exactly and with the default depth noise: the
//! footprint's intersection over union with the truth, the centroid error, the yaw error and the
//! error in the minimum grasp diameter, per object; prints a summary.
//!
//! `cargo run --release --example perception_accuracy -- [scenes] [tilt-degrees] [noise 0|1] [input]`
//! where `input` is `depth` (the default), `labels` (exact labels and heights, no depth) or `eroded`
//! (labels eroded by 2 pixels, with the depth), `touching` (each object's nearest neighbour slid
//! against it, as a push leaves a pair; exact labels with the depth) or `bars` (the thin-bar set of
//! `experiments/thin-bars.json`); `touching-depth` is `touching` without the labels, and
//! `touching-spill` is `touching` with each label spilled 2 pixels onto the neighbours it touches
//! (the lower id's mask takes in the edge of the higher's).
//! `PUSHMOG_FLYING`, `PUSHMOG_DROPPED` and `PUSHMOG_SIGMA` replace the noise's parameters;
//! `PUSHMOG_PRIOR=1` gives the true scene as the prior, and the pose's yaw error is measured too.
//! `PUSHMOG_LIBRARY=1` names the objects from the scenes' object set instead (no prior): how many
//! take their own shape's name (or that of a shape with the same outline), and the yaw error of the
//! pose found, up to the shape's symmetries.
//! `PUSHMOG_FIT_SIDES=1` turns on `PerceptionSettings::fit_sides`; `PUSHMOG_FIT_OUTLINE=0` turns off
//! `PerceptionSettings::fit_outline` (the median hull alone, as before that option).
//! `PUSHMOG_OBJECT_SET` names an object-set file (JSON) whose shapes the scenes are made of instead.
//! `PUSHMOG_FIRST_SEED` moves the scenes' seeds from `1..=scenes` to start there.
//! `PUSHMOG_WORST=1` also prints each object missed, and each found with IoU under 0.94 or a d*
//! error over 2.5 mm, with its true and perceived outlines (millimetres, table frame). The row
//! `iou, looks that plan` holds the objects of the looks whose `Perception::scene` gives a scene.
//! `PUSHMOG_DUMP=<folder>` writes each look there as files `pushmog perceive` reads
//! (`camera.toml`, `scene-<seed>.json`, `depth-<seed>.npy`, `labels-<seed>.npy`), so that a case
//! can be looked at again from the command line: `pushmog perceive --camera camera.toml --depth
//! depth-<seed>.npy --labels labels-<seed>.npy --state scene-<seed>.json --overlay o.svg` (the
//! scene file gives the workspace; its objects are the truth). The labels written are the exact
//! ones, whatever the input.

use std::collections::BTreeMap;

use nalgebra::Isometry2;
use pushmog::geometry::{ConvexPolygon, intersection_over_union, min_grasp_diameter};
use pushmog::perception::{
    Camera, Depth, DepthNoise, Frame, Identify, PerceptionSettings, add_noise, perceive,
    render_depth,
};
use pushmog::random::SeededRng;
use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};

/// The yaw, within ±10°, that turns `truth` (about its centroid) to fit `seen` best, and that fit.
fn best_yaw(truth: &ConvexPolygon, seen: &ConvexPolygon) -> (f64, f64) {
    let centred = |p: &ConvexPolygon| p.translated(&-p.centroid().coords);
    let (truth, seen) = (centred(truth), centred(seen));
    let fit =
        |yaw: f64| intersection_over_union(&truth.transformed(&Isometry2::rotation(yaw)), &seen);
    let mut best = (0.0, fit(0.0));
    for k in -100..=100 {
        let yaw = f64::from(k) * 0.1_f64.to_radians();
        let f = fit(yaw);
        if f > best.1 {
            best = (yaw, f);
        }
    }
    best
}

/// `labels` with every pixel whose window of radius `r` holds another label set to 0.
/// The turns (radians, in `[0, 2π)`) that map `shape` onto itself about its centroid: multiples of
/// a whole turn's `n`-th part for `n` up to 8.
fn symmetries(shape: &ConvexPolygon) -> Vec<f64> {
    let centred = shape.translated(&-shape.centroid().coords);
    let mut turns = vec![0.0];
    for n in 2..=8 {
        for j in 1..n {
            let t = std::f64::consts::TAU * f64::from(j) / f64::from(n);
            let turned = centred.transformed(&Isometry2::rotation(t));
            if intersection_over_union(&turned, &centred) > 0.999 {
                turns.push(t);
            }
        }
    }
    turns
}

/// `scene` with objects slid together in pairs: each object not yet paired, in order, draws its
/// nearest unpaired neighbour along the line between their centroids until they touch.
fn touching(scene: &pushmog::Scene) -> pushmog::Result<pushmog::Scene> {
    let mut objects = scene.objects().to_vec();
    let mut paired = vec![false; objects.len()];
    for i in 0..objects.len() {
        if paired[i] {
            continue;
        }
        let c = objects[i].world_centroid();
        let Some(j) = (0..objects.len())
            .filter(|&j| j != i && !paired[j])
            .min_by(|&a, &b| {
                let d = |k: usize| (objects[k].world_centroid() - c).norm();
                d(a).total_cmp(&d(b))
            })
        else {
            continue;
        };
        let direction = (c - objects[j].world_centroid()).normalize();
        let others: Vec<_> = (0..objects.len())
            .filter(|&k| k != j)
            .map(|k| objects[k].world_polygon())
            .collect();
        let moving = objects[j].world_polygon();
        let slide = others
            .iter()
            .filter_map(|o| pushmog::geometry::cast_distance(&moving, &direction, 1.0, o))
            .fold(1.0, f64::min);
        objects[j].pose.x += direction.x * slide;
        objects[j].pose.y += direction.y * slide;
        paired[i] = true;
        paired[j] = true;
    }
    scene.with_objects(objects)
}

/// `labels` with each label spilled `r` pixels onto the neighbours it touches, as a segmenter's
/// mask that takes in the edge of the object beside it: a labelled pixel within the `(2r + 1)²`
/// square of a lower label takes the lowest such label. The table stays unlabelled (with depth, a
/// spill onto the table is cut away with it).
fn spill(labels: &[u32], width: usize, r: usize) -> Vec<u32> {
    let height = labels.len() / width;
    (0..labels.len())
        .map(|i| {
            let (u, v) = (i % width, i / width);
            let own = labels[i];
            if own == 0 {
                return 0;
            }
            (v.saturating_sub(r)..=(v + r).min(height - 1))
                .flat_map(|y| (u.saturating_sub(r)..=(u + r).min(width - 1)).map(move |x| (x, y)))
                .map(|(x, y)| labels[y * width + x])
                .filter(|&l| l != 0)
                .fold(own, u32::min)
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let scenes: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(10);
    let tilt: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(0.0);
    let noisy = args.get(3).is_none_or(|a| a != "0");
    let input = args.get(4).map_or("depth", String::as_str);
    let settings = GeneratorSettings::default();
    let above = 0.7;
    let (xc, yc) = (0.3, 0.225);
    let fov = 2.0 * (640.0_f64 / 700.0).atan();
    let tilt = tilt.to_radians();
    let camera =
        Camera::looking_down(1280, 720, fov, xc, yc - above * tilt.tan(), above).tilted(tilt);
    let mut rows: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    let mut statuses: BTreeMap<String, usize> = BTreeMap::new();
    let mut missed = 0;
    let first: u64 = std::env::var("PUSHMOG_FIRST_SEED")
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or(1);
    for seed in first..first + scenes {
        let set = if let Ok(path) = std::env::var("PUSHMOG_OBJECT_SET") {
            serde_json::from_str(&std::fs::read_to_string(path)?)?
        } else if input == "bars" {
            serde_json::from_str(&std::fs::read_to_string("experiments/thin-bars.json")?)?
        } else {
            builtin_object_set()
        };
        let mut scene = generate_scene(&settings, &set, seed)?;
        if input.starts_with("touching") {
            scene = touching(&scene)?;
        }
        let rendered = render_depth(&scene, &camera)?;
        let depth = if noisy {
            let mut noise = DepthNoise::default();
            if let Ok(f) = std::env::var("PUSHMOG_FLYING") {
                noise.flying = f.parse()?;
            }
            if let Ok(f) = std::env::var("PUSHMOG_DROPPED") {
                noise.dropped = f.parse()?;
            }
            if let Ok(f) = std::env::var("PUSHMOG_SIGMA") {
                noise.sigma_per_square_metre = f.parse()?;
            }
            add_noise(&rendered.depth, 1280, &noise, &mut SeededRng::new(seed))
        } else {
            rendered.depth.clone()
        };
        let heights: BTreeMap<u32, f64> = (0..scene.len())
            .map(|k| (k as u32 + 1, scene.objects()[k].height))
            .collect();
        // Labels edited as a segmenter's would be, made only for the inputs that use them.
        let edited = match input {
            "eroded" => Some(pushmog::perception::erode_labels(&rendered.labels, 1280, 2)),
            "touching-spill" => Some(spill(&rendered.labels, 1280, 2)),
            _ => None,
        };
        let frame = match input {
            "touching" => Frame {
                depth: Some(Depth::Metres(&depth)),
                labels: Some(&rendered.labels),
                ..Frame::default()
            },
            "labels" => Frame {
                labels: Some(&rendered.labels),
                heights: Some(&heights),
                ..Frame::default()
            },
            "eroded" | "touching-spill" => Frame {
                depth: Some(Depth::Metres(&depth)),
                labels: edited.as_deref(),
                ..Frame::default()
            },
            _ => Frame {
                depth: Some(Depth::Metres(&depth)),
                ..Frame::default()
            },
        };
        if let Ok(folder) = std::env::var("PUSHMOG_DUMP") {
            let folder = std::path::Path::new(&folder);
            std::fs::create_dir_all(folder)?;
            std::fs::write(folder.join("camera.toml"), toml::to_string(&camera)?)?;
            std::fs::write(
                folder.join(format!("scene-{seed}.json")),
                serde_json::to_string_pretty(&scene.to_spec())?,
            )?;
            let rows = depth.len() / 1280;
            std::fs::write(
                folder.join(format!("depth-{seed}.npy")),
                pushmog::perception::write_npy_f32(&depth, rows, 1280),
            )?;
            std::fs::write(
                folder.join(format!("labels-{seed}.npy")),
                pushmog::perception::write_npy_u32(&rendered.labels, rows, 1280),
            )?;
        }
        let clock = std::time::Instant::now();
        let mut seen = perceive(
            &frame,
            &camera,
            scene.workspace(),
            scene.gripper(),
            std::env::var("PUSHMOG_PRIOR").is_ok().then_some(&scene),
            &PerceptionSettings {
                fit_sides: std::env::var("PUSHMOG_FIT_SIDES").is_ok_and(|v| v == "1"),
                fit_outline: !std::env::var("PUSHMOG_FIT_OUTLINE").is_ok_and(|v| v == "0"),
                ..PerceptionSettings::default()
            },
        )?;
        rows.entry("perceive ms")
            .or_default()
            .push(clock.elapsed().as_secs_f64() * 1e3);
        let library = std::env::var("PUSHMOG_LIBRARY").is_ok();
        if library {
            let clock = std::time::Instant::now();
            seen.name_from(&set, &Identify::default())?;
            rows.entry("naming ms")
                .or_default()
                .push(clock.elapsed().as_secs_f64() * 1e3);
        }
        for b in &seen.blobs {
            rows.entry("solidity").or_default().push(b.solidity);
            let s = serde_json::to_value(&b.status)?["status"]
                .as_str()
                .unwrap_or("?")
                .to_string();
            *statuses.entry(s).or_default() += 1;
        }
        let plans = seen.scene().is_ok();
        for k in 0..scene.len() {
            let truth = scene.world_polygon(k);
            let c = truth.centroid();
            let Some(object) = seen
                .objects
                .iter()
                .min_by(|a, b| {
                    let d = |o: &pushmog::scene::Object| (o.world_centroid() - c).norm();
                    d(a).total_cmp(&d(b))
                })
                .filter(|o| (o.world_centroid() - c).norm() < 0.02)
            else {
                if std::env::var("PUSHMOG_WORST").is_ok() {
                    println!("seed {seed} object {k} missed at {:.1?}", c.coords * 1e3);
                }
                missed += 1;
                continue;
            };
            let print = object.world_polygon();
            let iou = intersection_over_union(truth, &print);
            if plans {
                rows.entry("iou, looks that plan").or_default().push(iou);
            }
            rows.entry("iou").or_default().push(iou);
            rows.entry("centroid mm")
                .or_default()
                .push((print.centroid() - c).norm() * 1e3);
            rows.entry("yaw deg")
                .or_default()
                .push(best_yaw(truth, &print).0.abs().to_degrees());
            if object.id == scene.objects()[k].id && std::env::var("PUSHMOG_PRIOR").is_ok() {
                let turn =
                    pushmog::geometry::wrap_angle(object.pose.yaw - scene.objects()[k].pose.yaw);
                rows.entry("pose yaw deg")
                    .or_default()
                    .push(turn.abs().to_degrees());
            }
            if library {
                // The name of its own shape, or of one with the same outline (a set may repeat a
                // shape under several names, as the thin bars do).
                let own = &scene.objects()[k];
                let right = set
                    .objects
                    .iter()
                    .find(|s| Some(&s.name) == object.name.as_ref())
                    .and_then(|s| s.polygon().ok())
                    .is_some_and(|shape| shape.vertices() == own.polygon.vertices());
                rows.entry("named right")
                    .or_default()
                    .push(f64::from(u8::from(right)));
                if right {
                    let turn = object.pose.yaw - own.pose.yaw;
                    let error = symmetries(&own.polygon)
                        .iter()
                        .map(|t| pushmog::geometry::wrap_angle(turn - t).abs())
                        .fold(f64::INFINITY, f64::min);
                    rows.entry("named yaw deg")
                        .or_default()
                        .push(error.to_degrees());
                }
            }
            let d = min_grasp_diameter(&print).diameter - scene.min_grasp_diameter(k);
            if std::env::var("PUSHMOG_WORST").is_ok() && (iou < 0.94 || d.abs() > 0.0025) {
                let mm = |p: &ConvexPolygon| {
                    p.vertices()
                        .iter()
                        .map(|v| format!("({:.1},{:.1})", v.x * 1e3, v.y * 1e3))
                        .collect::<Vec<_>>()
                        .join(" ")
                };
                println!(
                    "seed {seed} object {k}: iou {:.4} d* {:+.2} mm, height {:.1} mm seen {:.1}\n  truth {}\n  seen  {}",
                    iou,
                    d * 1e3,
                    scene.objects()[k].height * 1e3,
                    object.height * 1e3,
                    mm(truth),
                    mm(&print)
                );
            }
            rows.entry("d* error mm").or_default().push(d * 1e3);
            rows.entry("height mm")
                .or_default()
                .push((object.height - scene.objects()[k].height).abs() * 1e3);
        }
    }
    println!(
        "scenes {scenes}, tilt {:.1}°, noise {noisy}, input {input}, missed {missed}",
        tilt.to_degrees()
    );
    println!("statuses {statuses:?}");
    for (name, mut values) in rows {
        values.sort_by(f64::total_cmp);
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n as f64;
        let p95 = values[(0.95 * (n - 1) as f64).round() as usize];
        println!(
            "{name:>12}: n {n}, mean {mean:.4}, min {:.4}, p95 {p95:.4}, max {:.4}",
            values[0],
            values[n - 1]
        );
    }
    Ok(())
}
