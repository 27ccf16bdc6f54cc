//! Whether a squeezed object can rest in equilibrium under its contact forces alone, with friction to
//! spare: the test the planar closing applies to every object it ends up pressing
//! (`formulations/grasping.md`, "Friction to spare").
//!
//! Each contact `k` touches the object at `p_k` with inward unit normal `n_k` and pushes with a force
//! inside its friction cone, narrowed to `share · μ_k`:
//! `f_k = λ_k⁺ (n_k + share·μ_k t_k) + λ_k⁻ (n_k − share·μ_k t_k)`, `λ ≥ 0`, `t_k ⊥ n_k`.
//! The object rests when some such forces, not all zero, balance: `Σ f_k = 0` and
//! `Σ (p_k − c) × f_k = 0`. Table friction and gravity are left out: the table carries a few
//! hundredths of a newton against a grip of tens, and gravity acts out of the plane. A small linear
//! program decides it (the sum of the `λ` is fixed to 1, so only a real squeeze counts).

use microlp::{ComparisonOp, OptimizationDirection, Problem};
use nalgebra::{Point2, Vector2};

use crate::geometry::cross;

/// One contact on the object.
#[derive(Clone, Copy, Debug)]
pub(super) struct Touch {
    /// Where it touches, metres.
    pub point: Point2<f64>,
    /// Unit normal pointing into the object.
    pub normal: Vector2<f64>,
    /// Coulomb friction coefficient of the contact.
    pub friction: f64,
}

/// Whether contact forces within `share` of each contact's friction cone can hold an object whose
/// centroid is `centroid` in equilibrium.
pub(super) fn balanced(centroid: &Point2<f64>, touches: &[Touch], share: f64) -> bool {
    if touches.len() < 2 {
        return false;
    }
    // Lever arms in units of the largest, so the moment row is as well scaled as the force rows.
    let reach = touches
        .iter()
        .map(|t| (t.point - centroid).norm())
        .fold(0.0, f64::max)
        .max(1e-6);
    let mut problem = Problem::new(OptimizationDirection::Minimize);
    let (mut fx, mut fy, mut moment, mut total) = (vec![], vec![], vec![], vec![]);
    for touch in touches {
        let tangent = Vector2::new(-touch.normal.y, touch.normal.x);
        let arm = (touch.point - centroid) / reach;
        for side in [1.0, -1.0] {
            let edge = touch.normal + tangent * (side * share * touch.friction);
            let lambda = problem.add_var(0.0, (0.0, f64::INFINITY));
            fx.push((lambda, edge.x));
            fy.push((lambda, edge.y));
            moment.push((lambda, cross(&arm, &edge)));
            total.push((lambda, 1.0));
        }
    }
    problem.add_constraint(fx.as_slice(), ComparisonOp::Eq, 0.0);
    problem.add_constraint(fy.as_slice(), ComparisonOp::Eq, 0.0);
    problem.add_constraint(moment.as_slice(), ComparisonOp::Eq, 0.0);
    problem.add_constraint(total.as_slice(), ComparisonOp::Eq, 1.0);
    problem.solve().is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(x: f64, y: f64, nx: f64, ny: f64) -> Touch {
        let normal = Vector2::new(nx, ny).normalize();
        Touch {
            point: Point2::new(x, y),
            normal,
            friction: 0.4,
        }
    }

    #[test]
    fn opposite_faces_pressed_on_one_line_balance() {
        let touches = [touch(-0.01, 0.0, 1.0, 0.0), touch(0.01, 0.0, -1.0, 0.0)];
        assert!(balanced(&Point2::origin(), &touches, 0.8));
    }

    #[test]
    fn a_squeeze_off_its_line_needs_friction_at_both_ends() {
        // Pressed at (−10, 0) and (10, 3) mm along x: the line between them leans atan(3/20) = 8.5°
        // from both normals, inside a cone of atan(0.4) = 21.8° and of atan(0.8 · 0.4) = 17.7°.
        let leaning = [touch(-0.01, 0.0, 1.0, 0.0), touch(0.01, 0.003, -1.0, 0.0)];
        assert!(balanced(&Point2::origin(), &leaning, 0.8));
        // At (10, 7) mm the line leans 19.3°: inside the full cone, outside the narrowed one.
        let steep = [touch(-0.01, 0.0, 1.0, 0.0), touch(0.01, 0.007, -1.0, 0.0)];
        assert!(balanced(&Point2::origin(), &steep, 1.0));
        assert!(!balanced(&Point2::origin(), &steep, 0.8));
    }

    #[test]
    fn one_contact_or_a_wedge_steeper_than_friction_does_not_hold() {
        assert!(!balanced(
            &Point2::origin(),
            &[touch(0.0, 0.01, 0.0, -1.0)],
            1.0
        ));
        // Two plates pressing a wedge whose faces lean 30° from the plates: the forces cannot cancel
        // inside cones of 21.8°.
        let wedge = [
            touch(
                -0.01,
                0.0,
                30f64.to_radians().cos(),
                30f64.to_radians().sin(),
            ),
            touch(
                0.01,
                0.0,
                -30f64.to_radians().cos(),
                30f64.to_radians().sin(),
            ),
        ];
        assert!(!balanced(&Point2::origin(), &wedge, 1.0));
    }
}
