//! Mutation fuzzing of every input format: scenes, plans, policy and simulator settings, experiment
//! and robot configurations. Each case takes a valid document, changes one to three of its values
//! (extreme numbers, removed fields, repeated or emptied arrays, truncated text) and feeds it to the
//! reader. Every input must be read or refused with an error: no panic. A scene that is read is
//! planned and the plan must pass the independent verifier; policy settings that are read plan a
//! small scene.
//!
//! Experiment logs are mutated in their header, with rows that then no longer match it.
//!
//! The short run in `cargo test` takes 48 cases per format; `PUSHMOG_FUZZ_CASES=5000 cargo test
//! fuzz` runs a longer campaign. Inputs that once broke the tool live in `fixtures/fuzz/` and run
//! every time (`regressions_are_read_or_refused`).

use std::panic::{AssertUnwindSafe, catch_unwind};

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use pushmog::exec::{SimSettings, ur5::RobotConfig};
use pushmog::experiment::ExperimentConfig;
use pushmog::json::{from_json, scene_from_json, to_json};
use pushmog::plan::{Plan, verify};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::{GeneratorSettings, Scene, builtin_object_set, generate_scene};
use serde_json::Value;

use super::support::fixture;

/// Numbers that broke tools before: zero, signs, the smallest subnormal, integer limits, huge and
/// tiny magnitudes.
const EXTREMES: [f64; 16] = [
    0.0,
    -1.0,
    1.0,
    -0.0,
    5e-324,
    1e-12,
    1e-3,
    0.5,
    7.0,
    1e12,
    4_294_967_295.0,
    9_007_199_254_740_993.0,
    1.8e19,
    1e300,
    -1e300,
    1e15,
];

/// One change to a JSON document.
#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the k-th number (in document order, wrapping) by an extreme value.
    Number(usize, usize),
    /// Remove the k-th object field.
    RemoveField(usize),
    /// Repeat the first element of the k-th array.
    Repeat(usize),
    /// Empty the k-th array.
    Empty(usize),
    /// Replace the k-th number by a string.
    Stringify(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), 0..EXTREMES.len()).prop_map(|(k, e)| Mutation::Number(k, e)),
        1 => any::<usize>().prop_map(Mutation::RemoveField),
        1 => any::<usize>().prop_map(Mutation::Repeat),
        1 => any::<usize>().prop_map(Mutation::Empty),
        1 => any::<usize>().prop_map(Mutation::Stringify),
    ]
}

/// Visits every node depth-first, calling `f` with a running index per node kind.
fn visit(value: &mut Value, f: &mut dyn FnMut(&mut Value)) {
    f(value);
    match value {
        Value::Array(items) => items.iter_mut().for_each(|v| visit(v, f)),
        Value::Object(fields) => fields.values_mut().for_each(|v| visit(v, f)),
        _ => {}
    }
}

fn count(value: &mut Value, kind: fn(&Value) -> bool) -> usize {
    let mut n = 0;
    visit(value, &mut |v| {
        if kind(v) {
            n += 1;
        }
    });
    n
}

/// Applies `f` to the `k`-th node (wrapping) of the given kind.
fn at(value: &mut Value, kind: fn(&Value) -> bool, k: usize, f: &mut dyn FnMut(&mut Value)) {
    let n = count(value, kind);
    if n == 0 {
        return;
    }
    let target = k % n;
    let mut seen = 0;
    visit(value, &mut |v| {
        if kind(v) {
            if seen == target {
                f(v);
            }
            seen += 1;
        }
    });
}

fn mutate(value: &mut Value, m: &Mutation) {
    match *m {
        Mutation::Number(k, e) => at(value, Value::is_number, k, &mut |v| {
            let x = EXTREMES[e];
            *v = if x.fract() == 0.0 && (0.0..1.8e19).contains(&x) {
                Value::from(x as u64)
            } else {
                Value::from(x)
            };
        }),
        Mutation::RemoveField(k) => at(value, Value::is_object, k, &mut |v| {
            if let Value::Object(fields) = v
                && let Some(key) = fields.keys().nth(k % fields.len().max(1)).cloned()
            {
                fields.remove(&key);
            }
        }),
        Mutation::Repeat(k) => at(value, Value::is_array, k, &mut |v| {
            if let Value::Array(items) = v
                && let Some(first) = items.first().cloned()
            {
                items.push(first);
            }
        }),
        Mutation::Empty(k) => at(value, Value::is_array, k, &mut |v| {
            if let Value::Array(items) = v {
                items.clear();
            }
        }),
        Mutation::Stringify(k) => at(value, Value::is_number, k, &mut |v| {
            *v = Value::from(v.to_string());
        }),
    }
}

