//! Figures built only from logs (plotters, SVG backend: no system packages), and the data files the
//! LaTeX write-up plots with pgfplots.

use plotters::prelude::*;

use super::log::Log;
use super::tables::{PAPER_OPT, summarise};
use crate::error::{Error, Result};
use crate::stats::t_95;

pub(super) const SIZE: (u32, u32) = (720, 440);
pub(super) const COLOURS: [RGBColor; 6] = [
    RGBColor(0x4e, 0x79, 0xa7),
    RGBColor(0xf2, 0x8e, 0x2b),
    RGBColor(0xe1, 0x57, 0x59),
    RGBColor(0x59, 0xa1, 0x4f),
    RGBColor(0xb0, 0x7a, 0xa1),
    RGBColor(0x76, 0xb7, 0xb2),
];

pub(super) fn plot_error<E: std::fmt::Display>(e: E) -> Error {
    Error::field("figure", "plot", e.to_string())
}

/// The chart's series legend at `position`, on a translucent white box with a black border, as
/// every figure draws it.
pub(super) fn draw_legend<'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    position: SeriesLabelPosition,
) -> Result<()> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(plot_error)
}

/// Objects per trip per policy with one-standard-deviation error bars; the paper's physical figures as
/// hollow markers where they exist.
///
/// # Errors
/// A drawing failure.
pub fn opt_per_policy_svg(log: &Log) -> Result<String> {
    let groups = summarise(log);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let top = groups
            .iter()
            .map(|g| g.opt.0 + g.opt.1)
            .chain(PAPER_OPT.iter().map(|p| p.1 + p.2))
            .fold(1.0, f64::max)
            * 1.15;
        let names: Vec<String> = groups.iter().map(|g| g.policy.clone()).collect();
        let count = names.len();
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "Objects per trip ({}, {} executor)",
                    log.header.config.name,
                    executor(log)
                ),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(-0.5f64..(count as f64 - 0.5), 0.0f64..top)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_labels(count.max(1))
            .x_label_formatter(&|x| {
                let k = x.round();
                if (x - k).abs() < 1e-6 && k >= 0.0 {
                    names.get(k as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            })
            .y_desc("objects per trip")
            .disable_x_mesh()
            .draw()
            .map_err(plot_error)?;
        for (k, g) in groups.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()];
            let x = k as f64 - 0.08;
            let ours = chart
                .draw_series(std::iter::once(ErrorBar::new_vertical(
                    x,
                    g.opt.0 - g.opt.1,
                    g.opt.0,
                    g.opt.0 + g.opt.1,
                    colour.filled().stroke_width(2),
                    12,
                )))
                .map_err(plot_error)?;
            if k == 0 {
                ours.label("pushmog, mean ± std over runs")
                    .legend(|(px, py)| Circle::new((px + 8, py), 5, COLOURS[0].filled()));
            }
            if let Some(&(_, m, s)) = PAPER_OPT.iter().find(|p| p.0 == g.policy) {
                let x = k as f64 + 0.12;
                chart
                    .draw_series(std::iter::once(ErrorBar::new_vertical(
                        x,
                        m - s,
                        m,
                        m + s,
                        BLACK.stroke_width(1),
                        8,
                    )))
                    .map_err(plot_error)?;
                let paper = chart
                    .draw_series(std::iter::once(Circle::new(
                        (x, m),
                        4,
                        BLACK.stroke_width(1),
                    )))
                    .map_err(plot_error)?;
                if g.policy == PAPER_OPT[0].0 {
                    paper
                        .label("Push-MOG paper, physical UR5")
                        .legend(|(px, py)| Circle::new((px + 8, py), 4, BLACK.stroke_width(1)));
                }
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// Half-width of the 95 % interval of a group's mean objects per trip (Student's t, [`t_95`]); 0
/// for fewer than two runs.
fn opt_interval(g: &super::tables::GroupSummary) -> f64 {
    if g.runs < 2 {
        0.0
    } else {
        t_95(g.runs) * g.opt.1 / (g.runs as f64).sqrt()
    }
}

fn executor(log: &Log) -> &'static str {
    log.header.config.executor.kind.name()
}

/// One line per policy of `y(group)` against `x(group)`.
fn lines_svg(
    log: &Log,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    x: impl Fn(&super::tables::GroupSummary) -> f64,
    y: impl Fn(&super::tables::GroupSummary) -> f64,
    log_y: bool,
) -> Result<String> {
    let groups = summarise(log);
    let mut policies: Vec<String> = Vec::new();
    for g in &groups {
        if !policies.contains(&g.policy) {
            policies.push(g.policy.clone());
        }
    }
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) =
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, 0.0f64);
    for g in &groups {
        x_lo = x_lo.min(x(g));
        x_hi = x_hi.max(x(g));
        y_lo = y_lo.min(y(g));
        y_hi = y_hi.max(y(g));
    }
    if !x_lo.is_finite() {
        return Err(Error::field("figure", "log", "the log has no rows to plot"));
    }
    let x_pad = ((x_hi - x_lo) * 0.05).max(1e-3);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let x_range = (x_lo - x_pad)..(x_hi + x_pad);
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(x_desc)
                    .y_desc(y_desc)
                    .draw()
                    .map_err(plot_error)?;
                for (k, policy) in policies.iter().enumerate() {
                    let colour = COLOURS[k % COLOURS.len()];
                    let points: Vec<(f64, f64)> = groups
                        .iter()
                        .filter(|g| &g.policy == policy)
                        .map(|g| (x(g), y(g)))
                        .collect();
                    chart
                        .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
                        .map_err(plot_error)?
                        .label(policy.clone())
                        .legend(move |(px, py)| {
                            PathElement::new(vec![(px, py), (px + 18, py)], colour.stroke_width(2))
                        });
                    chart
                        .draw_series(
                            points
                                .into_iter()
                                .map(|p| Circle::new(p, 3, colour.filled())),
                        )
                        .map_err(plot_error)?;
                }
                // plotters' default place for the legend.
                draw_legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
            }};
        }
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60);
        if log_y {
            let lo = (y_lo.max(1e-9) * 0.5).max(1e-9);
            draw!(
                builder
                    .build_cartesian_2d(x_range, (lo..y_hi * 2.0).log_scale())
                    .map_err(plot_error)?
            );
        } else {
            draw!(
                builder
                    .build_cartesian_2d(x_range, 0.0..y_hi * 1.15)
                    .map_err(plot_error)?
            );
        }
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// Picks per hour against the distance to the bin, one line per policy.
///
/// # Errors
/// A drawing failure, or a log without rows.
pub fn picks_per_hour_svg(log: &Log) -> Result<String> {
    lines_svg(
        log,
        "Picks per hour against bin distance",
        "distance to the bin (m)",
        "picks per hour",
        |g| g.bin_distance,
        |g| g.picks_per_hour,
        false,
    )
}

