//! The paper's pushes against SOCP push targets on the same clusters: the table `pushmog
//! compare-pushing` prints.
//!
//! For every seeded scene, the hierarchical clustering is computed once; each cluster of two or more
//! objects is planned by both push planners. Reported per planner: total push distance and number of
//! pushes per scene; the share of clusters whose predicted arrangement *fits the jaws* (some jaw pose
//! catches every member in one row, judged with unlimited friction, [`GraspModel::unlimited_friction`])
//! and the share the grasp model predicts *held* with its friction; and failures (clusters with a push
//! that could not be planned, or no row at all).
//!
//! Per-scene distance depends on how many clusters each planner pushes at all (a planner that fails
//! on a cluster pushes nothing there), so the report also compares the two on the same clusters:
//! those both plan without failure, and those both leave held by the grasp model.

use std::fmt::Write as _;

use super::tables::table::{Cell, Column, Table};
use crate::cluster::{Clusterer, Hierarchical};
use crate::error::Result;
use crate::grasp::{GraspModel, GraspPlanner, JawPose, MultiObject, MultiObjectSettings};
use crate::policy::PolicySettings;
use crate::push::{PushPlanner, SkipReason, Socp, TowardCentral, predict};
use crate::scene::{GeneratorSettings, ObjectId, ObjectSet, Scene, generate_scene};
use crate::stats::mean_std;

/// One planner's figures on one scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PushFigures {
    /// Total push distance, metres.
    pub distance: f64,
    /// Pushes planned.
    pub pushes: usize,
    /// Clusters of two or more objects.
    pub clusters: usize,
    /// Clusters whose predicted arrangement fits the jaws.
    pub fits: usize,
    /// Clusters the grasp model predicts held whole.
    pub held: usize,
    /// Clusters with a push that could not be planned, or with no row.
    pub failures: usize,
    /// Planning time, seconds.
    pub seconds: f64,
}

/// Both planners' push distance on the clusters of one scene that meet a condition for both.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SharedClusters {
    /// Clusters that meet it.
    pub clusters: usize,
    /// The paper's pushes' total distance on them, metres.
    pub central: f64,
    /// The SOCP's total distance on them, metres.
    pub socp: f64,
}

impl SharedClusters {
    fn add(&mut self, central: f64, socp: f64) {
        self.clusters += 1;
        self.central += central;
        self.socp += socp;
    }
}

/// Both planners on one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct PushComparison {
    /// The scene's seed.
    pub seed: u64,
    /// The paper's pushes toward the central object.
    pub central: PushFigures,
    /// SOCP push targets.
    pub socp: PushFigures,
    /// Clusters neither planner failed on.
    pub both_planned: SharedClusters,
    /// Clusters both planners leave held by the grasp model.
    pub both_held: SharedClusters,
}

/// Runs the comparison on the scenes of these generator seeds; `done` is told how many scenes are
/// finished after each one (for progress reports).
///
/// # Errors
/// Invalid settings or a scene that cannot be generated.
pub fn compare_pushing(
    generator: &GeneratorSettings,
    set: &ObjectSet,
    settings: &PolicySettings,
    seeds: std::ops::Range<u64>,
    done: &mut dyn FnMut(usize),
) -> Result<Vec<PushComparison>> {
    let problem = settings.problem()?;
    let clusterer = Hierarchical::new(settings.clustering.clone())?;
    let central = TowardCentral::new(settings.pushing.clone(), problem.clone())?;
    let socp = Socp::new(settings.socp.clone(), problem.clone())?;
    // Whether a row fits the jaws at all: the same problem with friction that never lets go.
    let fits_problem = problem.with_grasp_model(GraspModel::unlimited_friction())?;
    let fits = MultiObject::new(
        MultiObjectSettings {
            samples: 1,
            clearance_sigmas: 0.0,
            ..MultiObjectSettings::default()
        },
        fits_problem,
    )?;
    let holds = MultiObject::new(MultiObjectSettings::default(), problem)?;
    let mut rows = Vec::with_capacity(seeds.clone().count());
    for seed in seeds {
        let scene = generate_scene(generator, set, seed)?;
        let clusters = clusterer.cluster(&scene)?.value.clusters;
        let mut figures = [PushFigures::default(), PushFigures::default()];
        let mut both_planned = SharedClusters::default();
        let mut both_held = SharedClusters::default();
        for cluster in clusters.iter().filter(|c| c.len() > 1) {
            // Per planner: this cluster's distance, whether it failed, whether it is held.
            let mut this = [(0.0, false, false); 2];
            for ((planner, figure), this) in [&central as &dyn PushPlanner, &socp]
                .into_iter()
                .zip(figures.iter_mut())
                .zip(this.iter_mut())
            {
                let outcome = planner.plan(&scene, cluster)?;
                figure.clusters += 1;
                figure.seconds += outcome.stats.seconds;
                let plan = outcome.value;
                let failed = !outcome.status.has_answer()
                    || plan
                        .skipped
                        .iter()
                        .any(|s| s.reason != SkipReason::AlreadyInPlace);
                if failed {
                    figure.failures += 1;
                }
                figure.pushes += plan.pushes.len();
                let distance = plan.pushes.iter().map(|p| p.distance).sum::<f64>();
                figure.distance += distance;
                let after = predict(&scene, &plan.pushes)?;
                let hints: Vec<JawPose> = plan.intended_grasp.into_iter().collect();
                if holds_all(&fits, &after, cluster, &hints)? {
                    figure.fits += 1;
                }
                let held = holds_all(&holds, &after, cluster, &hints)?;
                if held {
                    figure.held += 1;
                }
                *this = (distance, failed, held);
            }
            let [
                (central, central_failed, central_held),
                (socp, socp_failed, socp_held),
            ] = this;
            if !central_failed && !socp_failed {
                both_planned.add(central, socp);
            }
            if central_held && socp_held {
                both_held.add(central, socp);
            }
        }
        let [central, socp] = figures;
        rows.push(PushComparison {
            seed,
            central,
            socp,
            both_planned,
            both_held,
        });
        done(rows.len());
    }
    Ok(rows)
}