fn cases() -> u32 {
    std::env::var("PUSHMOG_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(48)
}

/// Runs `check` on mutated copies of `seed`; a panic inside `check` fails with the input printed.
fn fuzz(seed: &Value, as_toml: bool, check: &dyn Fn(&str)) {
    let mut runner = TestRunner::new(Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    });
    let strategy = (proptest::collection::vec(mutation(), 1..=3), 0..20usize);
    runner
        .run(&strategy, |(mutations, cut)| {
            let mut value = seed.clone();
            for m in &mutations {
                mutate(&mut value, m);
            }
            let mut text = if as_toml {
                toml::to_string(&value).unwrap_or_else(|_| value.to_string())
            } else {
                value.to_string()
            };
            // One case in twenty is cut short, as a torn write leaves it.
            if cut == 0 {
                let mut end = text.len() * 2 / 3;
                while !text.is_char_boundary(end) {
                    end -= 1;
                }
                text.truncate(end);
            }
            let outcome = catch_unwind(AssertUnwindSafe(|| check(&text)));
            prop_assert!(outcome.is_ok(), "panicked on input:\n{text}");
            Ok(())
        })
        .unwrap();
}

/// Plans a scene that was read with the cheapest multi-object policy; the plan must verify.
fn plan_and_verify(scene: &Scene, kind: PolicyKind, settings: PolicySettings) {
    let Ok(policy) = Policy::new(kind, settings) else {
        return;
    };
    let mut executor = policy.ideal();
    if let Ok(plan) = policy.run(scene, &mut executor, 1) {
        let violations = verify(&plan);
        assert!(violations.is_empty(), "{violations:?}");
    }
}

fn small_scene() -> Scene {
    let settings = GeneratorSettings {
        objects: 6,
        ..GeneratorSettings::default()
    };
    generate_scene(&settings, &builtin_object_set(), 3).unwrap()
}

fn json_of(path: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(fixture(path)).unwrap()).unwrap()
}

#[test]
fn mutated_scenes_are_planned_or_refused() {
    fuzz(&json_of("good/minimal.json"), false, &|text| {
        if let Ok(scene) = scene_from_json(text, "fuzz") {
            plan_and_verify(&scene, PolicyKind::PushMog, PolicySettings::default());
        }
    });
}

#[test]
fn mutated_plans_are_verified_or_refused() {
    fuzz(&json_of("ur5/plan.json"), false, &|text| {
        if let Ok(plan) = from_json::<Plan>(text, "fuzz") {
            let _ = verify(&plan);
        }
    });
}

#[test]
fn mutated_policy_settings_plan_or_are_refused() {
    let seed: Value = serde_json::from_str(&to_json(&PolicySettings::default())).unwrap();
    let scene = small_scene();
    fuzz(&seed, false, &|text| {
        if let Ok(settings) = from_json::<PolicySettings>(text, "fuzz")
            && settings.validate().is_ok()
        {
            plan_and_verify(&scene, PolicyKind::PushMogOpt, settings);
        }
    });
}

#[test]
fn mutated_simulator_settings_are_read_or_refused() {
    let seed: Value = serde_json::from_str(&to_json(&SimSettings::default())).unwrap();
    fuzz(&seed, false, &|text| {
        if let Ok(settings) = from_json::<SimSettings>(text, "fuzz") {
            let _ = settings.validate();
        }
    });
}

#[test]
fn mutated_experiments_are_read_or_refused() {
    let text = std::fs::read_to_string(fixture("../../experiments/paper.toml")).unwrap();
    let seed: Value = toml::from_str(&text).unwrap();
    fuzz(&seed, true, &|text| {
        if let Ok(config) = ExperimentConfig::from_toml(text, "fuzz") {
            // Validation bounds the run count, so expanding the runs is cheap.
            assert!(config.runs().len() <= pushmog::experiment::MAX_RUNS);
        }
    });
}

#[test]
fn mutated_robot_configurations_are_read_or_refused() {
    let text = std::fs::read_to_string(fixture("../../robots/ur5-example.toml")).unwrap();
    let seed: Value = toml::from_str(&text).unwrap();
    fuzz(&seed, true, &|text| {
        let _ = RobotConfig::from_toml(text, "fuzz");
    });
}

