//! The paper's baselines piece by piece: clustering splits, pushes toward the central object, the
//! grasp model on known arrangements, and the conformance of every implementation of each trait.

use nalgebra::Point2;
use pushmog::cluster::{Clusterer, Hierarchical, fits_jaws, separability_conflicts};
use pushmog::geometry::ConvexPolygon;
use pushmog::grasp::{
    GraspModel, GraspPlanner, GraspRequest, JawPose, Mechanics, MultiObject, SingleObject, Squeeze,
    closed_motions, squeeze,
};
use pushmog::plan::{RunStatus, verify};
use pushmog::policy::{Policy, PolicyKind, PolicySettings};
use pushmog::problem::Problem;
use pushmog::push::{PushPlanner, TowardCentral, TowardCentralSettings, predict};
use pushmog::scene::{
    GeneratorSettings, Gripper, Object, ObjectId, Pose, Scene, Workspace, builtin_object_set,
    generate_scene,
};

fn polygon(points: &[(f64, f64)]) -> ConvexPolygon {
    ConvexPolygon::new(points.iter().map(|&(x, y)| Point2::new(x, y)).collect()).unwrap()
}

fn square(side: f64) -> ConvexPolygon {
    let h = side / 2.0;
    polygon(&[(-h, -h), (h, -h), (h, h), (-h, h)])
}

fn object(id: u32, outline: ConvexPolygon, x: f64, y: f64) -> Object {
    Object {
        id: ObjectId(id),
        name: None,
        polygon: outline,
        pose: Pose::new(x, y, 0.0),
        height: 0.03,
        mass: None,
    }
}

fn scene(objects: Vec<Object>) -> Scene {
    Scene::from_parts(Workspace::new(0.5, 0.4), Gripper::default(), objects).unwrap()
}

/// Index lists of a clustering, for the clustering checks.
fn clusters_as_indices(scene: &Scene, clusterer: &dyn Clusterer) -> (Vec<Vec<usize>>, f64) {
    let outcome = clusterer.cluster(scene).unwrap();
    let splits = outcome.stats.counter("splits").unwrap();
    let clusters = outcome
        .value
        .clusters
        .iter()
        .map(|c| scene.indices_of(c).unwrap())
        .collect();
    (clusters, splits)
}

#[test]
fn a_cluster_of_three_squares_splits_once() {
    // Σ d* = 90 mm > 75 mm: one split leaves a pair and a single.
    let s = scene(
        (0..3)
            .map(|k| object(k, square(0.03), 0.1 + 0.04 * k as f64, 0.2))
            .collect(),
    );
    let (clusters, splits) = clusters_as_indices(&s, &Hierarchical::default());
    assert_eq!(splits, 1.0);
    assert_eq!(clusters.len(), 2);
    assert!(clusters.iter().all(|c| fits_jaws(&s, c)));
}

#[test]
fn a_cluster_of_five_squares_splits_twice() {
    // A plus sign of 30 mm squares, 4 cm apart: all within 8 cm, Σ d* = 150 mm. The most even split
    // is 2 | 3 (60 | 90 mm); the three must split again.
    let at = [
        (0.0, 0.0),
        (0.04, 0.0),
        (-0.04, 0.0),
        (0.0, 0.04),
        (0.0, -0.04),
    ];
    let s = scene(
        at.iter()
            .enumerate()
            .map(|(k, &(x, y))| object(k as u32, square(0.03), 0.25 + x, 0.2 + y))
            .collect(),
    );
    let (clusters, splits) = clusters_as_indices(&s, &Hierarchical::default());
    assert_eq!(splits, 2.0);
    assert_eq!(clusters.len(), 3);
    assert!(clusters.iter().all(|c| fits_jaws(&s, c)));
    assert!(separability_conflicts(&s, &clusters).is_empty());
}

/// Three equal equilateral triangles, alternately up and down, sharing edges: a row 56 mm long.
fn triangle_row() -> Scene {
    let side = 0.028;
    let h = side * 3f64.sqrt() / 2.0;
    let up = polygon(&[(0.0, 0.0), (side, 0.0), (side / 2.0, h)]);
    let down = polygon(&[(side / 2.0, h), (side, 0.0), (3.0 * side / 2.0, h)]);
    scene(vec![
        object(0, up.clone(), 0.2, 0.2),
        object(1, down, 0.2, 0.2),
        object(2, up, 0.2 + side, 0.2),
    ])
}

