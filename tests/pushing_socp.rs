//! The push-target SOCP: known optima, infeasible clusters, and plans that verify.

use crate::support::boxes;
use nalgebra::Vector2;
use pushmog::cluster::{Clusterer, Hierarchical};
use pushmog::geometry::distance;
use pushmog::grasp::{GraspModel, GraspPlanner, GraspRequest, MultiObject, MultiObjectSettings};
use pushmog::outcome::Outcome;
use pushmog::plan::Status;
use pushmog::problem::Problem;
use pushmog::push::{
    PushPlan, PushPlanner, SkipReason, Socp, SocpSettings, TowardCentral, predict,
};
use pushmog::scene::{GeneratorSettings, ObjectId, Scene, builtin_object_set, generate_scene};

fn squares(side: f64, at: &[(f64, f64)]) -> Scene {
    boxes(side, side, at)
}

fn ids(n: u32) -> Vec<ObjectId> {
    (0..n).map(ObjectId).collect()
}

/// The default SOCP's plan for objects `0..n` of `scene`, which must be a best-found row.
fn best_row(scene: &Scene, n: u32) -> Outcome<PushPlan> {
    let outcome = Socp::default().plan(scene, &ids(n)).unwrap();
    assert_eq!(outcome.status, Status::BestFound, "{:?}", outcome.status);
    outcome
}

#[test]
fn two_squares_on_a_line_meet_with_the_least_total_push() {
    // 30 mm squares 100 mm apart. The row may span the usable gap less the margin, 75 − 10 = 65 mm,
    // so their centres may stay 65 − 30 = 35 mm apart: 65 mm of pushing in all, along the line.
    let scene = squares(0.03, &[(0.2, 0.2), (0.3, 0.2)]);
    let outcome = Socp::default().plan(&scene, &ids(2)).unwrap();
    assert_eq!(outcome.status, Status::BestFound);
    let total = outcome.stats.objective.unwrap();
    assert!((total - 0.065).abs() < 1e-6, "{total}");
    let after = predict(&scene, &outcome.value.pushes).unwrap();
    let gap = after.centroid(1).x - after.centroid(0).x;
    assert!((gap - 0.035).abs() < 1e-6, "{gap}");
    assert!((after.centroid(1).y - after.centroid(0).y).abs() < 1e-6);
    // Any split of the 65 mm is as short; one push saves the fixed time of a second.
    assert_eq!(outcome.value.pushes.len(), 1);
}

#[test]
fn a_symmetric_triple_pulls_its_ends_in() {
    // Three 20 mm squares 100 mm apart on a line. The row spans at most 65 mm, so the end centres
    // come within 45 mm: 155 mm of pushing, 77.5 mm each end by symmetry; the middle stays.
    let scene = squares(0.02, &[(0.15, 0.2), (0.25, 0.2), (0.35, 0.2)]);
    let outcome = Socp::default().plan(&scene, &ids(3)).unwrap();
    assert_eq!(outcome.status, Status::BestFound);
    let total = outcome.stats.objective.unwrap();
    assert!((total - 0.155).abs() < 1e-6, "{total}");
    let pushed: Vec<ObjectId> = outcome.value.pushes.iter().map(|p| p.object).collect();
    assert!(
        !pushed.contains(&ObjectId(1)),
        "the middle square is already in place"
    );
    for push in &outcome.value.pushes {
        assert!((push.distance - 0.0775).abs() < 1e-6, "{}", push.distance);
    }
}

#[test]
fn a_cluster_too_wide_for_the_jaws_is_infeasible() {
    // Three 30 mm squares need 90 mm in a row; the jaws give 75 mm.
    let scene = squares(0.03, &[(0.15, 0.2), (0.25, 0.2), (0.35, 0.2)]);
    let outcome = Socp::default().plan(&scene, &ids(3)).unwrap();
    assert_eq!(outcome.status, Status::Infeasible);
    assert!(outcome.value.pushes.is_empty());
    assert!(
        outcome
            .value
            .skipped
            .iter()
            .all(|s| s.reason == SkipReason::NoRow)
    );
}

