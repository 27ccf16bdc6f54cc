//! The experiment runner: reproducible tables, resumable and shardable logs.

use std::path::Path;

use pushmog::experiment::tables::{results_csv, results_latex, results_markdown};
use pushmog::experiment::{
    ExperimentConfig, LogRow, RunnerOptions, merge_logs, merge_logs_into, read_log, run_experiment,
    write_report,
};

use crate::support::{pushmog, scratch};

fn config(executor: &str) -> ExperimentConfig {
    let text = format!(
        r#"
name = "tiny"
seed = 4
[scenes]
objects = [8]
count = 3
first_seed = 2
workspace = [0.6, 0.45]
[executor]
kind = "{executor}"
[[policies]]
name = "sog"
[[policies]]
name = "push-mog"
"#
    );
    let config: ExperimentConfig = toml::from_str(&text).unwrap();
    config.validate().unwrap();
    config
}

fn options(log: &Path, shard: (usize, usize), limit: Option<usize>) -> RunnerOptions {
    RunnerOptions {
        log: log.to_path_buf(),
        shard,
        jobs: 2,
        progress: false,
        limit,
        example_plan: None,
    }
}

/// Rows without their wall-clock measurements.
fn figures(rows: &[LogRow]) -> Vec<LogRow> {
    rows.iter()
        .map(|r| LogRow {
            timing: Default::default(),
            ..r.clone()
        })
        .collect()
}

#[test]
fn the_same_config_and_seed_give_byte_identical_tables() {
    let dir = scratch("experiment-tables");
    let config = config("ideal");
    let (a, b) = (dir.join("a.jsonl"), dir.join("b.jsonl"));
    run_experiment(&config, Path::new("."), &options(&a, (0, 1), None)).unwrap();
    run_experiment(&config, Path::new("."), &options(&b, (0, 1), None)).unwrap();
    let (a, b) = (read_log(&a).unwrap(), read_log(&b).unwrap());
    assert_eq!(a.rows.len(), 6);
    assert_eq!(results_markdown(&a), results_markdown(&b));
    assert_eq!(results_csv(&a), results_csv(&b));
    assert_eq!(results_latex(&a), results_latex(&b));
    assert_eq!(figures(&a.rows), figures(&b.rows));
}

#[test]
fn an_interrupted_log_resumes_to_the_same_rows() {
    let dir = scratch("experiment-resume");
    let config = config("sim");
    let whole = dir.join("whole.jsonl");
    run_experiment(&config, Path::new("."), &options(&whole, (0, 1), None)).unwrap();
    // Stop after two runs, tear the file in the middle of a line, then resume.
    let broken = dir.join("broken.jsonl");
    let first =
        run_experiment(&config, Path::new("."), &options(&broken, (0, 1), Some(2))).unwrap();
    assert_eq!(first.made, 2);
    let mut text = std::fs::read_to_string(&broken).unwrap();
    text.push_str("{\"id\": 2, \"objects\": 8, \"scene_se");
    std::fs::write(&broken, text).unwrap();
    let rest = run_experiment(&config, Path::new("."), &options(&broken, (0, 1), None)).unwrap();
    assert_eq!((rest.resumed, rest.made), (2, 4));
    let (whole, broken) = (read_log(&whole).unwrap(), read_log(&broken).unwrap());
    assert_eq!(figures(&whole.rows), figures(&broken.rows));
    assert_eq!(results_markdown(&whole), results_markdown(&broken));
}

