//! Large tables: CPU time and peak memory of whole plans (`Policy::run` with the ideal executor, the
//! plan then written as JSON, as `pushmog plan` does) on generated scenes whose workspace grows with
//! the object count (0.6 m × 0.45 m scaled by √(n / 34), the paper's density).
//!
//! The aims are issue 38's: single-object picking (sog) plans 5000 objects within 60 s and 500 MB
//! peak; push-mog-opt plans 2000 objects within 120 s of CPU. Each case runs in a child process of
//! its own, so that its peak resident memory (Linux `VmHWM`) is its own. Run with
//! `cargo bench --bench large_tables`; about three minutes on one core.
#![allow(missing_docs, clippy::unwrap_used)]

use std::process::Command;

use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::scene::{GeneratorSettings, Workspace, builtin_object_set, generate_scene};

/// Policy, objects, aim in CPU seconds, aim in MB of peak memory.
const CASES: [(PolicyKind, usize, f64, Option<f64>); 3] = [
    (PolicyKind::Sog, 2000, 60.0, Some(500.0)),
    (PolicyKind::Sog, 5000, 60.0, Some(500.0)),
    (PolicyKind::PushMogOpt, 2000, 120.0, None),
];

const CHILD: &str = "PUSHMOG_LARGE_TABLE_CASE";

fn main() {
    if let Ok(case) = std::env::var(CHILD) {
        let k: usize = case.parse().unwrap();
        let (kind, objects, _, _) = CASES[k];
        let (cpu, carried) = plan(kind, objects);
        println!("{cpu} {} {carried}", peak_mb());
        return;
    }
    println!("| policy | objects | carried | CPU (s) | aim | peak memory (MB) | aim |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for (k, (kind, objects, cpu_aim, memory_aim)) in CASES.iter().enumerate() {
        let out = Command::new(std::env::current_exe().unwrap())
            .env(CHILD, k.to_string())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let figures: Vec<f64> = text
            .split_whitespace()
            .map(|f| f.parse().unwrap())
            .collect();
        let [cpu, peak, carried] = figures[..] else {
            panic!("the child printed {text}")
        };
        let memory_aim = memory_aim.map_or("–".to_string(), |mb| format!("≤ {mb}"));
        println!(
            "| {} | {objects} | {carried} | {cpu:.1} | ≤ {cpu_aim} | {peak:.0} | {memory_aim} |",
            kind.name()
        );
    }
}

/// Plans a generated table of `objects` and writes the plan as JSON; the CPU seconds this took
/// (the scene's generation left out) and the objects carried.
fn plan(kind: PolicyKind, objects: usize) -> (f64, usize) {
    let scale = (objects as f64 / 34.0).sqrt();
    let settings = GeneratorSettings {
        objects,
        workspace: Workspace::new(0.6 * scale, 0.45 * scale),
        ..GeneratorSettings::default()
    };
    let scene = generate_scene(&settings, &builtin_object_set(), 1).unwrap();
    let started = cpu_time::ProcessTime::now();
    let policy = Policy::new(kind, PolicySettings::default()).unwrap();
    let plan = policy.run(&scene, &mut policy.ideal(), 0).unwrap();
    let text = plan.to_json();
    std::hint::black_box(text.len());
    (started.elapsed().as_secs_f64(), plan.objects_carried())
}

/// The process's peak resident memory, MB (`VmHWM` of `/proc/self/status`).
fn peak_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status.lines().find(|l| l.starts_with("VmHWM:")).unwrap();
    let kb: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    kb / 1000.0
}
