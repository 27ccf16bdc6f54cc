//! Scenes through JSON: exact round trips and validation through the library API.

use nalgebra::Point2;
use proptest::prelude::*;
use pushmog::Error;
use pushmog::geometry::ConvexPolygon;
use pushmog::json::{scene_from_json, to_json};
use pushmog::scene::{
    GeneratorSettings, Gripper, Object, ObjectId, Pose, Scene, Workspace, builtin_object_set,
    generate_scene,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20))]

    #[test]
    fn scenes_round_trip_exactly(seed in any::<u64>(), objects in 0usize..40) {
        let settings = GeneratorSettings { objects, ..GeneratorSettings::default() };
        let scene = generate_scene(&settings, &builtin_object_set(), seed).unwrap();
        let text = to_json(&scene);
        let back = scene_from_json(&text, "round trip").unwrap();
        prop_assert_eq!(&back, &scene);
        prop_assert_eq!(to_json(&back), text);
        // serde's own reader agrees (deserialising a Scene validates it).
        let direct: Scene = serde_json::from_str(&to_json(&scene)).unwrap();
        prop_assert_eq!(direct, scene);
    }
}

fn square(side: f64) -> ConvexPolygon {
    let h = side / 2.0;
    ConvexPolygon::new(vec![
        Point2::new(-h, -h),
        Point2::new(h, -h),
        Point2::new(h, h),
        Point2::new(-h, h),
    ])
    .unwrap()
}

fn object(id: u32, x: f64, y: f64) -> Object {
    Object {
        id: ObjectId(id),
        name: None,
        polygon: square(0.03),
        pose: Pose::new(x, y, 0.0),
        height: 0.03,
        mass: None,
    }
}

#[test]
fn non_finite_pose_and_mass_are_refused_by_name() {
    let mut bad = object(7, f64::NAN, 0.1);
    let err = Scene::from_parts(
        Workspace::new(0.3, 0.3),
        Gripper::default(),
        vec![bad.clone()],
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            Error::InvalidObject {
                id: ObjectId(7),
                field: "pose",
                ..
            }
        ),
        "{err}"
    );
    bad.pose = Pose::new(0.1, 0.1, f64::INFINITY);
    let err = Scene::from_parts(
        Workspace::new(0.3, 0.3),
        Gripper::default(),
        vec![bad.clone()],
    )
    .unwrap_err();
    assert!(
        matches!(err, Error::InvalidObject { field: "pose", .. }),
        "{err}"
    );
    bad.pose = Pose::new(0.1, 0.1, 0.0);
    bad.mass = Some(f64::NAN);
    let err =
        Scene::from_parts(Workspace::new(0.3, 0.3), Gripper::default(), vec![bad]).unwrap_err();
    assert!(
        matches!(err, Error::InvalidObject { field: "mass", .. }),
        "{err}"
    );
}

#[test]
fn non_finite_vertices_are_refused_by_index() {
    let err = ConvexPolygon::new(vec![
        Point2::new(0.0, 0.0),
        Point2::new(f64::INFINITY, 0.0),
        Point2::new(0.0, 1.0),
    ])
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "vertex 1 has a coordinate that is NaN or infinite"
    );
}

#[test]
fn touching_objects_are_accepted_and_tiny_overlaps_tolerated() {
    // Two squares sharing an edge, as a pushed row would.
    let scene = Scene::from_parts(
        Workspace::new(0.3, 0.3),
        Gripper::default(),
        vec![object(1, 0.1, 0.1), object(2, 0.13, 0.1)],
    )
    .unwrap();
    assert_eq!(scene.len(), 2);
    let err = Scene::from_parts(
        Workspace::new(0.3, 0.3),
        Gripper::default(),
        vec![object(1, 0.1, 0.1), object(2, 0.129, 0.1)],
    )
    .unwrap_err();
    assert!(matches!(err, Error::Overlap { .. }), "{err}");
}

#[test]
fn wide_objects_are_accepted_but_flagged() {
    let mut wide = object(3, 0.15, 0.15);
    wide.polygon = square(0.08);
    let scene =
        Scene::from_parts(Workspace::new(0.3, 0.3), Gripper::default(), vec![wide]).unwrap();
    assert_eq!(scene.ungraspable(), vec![ObjectId(3)]);
    assert!(!scene.is_graspable(0));
}

#[test]
fn removing_objects_keeps_the_rest_intact() {
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 3).unwrap();
    let fewer = scene.without(&[ObjectId(0), ObjectId(5)]);
    assert_eq!(fewer.len(), scene.len() - 2);
    let rebuilt = scene.with_objects(fewer.objects().to_vec()).unwrap();
    assert_eq!(rebuilt, fewer);
}