#[test]
fn shards_merge_into_the_whole() {
    let dir = scratch("experiment-shards");
    let config = config("ideal");
    let whole = dir.join("whole.jsonl");
    run_experiment(&config, Path::new("."), &options(&whole, (0, 1), None)).unwrap();
    let shards: Vec<_> = (0..3)
        .map(|i| {
            let path = dir.join(format!("shard-{i}.jsonl"));
            run_experiment(&config, Path::new("."), &options(&path, (i, 3), None)).unwrap();
            path
        })
        .collect();
    let paths: Vec<&Path> = shards.iter().map(|p| p.as_path()).collect();
    let merged = merge_logs(&paths).unwrap();
    let whole_log = read_log(&whole).unwrap();
    assert_eq!(figures(&merged.rows), figures(&whole_log.rows));
    // Written row by row, the merge is the same log, header included, with the whole run's figures.
    let streamed = dir.join("streamed.jsonl");
    let (header, rows) = merge_logs_into(&paths, &streamed).unwrap();
    assert_eq!(rows, whole_log.rows.len());
    assert_eq!(header, whole_log.header);
    assert_eq!(read_log(&streamed).unwrap(), merged);
    // Shards given twice, or in another order, merge the same.
    let twice: Vec<&Path> = paths.iter().rev().chain(&paths).copied().collect();
    assert_eq!(merge_logs(&twice).unwrap(), merged);
    // A log of another configuration is refused.
    let other = dir.join("other.jsonl");
    let mut changed = config.clone();
    changed.seed = 5;
    run_experiment(&changed, Path::new("."), &options(&other, (0, 1), None)).unwrap();
    assert!(merge_logs(&[paths[0], other.as_path()]).is_err());
    // Resuming a log with another configuration is refused too.
    assert!(run_experiment(&changed, Path::new("."), &options(&whole, (0, 1), None)).is_err());
}