/// Objects per trip against the simulator's pad and object friction, one line per policy.
///
/// # Errors
/// A drawing failure, or a log without rows.
pub fn friction_svg(log: &Log) -> Result<String> {
    lines_svg(
        log,
        "Objects per trip against friction (simulated)",
        "pad and object friction",
        "objects per trip",
        |g| g.friction.unwrap_or(f64::NAN),
        |g| g.opt.0,
        false,
    )
}

/// Median clustering time against the number of objects, one line per policy (log scale).
///
/// # Errors
/// A drawing failure, or a log without rows.
pub fn planning_time_svg(log: &Log) -> Result<String> {
    lines_svg(
        log,
        "Clustering time against object count",
        "objects",
        "median clustering time per trip (ms)",
        |g| g.objects as f64,
        |g| g.clustering_median * 1e3,
        true,
    )
}

/// Objects per trip against push distance per run, one point per policy: the mean over its runs,
/// with a 95 % interval of that mean (Student's t, [`t_95`]) vertically. Policies that push more
/// should carry more objects per trip; this shows what each metre of pushing buys.
///
/// # Errors
/// A drawing failure, or a log without rows.
pub fn push_distance_svg(log: &Log) -> Result<String> {
    let groups = summarise(log);
    let (mut x_hi, mut y_lo, mut y_hi) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
    for g in &groups {
        x_hi = x_hi.max(g.push_distance);
        y_lo = y_lo.min(g.opt.0 - opt_interval(g));
        y_hi = y_hi.max(g.opt.0 + opt_interval(g));
    }
    if !y_lo.is_finite() {
        return Err(Error::field("figure", "log", "the log has no rows to plot"));
    }
    let y_pad = ((y_hi - y_lo) * 0.08).max(0.01);
    // Two more colours than the other figures need: a trade-off compares many variants.
    let colours: Vec<RGBColor> = COLOURS
        .iter()
        .copied()
        .chain([RGBColor(0x9c, 0x75, 0x5f), RGBColor(0x33, 0x33, 0x33)])
        .collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "Objects per trip against push distance ({}, {} executor)",
                    log.header.config.name,
                    executor(log)
                ),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(
                -0.02f64..(x_hi * 1.08).max(0.05),
                (y_lo - y_pad)..(y_hi + y_pad),
            )
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc("push distance per run (m)")
            .y_desc("objects per trip (mean, 95 % interval)")
            .draw()
            .map_err(plot_error)?;
        for (k, g) in groups.iter().enumerate() {
            let colour = colours[k % colours.len()];
            let (x, y, e) = (g.push_distance, g.opt.0, opt_interval(g));
            chart
                .draw_series(std::iter::once(ErrorBar::new_vertical(
                    x,
                    y - e,
                    y,
                    y + e,
                    colour.filled().stroke_width(2),
                    10,
                )))
                .map_err(plot_error)?
                .label(g.policy.clone())
                .legend(move |(px, py)| Circle::new((px + 8, py), 5, colour.filled()));
        }
        draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// Objects per trip per sweep variant (one row each, top to bottom in the configuration's order),