#[test]
fn an_outside_object_is_kept_clear() {
    // A third square sits just beside the line between the two cluster members.
    let scene = squares(0.03, &[(0.2, 0.2), (0.3, 0.2), (0.25, 0.237)]);
    let outcome = Socp::default().plan(&scene, &ids(2)).unwrap();
    assert_eq!(outcome.status, Status::BestFound);
    let after = predict(&scene, &outcome.value.pushes).unwrap();
    // The row closes to 35 mm between centres, passing below the outside square, which it keeps
    // the 2 mm clearance from (its 7 mm gap was larger).
    assert!((after.centroid(1).x - after.centroid(0).x - 0.035).abs() < 1e-6);
    for member in 0..2 {
        let gap = distance(after.world_polygon(member), after.world_polygon(2));
        assert!(gap >= 0.002 - 1e-6, "member {member}: {gap}");
    }
}

/// SOCP pushes on the clusters of seeded scenes: the predicted row fits between the jaws (all
/// members caught in one row, judged with unlimited friction) for most feasible clusters.
#[test]
fn socp_rows_fit_the_jaws_on_seeded_scenes() {
    let unlimited = Problem::default()
        .with_grasp_model(GraspModel::unlimited_friction())
        .unwrap();
    let geometric = MultiObject::new(
        MultiObjectSettings {
            samples: 1,
            clearance_sigmas: 0.0,
            ..MultiObjectSettings::default()
        },
        unlimited,
    )
    .unwrap();
    let (mut clusters, mut fits, mut infeasible) = (0, 0, 0);
    for seed in 0..10 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        let clustering = Hierarchical::default().cluster(&scene).unwrap().value;
        for cluster in clustering.clusters.iter().filter(|c| c.len() > 1) {
            clusters += 1;
            let outcome = Socp::default().plan(&scene, cluster).unwrap();
            if outcome.status == Status::Infeasible {
                infeasible += 1;
                continue;
            }
            let after = predict(&scene, &outcome.value.pushes).unwrap();
            let hints: Vec<_> = outcome.value.intended_grasp.into_iter().collect();
            let grasp = geometric
                .plan_with_hints(&after, cluster, &hints)
                .unwrap()
                .value;
            if grasp.is_some_and(|g| cluster.iter().all(|id| g.objects.contains(id))) {
                fits += 1;
            }
            // The paper's planner plans the same cluster without error too.
            TowardCentral::default().plan(&scene, cluster).unwrap();
        }
    }
    println!("{clusters} clusters, {fits} fit, {infeasible} infeasible");
    assert!(
        fits * 10 >= (clusters - infeasible) * 8,
        "{fits} of {clusters}"
    );
}

#[test]
fn a_member_the_fingers_cannot_reach_is_held_and_the_other_comes_to_it() {
    // Squares A and B 100 mm apart on a line, and C 4 mm behind A: no room to lower the fork between
    // A and C, so A cannot be pushed toward B. The row is made by B alone. Along x it would end with
    // a plate on C, which the grasp model refuses; B goes round instead, up 31 mm and across to stand
    // beside A along y, a row the model holds.
    let scene = squares(0.03, &[(0.2, 0.2), (0.3, 0.2), (0.166, 0.2)]);
    let outcome = Socp::default().plan(&scene, &ids(2)).unwrap();
    assert_eq!(outcome.status, Status::BestFound, "{:?}", outcome.status);
    let pushes = &outcome.value.pushes;
    assert!(pushes.iter().all(|p| p.object == ObjectId(1)), "{pushes:?}");
    let after = predict(&scene, pushes).unwrap();
    assert_eq!(after.centroid(0), scene.centroid(0));
    let gap = distance(after.world_polygon(0), after.world_polygon(1));
    assert!((gap - 0.001).abs() < 1e-6, "{gap}");
    assert_eq!(outcome.value.row_held, Some(true));
    let travelled: f64 = pushes.iter().map(|p| p.distance).sum();
    assert!((outcome.stats.objective.unwrap() - travelled).abs() < 1e-12);
}

