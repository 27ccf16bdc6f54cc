//! How many riders would fit, by the quasi-static checks of `pushmog::stack`, on push-mog-opt's plans
//! applied exactly: every row a multi-object grasp takes after its pushes may carry one object that
//! a later trip takes by itself. Prints, per support margin, the riders that fit per scene and the
//! objects per trip the plans would reach if each fitting rider rode (one trip saved per rider).
//! Nothing is simulated: physics decides which of them actually ride.
//!
//! `cargo run --release --example rider_room -- [scenes]` (seeds 1 to scenes, default 20)

use pushmog::plan::Plan;
use pushmog::policy::{Policy, PolicyKind};
use pushmog::push::predict;
use pushmog::scene::{GeneratorSettings, Scene, builtin_object_set, generate_scene};
use pushmog::stack::{NoPlacement, Row, StackSettings, place_rider};

/// Rider–row friction: the simulator's default object–object friction.
const FRICTION_OBJECT: f64 = 0.4;

/// Why offered riders were refused: too wide for the strip between the pads, no room on the top,
/// or sliding.
#[derive(Default)]
struct Refusals {
    too_wide: usize,
    no_room: usize,
    other: usize,
}

/// Riders that fit on `plan`'s rows, one per row, each rider taken from the single-object trips
/// after the row's trip, in trip order; every refusal on the way is counted in `refusals`.
fn riders(
    plan: &Plan,
    settings: &StackSettings,
    refusals: &mut Refusals,
) -> pushmog::Result<usize> {
    let mut used = vec![false; plan.trips.len()];
    let mut fitted = 0;
    for (k, trip) in plan.trips.iter().enumerate() {
        if trip.plan.grasp.objects.len() < 2 {
            continue;
        }
        let seen = Scene::new(trip.scene.to_spec())?;
        let table = predict(&seen, &trip.plan.pushes)?;
        let members: Vec<usize> = trip
            .plan
            .grasp
            .objects
            .iter()
            .filter_map(|&id| table.index_of(id))
            .collect();
        let angle = trip.plan.grasp.jaws.angle;
        let row = Row {
            outlines: members
                .iter()
                .map(|&i| table.world_polygon(i).clone())
                .collect(),
            heights: members.iter().map(|&i| table.objects()[i].height).collect(),
            axis: nalgebra::Vector2::new(angle.cos(), angle.sin()),
            // The pads judged from the row as it stands, as when this table was first measured
            // (`formulations/stacking.md`); the planner also judges them once closed.
            closing: None,
        };
        for (later, taken) in plan.trips.iter().zip(used.iter_mut()).skip(k + 1) {
            let single = &later.plan.grasp.objects;
            if *taken || single.len() != 1 {
                continue;
            }
            let Some(index) = table.index_of(single[0]) else {
                continue;
            };
            let rider = &table.objects()[index];
            let fits = place_rider(
                &row,
                &rider.polygon,
                rider.height,
                FRICTION_OBJECT,
                settings,
            );
            match fits {
                Ok(_) => {
                    *taken = true;
                    fitted += 1;
                    break;
                }
                Err(NoPlacement::TooWide) => refusals.too_wide += 1,
                Err(NoPlacement::NoRoom { .. }) => refusals.no_room += 1,
                Err(_) => refusals.other += 1,
            }
        }
    }
    Ok(fitted)
}

fn main() -> pushmog::Result<()> {
    let scenes: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(20);
    let policy = Policy::new(PolicyKind::PushMogOpt, Default::default())?;
    let plans: Vec<Plan> = (1..=scenes)
        .map(|seed| {
            let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed)?;
            policy.run(&scene, &mut policy.ideal(), seed)
        })
        .collect::<pushmog::Result<_>>()?;
    let objects: usize = plans
        .iter()
        .map(|p| p.trips.iter().map(|t| t.carried.len()).sum::<usize>())
        .sum();
    let trips: usize = plans.iter().map(|p| p.trips.len()).sum();
    let count = |wanted: fn(usize) -> bool| -> usize {
        plans
            .iter()
            .flat_map(|p| &p.trips)
            .filter(|t| wanted(t.plan.grasp.objects.len()))
            .count()
    };
    let (rows, singles) = (count(|n| n >= 2), count(|n| n == 1));
    println!(
        "push-mog-opt, plans applied exactly, seeds 1-{scenes}: {objects} objects in {trips} trips, {:.3} per trip",
        objects as f64 / trips as f64
    );
    println!(
        "rows (multi-object grasps) {:.2} per scene, single-object trips {:.2} per scene",
        rows as f64 / scenes as f64,
        singles as f64 / scenes as f64
    );
    println!(
        "| support margin (mm) | riders per scene | objects per trip with them | refused: too wide | no room | other |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    for margin in [0.003, 0.005, 0.008, 0.012] {
        let settings = StackSettings {
            support_margin: margin,
            ..StackSettings::default()
        };
        let mut fitted = 0;
        let mut refusals = Refusals::default();
        for plan in &plans {
            fitted += riders(plan, &settings, &mut refusals)?;
        }
        println!(
            "| {:.0} | {:.2} | {:.3} | {} | {} | {} |",
            margin * 1e3,
            fitted as f64 / scenes as f64,
            objects as f64 / (trips - fitted) as f64,
            refusals.too_wide,
            refusals.no_room,
            refusals.other
        );
    }
    Ok(())
}
