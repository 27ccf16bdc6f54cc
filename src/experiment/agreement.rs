//! How far the planner's grasp predictions hold in physics: every grasp a policy plans on seeded
//! scenes is replayed in the simulator from the scene the planner assumed (after its pushes), without
//! and with perception and actuation noise, and what physics carries is set against what was
//! predicted.
//!
//! Runs with the ideal executor give the trips, so the pushes land exactly where planned and only the
//! grasp model is judged. For each trip's grasp the simulator is set to the predicted table (with
//! noise: every pose moved by the perception noise, as the world differs from what the camera saw),
//! closes the jaws as planned (with actuation noise) and reports what it lifted. A grasp *holds* when
//! physics carries every object it predicted. A sample of the candidates the model refused — jaws
//! that catch two or more objects without a plate on any — is replayed too: physics carrying all
//! they catch is a *false refusal*.

use rayon::prelude::*;

use super::tables::table::{Cell, Column, Table};
use crate::error::Result;
use crate::exec::{Executor, Sim, SimSettings};
use crate::grasp::{Grasp, centre_line_offset};
use crate::policy::{Policy, PolicyKind, PolicySettings};
use crate::push::predict;
use crate::random::SeededRng;
use crate::scene::{GeneratorSettings, Scene, builtin_object_set, generate_scene, perturb};

/// What to replay.
#[derive(Clone, Debug)]
pub struct AgreementSettings {
    /// Scenes, seeded `first_seed`, `first_seed + 1`, …
    pub scenes: usize,
    /// Seed of the first scene.
    pub first_seed: u64,
    /// Objects per scene (the workspace keeps the 34-object density).
    pub objects: usize,
    /// The policy whose grasps are replayed.
    pub policy: PolicyKind,
    /// Its settings.
    pub policy_settings: PolicySettings,
    /// The simulator (its noise is used for the noisy replays; the noise-free ones zero it).
    pub sim: SimSettings,
    /// Refused candidates replayed per trip (0: none).
    pub refused_per_trip: usize,
}

impl Default for AgreementSettings {
    fn default() -> Self {
        Self {
            scenes: 10,
            first_seed: 1,
            objects: 34,
            policy: PolicyKind::PushMog,
            policy_settings: PolicySettings::default(),
            sim: SimSettings::default(),
            refused_per_trip: 2,
        }
    }
}

/// One replayed grasp.
#[derive(Clone, Debug, PartialEq)]
pub struct Replay {
    /// Scene seed.
    pub scene_seed: u64,
    /// Trip of the planner's run (0-based).
    pub trip: usize,
    /// Replayed with perception and actuation noise.
    pub noisy: bool,
    /// A candidate the model refused (rather than the grasp it planned).
    pub refused: bool,
    /// Objects predicted carried (for a refused candidate: objects caught between the plates).
    pub predicted: usize,
    /// Of those, how many physics carried.
    pub carried_predicted: usize,
    /// Objects physics carried in all.
    pub carried: usize,
    /// A plate or finger came down on an object.
    pub landed: bool,
    /// Furthest distance of a predicted object's centroid from the plates' centre line, metres.
    pub offset: f64,
}

impl Replay {
    /// Physics carried every predicted object.
    pub fn held(&self) -> bool {
        self.carried_predicted == self.predicted
    }
}

/// Replays every grasp of `settings.policy` on the seeded scenes (scenes in parallel).
///
/// # Errors
/// Invalid settings, or a scene the generator cannot place.
pub fn replay_grasps(settings: &AgreementSettings) -> Result<Vec<Replay>> {
    let policy = Policy::new(settings.policy, settings.policy_settings.clone())?;
    let generator = GeneratorSettings {
        objects: settings.objects,
        workspace: crate::scene::Workspace::new(
            0.6 * (settings.objects as f64 / 34.0).sqrt(),
            0.45 * (settings.objects as f64 / 34.0).sqrt(),
        ),
        ..GeneratorSettings::default()
    };
    let set = builtin_object_set();
    let per_scene: Vec<Result<Vec<Replay>>> = (0..settings.scenes as u64)
        .into_par_iter()
        .map(|k| {
            let seed = settings.first_seed + k;
            let scene = generate_scene(&generator, &set, seed)?;
            replay_scene(settings, &policy, &scene, seed)
        })
        .collect();
    let mut all = Vec::new();
    for replays in per_scene {
        all.extend(replays?);
    }
    Ok(all)
}

