//! One object as the simulator knows it: an extruded prism with its full spatial pose, and what a
//! camera above the table makes of it (upright, lying flat on a face, or neither).

use rapier3d_f64::math::{Rotation, Vector};

use crate::geometry::{ConvexPolygon, SIMPLIFY_TOLERANCE, hull_polygon};
use crate::perception::Solid;
use crate::scene::{ObjectId, Pose as PlanarPose};

/// One object as the simulator knows it: its prism and its full spatial pose.
#[derive(Clone, Debug)]
pub(super) struct Prism {
    pub id: ObjectId,
    pub name: Option<String>,
    pub polygon: ConvexPolygon,
    pub height: f64,
    pub mass: f64,
    pub translation: Vector,
    pub rotation: Rotation,
}

impl Prism {
    /// The pose seen from above: position of the body frame and yaw.
    pub fn planar_pose(&self) -> PlanarPose {
        let x_axis = self.rotation * Vector::X;
        PlanarPose::new(
            self.translation.x,
            self.translation.y,
            x_axis.y.atan2(x_axis.x),
        )
    }

    /// How far the object is tilted from upright, radians.
    pub fn tilt(&self) -> f64 {
        (self.rotation * Vector::Z)
            .dot(Vector::Z)
            .clamp(-1.0, 1.0)
            .acos()
    }

    /// The prism as an overhead camera sees it when it has toppled and lies flat on a face (three or
    /// more corners on the table): its footprint (about its centroid), where that sits (yaw 0) and
    /// how tall it stands now. `None` when it leans on something rather than lying flat.
    pub fn lying_flat(&self) -> Option<(ConvexPolygon, PlanarPose, f64)> {
        let corners: Vec<Vector> = self
            .points()
            .into_iter()
            .map(|p| self.rotation * p + self.translation)
            .collect();
        let low = corners.iter().map(|c| c.z).fold(f64::INFINITY, f64::min);
        let high = corners
            .iter()
            .map(|c| c.z)
            .fold(f64::NEG_INFINITY, f64::max);
        let on_table: Vec<nalgebra::Point2<f64>> = corners
            .iter()
            .filter(|c| c.z < low + 1e-3)
            .map(|c| nalgebra::Point2::new(c.x, c.y))
            .collect();
        let resting = hull_polygon(&on_table, SIMPLIFY_TOLERANCE)?;
        if resting.area() < 1e-6 {
            return None;
        }
        let all: Vec<nalgebra::Point2<f64>> = corners
            .iter()
            .map(|c| nalgebra::Point2::new(c.x, c.y))
            .collect();
        // Lying on a side face, each end face stands on edge and its corners seen from above lie on a
        // line up to rounding: the hull drops those within 0.1 mm of its edges.
        let footprint = hull_polygon(&all, SIMPLIFY_TOLERANCE)?;
        let centre = footprint.centroid();
        let local = footprint.translated(&-centre.coords);
        Some((local, PlanarPose::new(centre.x, centre.y, 0.0), high - low))
    }

    /// The prism as a convex solid where it stands now, for the camera's rendering.
    pub fn solid(&self) -> Solid {
        let axis = |v: Vector| {
            let turned = self.rotation * v;
            nalgebra::Vector3::new(turned.x, turned.y, turned.z)
        };
        let rotation =
            nalgebra::Rotation3::from_matrix_unchecked(nalgebra::Matrix3::from_columns(&[
                axis(Vector::X),
                axis(Vector::Y),
                axis(Vector::Z),
            ]));
        let t = self.translation;
        let translation = nalgebra::Vector3::new(t.x, t.y, t.z);
        Solid::moved_prism(self.id, &self.polygon, self.height, &rotation, &translation)
    }

    pub(super) fn points(&self) -> Vec<Vector> {
        self.polygon
            .vertices()
            .iter()
            .flat_map(|v| {
                [
                    Vector::new(v.x, v.y, 0.0),
                    Vector::new(v.x, v.y, self.height),
                ]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    /// A regular octagon of circumradius 20 mm, an edge facing −y, 30 mm tall, laid on that edge's
    /// side face: turned a quarter turn about x (give or take `error`), then by `yaw` about z.
    fn octagon_on_its_side(error: f64, yaw: f64) -> Prism {
        let r = 0.02;
        let vertices = (0..8)
            .map(|k| {
                let a = std::f64::consts::PI / 8.0 + std::f64::consts::FRAC_PI_4 * k as f64;
                Point2::new(r * a.cos(), r * a.sin())
            })
            .collect();
        Prism {
            id: ObjectId(1),
            name: None,
            polygon: ConvexPolygon::new(vertices).unwrap(),
            height: 0.03,
            mass: 0.05,
            translation: Vector::new(0.3, 0.2, 0.0),
            rotation: Rotation::from_rotation_z(yaw)
                * Rotation::from_rotation_x(std::f64::consts::FRAC_PI_2 + error),
        }
    }

    #[test]
    fn a_prism_lying_on_a_side_face_is_seen_as_a_rectangle() {
        let r: f64 = 0.02;
        let apothem = r * (std::f64::consts::PI / 8.0).cos();
        for error in [0.0, 1e-12, -1e-12, 1e-9, -1e-9, 1e-7, -1e-7, 1e-5] {
            for yaw in [0.0, 0.3, 1.0, 2.5, -2.0] {
                let prism = octagon_on_its_side(error, yaw);
                let (footprint, _, height) = prism
                    .lying_flat()
                    .unwrap_or_else(|| panic!("not seen lying flat, error {error}, yaw {yaw}"));
                // Seen from above: the octagon's width across flats (2 apothems) by the 30 mm it
                // was tall; it now stands as tall as it was wide.
                assert_eq!(
                    footprint.len(),
                    4,
                    "error {error}, yaw {yaw}: {footprint:?}"
                );
                let area = 2.0 * apothem * 0.03;
                assert!(
                    (footprint.area() - area).abs() < 1e-7,
                    "{}",
                    footprint.area()
                );
                assert!((height - 2.0 * apothem).abs() < 1e-6, "{height}");
            }
        }
    }
}
