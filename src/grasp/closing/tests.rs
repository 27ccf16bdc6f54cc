//! Closings checked against what physics says must happen.

use super::*;

fn square(x: f64, y: f64, side: f64) -> ConvexPolygon {
    let h = side / 2.0;
    ConvexPolygon::new(vec![
        Point2::new(x - h, y - h),
        Point2::new(x + h, y - h),
        Point2::new(x + h, y + h),
        Point2::new(x - h, y + h),
    ])
    .unwrap_or_else(|e| panic!("{e}"))
}

fn close(outlines: &[ConvexPolygon], centre: (f64, f64)) -> Closed {
    let bodies: Vec<Body<'_>> = outlines
        .iter()
        .map(|o| Body {
            outline: o,
            mass: 1000.0 * o.area() * 0.03,
        })
        .collect();
    let jaws = JawPose {
        center: Point2::new(centre.0, centre.1),
        angle: 0.0,
        opening: 0.085,
    };
    let caught: Vec<usize> = (0..outlines.len()).collect();
    simulate_closing(
        &bodies,
        &caught,
        &Gripper::default(),
        &jaws,
        &GraspModel::default(),
    )
}

#[test]
fn an_off_centre_cube_is_pushed_to_the_centre_and_gripped() {
    let closed = close(&[square(0.2, 0.15, 0.03)], (0.215, 0.15));
    assert!(closed.squeezing);
    assert_eq!(closed.gripped, vec![0]);
    let centre = closed.outlines[0].centroid();
    assert!((centre.x - 0.215).abs() < 5e-4, "{centre:?}");
    assert!((closed.opening - 0.04).abs() < 5e-4, "{}", closed.opening);
}

#[test]
fn a_half_gram_square_is_gripped() {
    // 5 mm × 5 mm × 20 mm of water density: 0.5 g against 50 g fingers.
    let outline = square(0.05, 0.05, 0.005);
    let bodies = [Body {
        outline: &outline,
        mass: 0.0005,
    }];
    let jaws = JawPose {
        center: Point2::new(0.05, 0.05),
        angle: 0.0,
        opening: 0.025,
    };
    let closed = simulate_closing(
        &bodies,
        &[0],
        &Gripper::default(),
        &jaws,
        &GraspModel::default(),
    );
    assert!(closed.squeezing);
    assert_eq!(closed.gripped, vec![0]);
}

#[test]
fn two_aligned_cubes_are_gripped_together() {
    let closed = close(
        &[square(0.2, 0.15, 0.03), square(0.231, 0.151, 0.03)],
        (0.215, 0.15),
    );
    assert!(closed.squeezing);
    assert_eq!(closed.gripped, vec![0, 1]);
}