#[test]
fn three_equilateral_triangles_in_a_row_slip() {
    let s = triangle_row();
    // Σ d* = 72.7 mm fits the 75 mm gap: the paper's footnote case.
    assert!(fits_jaws(&s, &[0, 1, 2]));
    let jaws = JawPose {
        center: Point2::new(0.2 + 0.028, 0.2 + 0.01),
        angle: 0.0,
        opening: 0.085,
    };
    let analytic = GraspModel {
        mechanics: Mechanics::Analytic,
        ..GraspModel::default()
    };
    let outcome = squeeze(&s, &jaws, &analytic);
    assert!(matches!(outcome, Squeeze::Slips { .. }), "{outcome:?}");
    // Only with far more friction than plates and tape give could the row hold.
    let grippy = GraspModel {
        friction_object: 2.0,
        friction_jaw: 2.0,
        ..analytic
    };
    assert!(matches!(squeeze(&s, &jaws, &grippy), Squeeze::Held { .. }));
    // The planar mechanics refuse the row too: some triangle turns out of it.
    let planar = squeeze(&s, &jaws, &GraspModel::default());
    assert!(!matches!(planar, Squeeze::Held { .. }), "{planar:?}");
}

#[test]
fn three_equilateral_triangles_are_handled_without_a_crash() {
    let s = triangle_row();
    for kind in PolicyKind::ALL {
        let policy = Policy::new(kind, PolicySettings::default()).unwrap();
        let plan = policy.run(&s, &mut policy.ideal(), 1).unwrap();
        assert!(verify(&plan).is_empty(), "{kind}: {:?}", verify(&plan));
        assert!(plan.trips.iter().all(|t| t.carried.len() < 3), "{kind}");
        // Touching neighbours leave no room for the jaws around a single triangle, and no pair holds
        // under the model's friction: a run may clear them or stop with a reason, never loop or crash.
        match &plan.status {
            RunStatus::Cleared => {}
            RunStatus::Stopped { remaining, reason } => {
                assert!(
                    !remaining.is_empty() && !reason.to_string().is_empty(),
                    "{kind}"
                );
            }
        }
    }
}

/// `multi.edge_margin`: a pair whose member lies within the margin of the workspace's edge is not
/// grasped together (a failed pair grasp near the edge squeezes objects out of the workspace); the
/// same pair farther in is. With `edge_along_plates` only the room along the plates counts.
#[test]
fn an_edge_margin_keeps_pairs_near_the_edge_apart() {
    let pair_at = |x: f64| {
        scene(vec![
            object(0, square(0.03), x, 0.2),
            object(1, square(0.03), x + 0.031, 0.2),
        ])
    };
    let with_margin = |margin: f64| {
        MultiObject::new(
            pushmog::grasp::MultiObjectSettings {
                edge_margin: margin,
                ..pushmog::grasp::MultiObjectSettings::default()
            },
            pushmog::problem::Problem::shared_default(),
        )
        .unwrap()
    };
    let both = [ObjectId(0), ObjectId(1)];
    let held = |planner: &MultiObject, scene: &Scene| {
        planner
            .plan(scene, &both)
            .unwrap()
            .value
            .map(|grasp| grasp.objects.len())
    };
    // The left square's outline 10 mm from the left edge.
    let near = pair_at(0.025);
    let inside = pair_at(0.2);
    assert_eq!(held(&with_margin(0.0), &near), Some(2));
    assert_eq!(held(&with_margin(0.02), &inside), Some(2));
    let refused = with_margin(0.02).plan(&near, &both).unwrap();
    assert_ne!(refused.value.map(|grasp| grasp.objects.len()), Some(2));
    assert!(
        refused
            .stats
            .counter("refused: near the workspace edge")
            .unwrap_or(0.0)
            > 0.0,
        "{:?}",
        refused.stats
    );
    assert!(
        pushmog::grasp::MultiObjectSettings {
            edge_margin: 0.5,
            ..Default::default()
        }
        .validate()
        .is_err()
    );
    // Measured along the plates only: the pair by the left edge closes along x, its plates run
    // along y with room to spare, and is grasped together; the same pair by the bottom edge has its
    // plates pointing at that edge, and is not.
    let along = MultiObject::new(
        pushmog::grasp::MultiObjectSettings {
            edge_margin: 0.02,
            edge_along_plates: true,
            ..pushmog::grasp::MultiObjectSettings::default()
        },
        pushmog::problem::Problem::shared_default(),
    )
    .unwrap();
    assert_eq!(held(&along, &near), Some(2));
    let by_the_bottom = scene(vec![
        object(0, square(0.03), 0.2, 0.025),
        object(1, square(0.03), 0.231, 0.025),
    ]);
    assert_eq!(held(&with_margin(0.0), &by_the_bottom), Some(2));
    assert_ne!(held(&along, &by_the_bottom), Some(2));
}

