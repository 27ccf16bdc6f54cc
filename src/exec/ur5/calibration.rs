//! Table-to-base calibration: the rigid transform that takes a point of the table frame (where scenes
//! and plans live, z = 0 on the table surface) to the robot's base frame.
//!
//! Given pairs (aᵢ, bᵢ), aᵢ = (xᵢ, yᵢ, 0) on the table and bᵢ the same point read on the pendant, the
//! least-squares rotation R and translation t minimise Σ‖R aᵢ + t − bᵢ‖². With the centroids ā, b̄
//! and H = Σ (aᵢ − ā)(bᵢ − b̄)ᵀ = U S Vᵀ (singular value decomposition), R = V D Uᵀ where D is the
//! identity except −1 against the smallest singular value when det(V Uᵀ) < 0 (so R is a rotation, not
//! a reflection), and t = b̄ − R ā. Three points not on one line fix R uniquely even though the aᵢ all
//! lie in one plane. The fit reports its root-mean-square and largest residual so a bad measurement
//! shows. See `formulations/calibration.md`.

use nalgebra::{Matrix3, Point3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// One measured pair: a point on the table and where the robot's tool centre point was when touching
/// it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Correspondence {
    /// The point in the table frame, `[x, y]`, metres.
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub table: [f64; 2],
    /// The same point in the base frame, `[x, y, z]`, metres.
    #[serde(deserialize_with = "crate::json::exact_array")]
    pub base: [f64; 3],
}

/// A fitted table-to-base transform.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    /// Rotation from the table frame to the base frame.
    pub rotation: Rotation3<f64>,
    /// Where the table origin lies in the base frame, metres.
    pub translation: Vector3<f64>,
    /// Root-mean-square distance between the transformed table points and the measured ones, metres.
    pub rms_residual: f64,
    /// The largest such distance, metres.
    pub max_residual: f64,
    /// Index of the point with the largest residual.
    pub worst_point: usize,
}

/// The smallest spread (standard deviation across the narrowest direction) the table points may
/// have, metres: below it they are too close to one line to fix the rotation.
const MIN_SPREAD: f64 = 0.005;

impl Calibration {
    /// Fits the transform to three or more pairs by least squares.
    ///
    /// # Errors
    /// [`Error::InvalidField`] for fewer than three pairs, a non-finite coordinate, or table points
    /// (nearly) on one line.
    pub fn fit(points: &[Correspondence]) -> Result<Self> {
        let bad = |reason: String| Err(Error::field("robot config", "calibration.points", reason));
        if points.len() < 3 {
            return bad(format!(
                "needs at least 3 point pairs, got {}",
                points.len()
            ));
        }
        if points
            .iter()
            .any(|p| p.table.iter().chain(&p.base).any(|v| !v.is_finite()))
        {
            return bad("every coordinate must be finite".to_string());
        }
        let a: Vec<Vector3<f64>> = points
            .iter()
            .map(|p| Vector3::new(p.table[0], p.table[1], 0.0))
            .collect();
        let b: Vec<Vector3<f64>> = points.iter().map(|p| Vector3::from(p.base)).collect();
        let n = points.len() as f64;
        let a_mean = a.iter().sum::<Vector3<f64>>() / n;
        let b_mean = b.iter().sum::<Vector3<f64>>() / n;

        let mut spread = Matrix3::zeros();
        let mut h = Matrix3::zeros();
        for (ai, bi) in a.iter().zip(&b) {
            let da = ai - a_mean;
            spread += da * da.transpose();
            h += da * (bi - b_mean).transpose();
        }
        let narrowest = spread
            .fixed_view::<2, 2>(0, 0)
            .symmetric_eigenvalues()
            .min()
            .max(0.0);
        if (narrowest / n).sqrt() < MIN_SPREAD {
            return bad(format!(
                "the table points lie (nearly) on one line (spread {:.2} mm across it); use \
                 points spread over the table",
                (narrowest / n).sqrt() * 1e3
            ));
        }

        let svd = h.svd(true, true);
        let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
            return bad("the singular value decomposition did not converge".to_string());
        };
        let v = v_t.transpose();
        let smallest = svd.singular_values.imin();
        let mut d = Matrix3::identity();
        if (v * u.transpose()).determinant() < 0.0 {
            d[(smallest, smallest)] = -1.0;
        }
        let rotation = Rotation3::from_matrix_unchecked(v * d * u.transpose());
        let translation = b_mean - rotation * a_mean;

        let residuals: Vec<f64> = a
            .iter()
            .zip(&b)
            .map(|(ai, bi)| (rotation * ai + translation - bi).norm())
            .collect();
        let (worst_point, max_residual) =
            residuals
                .iter()
                .copied()
                .enumerate()
                .fold(
                    (0, 0.0),
                    |best, (i, r)| if r > best.1 { (i, r) } else { best },
                );
        let rms_residual = (residuals.iter().map(|r| r * r).sum::<f64>() / n).sqrt();
        Ok(Self {
            rotation,
            translation,
            rms_residual,
            max_residual,
            worst_point,
        })
    }

    /// A table point at height `z` above the table plane, in the base frame.
    pub fn to_base(&self, x: f64, y: f64, z: f64) -> Point3<f64> {
        Point3::from(self.rotation * Vector3::new(x, y, z) + self.translation)
    }
}
