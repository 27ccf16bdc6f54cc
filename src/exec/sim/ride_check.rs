//! A first physics check of riders (`formulations/stacking.md`): a rider placed where
//! `stack::place_rider` puts it, on a pushed pair, goes with the pair through the grasp, the lift
//! and a carry at the arm's acceleration. The rider starts at rest on the row's top, as the place
//! action (`place.rs`) leaves it, so that the check judges the ride alone.

use rapier3d_f64::math::{Rotation, Vector};

use super::Sim;
use super::prism::Prism;
use super::settings::SimSettings;
use super::world::Stage;
use crate::geometry::ConvexPolygon;
use crate::scene::{Gripper, ObjectId};
use crate::stack::{Row, StackSettings, place_rider};

/// Density of the test objects, kg/m³ (the grasp model's default).
const DENSITY: f64 = 1000.0;

pub(super) fn square(half: f64) -> ConvexPolygon {
    ConvexPolygon::rectangle(
        &nalgebra::Point2::origin(),
        &nalgebra::Vector2::x(),
        half,
        half,
    )
}

pub(super) fn prism(
    id: u32,
    outline: ConvexPolygon,
    at: (f64, f64, f64),
    yaw: f64,
    height: f64,
) -> Prism {
    Prism {
        id: ObjectId(id),
        name: None,
        mass: DENSITY * outline.area() * height,
        polygon: outline,
        height,
        translation: Vector::new(at.0, at.1, at.2),
        rotation: Rotation::from_rotation_z(yaw),
    }
}

/// What became of a 20 mm cube resting on a pair of 35 mm cubes pushed together along x (70 mm of
/// the 75 mm the jaws open to), its centroid where `stack::place_rider` puts it and then `shift`
/// further along y, after the closing, a 10 cm lift and a 0.3 m carry at 1.2 m/s² (top speed
/// 0.5 m/s): how far it moved relative to the pair, metres, its tilt, radians, and how high its
/// base is above where it was put, metres.
fn ride(shift: f64) -> (f64, f64, f64) {
    let settings = SimSettings::default();
    let sim = Sim::new(settings.clone(), 1).expect("the default simulator settings are valid");
    let cube = square(0.0175);
    let row = Row {
        outlines: vec![
            cube.translated(&nalgebra::Vector2::new(0.0, 0.0)),
            cube.translated(&nalgebra::Vector2::new(0.035, 0.0)),
        ],
        heights: vec![0.035, 0.035],
        axis: nalgebra::Vector2::x(),
        closing: None,
    };
    let rider_outline = square(0.01);
    let stack = StackSettings::default();
    let placed = place_rider(&row, &rider_outline, 0.02, settings.friction_object, &stack)
        .expect("a 20 mm cube has a placement on a row of two 35 mm cubes");
    let mut prisms = vec![
        prism(0, cube.clone(), (0.0, 0.0, 0.0), 0.0, 0.035),
        prism(1, cube, (0.035, 0.0, 0.0), 0.0, 0.035),
        prism(
            2,
            rider_outline,
            (placed.pose.x, placed.pose.y + shift, placed.base),
            placed.pose.yaw,
            0.02,
        ),
    ];
    let above = placed.base + 0.02 + 0.005;
    let mut stage = Stage::new(
        &prisms,
        &[0, 1, 2],
        &Gripper::default(),
        &sim.stage_settings(),
        (0.0175, 0.0),
        above,
        0.0,
        0.085,
    );
    let relative = |prisms: &[Prism]| {
        let middle = (prisms[0].translation + prisms[1].translation) / 2.0;
        prisms[2].translation - middle
    };
    let before = relative(&prisms);
    let landed = stage.descend(above - settings.grasp_height, settings.vertical_speed);
    assert_eq!(landed, None);
    stage.close(settings.jaw_speed, settings.grip_force, 1.0);
    stage.wait(0.05);
    stage.travel(
        Vector::new(0.0, 0.0, settings.lift),
        settings.vertical_speed,
    );
    stage.carry(Vector::new(0.3, 0.0, 0.0), 0.5, stack.acceleration);
    stage.wait(settings.settle);
    stage.write_back(&mut prisms);
    let moved = (relative(&prisms) - before).length();
    (
        moved,
        prisms[2].tilt(),
        prisms[2].translation.z - placed.base,
    )
}

/// Placed by the checks, the rider goes with the pair: upright, within 1 mm of where it was put
/// relative to the pair, lifted with it.
#[test]
fn a_rider_placed_by_the_checks_rides_the_grasp_lift_and_carry() {
    let lift = SimSettings::default().lift;
    let (moved, tilt, raised) = ride(0.0);
    assert!(moved < 0.001, "the rider moved {moved} m on the pair");
    assert!(tilt < 1f64.to_radians(), "{tilt}");
    assert!(raised > 0.9 * lift, "{raised}");
}

/// The same rider with its centroid 2 mm beyond the top's edge is not carried: the check that
/// refuses it stands for something physical.
#[test]
fn a_rider_with_its_centroid_off_the_top_falls() {
    let lift = SimSettings::default().lift;
    let (moved, tilt, raised) = ride(0.0175 + 0.002);
    assert!(
        raised < 0.5 * lift || tilt > 30f64.to_radians(),
        "moved {moved}, tilt {tilt}, raised {raised}"
    );
}

