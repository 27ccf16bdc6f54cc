//! The table plane `z = a·x + b·y + c` in the table frame, fitted by least squares to the pixels that
//! see the table, so that a calibration a few millimetres off in height or a fraction of a degree in
//! tilt does not become an error in every object's height.
//!
//! The first fit takes the points within `start` of `z = 0` (the calibrated table); each refit keeps
//! the points within three root-mean-square residuals of the last plane (at least 2 mm), three times.

use nalgebra::{Matrix3, Point3, Vector3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The fitted table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TablePlane {
    /// `[a, b, c]` of `z = a·x + b·y + c`, the table frame's metres.
    pub coefficients: [f64; 3],
    /// The plane's height above the calibrated table at the workspace's centre, metres.
    pub offset: f64,
    /// The plane's angle to the calibrated table, radians.
    pub tilt: f64,
    /// Root-mean-square residual of the points kept, metres.
    pub residual: f64,
    /// How many points the last fit kept.
    pub points: usize,
}

impl TablePlane {
    /// The calibrated table `z = 0`, when nothing was fitted.
    pub fn calibrated() -> Self {
        Self {
            coefficients: [0.0; 3],
            offset: 0.0,
            tilt: 0.0,
            residual: 0.0,
            points: 0,
        }
    }

    /// The height of `p` above the plane, metres (vertical distance).
    pub fn height(&self, p: &Point3<f64>) -> f64 {
        let [a, b, c] = self.coefficients;
        p.z - (a * p.x + b * p.y + c)
    }

    /// Where the ray `centre + s·ray` meets the plane lifted by `lift`; `None` when it does not
    /// at `s > 0`.
    pub fn meet(&self, centre: &Point3<f64>, ray: &Vector3<f64>, lift: f64) -> Option<Point3<f64>> {
        let [a, b, c] = self.coefficients;
        let rate = ray.z - a * ray.x - b * ray.y;
        let s = (a * centre.x + b * centre.y + c + lift - centre.z) / rate;
        (rate.abs() > 1e-12 && s > 0.0).then(|| centre + ray * s)
    }
}

/// The plane fitted to `points`, measured at `middle` (the workspace centre); `None` with fewer
/// than 3 points near `z = 0` or a degenerate spread.
pub fn fit_table(points: &[Point3<f64>], start: f64, middle: (f64, f64)) -> Option<TablePlane> {
    let mut plane = TablePlane::calibrated();
    let mut band = start;
    for _ in 0..4 {
        let kept: Vec<&Point3<f64>> = points
            .iter()
            .filter(|p| plane.height(p).abs() <= band)
            .collect();
        if kept.len() < 3 {
            return None;
        }
        // Normal equations of z ≈ a·x + b·y + c, centred for conditioning.
        let n = kept.len() as f64;
        let mean = kept.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / n;
        let mut normal = Matrix3::zeros();
        let mut right = Vector3::zeros();
        for p in &kept {
            let d = p.coords - mean;
            let row = Vector3::new(d.x, d.y, 1.0);
            normal += row * row.transpose();
            right += row * d.z;
        }
        let solution = normal.lu().solve(&right)?;
        let (a, b) = (solution.x, solution.y);
        let c = mean.z + solution.z - a * mean.x - b * mean.y;
        plane.coefficients = [a, b, c];
        let squares: f64 = kept.iter().map(|p| plane.height(p).powi(2)).sum();
        plane.residual = (squares / n).sqrt();
        plane.points = kept.len();
        band = (3.0 * plane.residual).max(0.002);
    }
    let [a, b, c] = plane.coefficients;
    plane.offset = a * middle.0 + b * middle.1 + c;
    plane.tilt = (a * a + b * b).sqrt().atan();
    Some(plane)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_offset_table_is_recovered_beside_objects() {
        let (a, b, c) = (0.01, -0.004, 0.003);
        let mut points = Vec::new();
        for i in 0..50 {
            for j in 0..40 {
                let (x, y) = (f64::from(i) * 0.01, f64::from(j) * 0.01);
                let lift = if i > 30 && j > 20 { 0.03 } else { 0.0 };
                points.push(Point3::new(x, y, a * x + b * y + c + lift));
            }
        }
        let plane = fit_table(&points, 0.01, (0.25, 0.2)).unwrap();
        let [fa, fb, fc] = plane.coefficients;
        assert!((fa - a).abs() < 1e-9 && (fb - b).abs() < 1e-9 && (fc - c).abs() < 1e-9);
        assert!((plane.offset - (a * 0.25 + b * 0.2 + c)).abs() < 1e-9);
    }
}