fn replay_scene(
    settings: &AgreementSettings,
    policy: &Policy,
    scene: &Scene,
    seed: u64,
) -> Result<Vec<Replay>> {
    let mut ideal = policy.ideal();
    let plan = policy.run(scene, &mut ideal, seed)?;
    let mut replays = Vec::new();
    let noiseless = SimSettings::noiseless_from(&settings.sim);
    for (trip_index, trip) in plan.trips.iter().enumerate() {
        // The grasp was planned on the last table seen in the trip after the pushes that followed.
        let (seen, start) = trip.last_plan_scene();
        let predicted = predict(&Scene::new(seen.to_spec())?, &trip.plan.pushes[start..])?;
        let mut grasps: Vec<(bool, Grasp)> = vec![(false, trip.plan.grasp.clone())];
        if settings.refused_per_trip > 0
            && let Some(cluster) = trip.plan.cluster
        {
            let members = &trip.plan.clustering.clusters[cluster];
            for refused in policy
                .refused_candidates(&predicted, members)?
                .into_iter()
                .take(settings.refused_per_trip)
            {
                grasps.push((true, refused));
            }
        }
        for (refused, grasp) in grasps {
            let indices = predicted.indices_of(&grasp.objects)?;
            let offset = centre_line_offset(&predicted, &grasp.jaws, &indices);
            for noisy in [false, true] {
                let case_seed = seed
                    .wrapping_mul(1_000_003)
                    .wrapping_add(trip_index as u64 * 31 + u64::from(refused) * 7);
                let (sim_settings, world) = if noisy {
                    let mut rng = SeededRng::new(case_seed ^ 0x5eed);
                    let world = perturb(
                        &predicted,
                        &mut rng,
                        settings.sim.perception_position,
                        settings.sim.perception_yaw,
                    )?;
                    (settings.sim.clone(), world)
                } else {
                    (noiseless.clone(), predicted.clone())
                };
                let mut sim = Sim::new(sim_settings, case_seed)?;
                sim.reset(&world)?;
                let result = sim.grasp(&grasp)?;
                let carried_predicted = grasp
                    .objects
                    .iter()
                    .filter(|id| result.carried.contains(id))
                    .count();
                replays.push(Replay {
                    scene_seed: seed,
                    trip: trip_index,
                    noisy,
                    refused,
                    predicted: grasp.objects.len(),
                    carried_predicted,
                    carried: result.carried.len(),
                    landed: result.landing.is_some(),
                    offset,
                });
            }
        }
    }
    Ok(replays)
}

fn rate(held: usize, of: usize) -> String {
    if of == 0 {
        "–".to_string()
    } else {
        format!("{held}/{of} ({:.0} %)", 100.0 * held as f64 / of as f64)
    }
}

/// The agreement tables in Markdown: planned grasps by predicted object count against what physics
/// carried, without and with noise; false holds and false refusals; hold rate by centre-line offset.
pub fn agreement_markdown(replays: &[Replay], title: &str) -> String {
    let tables = [
        by_count_table(replays),
        false_answers_table(replays),
        by_offset_table(replays),
    ];
    let written: Vec<String> = tables.iter().map(Table::markdown).collect();
    format!("{title}\n\n{}", written.join("\n"))
}

/// The planned grasps that were not refused candidates, without or with noise.
fn planned(replays: &[Replay], noisy: bool) -> impl Iterator<Item = &Replay> + '_ {
    replays
        .iter()
        .filter(move |r| !r.refused && r.noisy == noisy)
}

fn noise(noisy: bool) -> Cell {
    Cell::Text(if noisy { "yes" } else { "no" }.to_string())
}

/// Planned grasps by predicted object count, without and with noise, against what was carried.
fn by_count_table(replays: &[Replay]) -> Table {
    let mut rows = Vec::new();
    let most = replays.iter().map(|r| r.predicted).max().unwrap_or(0);
    for k in 1..=most {
        for noisy in [false, true] {
            let group: Vec<&Replay> = planned(replays, noisy)
                .filter(|r| r.predicted == k)
                .collect();
            if group.is_empty() {
                continue;
            }
            let all = group.iter().filter(|r| r.held()).count();
            let none = group.iter().filter(|r| r.carried_predicted == 0).count();
            let landed = group.iter().filter(|r| r.landed).count();
            rows.push(vec![
                Cell::Number(k as f64),
                noise(noisy),
                Cell::Number(group.len() as f64),
                Cell::Text(rate(all, group.len())),
                Cell::Number((group.len() - all - none) as f64),
                Cell::Number(none as f64),
                Cell::Number(landed as f64),
            ]);
        }
    }
    Table {
        columns: vec![
            Column::markdown("predicted objects", 0),
            Column::markdown("noise", 0).left(),
            Column::markdown("grasps", 0),
            Column::markdown("all carried", 0),
            Column::markdown("some carried", 0),
            Column::markdown("none carried", 0),
            Column::markdown("landings", 0),
        ],
        rows,
    }
}

