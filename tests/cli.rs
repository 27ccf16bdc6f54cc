//! The command line: exit codes, messages that name the culprit, byte-identical generation.

use crate::support::{fixture, pushmog, scratch};

/// Every bad-input class gives exit code 1 and a message naming the culprit (object and field, or the
/// JSON position).
#[test]
fn bad_input_exits_1_and_names_the_culprit() {
    let cases: &[(&str, &[&str])] = &[
        (
            "too-few-vertices",
            &["object 4", "`vertices`", "at least 3 vertices"],
        ),
        (
            "infinite-coordinate",
            &["line 17", "objects[0].vertices[0][0]", "out of range"],
        ),
        (
            "non-convex",
            &["object 5", "`vertices`", "not convex", "vertex 2"],
        ),
        (
            "self-intersecting",
            &["object 6", "`vertices`", "intersects itself"],
        ),
        (
            "collinear-vertex",
            &["object 7", "`vertices`", "vertex 1 is collinear"],
        ),
        ("zero-area", &["object 8", "`vertices`", "zero area"]),
        ("duplicate-ids", &["object id 2", "entries 1 and 2"]),
        ("overlapping", &["objects 2 and 9 overlap"]),
        (
            "outside-workspace",
            &["object 10", "`pose`", "outside the workspace"],
        ),
        ("malformed", &["line 34, column 7", "objects[0]"]),
        (
            "absurd-scale",
            &["object 11", "`vertices`", "larger than the", "millimetres"],
        ),
        ("negative-height", &["object 12", "`height`"]),
        ("wrong-type", &["objects[0].height", "invalid type"]),
        ("unknown-field", &["objects[0].heigth", "unknown field"]),
        ("bad-gripper", &["gripper", "`plate_thickness`"]),
        ("bad-workspace", &["workspace", "`max`"]),
    ];
    for (name, expected) in cases {
        let path = fixture(&format!("bad/{name}.json"));
        let output = pushmog(&["scene", "check", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{name}: {stderr}");
        for part in *expected {
            assert!(
                stderr.contains(part),
                "{name}: `{part}` missing from: {stderr}"
            );
        }
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        // Rendering refuses the same input the same way.
        let render = pushmog(&["render", path.to_str().unwrap()]);
        assert_eq!(render.status.code(), Some(1), "render {name}");
    }
}

#[test]
fn every_bad_fixture_is_covered() {
    let listed = std::fs::read_dir(fixture("bad")).unwrap().count();
    assert_eq!(
        listed, 16,
        "add new fixtures to bad_input_exits_1_and_names_the_culprit"
    );
}

#[test]
fn ungraspable_objects_are_accepted_but_flagged() {
    let path = fixture("good/ungraspable.json");
    let output = pushmog(&["scene", "check", path.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("NO: wider than the 75.0 mm gap"),
        "{stdout}"
    );
    assert!(
        stdout.contains("1 of 3 objects ungraspable (ids 3)"),
        "{stdout}"
    );
}

#[test]
fn check_prints_each_minimum_grasp_diameter() {
    let path = fixture("good/minimal.json");
    let output = pushmog(&["scene", "check", path.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&output.stdout);
    // Two 30 mm squares.
    assert_eq!(stdout.matches("  30.00  yes").count(), 2, "{stdout}");
}

#[test]
fn usage_errors_exit_2_and_help_exits_0() {
    assert_eq!(pushmog(&["scene", "check"]).status.code(), Some(2));
    assert_eq!(pushmog(&["no-such-command"]).status.code(), Some(2));
    assert_eq!(
        pushmog(&["scene", "generate", "--objects", "many"])
            .status
            .code(),
        Some(2)
    );
    for args in [
        &["--help"][..],
        &["scene", "--help"],
        &["scene", "generate", "--help"],
        &["scene", "check", "--help"],
        &["render", "--help"],
        &["schema", "--help"],
        &["library", "--help"],
        &["demo", "--help"],
        &["plan", "--help"],
        &["run", "--help"],
        &["verify", "--help"],
    ] {
        let output = pushmog(args);
        assert_eq!(output.status.code(), Some(0), "{args:?}");
        assert!(String::from_utf8_lossy(&output.stdout).contains("Usage"));
    }
}

#[test]
fn missing_files_exit_1_with_the_path() {
    let output = pushmog(&["scene", "check", "/no/such/scene.json"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("/no/such/scene.json"));
}

#[test]
fn generate_is_byte_identical_per_seed() {
    let dir = scratch("generate");
    let run = |seed: &str, file: &str| {
        let path = dir.join(file);
        let output = pushmog(&[
            "scene",
            "generate",
            "--objects",
            "34",
            "--seed",
            seed,
            "-o",
            path.to_str().unwrap(),
        ]);
        assert_eq!(output.status.code(), Some(0));
        std::fs::read(path).unwrap()
    };
    let first = run("7", "a.json");
    assert_eq!(first, run("7", "b.json"));
    assert_ne!(first, run("8", "c.json"));
    // Standard output carries the same bytes.
    let stdout = pushmog(&["scene", "generate", "--seed", "7"]).stdout;
    assert_eq!(first, stdout);
}

#[test]
fn generate_reports_scenes_that_cannot_fit() {
    let output = pushmog(&[
        "scene",
        "generate",
        "--objects",
        "200",
        "--width",
        "0.3",
        "--depth",
        "0.3",
        "--max-samples",
        "2000",
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("placed only"));
}

#[test]
fn render_draws_every_object_with_its_id_and_a_scale_bar() {
    let dir = scratch("render");
    let scene = dir.join("scene.json");
    let svg = dir.join("scene.svg");
    pushmog(&[
        "scene",
        "generate",
        "--seed",
        "3",
        "-o",
        scene.to_str().unwrap(),
    ]);
    let output = pushmog(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
        "--grasp-diameters",
    ]);
    assert_eq!(output.status.code(), Some(0));
    let text = std::fs::read_to_string(svg).unwrap();
    assert!(text.starts_with("<svg"));
    // Workspace plus 34 objects.
    assert_eq!(text.matches("<polygon").count(), 35);
    assert!(text.contains("class=\"scale-bar\""));
    for id in 0..34 {
        assert!(text.contains(&format!(">{id}</text>")), "id {id}");
    }
}

#[test]
fn schemas_are_json_and_describe_the_fields() {
    for (format, field) in [
        ("scene", "workspace"),
        ("object-set", "objects"),
        ("policy", "socp"),
        ("sim", "grip_force"),
        ("plan", "trips"),
    ] {
        let output = pushmog(&["schema", format]);
        assert_eq!(output.status.code(), Some(0));
        let schema: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
        assert!(
            schema["properties"][field].is_object(),
            "{format}: {schema}"
        );
    }
}

#[test]
fn exported_library_generates_the_same_scene() {
    let dir = scratch("library");
    let set = dir.join("set.json");
    let output = pushmog(&["library", "--json", "-o", set.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0));
    let builtin = pushmog(&["scene", "generate", "--seed", "4"]).stdout;
    let loaded = pushmog(&[
        "scene",
        "generate",
        "--seed",
        "4",
        "--object-set",
        set.to_str().unwrap(),
    ])
    .stdout;
    assert_eq!(builtin, loaded);
}

#[test]
fn demo_writes_a_scene_and_a_drawing() {
    let dir = scratch("demo");
    let output = pushmog(&["demo", "--out", dir.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0));
    for file in ["scene.json", "scene.svg", "plan.json", "plan.svg"] {
        assert!(dir.join(file).exists(), "{file}");
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("| push-mog |"), "{stdout}");
}

#[test]
fn plan_run_verify_and_render_a_plan() {
    let dir = scratch("plan");
    let scene = dir.join("scene.json");
    let plan = dir.join("plan.json");
    let svg = dir.join("plan.svg");
    pushmog(&[
        "scene",
        "generate",
        "--seed",
        "2",
        "-o",
        scene.to_str().unwrap(),
    ]);
    let output = pushmog(&[
        "plan",
        scene.to_str().unwrap(),
        "--policy",
        "push-mog",
        "-o",
        plan.to_str().unwrap(),
    ]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let verified = pushmog(&["verify", plan.to_str().unwrap()]);
    assert_eq!(verified.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&verified.stdout).contains("no violations"));
    let drawn = pushmog(&[
        "render",
        plan.to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(drawn.status.code(), Some(0));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("class=\"trip-1\""));
    for policy in ["sog", "mog", "push-mog"] {
        let output = pushmog(&["run", scene.to_str().unwrap(), "--policy", policy]);
        assert_eq!(output.status.code(), Some(0), "{policy}");
        let stdout = String::from_utf8_lossy(&output.stdout);
        for field in [
            "trips",
            "objects per trip",
            "failed grasps",
            "status            cleared",
        ] {
            assert!(stdout.contains(field), "{policy}: {stdout}");
        }
    }
}

#[test]
fn unknown_policies_and_executors_are_named() {
    let scene = fixture("good/minimal.json");
    // Usage errors (exit 2) that list the choices.
    let output = pushmog(&["run", scene.to_str().unwrap(), "--policy", "greedy"]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("'greedy'"), "{stderr}");
    assert!(stderr.contains("push-mog-opt"), "{stderr}");
    let output = pushmog(&["run", scene.to_str().unwrap(), "--executor", "robot"]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("'robot'") && stderr.contains("sim"),
        "{stderr}"
    );
    let output = pushmog(&["render", scene.to_str().unwrap(), "--scale", "1e308"]);
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn a_tampered_plan_fails_verification() {
    let dir = scratch("tampered");
    let scene = dir.join("scene.json");
    let plan = dir.join("plan.json");
    pushmog(&[
        "scene",
        "generate",
        "--seed",
        "5",
        "-o",
        scene.to_str().unwrap(),
    ]);
    pushmog(&[
        "plan",
        scene.to_str().unwrap(),
        "-o",
        plan.to_str().unwrap(),
    ]);
    let mut value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&plan).unwrap()).unwrap();
    // Move the first grasp's jaws onto the middle of its first object: a plate now lands on it or
    // the row no longer lies between the plates.
    let trip = &mut value["trips"][0];
    let id = trip["grasp"]["objects"][0].as_u64().unwrap();
    let object = trip["scene"]["objects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["id"].as_u64() == Some(id))
        .unwrap()
        .clone();
    let (x, y) = (
        object["pose"]["x"].as_f64().unwrap(),
        object["pose"]["y"].as_f64().unwrap(),
    );
    let half = trip["grasp"]["jaws"]["opening"].as_f64().unwrap() / 2.0;
    trip["grasp"]["jaws"]["center"] = serde_json::json!([x + half, y]);
    trip["grasp"]["jaws"]["angle"] = serde_json::json!(0.0);
    std::fs::write(&plan, serde_json::to_string(&value).unwrap()).unwrap();
    let output = pushmog(&["verify", plan.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("trip 0: grasp"));
}

#[test]
fn run_in_the_simulator_with_a_replay() {
    let dir = scratch("sim-run");
    let scene = dir.join("scene.json");
    let replay = dir.join("replay.html");
    let generated = pushmog(&[
        "scene",
        "generate",
        "--objects",
        "6",
        "--width",
        "0.25",
        "--depth",
        "0.2",
        "--seed",
        "2",
        "-o",
        scene.to_str().unwrap(),
    ]);
    assert_eq!(generated.status.code(), Some(0));
    let output = pushmog(&[
        "run",
        scene.to_str().unwrap(),
        "--policy",
        "push-mog",
        "--executor",
        "sim",
        "--seed",
        "3",
        "--replay",
        replay.to_str().unwrap(),
    ]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    for field in [
        "executor sim",
        "objects per trip",
        "robot time",
        "picks per hour",
    ] {
        assert!(stdout.contains(field), "{stdout}");
    }
    let html = std::fs::read_to_string(replay).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.contains("<svg") && html.contains("trip 1 of"));
}

/// `cluster --policy-settings` clusters as a policy with those settings does: the MILP gets the
/// policy's time model (here a bin 2 m away), and its objective is the library's for the policy's
/// effective MILP settings. With `--settings` as well it is a usage error.
#[test]
fn cluster_takes_the_policys_shared_settings() {
    use pushmog::cluster::Clusterer;
    use pushmog::policy::PolicySettings;
    let dir = scratch("cluster-policy-settings");
    let scene = dir.join("scene.json");
    let settings = dir.join("policy.json");
    let text = r#"{"time_model": {"bin_distance": 2.0}, "min_push": 0.005}"#;
    std::fs::write(&settings, text).unwrap();
    pushmog(&[
        "scene",
        "generate",
        "--seed",
        "3",
        "-o",
        scene.to_str().unwrap(),
    ]);
    let objective = |args: &[&str]| {
        let output = pushmog(&[&["cluster", scene.to_str().unwrap()], args].concat());
        assert_eq!(output.status.code(), Some(0));
        let stdout = String::from_utf8(output.stdout).unwrap();
        let line = stdout.lines().find(|l| l.starts_with("objective")).unwrap();
        line.split_whitespace().nth(1).unwrap().to_string()
    };
    let policy: PolicySettings = serde_json::from_str(text).unwrap();
    let spec = std::fs::read_to_string(&scene).unwrap();
    let table =
        pushmog::scene::Scene::new(pushmog::json::from_json(&spec, "scene").unwrap()).unwrap();
    let expected = policy
        .milp_clusterer(policy.problem().unwrap(), policy.row_test())
        .unwrap()
        .cluster(&table)
        .unwrap()
        .stats
        .objective
        .unwrap();
    let given = objective(&["--policy-settings", settings.to_str().unwrap()]);
    assert_eq!(given, format!("{expected:.6}"));
    assert_ne!(given, objective(&[]));
    let both = pushmog(&[
        "cluster",
        scene.to_str().unwrap(),
        "--settings",
        settings.to_str().unwrap(),
        "--policy-settings",
        settings.to_str().unwrap(),
    ]);
    assert_eq!(both.status.code(), Some(2));
}

/// The settings file of the time-optimal policy (`experiments/push-mog-time.json`) is what the
/// picks-per-hour experiments give push-mog-time (with every move stopping, its time model aside),
/// and plans with it verify.
#[test]
fn the_push_mog_time_settings_file_plans_as_the_experiment_does() {
    let experiments = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let file = experiments.join("push-mog-time.json");
    let text = std::fs::read_to_string(&file).unwrap();
    let settings: pushmog::policy::PolicySettings = serde_json::from_str(&text).unwrap();
    for name in [
        "picks-per-hour",
        "picks-per-hour-unseen",
        "picks-per-hour-stopping",
        "picks-per-hour-unseen-stopping",
        "bin-distance-paired",
    ] {
        let config =
            pushmog::experiment::ExperimentConfig::read(&experiments.join(format!("{name}.toml")))
                .unwrap();
        let label =
            |p: &pushmog::experiment::PolicyConfig| p.label.as_deref() == Some("push-mog-time");
        let index = config.policies.iter().position(label).unwrap();
        let mut used = config.policy_settings(index, None, None).unwrap();
        if name.ends_with("-stopping") {
            assert!(!used.time_model.blend_free_moves);
            used.time_model = settings.time_model.clone();
        }
        assert_eq!(used, settings, "{name}");
    }
    let dir = scratch("push-mog-time");
    let (scene, plan) = (dir.join("scene.json"), dir.join("plan.json"));
    pushmog(&[
        "scene",
        "generate",
        "--seed",
        "3",
        "-o",
        scene.to_str().unwrap(),
    ]);
    let output = pushmog(&[
        "plan",
        scene.to_str().unwrap(),
        "--policy",
        "push-mog-opt",
        "--settings",
        file.to_str().unwrap(),
        "-o",
        plan.to_str().unwrap(),
    ]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(
        pushmog(&["verify", plan.to_str().unwrap()]).status.code(),
        Some(0)
    );
}

/// A named preset is its policy with its settings: `plan --policy push-mog-time-riders` writes the
/// plan of `--policy push-mog-opt` with the settings file and riders on, byte for byte, and
/// `--settings` are laid over the preset's.
#[test]
fn a_named_preset_plans_as_its_policy_with_its_settings() {
    let dir = scratch("preset-plan");
    let scene = dir.join("scene.json");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    pushmog(&[
        "scene",
        "generate",
        "--objects",
        "12",
        "--seed",
        "4",
        "-o",
        &path("scene.json"),
    ]);
    let experiments = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let mut settings: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(experiments.join("push-mog-time.json")).unwrap(),
    )
    .unwrap();
    settings["riders"] = serde_json::json!({ "enabled": true });
    std::fs::write(dir.join("written.json"), settings.to_string()).unwrap();
    std::fs::write(
        dir.join("over.json"),
        r#"{ "run": { "reach_past_edge": 0.05 } }"#,
    )
    .unwrap();
    let plan = |args: &[&str], out: &str| {
        let mut all = vec!["plan", scene.to_str().unwrap(), "--seed", "2"];
        all.extend_from_slice(args);
        let output_path = path(out);
        all.extend_from_slice(&["-o", &output_path]);
        let output = pushmog(&all);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        std::fs::read_to_string(dir.join(out)).unwrap()
    };
    let preset = plan(&["--policy", "push-mog-time-riders"], "preset.json");
    let written_out = plan(
        &[
            "--policy",
            "push-mog-opt",
            "--settings",
            &path("written.json"),
        ],
        "written-out.json",
    );
    assert_eq!(preset, written_out);
    assert!(preset.contains("\"riders\""), "a rider is planned");
    let over = plan(
        &[
            "--policy",
            "push-mog-time-riders",
            "--settings",
            &path("over.json"),
        ],
        "over-plan.json",
    );
    let over: serde_json::Value = serde_json::from_str(&over).unwrap();
    assert_eq!(over["settings"]["run"]["reach_past_edge"], 0.05);
    assert_eq!(over["settings"]["run"]["fuse_looks"], true);
    assert_eq!(over["settings"]["riders"]["enabled"], true);
    let unknown = pushmog(&["plan", scene.to_str().unwrap(), "--policy", "push-mog-fast"]);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("push-mog-time-riders"));
}
