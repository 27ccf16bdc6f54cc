//! Where pushing starts to pay: the bin distance at which a policy's picks per hour meet sog's.
//!
//! For each policy the paired ratio to sog, `r(d)` (mean of per-scene ratios, with the half-width `h(d)`
//! of its 95 % interval; `tables::GroupSummary::versus_sog`), is known at the swept distances
//! `d_1 < … < d_m`. The **break-even distance** is where `r` last rises through 1: if `r(d_m) < 1` the
//! policy never breaks even within the sweep; if `r(d_i) ≥ 1` at every `d_i` it is at or above sog
//! throughout; otherwise, with `d_k` the last distance where `r < 1`,
//! `d* = d_k + (1 − r_k)·(d_{k+1} − d_k)/(r_{k+1} − r_k)`, linear between the two sweep points (an
//! estimate: nothing is measured between them). Distances where the whole interval lies below 1
//! (`r + h < 1`) are where the policy is measurably slower than sog. See
//! `formulations/picks-per-hour.md`.

use std::fmt::Write as _;
use std::ops::Range;

use plotters::prelude::*;

use super::figures::{COLOURS, SIZE, draw_legend, plot_error};
use super::log::Log;
use super::tables::{GroupSummary, summarise};
use crate::error::{Error, Result};

/// A policy's ratio to sog at one bin distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RatioPoint {
    /// Bin distance, metres.
    pub distance: f64,
    /// Mean of the per-scene ratios of picks per hour to sog's.
    pub ratio: f64,
    /// Half-width of its 95 % interval.
    pub half_width: f64,
}

/// Where a policy meets sog along the swept distances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BreakEven {
    /// The ratio is at least 1 at every swept distance.
    Throughout,
    /// The ratio last rises through 1 at this distance, metres (linear between sweep points).
    At(f64),
    /// The ratio is below 1 at the farthest swept distance.
    NotWithin,
}

/// The break-even of `points` (any order; at least one point).
pub fn break_even(points: &[RatioPoint]) -> BreakEven {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    let Some(last_below) = sorted.iter().rposition(|p| p.ratio < 1.0) else {
        return BreakEven::Throughout;
    };
    let Some(above) = sorted.get(last_below + 1) else {
        return BreakEven::NotWithin;
    };
    let below = sorted[last_below];
    let rise = above.ratio - below.ratio;
    BreakEven::At(below.distance + (1.0 - below.ratio) * (above.distance - below.distance) / rise)
}

/// Each policy other than sog with its ratio points, in the log's order.
pub fn ratio_points(groups: &[GroupSummary]) -> Vec<(String, Vec<RatioPoint>)> {
    let mut out: Vec<(String, Vec<RatioPoint>)> = Vec::new();
    for g in groups {
        let Some((ratio, half_width)) = g.versus_sog else {
            continue;
        };
        let point = RatioPoint {
            distance: g.bin_distance,
            ratio,
            half_width,
        };
        match out.iter_mut().find(|(p, _)| *p == g.policy) {
            Some((_, points)) => points.push(point),
            None => out.push((g.policy.clone(), vec![point])),
        }
    }
    out
}

/// One Markdown line per policy: its break-even distance and where its interval lies below sog.
pub fn break_even_markdown(log: &Log) -> String {
    let mut out = String::new();
    for (policy, points) in ratio_points(&summarise(log)) {
        let meets = match break_even(&points) {
            BreakEven::Throughout => "at or above sog at every swept distance".to_string(),
            BreakEven::At(d) => {
                format!("breaks even with sog at {d:.2} m (linear between sweep points)")
            }
            BreakEven::NotWithin => "below sog at the farthest swept distance".to_string(),
        };
        let slower: Vec<String> = points
            .iter()
            .filter(|p| p.ratio + p.half_width < 1.0)
            .map(|p| format!("{:.2}", p.distance))
            .collect();
        let slower = if slower.is_empty() {
            "its 95 % interval reaches 1 or above everywhere".to_string()
        } else {
            format!(
                "measurably slower (whole 95 % interval below 1) at {} m",
                slower.join(", ")
            )
        };
        let _ = writeln!(out, "- {policy}: {meets}; {slower}");
    }
    out
}

