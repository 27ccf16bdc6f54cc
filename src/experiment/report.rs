//! Writes every table and figure of a log: Markdown, CSV and LaTeX tables (results and, apart,
//! wall-clock timing), SVG figures, and the example plan's drawing when there is one.

use std::path::{Path, PathBuf};

use super::break_even::{break_even_markdown, ratio_to_sog_svg};
use super::figures::{
    friction_svg, opt_per_policy_svg, picks_per_hour_svg, planning_time_svg, push_distance_svg,
    variants_svg,
};
use super::log::Log;
use super::tables::{
    results_csv, results_latex, results_markdown, summarise, timing_csv, timing_markdown,
};
use crate::error::Result;
use crate::json::write_text;

/// Where a report's files went.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReportPaths {
    /// Every file written.
    pub files: Vec<PathBuf>,
}

/// Writes the tables of `log` to `tables` (as `<name>.md`, `.csv`, `.tex`, and `<name>-timing.*`)
/// and its figures to `figures` (`<name>-opt.svg`, or `<name>-variants.svg` when the configuration
/// has sweep variants; the bin-distance, friction or object-count plot
/// when the log sweeps those, and with a bin-distance sweep the ratio to sog with each policy's
/// break-even distance, `<name>-ratio-to-sog.svg`, also stated under the Markdown table; objects per trip against push distance, `<name>-push-distance.svg`,
/// when it sweeps nothing and two or more of its policies push).
///
/// # Errors
/// I/O and drawing errors.
pub fn write_report(log: &Log, tables: &Path, figures: &Path) -> Result<ReportPaths> {
    let name = &log.header.config.name;
    let mut files = Vec::new();
    let mut put = |path: PathBuf, text: String| -> Result<()> {
        write_text(&path, &text)?;
        files.push(path);
        Ok(())
    };
    let config = &log.header.config;
    let by_distance = config.sweep.bin_distance.len() > 1;
    let mut markdown = results_markdown(log);
    let break_even_lines = if by_distance {
        break_even_markdown(log)
    } else {
        String::new()
    };
    if !break_even_lines.is_empty() {
        markdown.push('\n');
        markdown.push_str(&break_even_lines);
    }
    put(tables.join(format!("{name}.md")), markdown)?;
    put(tables.join(format!("{name}.csv")), results_csv(log))?;
    put(tables.join(format!("{name}.tex")), results_latex(log))?;
    put(
        tables.join(format!("{name}-timing.md")),
        timing_markdown(log),
    )?;
    put(tables.join(format!("{name}-timing.csv")), timing_csv(log))?;
    if config.sweep.variants.is_empty() {
        put(
            figures.join(format!("{name}-opt.svg")),
            opt_per_policy_svg(log)?,
        )?;
    } else {
        put(
            figures.join(format!("{name}-variants.svg")),
            variants_svg(log)?,
        )?;
    }
    if by_distance {
        put(
            figures.join(format!("{name}-picks-per-hour.svg")),
            picks_per_hour_svg(log)?,
        )?;
        if !break_even_lines.is_empty() {
            put(
                figures.join(format!("{name}-ratio-to-sog.svg")),
                ratio_to_sog_svg(log)?,
            )?;
        }
    }
    if config.sweep.friction.len() > 1 {
        put(
            figures.join(format!("{name}-friction.svg")),
            friction_svg(log)?,
        )?;
    }
    if config.scenes.objects.len() > 1 {
        put(
            figures.join(format!("{name}-planning-time.svg")),
            planning_time_svg(log)?,
        )?;
    }
    let sweeps = config.sweep.bin_distance.len() > 1
        || config.sweep.friction.len() > 1
        || !config.sweep.variants.is_empty()
        || config.scenes.objects.len() > 1;
    let pushing = summarise(log)
        .iter()
        .filter(|g| g.push_distance > 0.0)
        .count();
    if !sweeps && pushing >= 2 {
        put(
            figures.join(format!("{name}-push-distance.svg")),
            push_distance_svg(log)?,
        )?;
    }
    Ok(ReportPaths { files })
}