#[test]
fn targets_stay_clear_of_the_workspace_edge() {
    // Pushes end millimetres from their targets, and an object that leaves the workspace is lost:
    // targets keep the edge margin (5 mm), or the start's own distance from an edge if smaller.
    let margin = SocpSettings::default().edge_margin;
    let mut checked = 0;
    for seed in 0..10 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        let workspace = scene.workspace().clone();
        let room = |s: &Scene, i: usize| {
            let outline = s.world_polygon(i);
            let (x, y) = (
                outline.projection(&Vector2::x()),
                outline.projection(&Vector2::y()),
            );
            [
                x.0 - workspace.min[0],
                workspace.max[0] - x.1,
                y.0 - workspace.min[1],
                workspace.max[1] - y.1,
            ]
        };
        let clustering = Hierarchical::default().cluster(&scene).unwrap().value;
        for cluster in clustering.clusters.iter().filter(|c| c.len() > 1) {
            let outcome = Socp::default().plan(&scene, cluster).unwrap();
            let after = predict(&scene, &outcome.value.pushes).unwrap();
            for push in &outcome.value.pushes {
                let (before, now) = (
                    room(&scene, scene.index_of(push.object).unwrap()),
                    room(&after, after.index_of(push.object).unwrap()),
                );
                for side in 0..4 {
                    assert!(
                        now[side] >= margin.min(before[side]) - 1e-7,
                        "seed {seed}, object {}: {:.2} mm from an edge",
                        push.object,
                        now[side] * 1e3
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 50, "{checked} pushes");
}

#[test]
fn a_member_beside_its_neighbour_slides_along_then_across_into_the_row() {
    // Two 30 × 40 mm rectangles, one 50 mm above the other and 10 mm to its left. Only a row along x
    // fits the jaws (30 + 30 + 1 mm; along y 81 mm, and 3° off x already 65.1 mm), so one must come
    // down beside the other, and a straight push there drags its corner through the other's.
    let scene = boxes(0.03, 0.04, &[(0.30, 0.25), (0.31, 0.20)]);
    let outcome = best_row(&scene, 2);
    let pushes = &outcome.value.pushes;
    let mover = pushes[0].object;
    assert!(
        pushes.len() == 2 && pushes.iter().all(|p| p.object == mover),
        "{pushes:?}"
    );
    // Each leg is straight and clear of the other member all the way (sampled independently of the
    // planner's exact sweeps), and the second starts where the first ends.
    let other = 1 - mover.0 as usize;
    let mut at = scene.clone();
    for push in pushes {
        let index = at.index_of(mover).unwrap();
        assert!((at.objects()[index].pose.x - push.from.x).abs() < 1e-12);
        assert!((at.objects()[index].pose.y - push.from.y).abs() < 1e-12);
        for step in 0..=100 {
            let moved = at
                .world_polygon(index)
                .translated(&(push.displacement() * (f64::from(step) / 100.0)));
            assert!(
                distance(&moved, at.world_polygon(other)) > 0.0,
                "step {step}"
            );
        }
        at = predict(&at, std::slice::from_ref(push)).unwrap();
    }
    // They end in a row along x: side by side, 1 mm apart, centroids within 8 mm across.
    let (a, b) = (at.centroid(0), at.centroid(1));
    assert!(((b.x - a.x).abs() - 0.031).abs() < 1e-6, "{a} {b}");
    assert!((b.y - a.y).abs() <= 0.008 + 1e-9, "{a} {b}");
    assert_eq!(outcome.value.row_held, Some(true));
}

#[test]
fn members_each_nearly_in_place_still_close_a_row_too_wide() {
    // 30 mm squares 39 mm apart: the row (69 mm) exceeds the 65 mm allowed, so 4 mm must go. Split
    // between the two, 2 mm each is below `min_push` (3 mm), and holding both left the row as it
    // was; held one at a time, the other is pushed the whole 4 mm.
    let scene = squares(0.03, &[(0.2, 0.2), (0.239, 0.2)]);
    let outcome = best_row(&scene, 2);
    let pushes = &outcome.value.pushes;
    assert_eq!(pushes.len(), 1, "{pushes:?}");
    assert!(
        (pushes[0].distance - 0.004).abs() < 1e-6,
        "{}",
        pushes[0].distance
    );
    let after = predict(&scene, pushes).unwrap();
    let span = after.world_polygon(1).projection(&Vector2::x()).1
        - after.world_polygon(0).projection(&Vector2::x()).0;
    assert!(span <= 0.065 + 1e-6, "{span}");
}

#[test]
fn the_member_nearer_the_workspace_edge_is_the_one_pushed() {
    // 30 mm squares 100 mm apart on a line, the first 3 mm from the workspace's left edge. Either
    // may make the whole 65 mm push in the same time; pushing the second up to the first could
    // shove it out of the workspace, so the first is pushed, inward, and the second stays.
    let scene = squares(0.03, &[(0.018, 0.2), (0.118, 0.2)]);
    let outcome = best_row(&scene, 2);
    let pushes = &outcome.value.pushes;
    assert!(
        !pushes.is_empty() && pushes.iter().all(|p| p.object == ObjectId(0)),
        "{pushes:?}"
    );
    assert!(pushes.iter().all(|p| p.direction.x > 0.99), "{pushes:?}");
    let after = predict(&scene, pushes).unwrap();
    assert_eq!(after.centroid(1), scene.centroid(1));
    assert!((outcome.stats.objective.unwrap() - 0.065).abs() < 1e-6);
}

#[test]
fn a_flush_push_that_could_shove_a_held_member_out_is_refused() {
    // A 20 mm square turned 45° (no face toward its neighbour, so it can only be held), its left
    // corner 13.9 mm from the workspace's edge, and a 20 mm square 62 mm to its right. The only flush
    // row pushes the square left until it nearly touches the corner; with `held_edge_margin` at
    // 2 cm that push could shove the held one out of the workspace, so there is no row.
    let mut objects = squares(0.02, &[(0.028, 0.2), (0.09, 0.2)])
        .objects()
        .to_vec();
    objects[0].pose.yaw = std::f64::consts::FRAC_PI_4;
    let scene = squares(0.02, &[]).with_objects(objects).unwrap();
    let flush = |held_edge_margin: f64| {
        Socp::new(
            SocpSettings {
                flush: true,
                held_edge_margin,
                ..SocpSettings::default()
            },
            Problem::shared_default(),
        )
        .unwrap()
    };
    let free = flush(0.0).plan(&scene, &ids(2)).unwrap();
    assert_eq!(free.status, Status::BestFound, "{:?}", free.status);
    let pushes = &free.value.pushes;
    assert!(
        !pushes.is_empty() && pushes.iter().all(|p| p.object == ObjectId(1)),
        "{pushes:?}"
    );
    // The corner's room along the push, which the margin compares.
    let room = scene
        .world_polygon(0)
        .vertices()
        .iter()
        .map(|v| scene.workspace().room_along(v, &pushes[0].direction))
        .fold(f64::INFINITY, f64::min);
    assert!(room > 0.01 && room < 0.02, "{room}");
    let kept = flush(0.01).plan(&scene, &ids(2)).unwrap();
    assert_eq!(kept.value.pushes, free.value.pushes);
    let refused = flush(0.02).plan(&scene, &ids(2)).unwrap();
    assert!(refused.value.pushes.is_empty(), "{:?}", refused.value);
    assert!(
        refused.value.skipped.iter().any(|s| s.reason
            == SkipReason::WouldShoveOut {
                object: ObjectId(0)
            }),
        "{:?}",
        refused.value.skipped
    );
}

#[test]
fn rows_held_under_noise_are_grasped_by_the_multi_object_planner() {
    // With `robust_rows`, a row counts as held only when the multi-object planner's own judge (the
    // planar model on the predicted table and on copies moved by the noise, the pushed members' push
    // error included) carries every member at the intended jaws often enough. That planner, asked
    // on the predicted table, then finds a grasp of two or more objects.
    let multi = MultiObject::default();
    let robust = Socp::new(
        SocpSettings {
            robust_rows: true,
            ..SocpSettings::default()
        },
        Problem::shared_default(),
    )
    .unwrap()
    .with_judge(multi.clone());
    // The same judge with the setting off: rows judged by the grasp model alone.
    let nominal = Socp::new(
        SocpSettings {
            robust_rows: false,
            ..SocpSettings::default()
        },
        Problem::shared_default(),
    )
    .unwrap()
    .with_judge(multi.clone());
    let (mut clusters, mut held, mut held_nominal) = (0, 0, 0);
    for seed in 0..4 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        let clustering = Hierarchical::default().cluster(&scene).unwrap().value;
        for cluster in clustering.clusters.iter().filter(|c| c.len() > 1) {
            clusters += 1;
            if nominal.plan(&scene, cluster).unwrap().value.row_held == Some(true) {
                held_nominal += 1;
            }
            let plan = robust.plan(&scene, cluster).unwrap().value;
            if plan.row_held != Some(true) {
                continue;
            }
            held += 1;
            let after = predict(&scene, &plan.pushes).unwrap();
            let pushed: Vec<ObjectId> = plan.pushes.iter().map(|p| p.object).collect();
            let hints: Vec<_> = plan.intended_grasp.into_iter().collect();
            let request = GraspRequest::new(&after, cluster)
                .hints(&hints)
                .pushed(&pushed)
                .several();
            let grasp = multi.plan_request(&request).unwrap().value;
            assert!(
                grasp.is_some_and(|g| g.objects.len() >= 2),
                "seed {seed}, cluster {cluster:?}: a row held under noise has no grasp"
            );
        }
    }
    println!(
        "{clusters} clusters: {held} rows held under noise, {held_nominal} by the model alone"
    );
    assert!(held > 0);
}

#[test]
fn the_push_comparison_compares_the_same_clusters_within_its_totals() {
    let mut reported = Vec::new();
    let rows = pushmog::experiment::compare_pushing(
        &GeneratorSettings::default(),
        &builtin_object_set(),
        &pushmog::policy::PolicySettings::default(),
        1..3,
        &mut |done| reported.push(done),
    )
    .unwrap();
    assert_eq!(reported, vec![1, 2]);
    for row in &rows {
        let (central, socp) = (&row.central, &row.socp);
        assert_eq!(central.clusters, socp.clusters);
        // Clusters neither planner failed on: at most those each did not fail on, and their
        // distance a part of each planner's total.
        let planned = &row.both_planned;
        assert!(planned.clusters <= central.clusters - central.failures.max(socp.failures));
        assert!(planned.central <= central.distance + 1e-12);
        assert!(planned.socp <= socp.distance + 1e-12);
        let held = &row.both_held;
        assert!(held.clusters <= central.held.min(socp.held));
        assert!(held.central <= central.distance + 1e-12);
        assert!(held.socp <= socp.distance + 1e-12);
        assert!(
            planned.clusters > 0,
            "seed {}: no cluster both planned",
            row.seed
        );
    }
    let report = pushmog::experiment::push_comparison_markdown(&rows);
    assert!(
        report.contains("clusters neither planner failed on"),
        "{report}"
    );
}

/// Flush pushes (`socp.flush`): on seeded scenes, the MILP proposes pairs a flush push can line up;
/// every push push-mog-opt then makes meets a face of its object flat (within the cone of that
/// face's normal, the jaws closed to one block facing the face), and every plan, applied exactly,
/// verifies and clears the table.
#[test]
fn flush_pushes_meet_a_face_of_their_object_flat() {
    use pushmog::cluster::{FlushPairs, Milp, MilpSettings, RowTest};
    use pushmog::plan::{RunStatus, verify};
    use pushmog::policy::{Policy, PolicyKind, PolicySettings};
    use pushmog::push::flush::{PairRow, admits_flush_pair, block_opening, flush_face};
    let mut settings = PolicySettings::default();
    settings.socp.flush = true;
    let socp = settings.socp.clone();
    let policy = Policy::new(PolicyKind::PushMogOpt, settings).unwrap();
    let (mut pushes, mut pairs) = (0, 0);
    for seed in 0..4 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        // The MILP's pairs pass the flush pair test.
        let milp = Milp::new(MilpSettings::default(), Problem::shared_default())
            .unwrap()
            .with_rows(RowTest {
                margin: socp.margin,
                flush_pairs: Some(FlushPairs {
                    straddle: socp.straddle,
                    margin: socp.flush_margin,
                    cone: socp.flush_cone,
                    tight: socp.flush_gap,
                }),
            })
            .unwrap();
        let row = PairRow {
            row_limit: scene.gripper().usable_gap() - socp.margin,
            gap: socp.gap,
            straddle: socp.straddle,
            tight: Some(socp.flush_gap),
        };
        for cluster in milp.cluster(&scene).unwrap().value.clusters {
            if let [a, b] = cluster[..] {
                pairs += 1;
                let (a, b) = (scene.index_of(a).unwrap(), scene.index_of(b).unwrap());
                let cone = (socp.flush_margin, socp.flush_cone);
                assert!(admits_flush_pair(&scene, (a, b), row, cone));
            }
        }
        let plan = policy.run(&scene, &mut policy.ideal(), seed).unwrap();
        assert!(verify(&plan).is_empty(), "{:?}", verify(&plan));
        assert!(matches!(plan.status, RunStatus::Cleared));
        for trip in &plan.trips {
            let table = pushmog::scene::Scene::new(trip.scene.to_spec()).unwrap();
            for push in &trip.plan.pushes {
                pushes += 1;
                let Some(index) = table.index_of(push.object) else {
                    continue;
                };
                let outline = table.world_polygon(index);
                let face = flush_face(outline, socp.flush_margin, &push.direction, socp.flush_cone)
                    .expect("a face the push meets flat");
                let jaw_line = Vector2::new(push.fork.jaw_angle.cos(), push.fork.jaw_angle.sin());
                assert!(
                    jaw_line.dot(&face.normal).abs() < 1e-9,
                    "jaw line along the face"
                );
                assert!((push.fork.opening - block_opening(table.gripper())).abs() < 1e-12);
            }
        }
    }
    println!("{pairs} pairs proposed, {pushes} flush pushes");
    assert!(
        pairs >= 20 && pushes >= 10,
        "{pairs} pairs, {pushes} pushes"
    );
    // The verifier takes a jaw line up to 40° from perpendicular to the push (beyond any pad's
    // friction cone the fingers would slide along the face) and names one further off.
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 0).unwrap();
    let plan = policy.run(&scene, &mut policy.ideal(), 0).unwrap();
    let trip = plan
        .trips
        .iter()
        .find(|t| !t.plan.pushes.is_empty())
        .unwrap();
    let skewed = |degrees: f64| {
        let mut trip = trip.clone();
        let push = &mut trip.plan.pushes[0];
        push.fork.jaw_angle = push.direction.y.atan2(push.direction.x)
            + std::f64::consts::FRAC_PI_2
            + degrees.to_radians();
        pushmog::plan::verify_trip(&trip)
            .iter()
            .any(|v| v.contains("from perpendicular"))
    };
    assert!(!skewed(0.0) && !skewed(35.0));
    assert!(skewed(45.0) && skewed(-60.0));
}