/// Paired ratio of picks per hour to sog's against bin distance, one line per policy with its 95 %
/// interval, the line `ratio = 1` dashed, and each policy's break-even distance marked.
///
/// # Errors
/// A drawing failure, or a log with no policy paired with sog.
pub fn ratio_to_sog_svg(log: &Log) -> Result<String> {
    let lines = ratio_points(&summarise(log));
    let all: Vec<RatioPoint> = lines.iter().flat_map(|(_, p)| p.iter().copied()).collect();
    if all.is_empty() {
        return Err(Error::field(
            "figure",
            "log",
            "no policy has runs paired with sog's on the same scenes",
        ));
    }
    let (x, y) = axes(&all);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Picks per hour relative to sog, with break-even",
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x.clone(), y.clone())
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc("distance to the bin (m)")
            .y_desc("picks per hour / sog's, paired (95 % interval)")
            .draw()
            .map_err(plot_error)?;
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x.start, 1.0), (x.end, 1.0)],
                6,
                4,
                BLACK.stroke_width(1),
            ))
            .map_err(plot_error)?
            .label("sog (ratio 1)")
            .legend(|(px, py)| PathElement::new(vec![(px, py), (px + 18, py)], BLACK));
        // sog is the first colour of the other figures; keep each policy's colour there.
        for (k, (policy, points)) in lines.iter().enumerate() {
            let colour = COLOURS[(k + 1) % COLOURS.len()];
            let mut points = points.clone();
            points.sort_by(|a, b| a.distance.total_cmp(&b.distance));
            let meets = break_even(&points);
            let label = legend_label(policy, meets);
            chart
                .draw_series(LineSeries::new(
                    points.iter().map(|p| (p.distance, p.ratio)),
                    colour.stroke_width(2),
                ))
                .map_err(plot_error)?
                .label(label)
                .legend(move |(px, py)| {
                    PathElement::new(vec![(px, py), (px + 18, py)], colour.stroke_width(2))
                });
            chart
                .draw_series(points.iter().map(|p| {
                    ErrorBar::new_vertical(
                        p.distance,
                        p.ratio - p.half_width,
                        p.ratio,
                        p.ratio + p.half_width,
                        colour.filled().stroke_width(1),
                        8,
                    )
                }))
                .map_err(plot_error)?;
            if let BreakEven::At(d) = meets {
                chart
                    .draw_series(std::iter::once(TriangleMarker::new(
                        (d, 1.0),
                        7,
                        colour.filled(),
                    )))
                    .map_err(plot_error)?;
                chart
                    .draw_series(DashedLineSeries::new(
                        vec![(d, y.start), (d, 1.0)],
                        3,
                        3,
                        colour.stroke_width(1),
                    ))
                    .map_err(plot_error)?;
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// The figure's axes: the distances and the ratios' intervals (and the ratio 1), padded.
fn axes(all: &[RatioPoint]) -> (Range<f64>, Range<f64>) {
    let x_lo = all.iter().map(|p| p.distance).fold(f64::INFINITY, f64::min);
    let x_hi = all
        .iter()
        .map(|p| p.distance)
        .fold(f64::NEG_INFINITY, f64::max);
    let y_lo = all
        .iter()
        .map(|p| p.ratio - p.half_width)
        .fold(1.0, f64::min);
    let y_hi = all
        .iter()
        .map(|p| p.ratio + p.half_width)
        .fold(1.0, f64::max);
    let x_pad = ((x_hi - x_lo) * 0.05).max(1e-3);
    let y_pad = ((y_hi - y_lo) * 0.1).max(0.01);
    (
        (x_lo - x_pad)..(x_hi + x_pad),
        (y_lo - y_pad)..(y_hi + y_pad),
    )
}

/// A policy's line in the legend, with where it breaks even.
fn legend_label(policy: &str, meets: BreakEven) -> String {
    match meets {
        BreakEven::Throughout => format!("{policy} (≥ sog throughout)"),
        BreakEven::At(d) => format!("{policy} (break-even {d:.2} m)"),
        BreakEven::NotWithin => format!("{policy} (below sog at the far end)"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(distance: f64, ratio: f64) -> RatioPoint {
        RatioPoint {
            distance,
            ratio,
            half_width: 0.01,
        }
    }

    #[test]
    fn the_crossing_is_interpolated_between_the_last_point_below_and_the_next() {
        // Below at 0.3 (0.96) and above at 1.0 (1.03): 1 is reached 4/7 of the way.
        let points = [at(1.0, 1.03), at(0.1, 1.01), at(0.3, 0.96), at(2.0, 1.05)];
        let BreakEven::At(d) = break_even(&points) else {
            panic!("expected a crossing");
        };
        assert!((d - (0.3 + 0.7 * 4.0 / 7.0)).abs() < 1e-12, "{d}");
    }

    #[test]
    fn no_crossing_is_reported_as_such() {
        assert_eq!(
            break_even(&[at(0.1, 1.0), at(1.0, 1.2)]),
            BreakEven::Throughout
        );
        assert_eq!(
            break_even(&[at(0.1, 1.1), at(1.0, 0.9)]),
            BreakEven::NotWithin
        );
    }
}
