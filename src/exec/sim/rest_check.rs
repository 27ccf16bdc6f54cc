//! What a stage keeps is at rest: an object still moving when an action ends runs on until it
//! stops (`SimSettings::rest_wait`), since objects beyond the later actions' reach keep the poses
//! kept.

use rapier3d_f64::math::Rotation;

use super::Sim;
use super::ride_check::{prism, square};
use super::settings::SimSettings;
use super::world::Stage;
use crate::scene::Gripper;

/// A 30 mm cube let go 5 cm above the table, tipped 40°, the open jaws 0.3 m away, and the stage
/// ended 50 ms later, the cube still falling: the lowest of its corners above the table, metres,
/// and how far its tilt is from a face down, radians, as the stage keeps it.
fn let_go(rest_wait: f64) -> (f64, f64) {
    let settings = SimSettings {
        rest_wait,
        ..SimSettings::default()
    };
    let sim = Sim::new(settings, 1).expect("the simulator settings are valid");
    let mut cube = prism(0, square(0.015), (0.0, 0.0, 0.05), 0.0, 0.03);
    cube.rotation = Rotation::from_rotation_x(40f64.to_radians());
    let mut prisms = vec![cube];
    let mut stage = Stage::new(
        &prisms,
        &[0],
        &Gripper::default(),
        &sim.stage_settings(),
        (0.3, 0.0),
        0.1,
        0.0,
        0.085,
    );
    stage.wait(0.05);
    stage.write_back(&mut prisms);
    let cube = &prisms[0];
    let lowest = cube
        .points()
        .into_iter()
        .map(|p| (cube.rotation * p + cube.translation).z)
        .fold(f64::INFINITY, f64::min);
    let quarter = std::f64::consts::FRAC_PI_2;
    let tilt = cube.tilt();
    let off_face = (tilt - quarter * (tilt / quarter).round()).abs();
    (lowest, off_face)
}

/// Kept at once, the cube would stay in the air, tipped, wherever no later action reaches it; run
/// on until at rest, it lies on a face on the table.
#[test]
fn a_falling_object_is_kept_where_it_comes_to_rest() {
    let (lowest, off_face) = let_go(0.0);
    assert!(lowest > 0.02, "kept at once: lowest corner {lowest} m");
    assert!(off_face > 30f64.to_radians(), "{off_face}");
    let (lowest, off_face) = let_go(SimSettings::default().rest_wait);
    assert!(lowest.abs() < 0.001, "lowest corner {lowest} m");
    assert!(off_face < 1f64.to_radians(), "{off_face}");
}
