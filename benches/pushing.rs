//! Push planning times: the SOCP planner (axis search, sequencing, fork checks) against the paper's
//! pushes, per cluster and for every cluster of a 34-object scene.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use pushmog::cluster::{Clusterer, Hierarchical};
use pushmog::push::{PushPlanner, Socp, TowardCentral};
use pushmog::scene::{GeneratorSettings, ObjectId, Scene, builtin_object_set, generate_scene};

fn scene(seed: u64) -> Scene {
    generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap()
}

fn clusters(scene: &Scene) -> Vec<Vec<ObjectId>> {
    Hierarchical::default()
        .cluster(scene)
        .unwrap()
        .value
        .clusters
        .into_iter()
        .filter(|c| c.len() > 1)
        .collect()
}

fn pushing(c: &mut Criterion) {
    let scene = scene(1);
    let clusters = clusters(&scene);
    let socp = Socp::default();
    let central = TowardCentral::default();
    let mut group = c.benchmark_group("push");
    // Every multi-object cluster of the scene, one benchmark each (per-cluster times).
    for (k, cluster) in clusters.iter().enumerate() {
        let label = format!("{k}-size{}", cluster.len());
        group.bench_with_input(BenchmarkId::new("socp/cluster", &label), cluster, |b, c| {
            b.iter(|| socp.plan(&scene, c).unwrap())
        });
    }
    group.bench_function("socp/scene34", |b| {
        b.iter(|| {
            for cluster in &clusters {
                socp.plan(&scene, cluster).unwrap();
            }
        })
    });
    group.bench_function("toward-central/scene34", |b| {
        b.iter(|| {
            for cluster in &clusters {
                central.plan(&scene, cluster).unwrap();
            }
        })
    });
    group.finish();
}

criterion_group!(benches, pushing);
criterion_main!(benches);