/// A search the time limit ends says so: its answer is `time_limit` (the cheapest row solved in
/// time, whose pushes give a valid table) or a failure naming the limit, never `best_found` or
/// `infeasible`; a search that does not say so solved every row the unlimited search solves. A
/// limit that is not a positive duration is refused.
#[test]
fn a_search_cut_short_by_the_time_limit_says_so() {
    let unlimited = Socp::default();
    let limited = Socp::new(
        SocpSettings {
            time_limit: Some(0.001),
            ..SocpSettings::default()
        },
        Problem::shared_default(),
    )
    .unwrap();
    let mut cut = 0;
    for seed in 0..4 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        let clustering = Hierarchical::default().cluster(&scene).unwrap().value;
        for cluster in clustering.clusters.iter().filter(|c| c.len() > 1) {
            let full = unlimited.plan(&scene, cluster).unwrap();
            let short = limited.plan(&scene, cluster).unwrap();
            match &short.status {
                Status::TimeLimit => {
                    cut += 1;
                    // The pushes of the row found in time still give a valid table.
                    predict(&scene, &short.value.pushes).unwrap();
                }
                Status::Failed { reason } if reason.contains("time limit") => cut += 1,
                other => {
                    assert_eq!(other, &full.status, "seed {seed}, cluster {cluster:?}");
                    assert_eq!(
                        short.stats.counter("socp_solves"),
                        full.stats.counter("socp_solves"),
                        "seed {seed}, cluster {cluster:?}: not cut short, yet fewer rows solved"
                    );
                }
            }
        }
    }
    assert!(cut > 0, "a 1 ms limit cut no search short");
    for bad in [0.0, -1.0, f64::NAN] {
        let settings = SocpSettings {
            time_limit: Some(bad),
            ..SocpSettings::default()
        };
        assert!(
            Socp::new(settings, Problem::shared_default()).is_err(),
            "{bad}"
        );
    }
}
