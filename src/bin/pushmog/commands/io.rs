//! Reading and writing what the commands share: input files (or standard input), settings files
//! over defaults, a policy by name, and the summary of a run.

use std::io::Read as _;
use std::path::Path;

use pushmog::error::{Error, Result};
use pushmog::json;
use pushmog::plan::{Plan, RunStatus};
use pushmog::policy::Policy;
use pushmog::scene::Scene;

/// Reads a file, or standard input for `-`.
pub(super) fn read_input(path: &Path) -> Result<(String, String)> {
    if path == Path::new("-") {
        let mut bytes = Vec::new();
        std::io::stdin()
            .read_to_end(&mut bytes)
            .map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        Ok((
            json::text_from_bytes(bytes, "<stdin>")?,
            "<stdin>".to_string(),
        ))
    } else {
        Ok((json::read_text(path)?, path.display().to_string()))
    }
}

pub(crate) fn read_scene(path: &Path) -> Result<Scene> {
    let (text, name) = read_input(path)?;
    json::scene_from_json(&text, &name)
}

/// Writes to a file, or to standard output when no path is given.
pub(super) fn write_output(path: Option<&Path>, text: &str) -> Result<()> {
    match path {
        Some(path) => json::write_text(path, text),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

pub(super) fn settings_or_default<T: serde::de::DeserializeOwned + Default>(
    path: Option<&Path>,
) -> Result<T> {
    match path {
        Some(path) => {
            let (text, source) = read_input(path)?;
            json::from_json::<T>(&text, &source)
        }
        None => Ok(T::default()),
    }
}

/// The policy `name` (one of the six or a named preset) with the settings of the file `settings`
/// laid over its own.
pub(crate) fn policy(name: &str, settings: Option<&Path>) -> Result<Policy> {
    let (kind, settings) = match settings {
        Some(path) => {
            let (text, source) = read_input(path)?;
            pushmog::policy::preset::resolve(name, Some(&text), &source)?
        }
        None => pushmog::policy::preset::resolve(name, None, "settings")?,
    };
    Policy::new(kind, settings)
}

/// The figures of a run, one per line.
pub(crate) fn summary(plan: &Plan, objects: usize) -> String {
    let mut out = format!(
        "policy {} (executor {}, seed {})\n",
        plan.policy, plan.executor, plan.seed
    );
    out.push_str(&format!(
        "objects           {} on the table, {} carried\n",
        objects,
        plan.objects_carried()
    ));
    out.push_str(&format!("trips             {}\n", plan.trips.len()));
    out.push_str(&format!(
        "objects per trip  {:.3}\n",
        plan.objects_per_trip()
    ));
    out.push_str(&format!(
        "pushes            {} ({:.3} m in total)\n",
        plan.push_count(),
        plan.push_distance()
    ));
    let skipped: usize = plan.trips.iter().map(|t| t.plan.skipped_pushes.len()).sum();
    out.push_str(&format!("pushes skipped    {skipped}\n"));
    out.push_str(&format!("failed grasps     {}\n", plan.failed_grasps()));
    out.push_str(&format!(
        "robot time        {:.1} s ({:.0} picks per hour)\n",
        // Adding zero turns a negative zero into zero ("-0.0 s" for a run with no trips).
        plan.seconds + 0.0,
        plan.picks_per_hour() + 0.0
    ));
    out.push_str(&format!(
        "failed attempts   {}\n",
        plan.failed_attempts.len()
    ));
    if let Some(unproven) = plan.unproven_clusterings() {
        out.push_str(&format!(
            "clusterings       {} of {} trips proven optimal\n",
            plan.trips.len() - unproven,
            plan.trips.len()
        ));
    }
    // Trips counted from 1, as in the replay.
    for (k, trip) in plan.trips.iter().enumerate() {
        for lost in &trip.lost {
            out.push_str(&format!(
                "lost              object {} in trip {} ({})\n",
                lost.object,
                k + 1,
                lost.reason
            ));
        }
    }
    match &plan.status {
        RunStatus::Cleared => out.push_str("status            cleared\n"),
        RunStatus::Stopped { remaining, reason } => out.push_str(&format!(
            "status            stopped with {} objects left: {reason}\n",
            remaining.len()
        )),
    }
    out
}
