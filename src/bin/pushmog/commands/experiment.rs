//! `experiment`, `merge` and `report`: experiment logs, their tables and figures.

use std::path::Path;

use pushmog::error::{Error, Result};
use pushmog::experiment::{
    ExperimentConfig, Log, RunnerOptions, merge_logs_into, read_log, run_experiment, write_report,
};
use pushmog::json;
use pushmog::plan::Plan;
use pushmog::render::{RenderOptions, plan_svg};

use crate::ExperimentArgs;

use super::io::read_input;

fn parse_shard(text: &str) -> Result<(usize, usize)> {
    let bad = || {
        Error::field(
            "experiment",
            "--shard",
            format!("expected i/n with 0 ≤ i < n, got `{text}`"),
        )
    };
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

pub fn experiment(args: &ExperimentArgs) -> Result<()> {
    let config = ExperimentConfig::read(&args.config)?;
    let shard = match &args.shard {
        Some(text) => parse_shard(text)?,
        None => (0, 1),
    };
    let results = std::path::PathBuf::from("experiments/results");
    let log = args.log.clone().unwrap_or_else(|| {
        if shard.1 == 1 {
            results.join(format!("{}.jsonl", config.name))
        } else {
            results.join(format!(
                "{}.shard-{}-of-{}.jsonl",
                config.name, shard.0, shard.1
            ))
        }
    });
    let example = log.with_file_name(format!("{}-example-plan.json", config.name));
    let base = args.config.parent().unwrap_or(Path::new("."));
    let report = run_experiment(
        &config,
        base,
        &RunnerOptions {
            log: log.clone(),
            shard,
            jobs: args.jobs,
            progress: !args.quiet,
            limit: args.limit,
            example_plan: Some(example.clone()),
        },
    )?;
    eprintln!(
        "{}: {} runs in this shard, {} already logged, {} made now; log {}",
        config.name,
        report.total,
        report.resumed,
        report.made,
        log.display()
    );
    if report.resumed + report.made < report.total {
        eprintln!("stopped early: run the same command again to resume");
        return Ok(());
    }
    if shard.1 > 1 {
        eprintln!("shard done: join the shards with `pushmog merge`, then `pushmog report`");
        return Ok(());
    }
    report_files(
        &read_log(&log)?,
        &args.tables,
        &args.figures,
        Some(&example),
    )
}

fn report_files(log: &Log, tables: &Path, figures: &Path, example: Option<&Path>) -> Result<()> {
    let written = write_report(log, tables, figures)?;
    let mut files = written.files;
    if let Some(path) = example.filter(|p| p.exists()) {
        let (text, name) = read_input(path)?;
        let plan: Plan = json::from_json(&text, &name)?;
        let svg_path = figures.join(format!("{}-example.svg", log.header.config.name));
        let title = format!(
            "{}: run 0 ({}), clusters numbered in execution order",
            log.header.config.name, plan.policy
        );
        json::write_text(
            &svg_path,
            &plan_svg(&plan, &RenderOptions::default(), &title)?,
        )?;
        files.push(svg_path);
    }
    print!("{}", pushmog::experiment::tables::results_markdown(log));
    eprintln!();
    for file in &files {
        eprintln!("wrote {}", file.display());
    }
    Ok(())
}

pub fn merge(logs: &[std::path::PathBuf], output: &Path) -> Result<()> {
    let paths: Vec<&Path> = logs.iter().map(|p| p.as_path()).collect();
    let (header, rows) = merge_logs_into(&paths, output)?;
    eprintln!(
        "merged {} logs: {} of {} runs into {}",
        logs.len(),
        rows,
        header.runs,
        output.display()
    );
    Ok(())
}

pub fn report(path: &Path, tables: &Path, figures: &Path) -> Result<()> {
    let log = read_log(path)?;
    let example = path.with_file_name(format!("{}-example-plan.json", log.header.config.name));
    report_files(&log, tables, figures, Some(&example))
}
