//! Benchmarks of the baselines on 34-object scenes: clustering, push planning for one cluster, grasp
//! planning for one cluster, one trip of push-mog, push-mog-opt and push-mog-time (push-mog-opt priced
//! by expected robot time and pushing ahead, with the settings of `experiments/push-mog-time.json`;
//! the aim of issue 36 is a median of 50 ms per trip)
//! (`Policy::plan_trip`, the call the
//! Python package's `Planner.plan_trip` makes; `python/benches/plan_trip.py` times that one on the
//! same scene), and a whole push-mog run with the ideal executor. Policies cache the closings they
//! have judged (the MILP's last optimum travels in a run's `TripContext`, which `plan_trip` starts
//! afresh), so every iteration gets a fresh policy (built outside the timing): the figures are of
//! cold planning, not of answers recalled.
//!
//! Before the benchmarks it prints the median and 95th percentile of push-mog-time's planning per
//! trip over whole runs (seeds 1-5, plans applied exactly; wall-clock per call, so a shared machine
//! inflates it), on the library's outlines and on the same with rounded corners as a camera traces
//! them (18 to 48 vertices): the aim of issue 36 is a median of 50 ms per trip at 34 objects.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pushmog::cluster::{Clusterer, Hierarchical};
use pushmog::grasp::{GraspPlanner, MultiObject, SingleObject};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::push::{PushPlanner, TowardCentral, predict};
use pushmog::scene::{
    GeneratorSettings, ObjectId, ObjectSet, Scene, builtin_object_set, generate_scene,
};

fn scene() -> Scene {
    generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 1).unwrap()
}

/// The largest cluster of the scene's hierarchical clustering.
fn largest_cluster(scene: &Scene) -> Vec<ObjectId> {
    let clustering = Hierarchical::default().cluster(scene).unwrap().value;
    clustering
        .clusters
        .into_iter()
        .max_by_key(|c| c.len())
        .unwrap()
}

/// Prints the median and 95th percentile of push-mog-time's planning per trip over whole runs of
/// seeds 1-5 on `set`'s outlines, plans applied exactly.
fn print_planning_per_trip(settings: &PolicySettings, outlines: &str, set: &ObjectSet) {
    let mut per_trip: Vec<f64> = (1..=5)
        .flat_map(|seed| {
            let scene = generate_scene(&GeneratorSettings::default(), set, seed).unwrap();
            let policy = Policy::new(PolicyKind::PushMogOpt, settings.clone()).unwrap();
            let (_, timing) = policy.run_timed(&scene, &mut policy.ideal(), seed).unwrap();
            timing.planning
        })
        .collect();
    per_trip.sort_by(f64::total_cmp);
    let at = |q: f64| per_trip[((per_trip.len() - 1) as f64 * q).round() as usize] * 1e3;
    println!(
        "push-mog-time on {outlines}, planning per trip over {} trips (seeds 1-5): median {:.1} ms, \
         p95 {:.1} ms",
        per_trip.len(),
        at(0.5),
        at(0.95)
    );
}

fn baselines(c: &mut Criterion) {
    let scene = scene();
    let cluster = largest_cluster(&scene);
    let pushes = TowardCentral::default()
        .plan(&scene, &cluster)
        .unwrap()
        .value;
    let predicted = predict(&scene, &pushes.pushes).unwrap();

    c.bench_function("cluster/hierarchical/34", |b| {
        b.iter(|| Hierarchical::default().cluster(&scene).unwrap())
    });
    c.bench_function("push/toward-central/largest-cluster", |b| {
        b.iter(|| TowardCentral::default().plan(&scene, &cluster).unwrap())
    });
    c.bench_function("grasp/multi-object/largest-cluster", |b| {
        b.iter(|| MultiObject::default().plan(&predicted, &cluster).unwrap())
    });
    c.bench_function("grasp/single-object/one", |b| {
        b.iter(|| SingleObject::default().plan(&scene, &cluster[..1]).unwrap())
    });
    let fresh = |kind: PolicyKind| move || Policy::new(kind, PolicySettings::default()).unwrap();
    for kind in [PolicyKind::PushMog, PolicyKind::PushMogOpt] {
        c.bench_function(&format!("plan_trip/{}/34", kind.name()), |b| {
            b.iter_batched(
                fresh(kind),
                |policy| policy.plan_trip(&scene).unwrap(),
                BatchSize::SmallInput,
            )
        });
    }
    // push-mog-time's own settings file, as the experiments and the command line use it.
    let timed: PolicySettings =
        serde_json::from_str(include_str!("../experiments/push-mog-time.json")).unwrap();
    // The library's outlines, and the same with every corner rounded as a camera traces it.
    let rounded: ObjectSet =
        serde_json::from_str(include_str!("../experiments/rounded-corners.json")).unwrap();
    for (outlines, set) in [
        ("the library's outlines", builtin_object_set()),
        (
            "outlines with rounded corners (rounded-corners.json)",
            rounded,
        ),
    ] {
        print_planning_per_trip(&timed, outlines, &set);
    }
    c.bench_function("plan_trip/push-mog-time/34", |b| {
        b.iter_batched(
            || Policy::new(PolicyKind::PushMogOpt, timed.clone()).unwrap(),
            |policy| policy.plan_trip(&scene).unwrap(),
            BatchSize::SmallInput,
        )
    });
    c.bench_function("run/push-mog/34", |b| {
        b.iter_batched(
            fresh(PolicyKind::PushMog),
            |policy| policy.run(&scene, &mut policy.ideal(), 1).unwrap(),
            BatchSize::SmallInput,
        )
    });
}

criterion_group!(benches, baselines);
criterion_main!(benches);