/// `multi.centre_along_axis`: a row suggested 3 mm off its middle along the closing axis, grasped
/// there without the setting, is grasped at the middle with it, both plates 7.5 mm from the row,
/// the most room the nearer plate can have. With a neighbour so near that the middle would put a
/// plate 2.25 mm from it (under the 1.5 σ of screening), no grasp is moved there: the grasp taken
/// keeps its plates 1.5 σ from the neighbour.
#[test]
fn centring_along_the_axis_balances_the_plates_unless_a_neighbour_is_too_near() {
    // Two 29.5 mm squares 1 mm apart: 60 mm along x, in 75 mm between the open plates.
    let row = || {
        vec![
            object(0, square(0.0295), 0.2, 0.2),
            object(1, square(0.0295), 0.2305, 0.2),
        ]
    };
    let middle = Point2::new(0.21525, 0.2);
    let hint = JawPose {
        center: Point2::new(middle.x - 0.003, middle.y),
        angle: 0.0,
        opening: 0.085,
    };
    let both = [ObjectId(0), ObjectId(1)];
    let planner = |centre: bool| {
        MultiObject::new(
            pushmog::grasp::MultiObjectSettings {
                centre_along_axis: centre,
                ..pushmog::grasp::MultiObjectSettings::default()
            },
            Problem::shared_default(),
        )
        .unwrap()
    };
    let grasp_with = |centre: bool, s: &Scene| {
        planner(centre)
            .plan_request(&GraspRequest::new(s, &both).hints(&[hint]))
            .unwrap()
            .value
            .expect("the row is grasped")
    };
    let grasp = |s: &Scene| grasp_with(true, s);
    let gaps = |s: &Scene, jaws: &JawPose, objects: &[usize]| {
        jaws.plates(s.gripper()).map(|plate| {
            objects
                .iter()
                .map(|&i| pushmog::geometry::distance(&plate, s.world_polygon(i)))
                .fold(f64::INFINITY, f64::min)
        })
    };

    let alone = scene(row());
    let as_suggested = grasp_with(false, &alone);
    assert!(
        (as_suggested.jaws.center - hint.center).norm() < 1e-12,
        "{:?}",
        as_suggested.jaws
    );
    let centred = grasp(&alone);
    assert_eq!(centred.objects.len(), 2);
    assert!(
        (centred.jaws.center - middle).norm() < 1e-9,
        "{:?}",
        centred.jaws
    );
    for gap in gaps(&alone, &centred.jaws, &[0, 1]) {
        assert!((gap - 0.0075).abs() < 1e-9, "{gap}");
    }

    // A third square whose left side is 2.25 mm beyond where the right plate's outer face would
    // stand with the jaws at the middle.
    let mut crowded = row();
    crowded.push(object(2, square(0.0295), 0.27475, 0.2));
    let crowded = scene(crowded);
    let kept = grasp(&crowded);
    assert_eq!(kept.objects.len(), 2);
    let [left, right] = gaps(&crowded, &kept.jaws, &[2]);
    let sigma = pushmog::grasp::Noise::default().position_sigma(false);
    assert!(left.min(right) >= 1.5 * sigma - 1e-12, "{left} {right}");
}

