//! The results and timing tables as CSV: one serialised line type each, written by the csv crate,
//! which quotes fields that need it (policy labels are the user's text).

use super::{paper_reference, summarise};
use crate::experiment::log::Log;

/// One line of the results CSV, each figure as printed.
#[derive(serde::Serialize)]
struct ResultsLine {
    policy: String,
    objects: usize,
    bin_distance: String,
    friction: String,
    /// Only in logs of configurations with sweep variants, so other logs' CSV stays as it was.
    #[serde(skip_serializing_if = "Option::is_none")]
    variant: Option<String>,
    runs: usize,
    opt_mean: String,
    opt_std: String,
    paper_opt_mean: String,
    paper_opt_std: String,
    trips: String,
    pushes: String,
    push_distance: String,
    failed_grasps: String,
    landings: String,
    cleared: usize,
    robot_seconds: String,
    picks_per_hour: String,
    picks_per_hour_95: String,
    versus_sog: String,
    versus_sog_95: String,
}

/// One line of the timing CSV.
#[derive(serde::Serialize)]
struct TimingLine {
    policy: String,
    objects: usize,
    bin_distance: String,
    friction: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    variant: Option<String>,
    planning_median: String,
    planning_p95: String,
    clustering_median: String,
    cpu_median: String,
}

/// `lines` as CSV with a header of their field names; fields that hold a comma, a quote or a line
/// break (policy labels are the user's text) are quoted.
fn csv_text<T: serde::Serialize>(lines: impl IntoIterator<Item = T>) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    // Flat records of strings and counts, written to memory: no step here can fail.
    for line in lines {
        writer
            .serialize(line)
            .expect("a flat record serialises to memory");
    }
    let bytes = writer.into_inner().expect("memory takes every byte");
    String::from_utf8(bytes).expect("CSV of UTF-8 strings is UTF-8")
}

/// The results as CSV (one line per group; no wall-clock columns).
pub fn results_csv(log: &Log) -> String {
    csv_text(summarise(log).into_iter().map(|g| {
        let paper = paper_reference(&g);
        ResultsLine {
            policy: g.policy.clone(),
            objects: g.objects,
            bin_distance: g.bin_distance.to_string(),
            friction: g.friction.map_or(String::new(), |f| f.to_string()),
            variant: g.variant.clone(),
            runs: g.runs,
            opt_mean: format!("{:.6}", g.opt.0),
            opt_std: format!("{:.6}", g.opt.1),
            paper_opt_mean: paper.map_or(String::new(), |(m, _)| format!("{m}")),
            paper_opt_std: paper.map_or(String::new(), |(_, s)| format!("{s}")),
            trips: format!("{:.4}", g.trips),
            pushes: format!("{:.4}", g.pushes),
            push_distance: format!("{:.6}", g.push_distance),
            failed_grasps: format!("{:.4}", g.failed_grasps),
            landings: format!("{:.4}", g.landings),
            cleared: g.cleared,
            robot_seconds: format!("{:.4}", g.robot_seconds),
            picks_per_hour: format!("{:.4}", g.picks_per_hour),
            picks_per_hour_95: format!("{:.4}", g.picks_per_hour_95),
            versus_sog: g
                .versus_sog
                .map_or(String::new(), |(m, _)| format!("{m:.6}")),
            versus_sog_95: g
                .versus_sog
                .map_or(String::new(), |(_, h)| format!("{h:.6}")),
        }
    }))
}

/// The wall-clock figures as CSV.
pub fn timing_csv(log: &Log) -> String {
    csv_text(summarise(log).into_iter().map(|g| TimingLine {
        policy: g.policy.clone(),
        objects: g.objects,
        bin_distance: g.bin_distance.to_string(),
        friction: g.friction.map_or(String::new(), |f| f.to_string()),
        variant: g.variant.clone(),
        planning_median: format!("{:.9}", g.planning_median),
        planning_p95: format!("{:.9}", g.planning_p95),
        clustering_median: format!("{:.9}", g.clustering_median),
        cpu_median: if g.cpu_median > 0.0 {
            format!("{:.6}", g.cpu_median)
        } else {
            String::new()
        },
    }))
}
