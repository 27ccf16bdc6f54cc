//! `compare-clustering`, `compare-pushing` and `grasp-agreement`: planners compared over seeded
//! scenes.

use pushmog::cluster::{Milp, MilpSettings};
use pushmog::error::Result;
use pushmog::experiment::agreement::{
    AgreementSettings, agreement_markdown, agreement_svg, replay_grasps,
};
use pushmog::experiment::{compare_clustering as compare, comparison_markdown, per_scene_markdown};
use pushmog::json;
use pushmog::policy::PolicySettings;
use pushmog::problem::Problem;
use pushmog::scene::{GeneratorSettings, Workspace, builtin_object_set};

use crate::{AgreementArgs, CompareArgs, ComparePushingArgs};

use super::io::{policy, settings_or_default};

pub fn grasp_agreement(args: &AgreementArgs) -> Result<()> {
    let policy = policy(&args.policy, args.settings.as_deref())?;
    let settings = AgreementSettings {
        scenes: args.scenes,
        first_seed: args.seed,
        objects: args.objects,
        policy: policy.kind(),
        policy_settings: policy.settings().clone(),
        sim: settings_or_default(args.sim_settings.as_deref())?,
        refused_per_trip: args.refused,
    };
    let replays = replay_grasps(&settings)?;
    let title = format!(
        "Grasp agreement — {} on {} scenes of {} objects (seeds {}–{}), simulator replays",
        args.policy,
        args.scenes,
        args.objects,
        args.seed,
        args.seed + args.scenes.saturating_sub(1) as u64
    );
    let text = agreement_markdown(&replays, &title);
    if let Some(path) = &args.output {
        json::write_text(path, &text)?;
    }
    if let Some(path) = &args.figure {
        let caption = format!(
            "Multi-object grasps held in the simulator ({})",
            args.policy
        );
        json::write_text(path, &agreement_svg(&replays, &caption)?)?;
    }
    print!("{text}");
    Ok(())
}

pub fn compare_clustering(args: &CompareArgs) -> Result<()> {
    let milp = Milp::new(
        settings_or_default::<MilpSettings>(args.settings.as_deref())?,
        Problem::shared_default(),
    )?;
    // Keep the default object density when the count changes: area grows with the count.
    let base = GeneratorSettings::default();
    let scale = (args.objects as f64 / base.objects as f64).sqrt().max(1.0);
    let generator = GeneratorSettings {
        objects: args.objects,
        workspace: Workspace::new(
            base.workspace.width() * scale,
            base.workspace.depth() * scale,
        ),
        ..base
    };
    eprintln!(
        "comparing on {} scenes of {} objects (seeds {}–{})",
        args.scenes,
        args.objects,
        args.seed,
        (args.seed + args.scenes as u64).saturating_sub(1)
    );
    let rows = compare(
        &generator,
        &builtin_object_set(),
        &milp,
        args.scenes,
        args.seed,
    )?;
    print!("{}", comparison_markdown(&rows));
    if args.per_scene {
        print!("\n{}", per_scene_markdown(&rows));
    }
    for r in &rows {
        for v in &r.violations {
            eprintln!("seed {}: {v}", r.seed);
        }
    }
    Ok(())
}

pub fn compare_pushing(args: &ComparePushingArgs) -> Result<()> {
    let settings: PolicySettings = settings_or_default(args.settings.as_deref())?;
    eprintln!(
        "comparing pushes on {} scenes (seeds {}–{})",
        args.scenes,
        args.seed,
        (args.seed + args.scenes as u64).saturating_sub(1)
    );
    let rows = pushmog::experiment::compare_pushing(
        &GeneratorSettings::default(),
        &builtin_object_set(),
        &settings,
        args.seed..args.seed + args.scenes as u64,
        &mut |done| {
            if done % 10 == 0 || done == args.scenes {
                eprintln!("  {done}/{} scenes compared", args.scenes);
            }
        },
    )?;
    print!("{}", pushmog::experiment::push_comparison_markdown(&rows));
    Ok(())
}