/// Two 30 mm squares, at x = 0.2 m and at `second`, and jaws 85 mm open across them, centred
/// between them along x.
fn two_squares(second: f64) -> (Scene, JawPose) {
    let s = scene(vec![
        object(0, square(0.03), 0.2, 0.2),
        object(1, square(0.03), second, 0.2),
    ]);
    let jaws = JawPose {
        center: Point2::new(0.5 * (0.2 + second), 0.2),
        angle: 0.0,
        opening: 0.085,
    };
    (s, jaws)
}

/// The planar closing says where it leaves each member: two 30 mm squares 10 mm apart end
/// touching, the row centred between the coupled plates and as wide as the squeeze says, each
/// square slid about 5 mm toward the other without turning. The analytic model does not say.
#[test]
fn the_closing_says_where_it_leaves_each_member() {
    let (s, jaws) = two_squares(0.24);
    let model = GraspModel::default();
    let Squeeze::Held { width, .. } = squeeze(&s, &jaws, &model) else {
        panic!("the pair is held");
    };
    let motions = closed_motions(&s, &jaws, &model, &[0, 1]).expect("both members take part");
    let axis = nalgebra::Vector2::x();
    let (lo, hi) = [0, 1]
        .iter()
        .map(|&i| {
            s.world_polygon(i)
                .transformed(&motions[i])
                .projection(&axis)
        })
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
            (lo.min(a), hi.max(b))
        });
    assert!((hi - lo - width).abs() < 5e-4, "{lo} {hi} {width}");
    assert!((0.5 * (lo + hi) - 0.22).abs() < 5e-4, "{lo} {hi}");
    for (i, toward) in [(0, 1.0), (1, -1.0)] {
        let shift = motions[i].translation.vector;
        assert!((toward * shift.x - 0.005).abs() < 5e-4, "{i}: {shift}");
        assert!(motions[i].rotation.angle().abs() < 1e-3, "{i}");
    }
    let analytic = GraspModel {
        mechanics: Mechanics::Analytic,
        ..model
    };
    assert_eq!(closed_motions(&s, &jaws, &analytic, &[0, 1]), None);
}

#[test]
fn two_squares_side_by_side_are_held_together() {
    let (s, jaws) = two_squares(0.231);
    let analytic = GraspModel {
        mechanics: Mechanics::Analytic,
        ..GraspModel::default()
    };
    match squeeze(&s, &jaws, &analytic) {
        Squeeze::Held { objects, width } => {
            assert_eq!(objects, vec![0, 1]);
            assert!((width - 0.060).abs() < 1e-9, "{width}");
        }
        other => panic!("{other:?}"),
    }
    // The planar mechanics close on the same row, squeezed a fraction of a millimetre.
    match squeeze(&s, &jaws, &GraspModel::default()) {
        Squeeze::Held { mut objects, width } => {
            objects.sort_unstable();
            assert_eq!(objects, vec![0, 1]);
            assert!((width - 0.060).abs() < 5e-4, "{width}");
        }
        other => panic!("{other:?}"),
    }
    // Turned 90°, the jaws catch both squares side by side: not a row.
    let across = JawPose {
        angle: std::f64::consts::FRAC_PI_2,
        ..jaws
    };
    assert!(matches!(
        squeeze(&s, &across, &GraspModel::default()),
        Squeeze::NotARow { .. }
    ));
}

#[test]
fn pushes_toward_the_central_object_end_touching_it_or_a_set_gap_short() {
    let s = scene(vec![
        object(0, square(0.03), 0.20, 0.2),
        object(1, square(0.03), 0.26, 0.2),
        object(2, square(0.03), 0.32, 0.2),
    ]);
    let ids = [ObjectId(0), ObjectId(1), ObjectId(2)];
    // Object 1 is central; both others move toward it: the whole 30 mm of free travel by default,
    // 28 mm with a 2 mm gap.
    let gapped = TowardCentral::new(
        TowardCentralSettings { stop_gap: 0.002 },
        Problem::shared_default(),
    )
    .unwrap();
    for (pusher, travel) in [(TowardCentral::default(), 0.03), (gapped, 0.028)] {
        let plan = pusher.plan(&s, &ids).unwrap().value;
        assert_eq!(plan.pushes.len(), 2, "{plan:?}");
        for push in &plan.pushes {
            assert!((push.distance - travel).abs() < 1e-6, "{}", push.distance);
        }
        let after = predict(&s, &plan.pushes).unwrap();
        let x: Vec<f64> = after.objects().iter().map(|o| o.pose.x).collect();
        assert!(
            (x[0] - (0.2 + travel)).abs() < 1e-6 && (x[2] - (0.32 - travel)).abs() < 1e-6,
            "{x:?}"
        );
    }
}

