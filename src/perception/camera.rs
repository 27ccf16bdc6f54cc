//! The depth camera: pinhole intrinsics, where it stands over the table, and the units of its depth.
//!
//! OpenCV's conventions: pixel `(u, v)` has its centre at integer coordinates, `u` along a row, `v`
//! down the columns; a depth value is the point's camera `z`, not its distance along the ray. So the
//! point seen at pixel `(u, v)` with depth `z` is `z·((u − cx)/fx, (v − cy)/fy, 1)` in the camera frame
//! and `p_table = R·p_cam + t` in the table frame. With the ray `r = R·((u − cx)/fx, (v − cy)/fy, 1)`
//! the point is `t + z·r`: the depth itself is the ray's parameter.

use nalgebra::{Matrix3, Point2, Point3, Vector3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result, in_range};

/// Largest image side accepted, pixels.
pub const MAX_PIXELS_PER_SIDE: u32 = 16_384;

/// How far from straight down the optical axis may point, radians (45°): beyond that the two-plane
/// footprint still holds, but the near walls hide much of the table and the pixels grow long.
pub const MAX_CAMERA_TILT: f64 = std::f64::consts::FRAC_PI_4;

/// Pinhole intrinsics, pixels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Intrinsics {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Focal length along `u`, pixels.
    pub fx: f64,
    /// Focal length along `v`, pixels.
    pub fy: f64,
    /// Principal point `u`, pixels.
    pub cx: f64,
    /// Principal point `v`, pixels.
    pub cy: f64,
}

/// What a unit of a 16-bit depth image is.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DepthUnits {
    /// Metres per unit of a 16-bit depth image: 0.001 for a RealSense D400, 0.00025 for an L515,
    /// 0.0001 for a D405. Required for 16-bit input; floating-point depth is in metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
}

/// Where the camera stands: `p_table = R·p_cam + t`, metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Extrinsics {
    /// `R`, rows of a rotation matrix from the camera frame to the table frame.
    pub rotation: [[f64; 3]; 3],
    /// `t`, the camera's optical centre in the table frame, metres.
    pub translation: [f64; 3],
}

/// A calibrated depth camera over the table (`pushmog schema camera`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Pinhole intrinsics.
    pub intrinsics: Intrinsics,
    /// Units of 16-bit depth.
    #[serde(default)]
    pub depth: DepthUnits,
    /// Camera → table.
    pub extrinsics: Extrinsics,
}

/// The RealSense models whose depth unit a wrong scale most likely came from, metres per unit.
pub const KNOWN_SCALES: [(&str, f64); 3] = [
    ("RealSense D400 series", 0.001),
    ("RealSense L515", 0.00025),
    ("RealSense D405", 0.0001),
];

impl Camera {
    /// A camera `height` metres straight above the table point `(x, y)`, image `u` along the table's
    /// x and `v` against its y, with a horizontal field of view of `fov` radians: the set-up the tests
    /// and the simulator's camera use.
    pub fn looking_down(width: u32, height: u32, fov: f64, x: f64, y: f64, above: f64) -> Self {
        let f = 0.5 * f64::from(width) / (0.5 * fov).tan();
        Self {
            intrinsics: Intrinsics {
                width,
                height,
                fx: f,
                fy: f,
                cx: 0.5 * f64::from(width) - 0.5,
                cy: 0.5 * f64::from(height) - 0.5,
            },
            depth: DepthUnits::default(),
            extrinsics: Extrinsics {
                rotation: [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
                translation: [x, y, above],
            },
        }
    }

    /// This camera turned by `angle` radians about the table's x axis through its optical centre
    /// (a tilt from straight down).
    pub fn tilted(self, angle: f64) -> Self {
        self.turned(&nalgebra::Rotation3::from_axis_angle(
            &Vector3::x_axis(),
            angle,
        ))
    }

    /// This camera turned by `turn`, a rotation in the table frame, about its optical centre.
    pub fn turned(mut self, turn: &nalgebra::Rotation3<f64>) -> Self {
        let rotation = turn.matrix() * self.rotation();
        for (i, row) in self.extrinsics.rotation.iter_mut().enumerate() {
            for (j, value) in row.iter_mut().enumerate() {
                *value = rotation[(i, j)];
            }
        }
        self
    }

    /// `R` as a matrix.
    pub fn rotation(&self) -> Matrix3<f64> {
        let r = &self.extrinsics.rotation;
        Matrix3::new(
            r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2],
        )
    }

    /// The optical centre in the table frame.
    pub fn centre(&self) -> Point3<f64> {
        Point3::from(Vector3::from(self.extrinsics.translation))
    }

