//! Rows with a rider, each put on the table alone and carried out in the simulator several times:
//! the rider put down on the row by the place action, then the row grasped, lifted and carried
//! sideways as in every trip with riders aboard (`formulations/stacking.md`, "Rows turning in the
//! jaws"). Prints, per row, how many runs carried the rider and the whole row.
//!
//! The rows come from `experiments/data/rows-with-riders.json`, where each entry holds a scene (the
//! row's members as they stood once the jaws had closed, and the rider on the table beside them), the
//! rider's place action and the row's grasp. `python/examples/mujoco_rows.py` runs the same file in
//! MuJoCo.
//!
//! `cargo run --release --example rows_with_riders -- [file] [runs per row]` (defaults: the file
//! above, 5 runs). Runs differ by the simulator's seed, which draws its actuation noise.

use pushmog::exec::{Executor, Sim, SimSettings};
use pushmog::grasp::Grasp;
use pushmog::plan::Rider;
use pushmog::scene::Scene;
use serde::Deserialize;

/// One row of the file.
#[derive(Deserialize)]
struct Entry {
    source: Source,
    scene: Scene,
    rider: Rider,
    grasp: Grasp,
}

/// Where the row was found.
#[derive(Deserialize)]
struct Source {
    scene_seed: u64,
    rapier_turn_degrees: f64,
}

/// What the runs of one row gave.
#[derive(Default)]
struct Tally {
    runs: usize,
    rider_carried: usize,
    row_carried: usize,
    landed: usize,
}

impl Tally {
    fn add(&mut self, other: &Tally) {
        self.runs += other.runs;
        self.rider_carried += other.rider_carried;
        self.row_carried += other.row_carried;
        self.landed += other.landed;
    }
}

fn run(entry: &Entry, seed: u64, tally: &mut Tally) -> pushmog::Result<()> {
    let mut sim = Sim::new(SimSettings::default(), seed)?;
    sim.reset(&entry.scene)?;
    tally.runs += 1;
    if sim.place(&entry.rider)?.is_some() {
        tally.landed += 1;
        return Ok(());
    }
    let result = sim.grasp(&entry.grasp)?;
    if result.landing.is_some() {
        tally.landed += 1;
        return Ok(());
    }
    if result.carried.contains(&entry.rider.object) {
        tally.rider_carried += 1;
    }
    if entry
        .grasp
        .objects
        .iter()
        .all(|id| result.carried.contains(id))
    {
        tally.row_carried += 1;
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .unwrap_or_else(|| "experiments/data/rows-with-riders.json".to_string());
    let runs: u64 = match args.next() {
        Some(text) => text
            .parse()
            .map_err(|_| format!("runs per row must be a whole number, not {text:?}"))?,
        None => 5,
    };
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
    let entries: Vec<Entry> = serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    println!(
        "| row | scene seed | turn logged in rapier, ° | rider carried | row carried whole | landed |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    let mut total = Tally::default();
    for (index, entry) in entries.iter().enumerate() {
        let mut tally = Tally::default();
        for seed in 0..runs {
            run(entry, seed + 1, &mut tally)?;
        }
        println!(
            "| {index} | {} | {:.1} | {}/{} | {}/{} | {} |",
            entry.source.scene_seed,
            entry.source.rapier_turn_degrees,
            tally.rider_carried,
            tally.runs,
            tally.row_carried,
            tally.runs,
            tally.landed
        );
        total.add(&tally);
    }
    println!(
        "\nAll rows: rider carried {}/{}, row carried whole {}/{}, landed {}",
        total.rider_carried, total.runs, total.row_carried, total.runs, total.landed
    );
    Ok(())
}
