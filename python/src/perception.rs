//! Perception across the boundary: images cross as little-endian bytes with their sizes (the Python
//! half makes them from numpy arrays), the camera, settings and reports as JSON.

use std::collections::BTreeMap;

use pushmog::json::{self, to_json};
use pushmog::perception::{
    Camera, Depth, DepthNoise, Frame, Identify, PerceptionSettings, add_noise, perceive as look,
    render_depth,
};
use pushmog::random::SeededRng;
use pushmog::scene::{ObjectSet, builtin_object_set};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::{Scene, check, check_settings};

/// Little-endian bytes as `f32`, `u16` or `u32` values, refused when their count is not `pixels`.
fn values<T, const N: usize>(
    bytes: &[u8],
    pixels: usize,
    what: &str,
    from: fn([u8; N]) -> T,
) -> PyResult<Vec<T>> {
    if bytes.len() != pixels * N {
        return Err(crate::settings_error(format!(
            "{what} has {} bytes, the camera's image needs {pixels} values of {N} bytes",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(N)
        .map(|c| from(c.try_into().expect("chunks of N bytes")))
        .collect())
}

/// One look (`pushmog::perception::perceive`): depth as `float32` metres (`depth_kind = "f32"`) or
/// `uint16` units (`"u16"`), labels as `uint32`, heights per label as JSON. With `library` (an
/// object set as JSON, or `"builtin"`) objects seen without a prior are named from it
/// (`Perception::name_from`). Returns the report as JSON, the objects as a scene when no blob
/// blocks planning, and otherwise the reason.
#[pyfunction]
#[pyo3(signature = (camera, depth, depth_kind, labels, heights, state, prior, settings, library = None))]
#[allow(clippy::too_many_arguments)]
pub fn perceive(
    py: Python<'_>,
    camera: &str,
    depth: Option<&[u8]>,
    depth_kind: &str,
    labels: Option<&[u8]>,
    heights: Option<&str>,
    state: &Scene,
    prior: Option<&Scene>,
    settings: Option<&str>,
    library: Option<&str>,
) -> PyResult<(String, Option<Scene>, Option<String>)> {
    let library: Option<ObjectSet> = match library {
        Some("builtin") => Some(builtin_object_set()),
        Some(text) => {
            let set: ObjectSet = check_settings(json::from_json(text, "library"))?;
            check_settings(set.validate())?;
            Some(set)
        }
        None => None,
    };
    let camera: Camera = check_settings(json::from_json(camera, "camera"))?;
    let settings: PerceptionSettings = match settings {
        Some(text) => check_settings(json::from_json(text, "settings"))?,
        None => PerceptionSettings::default(),
    };
    let heights: Option<BTreeMap<u32, f64>> = heights
        .map(|text| check_settings(json::from_json(text, "heights")))
        .transpose()?;
    let pixels = camera.intrinsics.width as usize * camera.intrinsics.height as usize;
    let metres = match (depth, depth_kind) {
        (Some(bytes), "f32") => Some(values(bytes, pixels, "depth", f32::from_le_bytes)?),
        _ => None,
    };
    let units = match (depth, depth_kind) {
        (Some(bytes), "u16") => Some(values(bytes, pixels, "depth", u16::from_le_bytes)?),
        _ => None,
    };
    let labels = labels
        .map(|bytes| values(bytes, pixels, "labels", u32::from_le_bytes))
        .transpose()?;
    let frame = Frame {
        depth: match (&metres, &units) {
            (Some(m), _) => Some(Depth::Metres(m)),
            (None, Some(u)) => Some(Depth::Units(u)),
            (None, None) => None,
        },
        labels: labels.as_deref(),
        heights: heights.as_ref(),
    };
    let (workspace, gripper) = (state.scene.workspace(), state.scene.gripper());
    let prior = prior.map(|p| &p.scene);
    let seen = py.detach(|| {
        let mut seen = look(&frame, &camera, workspace, gripper, prior, &settings)?;
        if let Some(set) = &library {
            seen.name_from(set, &Identify::default())?;
        }
        Ok::<_, pushmog::Error>(seen)
    });
    // Every error of a look is one of its inputs: the camera, an image, the settings, the set.
    let seen = check_settings(seen)?;
    let report = to_json(&seen.report());
    Ok(match seen.scene() {
        Ok(scene) => (report, Some(Scene { scene }), None),
        Err(error) => (report, None, Some(error.to_string())),
    })
}

/// The exact depth (`float32` metres, NaN for nothing) and labels (`uint32`, `k + 1` for the `k`-th
/// of the returned ids) `camera` sees of `scene`, with the test noise when `noise` (JSON, `{}` for
/// the defaults) is given, drawn from `seed`.
#[pyfunction]
#[pyo3(signature = (scene, camera, noise = None, seed = 0))]
pub fn render<'py>(
    py: Python<'py>,
    scene: &Scene,
    camera: &str,
    noise: Option<&str>,
    seed: u64,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, Vec<u32>)> {
    let camera: Camera = check_settings(json::from_json(camera, "camera"))?;
    let noise: Option<DepthNoise> = noise
        .map(|text| check_settings(json::from_json(text, "noise")))
        .transpose()?;
    let rendered = check(py.detach(|| render_depth(&scene.scene, &camera)))?;
    let width = camera.intrinsics.width as usize;
    let depth = match noise {
        Some(noise) => add_noise(&rendered.depth, width, &noise, &mut SeededRng::new(seed)),
        None => rendered.depth,
    };
    let depth: Vec<u8> = depth.iter().flat_map(|v| v.to_le_bytes()).collect();
    let labels: Vec<u8> = rendered
        .labels
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    Ok((
        PyBytes::new(py, &depth),
        PyBytes::new(py, &labels),
        rendered.ids.iter().map(|id| id.0).collect(),
    ))
}