/// Multi-object grasps held, false holds, and refused candidates that physics held.
fn false_answers_table(replays: &[Replay]) -> Table {
    let rows = [false, true]
        .into_iter()
        .map(|noisy| {
            let multi: Vec<&Replay> = planned(replays, noisy)
                .filter(|r| r.predicted >= 2)
                .collect();
            let held = multi.iter().filter(|r| r.held()).count();
            let refused: Vec<&Replay> = replays
                .iter()
                .filter(|r| r.refused && r.noisy == noisy)
                .collect();
            let false_refusals = refused.iter().filter(|r| r.held()).count();
            vec![
                noise(noisy),
                Cell::Text(rate(held, multi.len())),
                Cell::Text(rate(multi.len() - held, multi.len())),
                Cell::Number(refused.len() as f64),
                Cell::Text(rate(false_refusals, refused.len())),
            ]
        })
        .collect();
    Table {
        columns: vec![
            Column::markdown("noise", 0).left(),
            Column::markdown("multi-object grasps held", 0),
            Column::markdown("false holds", 0),
            Column::markdown("refused candidates replayed", 0),
            Column::markdown("false refusals", 0),
        ],
        rows,
    }
}

/// Hold rate of multi-object grasps by the furthest caught centroid's distance from the jaw centre
/// line, without and with noise.
fn by_offset_table(replays: &[Replay]) -> Table {
    let rows = OFFSET_BINS
        .iter()
        .map(|&(lo, hi)| {
            let cell = |noisy: bool| {
                let group: Vec<&Replay> = planned(replays, noisy)
                    .filter(|r| r.predicted >= 2 && r.offset >= lo && r.offset < hi)
                    .collect();
                Cell::Text(rate(group.iter().filter(|r| r.held()).count(), group.len()))
            };
            let label = if hi.is_finite() {
                format!("{:.0}–{:.0} mm", lo * 1e3, hi * 1e3)
            } else {
                format!("over {:.0} mm", lo * 1e3)
            };
            vec![Cell::Text(label), cell(false), cell(true)]
        })
        .collect();
    Table {
        columns: vec![
            Column::markdown("furthest centroid from the jaw centre line", 0).left(),
            Column::markdown("held, no noise", 0),
            Column::markdown("held, with noise", 0),
        ],
        rows,
    }
}

/// Offset bins of the agreement report, metres.
pub const OFFSET_BINS: [(f64, f64); 5] = [
    (0.0, 0.005),
    (0.005, 0.010),
    (0.010, 0.015),
    (0.015, 0.020),
    (0.020, f64::INFINITY),
];

/// Hold rate of the planned multi-object grasps against the furthest caught centroid's distance from
/// the plates' centre line, without and with noise, as an SVG figure.
///
/// # Errors
/// A drawing failure.
pub fn agreement_svg(replays: &[Replay], title: &str) -> Result<String> {
    use plotters::prelude::*;
    let plot = |e: &dyn std::fmt::Display| crate::Error::field("figure", "plot", e.to_string());
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 440)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0f64..25.0, 0.0f64..105.0)
            .map_err(|e| plot(&e))?;
        chart
            .configure_mesh()
            .x_desc("furthest caught centroid from the jaw centre line (mm; bins of 5 mm, the last open)")
            .y_desc("multi-object grasps held (%)")
            .draw()
            .map_err(|e| plot(&e))?;
        for (noisy, colour, label) in [
            (false, RGBColor(0x4e, 0x79, 0xa7), "no noise"),
            (true, RGBColor(0xe1, 0x57, 0x59), "with noise"),
        ] {
            let points: Vec<(f64, f64)> = OFFSET_BINS
                .iter()
                .filter_map(|&(lo, hi)| {
                    let group: Vec<&Replay> = planned(replays, noisy)
                        .filter(|r| r.predicted >= 2 && r.offset >= lo && r.offset < hi)
                        .collect();
                    (!group.is_empty()).then(|| {
                        let held = group.iter().filter(|r| r.held()).count();
                        (lo * 1e3 + 2.5, 100.0 * held as f64 / group.len() as f64)
                    })
                })
                .collect();
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
                .map_err(|e| plot(&e))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(
                    points
                        .into_iter()
                        .map(|p| Circle::new(p, 4, colour.filled())),
                )
                .map_err(|e| plot(&e))?;
        }
        super::figures::draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
        root.present().map_err(|e| plot(&e))?;
    }
    Ok(svg)
}