fn holds_all(
    planner: &MultiObject,
    scene: &Scene,
    cluster: &[ObjectId],
    hints: &[JawPose],
) -> Result<bool> {
    let grasp = planner.plan_with_hints(scene, cluster, hints)?.value;
    Ok(grasp.is_some_and(|g| cluster.iter().all(|id| g.objects.contains(id))))
}

fn quantile(values: &[f64], q: f64) -> f64 {
    crate::stats::quantile(values, q).unwrap_or(f64::NAN)
}

/// The table: per push planner, push distance per scene (mean ± standard deviation, median, p90),
/// pushes per scene, rows that fit and that the grasp model holds, failures and planning time.
fn push_table(rows: &[PushComparison]) -> Table {
    let line = |name: &str, pick: fn(&PushComparison) -> &PushFigures| {
        let distances: Vec<f64> = rows.iter().map(|r| pick(r).distance).collect();
        let (mean, std) = mean_std(&distances);
        let clusters: usize = rows.iter().map(|r| pick(r).clusters).sum();
        let fits: usize = rows.iter().map(|r| pick(r).fits).sum();
        let held: usize = rows.iter().map(|r| pick(r).held).sum();
        let failures: usize = rows.iter().map(|r| pick(r).failures).sum();
        let pushes: f64 =
            rows.iter().map(|r| pick(r).pushes as f64).sum::<f64>() / rows.len().max(1) as f64;
        let seconds: f64 = rows.iter().map(|r| pick(r).seconds).sum();
        let share = |k: usize| {
            let percent = 100.0 * k as f64 / clusters.max(1) as f64;
            Cell::Text(format!("{k}/{clusters} ({percent:.1} %)"))
        };
        vec![
            Cell::Text(name.to_string()),
            Cell::Interval(mean, std),
            Cell::Number(quantile(&distances, 0.5)),
            Cell::Number(quantile(&distances, 0.9)),
            Cell::Number(pushes),
            share(fits),
            share(held),
            Cell::Number(failures as f64),
            Cell::Number(1e3 * seconds / clusters.max(1) as f64),
        ]
    };
    Table {
        columns: vec![
            Column::markdown("pushes", 0).left(),
            Column::markdown("push distance per scene (m)", 3).left(),
            Column::markdown("median", 3),
            Column::markdown("p90", 3),
            Column::markdown("pushes per scene", 1),
            Column::markdown("row fits the jaws", 0),
            Column::markdown("held by the grasp model", 0),
            Column::markdown("failures", 0),
            Column::markdown("planning time per cluster (ms)", 3),
        ],
        rows: vec![
            line("toward central (paper)", |r| &r.central),
            line("socp", |r| &r.socp),
        ],
    }
}

/// The Markdown report of a comparison: the table, then the paired findings.
pub fn push_comparison_markdown(rows: &[PushComparison]) -> String {
    let mut out = push_table(rows).markdown();
    let central: f64 = rows.iter().map(|r| r.central.distance).sum();
    let socp: f64 = rows.iter().map(|r| r.socp.distance).sum();
    let ratios: Vec<f64> = rows
        .iter()
        .filter(|r| r.central.distance > 0.0)
        .map(|r| r.socp.distance / r.central.distance)
        .collect();
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "- mean push distance, SOCP against the paper: {:.3} ({:+.1} %)",
        socp / central.max(1e-12),
        100.0 * (socp / central.max(1e-12) - 1.0)
    );
    let _ = writeln!(
        out,
        "- per-scene ratio SOCP / paper: min {:.3}, p10 {:.3}, median {:.3}, p90 {:.3}, max {:.3}; SOCP shorter on {}/{} scenes",
        quantile(&ratios, 0.0),
        quantile(&ratios, 0.1),
        quantile(&ratios, 0.5),
        quantile(&ratios, 0.9),
        quantile(&ratios, 1.0),
        ratios.iter().filter(|&&r| r < 1.0).count(),
        ratios.len()
    );
    for (what, pick) in [
        (
            "neither planner failed on",
            (|r: &PushComparison| &r.both_planned) as fn(&PushComparison) -> &SharedClusters,
        ),
        (
            "both leave held by the grasp model",
            |r: &PushComparison| &r.both_held,
        ),
    ] {
        let clusters: usize = rows.iter().map(|r| pick(r).clusters).sum();
        let central: f64 = rows.iter().map(|r| pick(r).central).sum();
        let socp: f64 = rows.iter().map(|r| pick(r).socp).sum();
        let per = |total: f64| 1e3 * total / clusters.max(1) as f64;
        let _ = writeln!(
            out,
            "- on the {clusters} clusters {what}: paper {:.1} mm, SOCP {:.1} mm of pushing per cluster ({:+.1} %)",
            per(central),
            per(socp),
            100.0 * (socp / central.max(1e-12) - 1.0)
        );
    }
    out
}