#[test]
fn mutated_experiment_logs_are_read_or_refused() {
    let text = std::fs::read_to_string(fixture("../../experiments/results/paper.jsonl")).unwrap();
    let mut lines = text.lines();
    let header: Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    let rows: Vec<&str> = lines.take(3).collect();
    let folder = super::support::scratch("fuzz-logs");
    let counter = std::sync::atomic::AtomicUsize::new(0);
    // The header is mutated; the rows follow it unchanged, so a header that no longer describes
    // them must be refused rather than read.
    fuzz(&header, false, &|text| {
        let n = counter.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let path = folder.join(format!("log-{n}.jsonl"));
        let mut log = format!("{text}\n");
        for row in &rows {
            log.push_str(row);
            log.push('\n');
        }
        std::fs::write(&path, log).unwrap();
        if let Ok(log) = pushmog::experiment::read_log(&path) {
            let _ = pushmog::experiment::tables::results_markdown(&log);
        }
    });
}

/// Every input in `fixtures/fuzz/` once crashed, hung, exhausted memory or was accepted silently.
/// Each is now read and handled, or refused with an error; scenes that are read are planned by the
/// optimal policy and the plan verifies. `bounded-scene-*`, `robot-*`, `policy-*`, `sim-*` and
/// `experiment-*` inputs must be refused (issue 38 added the values without a bound).
#[test]
fn regressions_are_read_or_refused() {
    let folder = fixture("fuzz");
    let mut seen = 0;
    for entry in std::fs::read_dir(&folder).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let text = std::fs::read_to_string(&path).unwrap();
        seen += 1;
        let kind = name.split('.').next().unwrap_or_default();
        if name.starts_with("scene-") {
            if let Ok(scene) = scene_from_json(&text, &name) {
                plan_and_verify(&scene, PolicyKind::PushMogOpt, PolicySettings::default());
            }
        } else if name.starts_with("policy-") {
            if let Ok(settings) = from_json::<PolicySettings>(&text, &name) {
                assert!(settings.validate().is_err(), "{name} should be refused");
            }
        } else if name.starts_with("sim-") {
            if let Ok(settings) = from_json::<SimSettings>(&text, &name) {
                assert!(settings.validate().is_err(), "{name} should be refused");
            }
        } else if name.starts_with("experiment-") {
            assert!(
                ExperimentConfig::from_toml(&text, &name).is_err(),
                "{name} should be refused"
            );
        } else if name.starts_with("bounded-scene-") {
            assert!(
                scene_from_json(&text, &name).is_err(),
                "{name} should be refused"
            );
        } else if name.starts_with("robot-") {
            assert!(
                RobotConfig::from_toml(&text, &name).is_err(),
                "{name} should be refused"
            );
        } else {
            panic!("{name}: unknown kind {kind}");
        }
    }
    assert!(seen > 0);
}

/// A convex contour of 10 000 vertices (a dense segmentation outline) is read as an outline of at
/// most 64 vertices within 0.1 mm of it, and planned.
#[test]
fn a_dense_contour_is_simplified_and_planned() {
    let contour: Vec<[f64; 2]> = (0..10_000)
        .map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / 10_000.0;
            [0.03 * a.cos(), 0.02 * a.sin()]
        })
        .collect();
    let text = serde_json::json!({
        "workspace": {"min": [0.0, 0.0], "max": [0.6, 0.45]},
        "objects": [
            {"id": 0, "vertices": contour, "height": 0.03, "pose": {"x": 0.2, "y": 0.2, "yaw": 0.3}},
            {"id": 1, "vertices": [[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]],
             "height": 0.03, "pose": {"x": 0.25, "y": 0.2, "yaw": 0.0}}
        ]
    })
    .to_string();
    let scene = scene_from_json(&text, "dense").unwrap();
    let outline = &scene.objects()[0].polygon;
    assert!(
        outline.len() <= pushmog::geometry::SIMPLIFY_ABOVE,
        "{}",
        outline.len()
    );
    for &[x, y] in &contour {
        let gap = pushmog::geometry::point_distance(outline, &nalgebra::Point2::new(x, y));
        assert!(
            gap <= pushmog::geometry::SIMPLIFY_TOLERANCE + 1e-12,
            "{gap}"
        );
    }
    plan_and_verify(&scene, PolicyKind::PushMogOpt, PolicySettings::default());
}