    /// The table-frame ray `r` of pixel `(u, v)`, scaled so that the point at depth `z` is
    /// `centre + z·r`.
    pub fn ray(&self, u: f64, v: f64) -> Vector3<f64> {
        let k = &self.intrinsics;
        self.rotation() * Vector3::new((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0)
    }

    /// The rays of every pixel, row-major ([`Camera::ray`] for each, the rotation built once).
    pub fn rays(&self) -> Vec<Vector3<f64>> {
        let k = &self.intrinsics;
        let r = self.rotation();
        let (x, y, z) = (
            r.column(0).into_owned(),
            r.column(1).into_owned(),
            r.column(2).into_owned(),
        );
        let mut rays = Vec::with_capacity(k.width as usize * k.height as usize);
        for v in 0..k.height {
            let b = (f64::from(v) - k.cy) / k.fy;
            let row = z + y * b;
            for u in 0..k.width {
                rays.push(row + x * ((f64::from(u) - k.cx) / k.fx));
            }
        }
        rays
    }

    /// The pixel `(u, v)` where the table point `p` is seen, and its depth; `None` behind the camera.
    pub fn project(&self, p: &Point3<f64>) -> Option<(Point2<f64>, f64)> {
        let q = self.rotation().transpose() * (p - self.centre());
        if q.z <= 0.0 {
            return None;
        }
        let k = &self.intrinsics;
        Some((
            Point2::new(k.fx * q.x / q.z + k.cx, k.fy * q.y / q.z + k.cy),
            q.z,
        ))
    }

    /// Checks the camera: positive finite intrinsics, a proper rotation, an optical centre above the
    /// table, an optical axis within [`MAX_CAMERA_TILT`] of straight down, a positive depth scale.
    ///
    /// # Errors
    /// An [`Error::InvalidField`] naming the field (`intrinsics.fx`, `extrinsics.rotation`, …).
    pub fn validate(&self) -> Result<()> {
        let k = &self.intrinsics;
        for (field, side) in [
            ("intrinsics.width", k.width),
            ("intrinsics.height", k.height),
        ] {
            if side == 0 || side > MAX_PIXELS_PER_SIDE {
                return Err(Error::field(
                    "camera",
                    field,
                    format!("must be between 1 and {MAX_PIXELS_PER_SIDE} pixels, got {side}"),
                ));
            }
        }
        for (field, value) in [("intrinsics.fx", k.fx), ("intrinsics.fy", k.fy)] {
            in_range(
                "camera",
                field,
                value,
                (1.0, 1e6),
                "a focal length in pixels",
            )?;
        }
        for (field, value) in [("intrinsics.cx", k.cx), ("intrinsics.cy", k.cy)] {
            in_range(
                "camera",
                field,
                value,
                (-1e6, 1e6),
                "a principal point in pixels",
            )?;
        }
        let r = self.rotation();
        let off = (r.transpose() * r - Matrix3::identity()).abs().max();
        if !off.is_finite() || off > 1e-6 || (r.determinant() - 1.0).abs() > 1e-6 {
            return Err(Error::field(
                "camera",
                "extrinsics.rotation",
                format!(
                    "is not a rotation: RᵀR differs from the identity by {off:.2e} and det R = {:.6} \
                     (rows are the table-frame coordinates of the camera's x, y, z axes transposed; \
                     a mirror has det −1)",
                    r.determinant()
                ),
            ));
        }
        let t = self.extrinsics.translation;
        for (axis, value) in t.iter().enumerate() {
            in_range(
                "camera",
                [
                    "extrinsics.translation[0]",
                    "extrinsics.translation[1]",
                    "extrinsics.translation[2]",
                ][axis],
                *value,
                (-100.0, 100.0),
                "metres in the table frame",
            )?;
        }
        if t[2] <= 0.0 {
            return Err(Error::field(
                "camera",
                "extrinsics.translation[2]",
                format!("the camera must be above the table (z > 0), got {} m", t[2]),
            ));
        }
        let axis = r * Vector3::z();
        let tilt = (-axis.z).clamp(-1.0, 1.0).acos();
        if tilt > MAX_CAMERA_TILT {
            return Err(Error::field(
                "camera",
                "extrinsics.rotation",
                format!(
                    "the camera does not look down at the table: its optical axis is {:.1}° from \
                     straight down (at most {:.0}°); the third column of R is the axis in the table \
                     frame and should point along −z",
                    tilt.to_degrees(),
                    MAX_CAMERA_TILT.to_degrees()
                ),
            ));
        }
        if let Some(scale) = self.depth.scale {
            in_range(
                "camera",
                "depth.scale",
                scale,
                (1e-7, 1.0),
                "metres per depth unit",
            )?;
        }
        Ok(())
    }
}
