//! The time model against the real cell's logs in `experiments/data/`: its parameters are derived
//! from them again here, and its trips and picks per hour reproduce theirs.

use std::collections::BTreeMap;
use std::path::PathBuf;

use pushmog::scene::Gripper;
use pushmog::time_model::TimeModel;

/// One timed attempt of the real cell.
struct Attempt {
    scene: u32,
    multi: bool,
    index: u32,
    execution: Option<f64>,
    planning: f64,
}

/// One scene of the real cell, for one kind of grasp.
struct SceneRecord {
    scene: u32,
    multi: bool,
    objects: u32,
    left: u32,
}

fn data(name: &str) -> Vec<Vec<String>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("experiments/data")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .skip(1)
        .map(|line| line.split(',').map(str::to_string).collect())
        .collect()
}

fn attempts() -> Vec<Attempt> {
    data("real-cell-attempts.csv")
        .into_iter()
        .map(|row| Attempt {
            scene: row[0].parse().unwrap(),
            multi: row[1] == "multi",
            index: row[2].parse().unwrap(),
            execution: (!row[3].is_empty()).then(|| row[3].parse().unwrap()),
            planning: row[4].parse().unwrap(),
        })
        .collect()
}

fn scenes() -> Vec<SceneRecord> {
    data("real-cell-scenes.csv")
        .into_iter()
        .map(|row| SceneRecord {
            scene: row[0].parse().unwrap(),
            multi: row[1] == "multi",
            objects: row[2].parse().unwrap(),
            left: row[3].parse().unwrap(),
        })
        .collect()
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    }
}

/// Picks per hour as the logs' authors computed them: per scene, the objects picked over the summed
/// execution and planning time of the attempts logged without a gap from the first; the mean over
/// scenes. `per_attempt` replaces the logged times of an attempt with the model's, when given.
fn picks_per_hour(multi: bool, per_attempt: Option<f64>) -> f64 {
    let attempts = attempts();
    let mut by_scene: BTreeMap<u32, Vec<&Attempt>> = BTreeMap::new();
    for attempt in attempts.iter().filter(|a| a.multi == multi) {
        by_scene.entry(attempt.scene).or_default().push(attempt);
    }
    let mut rates = Vec::new();
    for record in scenes().iter().filter(|s| s.multi == multi) {
        let mut list = by_scene.remove(&record.scene).unwrap_or_default();
        list.sort_by_key(|a| a.index);
        let counted: Vec<&Attempt> = list
            .iter()
            .enumerate()
            .take_while(|(k, a)| a.index as usize == *k && a.execution.is_some())
            .map(|(_, a)| *a)
            .collect();
        if counted.is_empty() {
            continue;
        }
        let seconds: f64 = match per_attempt {
            Some(each) => each * counted.len() as f64,
            None => counted
                .iter()
                .map(|a| a.execution.unwrap_or(0.0) + a.planning)
                .sum(),
        };
        rates.push(3600.0 * f64::from(record.objects - record.left) / seconds);
    }
    rates.iter().sum::<f64>() / rates.len() as f64
}

#[test]
fn time_model_fit() {
    let attempts = attempts();
    let execution = median(attempts.iter().filter_map(|a| a.execution).collect());
    let planning = median(attempts.iter().map(|a| a.planning).collect());
    println!(
        "real cell: {} timed attempts, median execution {execution:.3} s, median planning {planning:.3} s",
        attempts.iter().filter(|a| a.execution.is_some()).count()
    );
    let model = TimeModel::default();
    let settle = model.fit_settle(execution).unwrap();
    println!(
        "fitted settle {settle:.4} s per command (default {:.4} s)",
        model.arm_settle
    );
    // The defaults are the fit, derived again from the data.
    assert!((settle - model.arm_settle).abs() < 0.001);
    assert!((settle - model.gripper_settle).abs() < 0.001);
    assert!((planning - model.observation).abs() < 0.01);
    // The model's single-object trip, every move stopping as the real cell's did, is the real one;
    // blending the lift into the run to the bin saves one settle.
    let stopping = TimeModel {
        blend_free_moves: false,
        ..model.clone()
    };
    let trip = stopping.nominal_trip_seconds(&Gripper::default());
    let blended = model.nominal_trip_seconds(&Gripper::default());
    println!("model trip {trip:.2} s against {execution:.2} s ({blended:.2} s blending)");
    assert!((trip - execution).abs() < 0.001 * execution);
    assert!((trip - blended - model.arm_settle).abs() < 1e-9);
}

#[test]
fn time_model_reproduces_picks_per_hour() {
    // The real cell stopped after every move.
    let model = TimeModel {
        blend_free_moves: false,
        ..TimeModel::default()
    };
    let per_attempt = model.nominal_trip_seconds(&Gripper::default()) + model.observation;
    for (multi, published) in [(false, 212.0), (true, 340.0)] {
        let logged = picks_per_hour(multi, None);
        let modelled = picks_per_hour(multi, Some(per_attempt));
        println!(
            "{}: published {published}, from the logs {logged:.1}, with the model's times {modelled:.1} picks per hour",
            if multi {
                "multi-object"
            } else {
                "single-object"
            }
        );
        // The logs give the published figure back.
        assert!((logged - published).abs() < 0.01 * published);
        // The model's times give it within 10 %.
        assert!((modelled - published).abs() < 0.1 * published);
    }
}

/// Perception is a cell parameter apart from planning: each observation of a run (every trip, every
/// fruitless planning attempt, every look during a trip) costs it once more, and nothing else changes.
#[test]
fn perception_is_charged_once_per_observation() {
    use pushmog::policy::{Policy, PolicyKind, PolicySettings};
    use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 3).unwrap();
    let run = |perception: f64| {
        let mut settings = PolicySettings::default();
        settings.time_model.perception = perception;
        let policy = Policy::new(PolicyKind::PushMog, settings).unwrap();
        policy.run(&scene, &mut policy.ideal(), 3).unwrap()
    };
    let (without, with) = (run(0.0), run(0.5));
    assert!(with.trips == without.trips);
    let looks: usize = without.trips.iter().map(|t| t.looks.len()).sum();
    assert!(looks > 0);
    let observations = without.trips.len() + without.failed_attempts.len() + looks;
    let extra = with.seconds - without.seconds;
    assert!((extra - 0.5 * observations as f64).abs() < 1e-6, "{extra}");
}