#[test]
fn killing_the_command_midway_and_restarting_gives_the_same_log() {
    let dir = scratch("experiment-kill");
    let config_path = dir.join("tiny.toml");
    std::fs::write(
        &config_path,
        "name = \"tiny\"\nseed = 3\n[scenes]\nobjects = [10]\ncount = 4\n[executor]\nkind = \"sim\"\n\
         [[policies]]\nname = \"sog\"\n[[policies]]\nname = \"push-mog\"\n",
    )
    .unwrap();
    let log = |name: &str| dir.join(name);
    let run = |log_path: &Path| {
        pushmog(&[
            "experiment",
            config_path.to_str().unwrap(),
            "--log",
            log_path.to_str().unwrap(),
            "--tables",
            dir.join("tables").to_str().unwrap(),
            "--figures",
            dir.join("figures").to_str().unwrap(),
            "--quiet",
        ])
    };
    assert_eq!(run(&log("whole.jsonl")).status.code(), Some(0));
    // Start, kill it hard after a moment, restart.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pushmog"))
        .args([
            "experiment",
            config_path.to_str().unwrap(),
            "--log",
            log("killed.jsonl").to_str().unwrap(),
            "--quiet",
            "--jobs",
            "1",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(700));
    let _ = child.kill();
    let _ = child.wait();
    assert_eq!(run(&log("killed.jsonl")).status.code(), Some(0));
    let whole = read_log(&log("whole.jsonl")).unwrap();
    let killed = read_log(&log("killed.jsonl")).unwrap();
    assert_eq!(figures(&whole.rows), figures(&killed.rows));
    assert!(dir.join("tables/tiny.md").exists());
    assert!(dir.join("figures/tiny-opt.svg").exists());
}

#[test]
fn bad_configurations_are_refused_with_the_field() {
    let dir = scratch("experiment-bad");
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        "name = \"bad\"\n[scenes]\nobjects = []\ncount = 1\n[[policies]]\nname = \"sog\"\n",
    )
    .unwrap();
    let output = pushmog(&["experiment", path.to_str().unwrap(), "--quiet"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("scenes"));
    std::fs::write(
        &path,
        "name = \"bad\"\n[scenes]\nobjects = [5]\ncount = 1\n[[policies]]\nname = \"greedy\"\n",
    )
    .unwrap();
    let output = pushmog(&["experiment", path.to_str().unwrap(), "--quiet"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("greedy"));
}

/// Two `experiment` processes on one log: the second is refused at once with a clear message, the
/// first finishes, and the log equals an uninterrupted run's.
#[test]
fn a_second_writer_is_refused_and_the_log_stays_whole() {
    let dir = scratch("experiment-two-writers");
    let config_path = dir.join("tiny.toml");
    std::fs::write(
        &config_path,
        "name = \"tiny\"\nseed = 3\n[scenes]\nobjects = [10]\ncount = 4\n[executor]\nkind = \"sim\"\n\
         [[policies]]\nname = \"sog\"\n[[policies]]\nname = \"push-mog\"\n",
    )
    .unwrap();
    let args = |log: &Path| {
        vec![
            "experiment".to_string(),
            config_path.display().to_string(),
            "--log".to_string(),
            log.display().to_string(),
            "--tables".to_string(),
            dir.join("tables").display().to_string(),
            "--figures".to_string(),
            dir.join("figures").display().to_string(),
            "--quiet".to_string(),
            "--jobs".to_string(),
            "1".to_string(),
        ]
    };
    let shared = dir.join("shared.jsonl");
    let mut first = std::process::Command::new(env!("CARGO_BIN_EXE_pushmog"))
        .args(args(&shared))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    let second = std::process::Command::new(env!("CARGO_BIN_EXE_pushmog"))
        .args(args(&shared))
        .output()
        .unwrap();
    let finished = first.wait().unwrap();
    assert!(finished.success());
    assert_eq!(second.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(stderr.contains("another `pushmog experiment`"), "{stderr}");
    let whole = dir.join("whole.jsonl");
    let alone = std::process::Command::new(env!("CARGO_BIN_EXE_pushmog"))
        .args(args(&whole))
        .output()
        .unwrap();
    assert!(alone.status.success());
    assert_eq!(
        figures(&read_log(&shared).unwrap().rows),
        figures(&read_log(&whole).unwrap().rows)
    );
}

/// Damaged logs: a header without its newline is finished, not cut, on resume; a duplicated row is
/// refused by resume and by `report`, naming its line counted from the top of the file.
#[test]
fn damaged_logs_are_mended_or_refused_with_the_line() {
    let dir = scratch("experiment-damaged");
    let config = config("ideal");
    let log = dir.join("log.jsonl");
    run_experiment(&config, &dir, &options(&log, (0, 1), Some(0))).unwrap();
    let text = std::fs::read_to_string(&log).unwrap();
    assert_eq!(text.matches('\n').count(), 1);
    std::fs::write(&log, text.trim_end()).unwrap();
    run_experiment(&config, &dir, &options(&log, (0, 1), None)).unwrap();
    let whole = dir.join("whole.jsonl");
    run_experiment(&config, &dir, &options(&whole, (0, 1), None)).unwrap();
    assert_eq!(
        figures(&read_log(&log).unwrap().rows),
        figures(&read_log(&whole).unwrap().rows)
    );
    // Duplicate the last row.
    let text = std::fs::read_to_string(&log).unwrap();
    let last = text.lines().last().unwrap().to_string();
    std::fs::write(&log, format!("{text}{last}\n")).unwrap();
    let lines = text.lines().count() + 1;
    let error = read_log(&log).unwrap_err().to_string();
    assert!(
        error.contains(&format!("line {lines}")) && error.contains("twice"),
        "{error}"
    );
    let error = run_experiment(&config, &dir, &options(&log, (0, 1), None))
        .unwrap_err()
        .to_string();
    assert!(error.contains("twice"), "{error}");
    let report = pushmog(&["report", log.to_str().unwrap()]);
    assert_eq!(report.status.code(), Some(1));
}

/// Issue 38, defect 7: a header or row that no longer agrees with the log's own configuration is
/// refused by `read_log` (and so by `report` and a resume), naming what disagrees.
#[test]
fn edited_logs_are_refused_with_what_disagrees() {
    let dir = scratch("experiment-edited");
    let config = config("ideal");
    let log = dir.join("log.jsonl");
    run_experiment(&config, &dir, &options(&log, (0, 1), None)).unwrap();
    let text = std::fs::read_to_string(&log).unwrap();
    let header = text.lines().next().unwrap();
    let runs = config.runs().len();
    let hash = read_log(&log).unwrap().header.config_hash;
    let row = text.lines().nth(1).unwrap();
    let carried = row.split("\"carried\":").nth(1).unwrap();
    let carried = &carried[..carried.find(',').unwrap()];
    let cases = [
        (
            header.to_string(),
            header.replace(&hash, "0123456789abcdef"),
            "config_hash",
        ),
        (
            header.to_string(),
            header.replace(
                &format!("\"runs\":{runs}"),
                &format!("\"runs\":{}", runs + 1),
            ),
            "runs",
        ),
        (
            row.to_string(),
            row.replace(&format!("\"carried\":{carried},"), "\"carried\":1000,"),
            "carried 1000",
        ),
    ];
    for (from, to, named) in cases {
        assert_ne!(from, to, "{named}: the edit changed nothing");
        let edited = dir.join("edited.jsonl");
        std::fs::write(&edited, text.replacen(&from, &to, 1)).unwrap();
        let error = read_log(&edited).unwrap_err().to_string();
        assert!(error.contains(named), "{named}: {error}");
        let resumed = run_experiment(&config, &dir, &options(&edited, (0, 1), None));
        assert!(resumed.is_err(), "{named}: resumed");
    }
}

/// Issue 38, defect 6: two policies with one label would be merged into one table row.
#[test]
fn two_policies_with_one_label_are_refused_naming_both() {
    let mut config = config("ideal");
    config.policies[1].name = config.policies[0].name;
    let error = config.validate().unwrap_err().to_string();
    assert!(
        error.contains("policies 1 and 2") && error.contains("`sog`"),
        "{error}"
    );
    config.policies[1].label = Some("sog, again".to_string());
    config.validate().unwrap();
}

#[test]
fn a_workspace_with_three_numbers_is_refused() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/paper.toml"),
    )
    .unwrap()
    .replacen("[scenes]\n", "[scenes]\nworkspace = [0.6, 0.45, 9.0]\n", 1);
    let err = pushmog::experiment::ExperimentConfig::from_toml(&text, "bad").unwrap_err();
    assert!(err.to_string().contains("exactly 2"), "{err}");
}

#[test]
fn a_logged_simulated_run_is_replayed_by_pushmog_run_with_its_run_seed() {
    let dir = scratch("experiment-replay");
    let mut config = config("sim");
    // The command line's default workspace, as `pushmog scene generate` makes it.
    config.scenes.keep_density = false;
    let log = dir.join("log.jsonl");
    let mut options = options(&log, (3, 6), None);
    options.jobs = 1;
    run_experiment(&config, Path::new("."), &options).unwrap();
    let rows = read_log(&log).unwrap().rows;
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    assert_eq!(row.policy, "push-mog");
    let scene = dir.join("scene.json");
    let seed = row.scene_seed.to_string();
    let generated = pushmog(&[
        "scene",
        "generate",
        "--objects",
        "8",
        "--seed",
        &seed,
        "-o",
        scene.to_str().unwrap(),
    ]);
    assert!(generated.status.success());
    let run_seed = row.run_seed.to_string();
    let replayed = pushmog(&[
        "run",
        scene.to_str().unwrap(),
        "--policy",
        "push-mog",
        "--executor",
        "sim",
        "--seed",
        &run_seed,
    ]);
    assert!(replayed.status.success());
    let text = String::from_utf8(replayed.stdout).unwrap();
    let expected_trips = format!("trips             {}\n", row.trips);
    let expected_carried = format!("{} carried", row.carried);
    let expected_pushes = format!(
        "pushes            {} ({:.3} m",
        row.pushes, row.push_distance
    );
    for expected in [&expected_trips, &expected_carried, &expected_pushes] {
        assert!(
            text.contains(expected.as_str()),
            "{expected:?} not in\n{text}"
        );
    }
}

#[test]
fn the_push_distance_figure_is_drawn_when_two_policies_push() {
    let dir = scratch("experiment-push-distance");
    let text = r#"
name = "pushing"
seed = 5
[scenes]
objects = [20]
count = 2
[executor]
kind = "ideal"
[[policies]]
name = "sog"
[[policies]]
name = "push-mog"
[[policies]]
name = "push-mog-socp"
label = "socp rows"
"#;
    let config: ExperimentConfig = toml::from_str(text).unwrap();
    let log_path = dir.join("pushing.jsonl");
    run_experiment(&config, Path::new("."), &options(&log_path, (0, 1), None)).unwrap();
    let log = read_log(&log_path).unwrap();
    let pushing = log
        .rows
        .iter()
        .filter(|r| r.push_distance > 0.0)
        .map(|r| r.policy.as_str())
        .collect::<std::collections::BTreeSet<_>>();
    assert_eq!(pushing.len(), 2, "both pushing policies push: {pushing:?}");
    write_report(&log, &dir, &dir).unwrap();
    let svg = std::fs::read_to_string(dir.join("pushing-push-distance.svg")).unwrap();
    for label in ["sog", "push-mog", "socp rows", "push distance per run"] {
        assert!(svg.contains(label), "{label} missing from the figure");
    }
    // One pushing policy: nothing to compare, no figure.
    let single = dir.join("single");
    let two = dir.join("two.jsonl");
    run_experiment(
        &self::config("ideal"),
        Path::new("."),
        &options(&two, (0, 1), None),
    )
    .unwrap();
    write_report(&read_log(&two).unwrap(), &single, &single).unwrap();
    assert!(single.join("tiny-opt.svg").exists());
    assert!(!single.join("tiny-push-distance.svg").exists());
}

/// Policy labels are the user's text: one holding a comma and quotes comes back whole from the
/// results CSV, and every line has as many fields as the header.
#[test]
fn a_label_with_commas_and_quotes_stays_one_csv_field() {
    use pushmog::experiment::tables::timing_csv;
    let dir = scratch("experiment-csv-label");
    let label = r#"sog, "the baseline""#;
    let mut config = config("ideal");
    config.scenes.count = 1;
    config.policies[0].label = Some(label.to_string());
    let path = dir.join("label.jsonl");
    run_experiment(&config, Path::new("."), &options(&path, (0, 1), None)).unwrap();
    let log = read_log(&path).unwrap();
    for text in [results_csv(&log), timing_csv(&log)] {
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let width = reader.headers().unwrap().len();
        let policies: Vec<String> = reader
            .records()
            .map(|record| {
                let record = record.unwrap();
                assert_eq!(record.len(), width, "{text}");
                record[0].to_string()
            })
            .collect();
        assert_eq!(policies, [label, "push-mog"], "{text}");
    }
}

/// The header names what each policy's planners can claim: only the MILP proves an optimum, and
/// the time limits are the settings'.
#[test]
fn the_log_header_says_what_each_planner_can_claim() {
    let dir = scratch("experiment-abilities");
    let mut config = config("ideal");
    let text = r#"
name = "push-mog-opt"
label = "limited"
settings = { milp = { time_limit = 5.0 }, socp = { time_limit = 0.5 } }
"#;
    config.policies.push(toml::from_str(text).unwrap());
    let log = dir.join("log.jsonl");
    run_experiment(&config, Path::new("."), &options(&log, (0, 1), Some(0))).unwrap();
    let header = read_log(&log).unwrap().header;
    let labels: Vec<&str> = header.abilities.iter().map(|a| a.policy.as_str()).collect();
    assert_eq!(labels, ["sog", "push-mog", "limited"]);
    let [sog, push_mog, limited] = [0, 1, 2].map(|k| &header.abilities[k].planners);
    assert!(sog.clusterer.is_none() && sog.pusher.is_none() && sog.multi_object.is_none());
    let hierarchical = push_mog.clusterer.as_ref().unwrap();
    assert_eq!(hierarchical.name, "hierarchical");
    assert!(!hierarchical.proves_optimality && hierarchical.time_limit.is_none());
    let milp = limited.clusterer.as_ref().unwrap();
    assert_eq!(milp.name, "milp");
    assert!(milp.proves_optimality);
    assert_eq!(milp.time_limit, Some(5.0));
    let socp = limited.pusher.as_ref().unwrap();
    assert_eq!(socp.name, "socp");
    assert!(!socp.proves_optimality);
    assert_eq!(socp.time_limit, Some(0.5));
    for planners in [sog, push_mog, limited] {
        assert!(!planners.single_object.proves_optimality);
    }
}

/// Sweep variants lay their settings over each policy's, key by key; every run carries its
/// variant's label, the tables gain a variant column, and a slower arm takes longer for the same
/// plans (the ideal executor and sog make the same trips whatever the time model).
#[test]
fn sweep_variants_change_the_settings_they_name_and_nothing_else() {
    let dir = scratch("experiment-variants");
    let mut text = toml::to_string(&config("ideal")).unwrap();
    text.push_str(
        r#"
[[sweep.variants]]
label = "as set"

[[sweep.variants]]
label = "slow arm"
policies = { time_model = { travel_acceleration = 0.5 } }
"#,
    );
    let config = ExperimentConfig::from_toml(&text, "variants").unwrap();
    let slow = config.policy_settings(1, None, Some(1)).unwrap();
    let as_set = config.policy_settings(1, None, Some(0)).unwrap();
    assert_eq!(slow.time_model.travel_acceleration, 0.5);
    assert_eq!(
        pushmog::time_model::TimeModel {
            travel_acceleration: as_set.time_model.travel_acceleration,
            ..slow.time_model.clone()
        },
        as_set.time_model
    );
    assert_eq!(
        pushmog::policy::PolicySettings {
            time_model: as_set.time_model.clone(),
            ..slow.clone()
        },
        as_set
    );
    let path = dir.join("variants.jsonl");
    run_experiment(&config, Path::new("."), &options(&path, (0, 1), None)).unwrap();
    let log = read_log(&path).unwrap();
    assert_eq!(log.rows.len(), 12);
    for pair in log.rows.chunks(4) {
        // Per scene: sog and push-mog as set, then both with the slow arm.
        let labels: Vec<_> = pair.iter().map(|r| r.variant.as_deref().unwrap()).collect();
        assert_eq!(labels, ["as set", "as set", "slow arm", "slow arm"]);
        let (fast, slow) = (&pair[0], &pair[2]);
        assert_eq!((fast.policy.as_str(), slow.policy.as_str()), ("sog", "sog"));
        assert_eq!(fast.trips, slow.trips);
        assert!(
            slow.robot_seconds > fast.robot_seconds,
            "{fast:?}\n{slow:?}"
        );
    }
    let markdown = results_markdown(&log);
    assert!(
        markdown.contains("| variant") && markdown.contains("slow arm"),
        "{markdown}"
    );
    let csv = results_csv(&log);
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let headers = reader.headers().unwrap().clone();
    let column = headers.iter().position(|h| h == "variant").unwrap();
    let variants: Vec<String> = reader
        .records()
        .map(|r| r.unwrap()[column].to_string())
        .collect();
    assert_eq!(
        variants,
        ["as set", "as set", "slow arm", "slow arm"],
        "{csv}"
    );
    // The figure of objects per trip by variant takes the per-policy figure's place.
    let report = write_report(&log, &dir.join("tables"), &dir.join("figures")).unwrap();
    let names: Vec<String> = report
        .files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.contains(&"tiny-variants.svg".to_string()),
        "{names:?}"
    );
    assert!(!names.contains(&"tiny-opt.svg".to_string()), "{names:?}");
    let svg = std::fs::read_to_string(dir.join("figures").join("tiny-variants.svg")).unwrap();
    assert!(
        svg.contains("slow arm") && svg.contains("push-mog"),
        "{svg}"
    );
    // Without variants the CSV has no such column, as before variants existed.
    let mut plain = self::config("ideal");
    plain.scenes.count = 1;
    let path = dir.join("plain.jsonl");
    run_experiment(&plain, Path::new("."), &options(&path, (0, 1), None)).unwrap();
    let csv = results_csv(&read_log(&path).unwrap());
    assert!(
        csv.starts_with("policy,objects,bin_distance,friction,runs,"),
        "{csv}"
    );
}