#[test]
fn a_push_blocked_by_an_outside_object_is_reported() {
    // Object 2 sits between the two cluster members.
    let s = scene(vec![
        object(0, square(0.03), 0.20, 0.2),
        object(1, square(0.03), 0.30, 0.2),
        object(2, square(0.02), 0.25, 0.2),
    ]);
    let plan = TowardCentral::default()
        .plan(&s, &[ObjectId(0), ObjectId(1)])
        .unwrap()
        .value;
    assert!(plan.pushes.is_empty());
    assert_eq!(plan.skipped.len(), 1);
    assert_eq!(
        plan.skipped[0].reason,
        pushmog::push::SkipReason::BlockedBy {
            object: ObjectId(2)
        }
    );
}

/// One conformance suite per trait, over every implementation (the MILP and the SOCP included), on
/// the same seeded scenes: clusterings cover every object once and pass the verifier, pushes leave
/// no object unaccounted for, grasps take a member within the stroke, and each answer's status
/// agrees with its value and with what the planner says it can claim.
#[test]
fn conformance_of_every_planner() {
    use pushmog::cluster::{Milp, MilpSettings};
    use pushmog::outcome::{Abilities, Status};
    use pushmog::plan::verify_clustering;
    use pushmog::push::Socp;
    let clusterers: Vec<Box<dyn Clusterer>> = vec![
        Box::new(Hierarchical::default()),
        Box::new(Milp::new(MilpSettings::default(), Problem::shared_default()).unwrap()),
    ];
    let pushers: Vec<Box<dyn PushPlanner>> = vec![
        Box::new(TowardCentral::default()),
        Box::new(Socp::default()),
    ];
    let graspers: Vec<Box<dyn GraspPlanner>> = vec![
        Box::new(SingleObject::default()),
        Box::new(MultiObject::default()),
    ];
    // A status claims no more than its planner can: optimal only from one that proves optima, a
    // time limit only from one that has one.
    let claims = |status: &Status, abilities: &Abilities| {
        (abilities.proves_optimality || *status != Status::Optimal)
            && (abilities.time_limit.is_some() || *status != Status::TimeLimit)
    };
    for seed in 0..5 {
        let s = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        for clusterer in &clusterers {
            let outcome = clusterer.cluster(&s).unwrap();
            let name = clusterer.name();
            assert!(outcome.status.has_answer(), "{name}: {:?}", outcome.status);
            assert!(claims(&outcome.status, &clusterer.abilities()), "{name}");
            let clusters: Vec<Vec<usize>> = outcome
                .value
                .clusters
                .iter()
                .map(|c| s.indices_of(c).unwrap())
                .collect();
            let mut all: Vec<usize> = clusters.iter().flatten().copied().collect();
            all.sort_unstable();
            assert_eq!(all, (0..s.len()).collect::<Vec<_>>(), "{name}");
            assert!(clusters.iter().all(|c| fits_jaws(&s, c)), "{name}");
            assert!(separability_conflicts(&s, &clusters).is_empty(), "{name}");
            assert!(verify_clustering(&s, &outcome.value).is_empty(), "{name}");
            for cluster in &outcome.value.clusters {
                for pusher in &pushers {
                    let answer = pusher.plan(&s, cluster).unwrap();
                    let name = pusher.name();
                    assert!(
                        claims(&answer.status, &pusher.abilities()),
                        "{name}: {:?} {:?}",
                        answer.status,
                        cluster
                    );
                    let plan = answer.value;
                    if !answer.status.has_answer() {
                        assert!(plan.pushes.is_empty(), "{name}: {:?}", answer.status);
                    }
                    // Every object but the one the others are pushed toward is pushed or
                    // skipped with a reason, and only members are pushed.
                    assert!(
                        plan.pushes.len() + plan.skipped.len() + 1 >= cluster.len(),
                        "{name}"
                    );
                    assert!(
                        plan.pushes.iter().all(|p| cluster.contains(&p.object)),
                        "{name}"
                    );
                    let after = predict(&s, &plan.pushes).unwrap();
                    for grasper in &graspers {
                        let answer = grasper.plan(&after, cluster).unwrap();
                        let name = grasper.name();
                        assert_eq!(answer.value.is_some(), answer.status.has_answer(), "{name}");
                        assert!(claims(&answer.status, &grasper.abilities()), "{name}");
                        if let Some(grasp) = answer.value {
                            assert!(
                                grasp.objects.iter().any(|id| cluster.contains(id)),
                                "{name}"
                            );
                            assert!(grasp.jaws.opening <= s.gripper().stroke + 1e-12, "{name}");
                        }
                    }
                }
            }
        }
        // Unknown ids are misuse, reported as errors.
        for pusher in &pushers {
            assert!(
                pusher.plan(&s, &[ObjectId(999)]).is_err(),
                "{}",
                pusher.name()
            );
        }
        for grasper in &graspers {
            assert!(
                grasper.plan(&s, &[ObjectId(999)]).is_err(),
                "{}",
                grasper.name()
            );
        }
    }
}

