//! Parallel-jaw geometry seen from above.
//!
//! Plates are rectangles `plate_thickness` along the closing axis `a` and `plate_length` across it,
//! centred at `c ± a·s/2` for an opening `s` (distance between plate centres). The region between
//! the plate faces is the rectangle of half-length `s/2 − t/2` along `a` and `plate_length/2` across.

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::geometry::ConvexPolygon;
use crate::scene::Gripper;

/// Where the open jaws are lowered.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct JawPose {
    /// Gripper centre in the table frame, metres.
    #[schemars(with = "[f64; 2]")]
    pub center: Point2<f64>,
    /// Direction of the closing axis, radians (the jaws close along `(cos, sin)` of it).
    pub angle: f64,
    /// Distance between the plate centres before closing, metres.
    pub opening: f64,
}

impl JawPose {
    /// Whether `other` puts the jaws in practically the same place: centres within 3 mm, closing
    /// axes within 5° (either way round) and openings within 3 mm. A grasp that failed there would
    /// most likely fail again.
    pub fn same_place(&self, other: &JawPose) -> bool {
        let turn = (self.angle - other.angle).rem_euclid(std::f64::consts::PI);
        let turn = turn.min(std::f64::consts::PI - turn);
        nalgebra::distance(&self.center, &other.center) < 0.003
            && turn < 5f64.to_radians()
            && (self.opening - other.opening).abs() < 0.003
    }

    /// The unit closing axis.
    pub fn axis(&self) -> Vector2<f64> {
        Vector2::new(self.angle.cos(), self.angle.sin())
    }

    /// Distance between the plate faces, metres.
    pub fn gap(&self, gripper: &Gripper) -> f64 {
        self.opening - gripper.plate_thickness
    }

    /// The two plate footprints.
    pub fn plates(&self, gripper: &Gripper) -> [ConvexPolygon; 2] {
        let axis = self.axis();
        [1.0, -1.0].map(|side| {
            ConvexPolygon::rectangle(
                &(self.center + axis * (side * self.opening / 2.0)),
                &axis,
                gripper.plate_thickness / 2.0,
                gripper.plate_length / 2.0,
            )
        })
    }

    /// The region between the plate faces.
    pub fn between(&self, gripper: &Gripper) -> ConvexPolygon {
        ConvexPolygon::rectangle(
            &self.center,
            &self.axis(),
            self.gap(gripper) / 2.0,
            gripper.plate_length / 2.0,
        )
    }
}
