//! `plan`, `run` and `cluster`: a policy or a clusterer on one scene.

use pushmog::cluster::{Clusterer, Hierarchical, HierarchicalSettings, Milp, MilpSettings};
use pushmog::error::Result;
use pushmog::exec::SimSettings;
use pushmog::json;
use pushmog::policy::PolicySettings;
use pushmog::problem::Problem;
use pushmog::render::{RenderOptions, replay_html};

use crate::{ClusterArgs, ClusterMethod, PlanArgs, RunArgs};

use super::io::{policy, read_scene, settings_or_default, summary, write_output};

pub fn plan(args: &PlanArgs) -> Result<()> {
    let scene = read_scene(&args.scene)?;
    let policy = policy(&args.policy, args.settings.as_deref())?;
    let mut executor = policy.ideal();
    let plan = policy.run(&scene, &mut executor, args.seed)?;
    write_output(args.output.as_deref(), &plan.to_json())?;
    eprint!("{}", summary(&plan, scene.len()));
    Ok(())
}

pub fn run(args: &RunArgs) -> Result<()> {
    let scene = read_scene(&args.scene)?;
    let policy = policy(&args.policy, args.settings.as_deref())?;
    let mut sim: SimSettings = settings_or_default(args.sim_settings.as_deref())?;
    if args.noiseless {
        sim = SimSettings::noiseless_from(&sim);
    }
    let mut executor = args.executor.build(policy.problem(), sim, args.seed)?;
    let plan = policy.run(&scene, executor.as_mut(), args.seed)?;
    if let Some(path) = &args.plan {
        json::write_text(path, &plan.to_json())?;
    }
    if let Some(path) = &args.replay {
        json::write_text(path, &replay_html(&plan, &RenderOptions::default())?)?;
    }
    print!("{}", summary(&plan, scene.len()));
    Ok(())
}

pub fn cluster(args: &ClusterArgs) -> Result<()> {
    let scene = read_scene(&args.scene)?;
    let settings = args.settings.as_deref();
    // As a policy with these settings builds its clusterer: shared settings filled in.
    let policy = match args.policy_settings.as_deref() {
        Some(path) => {
            let settings: PolicySettings = settings_or_default(Some(path))?;
            settings.validate()?;
            Some(settings)
        }
        None => None,
    };
    let outcome = match args.method {
        ClusterMethod::Milp => {
            let milp = match &policy {
                Some(policy) => policy.milp_clusterer(policy.problem()?, policy.row_test())?,
                None => Milp::new(
                    settings_or_default::<MilpSettings>(settings)?,
                    Problem::shared_default(),
                )?,
            };
            milp.cluster(&scene)?
        }
        ClusterMethod::Hierarchical => {
            let hierarchical = match &policy {
                Some(policy) => policy.clustering.clone(),
                None => settings_or_default::<HierarchicalSettings>(settings)?,
            };
            Hierarchical::new(hierarchical)?.cluster(&scene)?
        }
    };
    for (k, cluster) in outcome.value.clusters.iter().enumerate() {
        let ids: Vec<String> = cluster.iter().map(|id| id.to_string()).collect();
        println!("cluster {k:>3}: {}", ids.join(" "));
    }
    println!("\nstatus       {:?}", outcome.status);
    if let Some(fallback) = &outcome.value.fallback {
        println!("fallback     {fallback:?}");
    }
    let stats = &outcome.stats;
    println!("clusters     {}", outcome.value.len());
    if let Some(objective) = stats.objective {
        println!("objective    {objective:.6}");
    }
    if let Some(bound) = stats.bound {
        println!("bound        {bound:.6}");
    }
    if let Some(gap) = stats.gap {
        println!("gap          {gap:.2e}");
    }
    println!("solve time   {:.2} ms", stats.seconds * 1e3);
    if let Some(backend) = &stats.backend_status {
        println!("backend      {backend}");
    }
    for (name, value) in &stats.counters {
        println!("{name:<12} {value}");
    }
    Ok(())
}