/// A variant that names a setting nobody has, repeats a label, or changes the simulator of an
/// ideal executor is refused, naming the variant.
#[test]
fn bad_sweep_variants_are_refused_naming_the_variant() {
    let base = toml::to_string(&config("ideal")).unwrap();
    for (variant, expected) in [
        (
            "[[sweep.variants]]\nlabel = \"typo\"\npolicies = { time_model = { travel_aceleration = 1.0 } }\n",
            "typo",
        ),
        (
            "[[sweep.variants]]\nlabel = \"a\"\n[[sweep.variants]]\nlabel = \"a\"\n",
            "two variants",
        ),
        (
            "[[sweep.variants]]\nlabel = \"sticky\"\nsim = { friction_object = 0.6 }\n",
            "sticky",
        ),
        ("[[sweep.variants]]\nlabel = \" \"\n", "needs a label"),
    ] {
        let text = format!("{base}\n{variant}");
        let error = ExperimentConfig::from_toml(&text, "bad")
            .unwrap_err()
            .to_string();
        assert!(error.contains(expected), "{variant}: {error}");
    }
}

/// A policy's `settings_file` is read relative to the configuration's folder and its own `settings`
/// are laid over it key by key: the configuration read is the one with everything written inline,
/// down to its `config_hash` (so logs of either resume from the other). A file that cannot be read,
/// or holds something that is not policy settings, is refused naming the file.
#[test]
fn a_settings_file_is_the_same_configuration_as_its_settings_written_inline() {
    let dir = scratch("experiment-settings-file");
    std::fs::create_dir_all(dir.join("shared")).unwrap();
    std::fs::write(
        dir.join("shared/mine.json"),
        r#"{ "pricing": { "objective": "expected_time", "push_ahead": true },
            "time_model": { "observation": 2.0, "arm_settle": 0.5 } }"#,
    )
    .unwrap();
    let head = "name = \"file\"\n[scenes]\nobjects = [8]\ncount = 2\n[[policies]]\nname = \"sog\"\n\
                [[policies]]\nname = \"push-mog-opt\"\n";
    let with_file = format!(
        "{head}settings_file = \"shared/mine.json\"\nsettings = {{ time_model = {{ arm_settle = 0.7 }}, \
         milp = {{ max_diameter = 0.12 }} }}\n"
    );
    let inline = format!(
        "{head}settings = {{ pricing = {{ objective = \"expected_time\", push_ahead = true }}, \
         time_model = {{ observation = 2.0, arm_settle = 0.7 }}, milp = {{ max_diameter = 0.12 }} }}\n"
    );
    let path = dir.join("file.toml");
    std::fs::write(&path, &with_file).unwrap();
    let read = ExperimentConfig::read(&path).unwrap();
    let written = ExperimentConfig::from_toml(&inline, "inline").unwrap();
    assert_eq!(read, written);
    assert_eq!(
        pushmog::experiment::log::config_hash(&read),
        pushmog::experiment::log::config_hash(&written)
    );
    assert_eq!(read.policies[1].settings.time_model.arm_settle, 0.7);
    assert_eq!(read.policies[1].settings.time_model.observation, 2.0);
    assert!(read.policies[1].settings_file.is_none());

    // From text, the file is found from the current directory, not from the configuration's.
    let missing = ExperimentConfig::from_toml(&with_file, "text").unwrap_err();
    assert!(missing.to_string().contains("mine.json"), "{missing}");
    std::fs::write(
        dir.join("shared/mine.json"),
        r#"{ "pricing": { "objective": "expected_time", "pushahead": true } }"#,
    )
    .unwrap();
    let wrong = ExperimentConfig::read(&path).unwrap_err().to_string();
    assert!(
        wrong.contains("mine.json") && wrong.contains("pushahead"),
        "{wrong}"
    );
    std::fs::write(&path, format!("{head}settings_file = 3\n")).unwrap();
    let not_a_path = ExperimentConfig::read(&path).unwrap_err().to_string();
    assert!(not_a_path.contains("settings_file"), "{not_a_path}");
}

