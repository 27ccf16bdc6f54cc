//! A frame's input checked and turned into metres: sizes, the 16-bit depth scale, the workspace in
//! view. Every error names its field.

use std::collections::BTreeMap;

use nalgebra::Point3;

use super::camera::{Camera, KNOWN_SCALES};
use crate::error::{Error, Result};
use crate::scene::Workspace;

/// Depth as the camera gives it.
#[derive(Clone, Copy, Debug)]
pub enum Depth<'a> {
    /// Row-major camera `z`, metres; 0, negative or non-finite for no return.
    Metres(&'a [f32]),
    /// Row-major camera `z` in units of the camera's `depth.scale`; 0 for no return.
    Units(&'a [u16]),
}

/// One look: depth, instance labels, or both.
#[derive(Clone, Copy, Debug, Default)]
pub struct Frame<'a> {
    /// The depth image, if any.
    pub depth: Option<Depth<'a>>,
    /// Row-major instance labels, 0 for none, if any.
    pub labels: Option<&'a [u32]>,
    /// The top height of each label's object above the table, metres, for labels without depth.
    pub heights: Option<&'a BTreeMap<u32, f64>>,
}

/// The depth in metres, NaN where there is none; `None` without depth.
pub fn depth_in_metres(frame: &Frame, camera: &Camera) -> Result<Option<Vec<f64>>> {
    let pixels = camera.intrinsics.width as usize * camera.intrinsics.height as usize;
    let size_error = |field: &str, len: usize| {
        Error::field(
            "frame",
            field,
            format!(
                "has {len} values, but the camera's image is {}×{} = {pixels} pixels",
                camera.intrinsics.width, camera.intrinsics.height
            ),
        )
    };
    if let Some(labels) = frame.labels
        && labels.len() != pixels
    {
        return Err(size_error("labels", labels.len()));
    }
    let depth: Vec<f64> = match frame.depth {
        None => return Ok(None),
        Some(Depth::Metres(values)) => {
            if values.len() != pixels {
                return Err(size_error("depth", values.len()));
            }
            values
                .iter()
                .map(|&z| {
                    if z.is_finite() && z > 0.0 {
                        f64::from(z)
                    } else {
                        f64::NAN
                    }
                })
                .collect()
        }
        Some(Depth::Units(values)) => {
            if values.len() != pixels {
                return Err(size_error("depth", values.len()));
            }
            let Some(scale) = camera.depth.scale else {
                return Err(Error::field(
                    "camera",
                    "depth.scale",
                    "a 16-bit depth image needs the camera's depth scale in metres per unit \
                     (0.001 for a RealSense D400, 0.00025 for an L515, 0.0001 for a D405)",
                ));
            };
            let depth: Vec<f64> = values
                .iter()
                .map(|&z| {
                    if z == 0 {
                        f64::NAN
                    } else {
                        f64::from(z) * scale
                    }
                })
                .collect();
            check_scale(&depth, camera, scale)?;
            depth
        }
    };
    Ok(Some(depth))
}

/// The depth the calibration expects at the principal point: where its ray meets `z = 0`.
fn expected_depth(camera: &Camera) -> f64 {
    let k = &camera.intrinsics;
    let ray = camera.ray(k.cx, k.cy);
    -camera.extrinsics.translation[2] / ray.z
}

/// Refuses a scale that puts the median depth more than 25 % from what the calibration expects,
/// naming the model whose unit would fit.
fn check_scale(depth: &[f64], camera: &Camera, scale: f64) -> Result<()> {
    let mut valid: Vec<f64> = depth.iter().copied().filter(|z| z.is_finite()).collect();
    if valid.is_empty() {
        return Ok(());
    }
    let middle = valid.len() / 2;
    let median = *valid.select_nth_unstable_by(middle, f64::total_cmp).1;
    let expected = expected_depth(camera);
    let ratio = median / expected;
    if (0.75..=1.25).contains(&ratio) {
        return Ok(());
    }
    let raw_median = median / scale;
    let likely = KNOWN_SCALES
        .iter()
        .min_by(|a, b| {
            let off = |s: f64| (raw_median * s / expected).ln().abs();
            off(a.1).total_cmp(&off(b.1))
        })
        .map(|(model, s)| {
            format!(
                "; a scale of {s} ({model}) would give {:.3} m",
                raw_median * s
            )
        })
        .unwrap_or_default();
    Err(Error::field(
        "camera",
        "depth.scale",
        format!(
            "{scale} m per unit puts the median depth at {median:.3} m, but the camera stands \
             {expected:.3} m from the table along its axis{likely}"
        ),
    ))
}

/// Refuses a workspace whose corners the camera does not see.
pub fn check_workspace_in_view(camera: &Camera, workspace: &Workspace) -> Result<()> {
    let (lo, hi) = (workspace.min, workspace.max);
    let k = &camera.intrinsics;
    for corner in [
        [lo[0], lo[1]],
        [hi[0], lo[1]],
        [hi[0], hi[1]],
        [lo[0], hi[1]],
    ] {
        let seen = camera.project(&Point3::new(corner[0], corner[1], 0.0));
        let inside = seen.is_some_and(|(p, _)| {
            p.x >= -0.5
                && p.y >= -0.5
                && p.x <= f64::from(k.width) - 0.5
                && p.y <= f64::from(k.height) - 0.5
        });
        if !inside {
            let at = seen.map_or("behind the camera".to_string(), |(p, _)| {
                format!("at pixel ({:.1}, {:.1})", p.x, p.y)
            });
            return Err(Error::field(
                "workspace",
                "min/max",
                format!(
                    "the corner ({}, {}) m is outside the camera's {}×{} image ({at}); the camera \
                     must see the whole workspace",
                    corner[0], corner[1], k.width, k.height
                ),
            ));
        }
    }
    Ok(())
}
