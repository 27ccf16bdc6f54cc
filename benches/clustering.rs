//! Time to a proven optimum of the clustering MILP (default backend) at 34, 60, 100 and 200 objects,
//! at the default object density, for both objectives; the hierarchical heuristic for reference.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use pushmog::cluster::{ClusterObjective, Clusterer, Hierarchical, Milp, MilpSettings};
use pushmog::plan::Status;
use pushmog::problem::Problem;
use pushmog::scene::{GeneratorSettings, Scene, Workspace, builtin_object_set, generate_scene};

/// A scene of `n` objects with the workspace grown to keep the 34-object density.
fn scene(n: usize, seed: u64) -> Scene {
    let base = GeneratorSettings::default();
    let scale = (n as f64 / 34.0).sqrt().max(1.0);
    let settings = GeneratorSettings {
        objects: n,
        workspace: Workspace::new(
            base.workspace.width() * scale,
            base.workspace.depth() * scale,
        ),
        ..base
    };
    generate_scene(&settings, &builtin_object_set(), seed).unwrap()
}

fn clustering(c: &mut Criterion) {
    let mut group = c.benchmark_group("cluster");
    group.sample_size(10);
    for n in [34, 60, 100, 200] {
        let scene = scene(n, 1);
        group.bench_with_input(BenchmarkId::new("hierarchical", n), &scene, |b, s| {
            b.iter(|| Hierarchical::default().cluster(s).unwrap())
        });
        for (name, objective) in [
            ("milp-time", ClusterObjective::Time),
            ("milp-fewest", ClusterObjective::FewestClusters),
        ] {
            let milp = Milp::new(
                MilpSettings {
                    objective,
                    ..MilpSettings::default()
                },
                Problem::shared_default(),
            )
            .unwrap();
            // Benchmark only what is proven optimal: time to proof, not time to a time limit.
            assert_eq!(
                milp.cluster(&scene).unwrap().status,
                Status::Optimal,
                "{name} {n}"
            );
            group.bench_with_input(BenchmarkId::new(name, n), &scene, |b, s| {
                b.iter(|| milp.cluster(s).unwrap())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, clustering);
criterion_main!(benches);
