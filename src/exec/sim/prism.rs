//! One object as the simulator knows it: an extruded prism with its full spatial pose, and what a
//! camera above the table makes of it (upright, lying flat on a face, or neither).

use rapier3d_f64::math::{Rotation, Vector};

use crate::geometry::ConvexPolygon;
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
        let resting = ConvexPolygon::new(crate::geometry::convex_hull(&on_table)).ok()?;
        if resting.area() < 1e-6 {
            return None;
        }
        let all: Vec<nalgebra::Point2<f64>> = corners
            .iter()
            .map(|c| nalgebra::Point2::new(c.x, c.y))
            .collect();
        let footprint = ConvexPolygon::new(crate::geometry::convex_hull(&all)).ok()?;
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