/// A 40 mm cube 30 mm tall and, 10 mm beyond it along the closing axis, a slab 10 mm thick and 5 mm
/// lower (beyond the top's tolerance, so riders rest on the cube alone), at `x` metres, as a scene
/// for the grasp model, and the jaws centred on them.
fn cube_and_slab(x: f64) -> (crate::scene::Scene, crate::grasp::JawPose) {
    use crate::scene::{Object, Pose, Scene, Workspace};
    let slab = ConvexPolygon::rectangle(
        &nalgebra::Point2::origin(),
        &nalgebra::Vector2::x(),
        0.005,
        0.02,
    );
    let objects = vec![
        Object {
            id: ObjectId(0),
            name: None,
            polygon: square(0.02),
            pose: Pose::new(x, 0.2, 0.0),
            height: 0.03,
            mass: None,
        },
        Object {
            id: ObjectId(1),
            name: None,
            polygon: slab,
            pose: Pose::new(x + 0.035, 0.2, 0.0),
            height: 0.025,
            mass: None,
        },
    ];
    let scene = Scene::from_parts(Workspace::default(), Gripper::default(), objects)
        .expect("the two objects lie apart inside the workspace");
    let jaws = crate::grasp::JawPose {
        center: nalgebra::Point2::new(x + 0.01, 0.2),
        angle: 0.0,
        opening: 0.085,
    };
    (scene, jaws)
}

/// The least clearance along the closing axis between the rider (prism 2) and the plates' faces
/// once the jaws have closed on the cube and slab in rapier, metres.
fn clearance_once_closed(placed: &crate::stack::Placement, rider: &ConvexPolygon) -> f64 {
    let settings = SimSettings::default();
    let sim = Sim::new(settings.clone(), 1).expect("the default simulator settings are valid");
    let (scene, jaws) = cube_and_slab(0.3);
    let mut prisms: Vec<Prism> = scene
        .objects()
        .iter()
        .map(|o| {
            prism(
                o.id.0,
                o.polygon.clone(),
                (o.pose.x, o.pose.y, 0.0),
                0.0,
                o.height,
            )
        })
        .collect();
    prisms.push(prism(
        2,
        rider.clone(),
        (placed.pose.x, placed.pose.y, placed.base),
        placed.pose.yaw,
        0.02,
    ));
    let above = placed.base + 0.02 + 0.005;
    let gripper = Gripper::default();
    let mut stage = Stage::new(
        &prisms,
        &[0, 1, 2],
        &gripper,
        &sim.stage_settings(),
        (jaws.center.x, jaws.center.y),
        above,
        0.0,
        jaws.opening,
    );
    assert_eq!(
        stage.descend(above - settings.grasp_height, settings.vertical_speed),
        None
    );
    stage.close(settings.jaw_speed, settings.grip_force, 2.0);
    stage.wait(0.05);
    let half_gap = 0.5 * (stage.opening() - gripper.plate_thickness);
    stage.write_back(&mut prisms);
    let (front, back) = prisms[2]
        .polygon
        .transformed(&prisms[2].planar_pose().isometry())
        .projection(&nalgebra::Vector2::x());
    (front - (jaws.center.x - half_gap)).min(jaws.center.x + half_gap - back)
}

/// Where the pads end decides whether a pad meets the rider. A bar 48 mm long set on the cube
/// reaching over the slab clears both pads by the margin as the row stands; the closing carries
/// the cube toward the slab and brings the slab's pad in, so the check with the grasp model's
/// closing refuses it, and in rapier a pad comes against it. The shorter bar that check places
/// stays clear of both pads in rapier.
#[test]
fn where_the_pads_end_decides_whether_a_pad_meets_the_rider() {
    let (scene, jaws) = cube_and_slab(0.3);
    let model = crate::problem::GraspModel::default();
    let closing = crate::grasp::closed_motions(&scene, &jaws, &model, &[0, 1]);
    assert!(closing.is_some(), "the model holds the pair");
    let row = |closing| Row {
        outlines: (0..2).map(|i| scene.world_polygon(i).clone()).collect(),
        heights: vec![0.03, 0.025],
        axis: nalgebra::Vector2::x(),
        closing,
    };
    // Bars along the closing axis only.
    let stack = StackSettings {
        yaws: 2,
        ..StackSettings::default()
    };
    let bar = |length: f64| {
        ConvexPolygon::rectangle(
            &nalgebra::Point2::origin(),
            &nalgebra::Vector2::x(),
            length / 2.0,
            0.01,
        )
    };
    let long = bar(0.048);
    let standing = place_rider(&row(None), &long, 0.02, 0.4, &stack)
        .expect("as the row stands the long bar fits between the pads");
    assert_eq!(
        place_rider(&row(closing.clone()), &long, 0.02, 0.4, &stack),
        Err(crate::stack::NoPlacement::PadsClose)
    );
    let pressed = clearance_once_closed(&standing, &long);
    assert!(pressed < 0.001, "a pad ends {pressed} m from the long bar");
    let short = bar(0.036);
    let placed = place_rider(&row(closing), &short, 0.02, 0.4, &stack)
        .expect("the short bar has a placement clear of the closed pads");
    let clear = clearance_once_closed(&placed, &short);
    assert!(clear > 0.003, "a pad ends {clear} m from the short bar");
}
