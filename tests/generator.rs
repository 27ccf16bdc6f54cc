//! The seeded scene generator.

use pushmog::Error;
use pushmog::geometry::overlap;
use pushmog::json::to_json;
use pushmog::scene::{GeneratorSettings, Workspace, builtin_object_set, generate_scene};

#[test]
fn same_seed_same_bytes_other_seed_other_scene() {
    let settings = GeneratorSettings::default();
    let set = builtin_object_set();
    let a = to_json(&generate_scene(&settings, &set, 11).unwrap());
    let b = to_json(&generate_scene(&settings, &set, 11).unwrap());
    let c = to_json(&generate_scene(&settings, &set, 12).unwrap());
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn a_default_scene_uses_every_library_shape_once() {
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 5).unwrap();
    let mut names: Vec<&str> = scene
        .objects()
        .iter()
        .map(|o| o.name.as_deref().unwrap())
        .collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), 34);
    // Every pair is apart and every object inside (the Scene checked it; confirm independently).
    for i in 0..scene.len() {
        for j in i + 1..scene.len() {
            assert!(!overlap(
                scene.world_polygon(i),
                scene.world_polygon(j),
                0.0
            ));
        }
    }
}

#[test]
fn more_objects_than_the_library_repeat_the_set() {
    let settings = GeneratorSettings {
        objects: 80,
        workspace: Workspace::new(1.0, 0.8),
        ..GeneratorSettings::default()
    };
    let scene = generate_scene(&settings, &builtin_object_set(), 2).unwrap();
    assert_eq!(scene.len(), 80);
}

#[test]
fn objects_that_cannot_fit_give_a_clear_error() {
    let settings = GeneratorSettings {
        objects: 34,
        workspace: Workspace::new(0.2, 0.2),
        max_samples: 5_000,
        ..GeneratorSettings::default()
    };
    let err = generate_scene(&settings, &builtin_object_set(), 1).unwrap_err();
    match &err {
        Error::Placement {
            requested,
            placed,
            samples,
            ..
        } => {
            assert_eq!(*requested, 34);
            assert!(*placed < 34);
            assert_eq!(*samples, 5_000);
        }
        other => panic!("unexpected error {other}"),
    }
    assert!(
        err.to_string()
            .contains("larger workspace or fewer objects")
    );
    // A workspace narrower than one circle fails at once.
    let tiny = GeneratorSettings {
        workspace: Workspace::new(0.03, 0.03),
        ..GeneratorSettings::default()
    };
    assert!(matches!(
        generate_scene(&tiny, &builtin_object_set(), 1),
        Err(Error::Placement { placed: 0, .. })
    ));
}
