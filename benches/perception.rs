//! `perceive` on a 1280 × 720 depth frame of a 34-object table with the default noise, one thread,
//! the frame already in memory (issue 40's aim: a median of 20 ms or less), with the default settings,
//! with `fit_sides`, without `fit_outline` (the median hull alone), and with exact instance labels.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{Criterion, criterion_group, criterion_main};
use pushmog::perception::{
    Camera, Depth, DepthNoise, Frame, PerceptionSettings, add_noise, perceive, render_depth,
};
use pushmog::random::SeededRng;
use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};

fn perception(c: &mut Criterion) {
    let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 1).unwrap();
    // 1 mm per pixel on the table from 0.7 m.
    let camera = Camera::looking_down(1280, 720, 2.0 * (640.0_f64 / 700.0).atan(), 0.3, 0.225, 0.7);
    let rendered = render_depth(&scene, &camera).unwrap();
    let depth = add_noise(
        &rendered.depth,
        1280,
        &DepthNoise::default(),
        &mut SeededRng::new(1),
    );
    let frame = Frame {
        depth: Some(Depth::Metres(&depth)),
        ..Frame::default()
    };
    for (name, fit_sides, fit_outline) in [
        ("perceive/1280x720/34-objects", false, true),
        ("perceive/1280x720/34-objects/fit-sides", true, true),
        ("perceive/1280x720/34-objects/hull-only", false, false),
    ] {
        let settings = PerceptionSettings {
            fit_sides,
            fit_outline,
            ..PerceptionSettings::default()
        };
        c.bench_function(name, |b| {
            b.iter(|| {
                perceive(
                    &frame,
                    &camera,
                    scene.workspace(),
                    scene.gripper(),
                    None,
                    &settings,
                )
                .unwrap()
            })
        });
    }
    // The same look with the renderer's exact instance labels, as a segmenter would give them.
    let labelled = Frame {
        depth: Some(Depth::Metres(&depth)),
        labels: Some(&rendered.labels),
        ..Frame::default()
    };
    c.bench_function("perceive/1280x720/34-objects/labels", |b| {
        b.iter(|| {
            perceive(
                &labelled,
                &camera,
                scene.workspace(),
                scene.gripper(),
                None,
                &PerceptionSettings::default(),
            )
            .unwrap()
        })
    });
    c.bench_function("render_depth/1280x720/34-objects", |b| {
        b.iter(|| render_depth(&scene, &camera).unwrap())
    });
}

criterion_group!(benches, perception);
criterion_main!(benches);