/// A preset's name in a policy entry is its policy with its settings, the entry's own laid over
/// them, labelled with the preset's name unless the entry gives a label: the configuration read is
/// the one written out with the settings file, down to its `config_hash`.
#[test]
fn a_preset_name_is_the_same_configuration_as_its_settings_written_out() {
    let experiments = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let head = "name = \"presets\"\n[scenes]\nobjects = [8]\ncount = 2\n";
    let named = format!(
        "{head}[[policies]]\nname = \"push-mog-time-riders\"\nsettings = {{ run = {{ reach_past_edge = 0.05 }} }}\n\
         [[policies]]\nname = \"push-mog-opt-riders\"\nlabel = \"opt with riders\"\n"
    );
    let written = format!(
        "{head}[[policies]]\nname = \"push-mog-opt\"\nlabel = \"push-mog-time-riders\"\n\
         settings_file = \"push-mog-time.json\"\n\
         settings = {{ riders = {{ enabled = true }}, run = {{ reach_past_edge = 0.05 }} }}\n\
         [[policies]]\nname = \"push-mog-opt\"\nlabel = \"opt with riders\"\n\
         settings = {{ riders = {{ enabled = true }} }}\n"
    );
    let named = ExperimentConfig::from_toml(&named, "named").unwrap();
    let written = ExperimentConfig::from_toml_in(&written, "written", &experiments).unwrap();
    assert_eq!(named, written);
    assert_eq!(
        pushmog::experiment::log::config_hash(&named),
        pushmog::experiment::log::config_hash(&written)
    );
    assert!(named.policies[0].settings.run.fuse_looks);
    assert_eq!(named.policies[0].settings.run.reach_past_edge, 0.05);
    let wrong = format!("{head}[[policies]]\nname = \"push-mog-time\"\nsettings = {{ run = 3 }}\n");
    let error = ExperimentConfig::from_toml(&wrong, "wrong").unwrap_err();
    assert!(error.to_string().contains("run"), "{error}");
}

/// The README's main job (`cargo run --release -- experiment experiments/paper.toml`) resumes the
/// committed log: its header must be of the configuration as the code reads it now, or the command
/// refuses the log. A new setting with a default changes the hash, so a change that adds one must
/// run the main job again and commit its log.
#[test]
fn the_main_jobs_committed_log_is_of_its_configuration_as_read_now() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = ExperimentConfig::read(&root.join("experiments/paper.toml")).unwrap();
    let log = read_log(&root.join("experiments/results/paper.jsonl")).unwrap();
    assert_eq!(
        log.header.config_hash,
        pushmog::experiment::log::config_hash(&config),
        "experiments/results/paper.jsonl was written by another configuration: run the main job again"
    );
    assert_eq!(log.rows.len(), log.header.runs, "the log is not complete");
}