/// A request for several objects is answered with two or more objects or nothing, and finds a grasp of two or more
/// wherever the full search ranks one first, with a probability at least as high; on the tables
/// predicted after pushes it also finds pairs where the full search preferred one object.
#[test]
fn a_request_for_several_finds_the_pairs_the_full_search_finds() {
    let planner = MultiObject::default();
    let (mut several, mut pairs_first) = (0, 0);
    for seed in 0..6 {
        let scene =
            generate_scene(&GeneratorSettings::default(), &builtin_object_set(), seed).unwrap();
        let clustering = Hierarchical::default().cluster(&scene).unwrap().value;
        for cluster in clustering.clusters.iter().filter(|c| c.len() > 1) {
            // On the table predicted after the cluster's SOCP pushes, as a policy asks.
            let pushes = pushmog::push::Socp::default()
                .plan(&scene, cluster)
                .unwrap()
                .value;
            let after = predict(&scene, &pushes.pushes).unwrap();
            let hints: Vec<JawPose> = pushes.intended_grasp.into_iter().collect();
            let pushed: Vec<ObjectId> = pushes.pushes.iter().map(|p| p.object).collect();
            let request = GraspRequest::new(&after, cluster)
                .hints(&hints)
                .pushed(&pushed);
            let all = planner.plan_request(&request).unwrap();
            let only = planner.plan_request(&request.several()).unwrap();
            if let Some(grasp) = &only.value {
                assert!(grasp.objects.len() >= 2, "seed {seed}: {grasp:?}");
                several += 1;
            }
            if all.value.as_ref().is_some_and(|g| g.objects.len() >= 2) {
                pairs_first += 1;
                let found = only.value.as_ref().expect("a grasp of two or more");
                assert!(
                    only.stats.counter("probability") >= all.stats.counter("probability"),
                    "seed {seed}"
                );
                assert!(found.objects.len() >= 2);
            }
        }
    }
    assert!(several >= pairs_first);
    assert!(
        several > pairs_first,
        "the full search never preferred one object to a pair"
    );
    println!("{several} grasps of two or more, {pairs_first} ranked first by the full search");
}

/// An executor asked to act before it was given a table says so as misuse, and a setting that asks
/// for a part this build left out names the feature.
#[test]
fn misuse_and_missing_features_are_their_own_errors() {
    use pushmog::Error;
    use pushmog::exec::{Executor, Ideal};
    use pushmog::grasp::GraspModel;
    let grasp = crate::support::stray_grasp();
    let mut ideal = Ideal::new(GraspModel::default());
    assert!(matches!(ideal.grasp(&grasp), Err(Error::Misuse { .. })));
    if !cfg!(feature = "highs") {
        let mut settings = PolicySettings::default();
        settings.milp.backend = pushmog::cluster::MilpBackend::Highs;
        let refused = Policy::new(PolicyKind::PushMogOpt, settings).unwrap_err();
        assert!(
            matches!(
                &refused,
                Error::NotCompiled {
                    feature: "highs",
                    ..
                }
            ),
            "{refused}"
        );
    }
}