/// each policy a marker with the 95 % interval of its mean (Student's t, [`t_95`]).
///
/// # Errors
/// A drawing failure, or a log without rows of variants.
pub fn variants_svg(log: &Log) -> Result<String> {
    let groups: Vec<_> = summarise(log)
        .into_iter()
        .filter(|g| g.variant.is_some())
        .collect();
    let mut variants: Vec<String> = Vec::new();
    let mut policies: Vec<String> = Vec::new();
    for g in &groups {
        let variant = g.variant.clone().unwrap_or_default();
        if !variants.contains(&variant) {
            variants.push(variant);
        }
        if !policies.contains(&g.policy) {
            policies.push(g.policy.clone());
        }
    }
    if groups.is_empty() {
        return Err(Error::field(
            "figure",
            "log",
            "the log has no variants to plot",
        ));
    }
    let x_hi = groups
        .iter()
        .map(|g| g.opt.0 + opt_interval(g))
        .fold(1.0, f64::max)
        * 1.08;
    let rows = variants.len();
    let height = 120 + 44 * rows as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (SIZE.0, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        // Row k of the list is drawn at y = rows - 1 - k, so the first variant is on top.
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "Objects per trip by variant ({}, {} executor)",
                    log.header.config.name,
                    executor(log)
                ),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(190)
            .build_cartesian_2d(0.0f64..x_hi, -0.5f64..(rows as f64 - 0.5))
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .y_labels(rows.max(1))
            .y_label_formatter(&|y| {
                let k = y.round();
                if (y - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < rows {
                    variants[rows - 1 - k as usize].clone()
                } else {
                    String::new()
                }
            })
            .x_desc("objects per trip (mean, 95 % interval)")
            .disable_y_mesh()
            .draw()
            .map_err(plot_error)?;
        let spread = 0.6 / policies.len().max(1) as f64;
        for (p, policy) in policies.iter().enumerate() {
            let colour = COLOURS[p % COLOURS.len()];
            let offset = 0.3 - spread * (p as f64 + 0.5);
            let bars: Vec<_> = groups
                .iter()
                .filter(|g| &g.policy == policy)
                .filter_map(|g| {
                    let k = variants
                        .iter()
                        .position(|v| Some(v) == g.variant.as_ref())?;
                    let y = (rows - 1 - k) as f64 + offset;
                    let e = opt_interval(g);
                    Some(ErrorBar::new_horizontal(
                        y,
                        g.opt.0 - e,
                        g.opt.0,
                        g.opt.0 + e,
                        colour.filled().stroke_width(2),
                        8,
                    ))
                })
                .collect();
            chart
                .draw_series(bars)
                .map_err(plot_error)?
                .label(policy.clone())
                .legend(move |(px, py)| Circle::new((px + 8, py), 5, colour.filled()));
        }
        // Objects per trip lie near 1 or above, so the chart's left is mostly free.
        draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}
