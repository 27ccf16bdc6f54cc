//! `perceive`: a depth image (and labels) from files to a scene file, a report and an overlay.

use std::collections::BTreeMap;
use std::path::Path;

use pushmog::error::{Error, Result};
use pushmog::json::{self, to_json};
use pushmog::perception::{
    Camera, Frame, Identify, Npy, NpyData, PerceptionSettings, overlay_svg, perceive as look,
    read_npy,
};
use pushmog::scene::{Gripper, ObjectSet, Scene, Workspace, builtin_object_set};

use crate::PerceiveArgs;

use super::io::{read_scene, settings_or_default, write_output};

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Reads a `.npy` array or a grey-scale `.png` (8 or 16 bits).
fn read_image(path: &Path) -> Result<Npy> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    if bytes.starts_with(b"\x93NUMPY") {
        return read_npy(&bytes, &name);
    }
    let bad = |reason: String| Error::field(name.clone(), "png", reason);
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder
        .read_info()
        .map_err(|e| bad(format!("neither a .npy nor a readable PNG file: {e}")))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| bad("the image is too large".into()))?;
    let mut buffer = vec![0; size];
    let frame = reader
        .next_frame(&mut buffer)
        .map_err(|e| bad(e.to_string()))?;
    if frame.color_type != png::ColorType::Grayscale {
        return Err(bad(format!(
            "a depth or label image must be one grey channel, this is {:?}",
            frame.color_type
        )));
    }
    let (rows, columns) = (frame.height as usize, frame.width as usize);
    let data = &buffer[..frame.buffer_size()];
    let data = match frame.bit_depth {
        png::BitDepth::Sixteen => NpyData::Unsigned16(
            data.chunks_exact(2)
                .map(|b| u16::from_be_bytes([b[0], b[1]]))
                .collect(),
        ),
        png::BitDepth::Eight => NpyData::Integer(data.iter().map(|&b| u32::from(b)).collect()),
        depth => return Err(bad(format!("{depth:?}-bit grey is not read: 8 or 16 bits"))),
    };
    Ok(Npy {
        rows,
        columns,
        data,
    })
}

/// The image at `path` (if given), refused unless its size is the camera's; `flag` names it.
fn read_for(path: Option<&Path>, camera: &Camera, flag: &str) -> Result<Option<Npy>> {
    let Some(path) = path else { return Ok(None) };
    let image = read_image(path)?;
    let k = &camera.intrinsics;
    if (image.rows, image.columns) != (k.height as usize, k.width as usize) {
        return Err(Error::field(
            "perceive",
            flag,
            format!(
                "the image is {} wide and {} high, the camera's {} and {}",
                image.columns, image.rows, k.width, k.height
            ),
        ));
    }
    Ok(Some(image))
}

/// An object set from a JSON file, or the built-in one for `builtin`.
pub(crate) fn read_library(path: &Path) -> Result<ObjectSet> {
    if path == Path::new("builtin") {
        return Ok(builtin_object_set());
    }
    let set: ObjectSet = json::from_json(&json::read_text(path)?, &path.display().to_string())?;
    set.validate()?;
    Ok(set)
}

/// The camera from a TOML file (or JSON, by its extension).
pub(crate) fn read_camera(path: &Path) -> Result<Camera> {
    let name = path.display().to_string();
    let text = json::read_text(path)?;
    let camera: Camera = if path.extension().is_some_and(|e| e == "json") {
        json::from_json(&text, &name)?
    } else {
        toml::from_str(&text).map_err(|e| Error::field(name, "toml", e.to_string()))?
    };
    camera.validate()?;
    Ok(camera)
}

pub fn perceive(args: &PerceiveArgs) -> Result<()> {
    let camera = read_camera(&args.camera)?;
    let settings: PerceptionSettings = settings_or_default(args.settings.as_deref())?;
    let prior: Option<Scene> = args.prior.as_deref().map(read_scene).transpose()?;
    let state: Option<Scene> = args.state.as_deref().map(read_scene).transpose()?;
    let (workspace, gripper) = match state.as_ref().or(prior.as_ref()) {
        Some(s) => (s.workspace().clone(), s.gripper().clone()),
        None => (Workspace::default(), Gripper::default()),
    };
    let depth = read_for(args.depth.as_deref(), &camera, "--depth")?;
    let labels = read_for(args.labels.as_deref(), &camera, "--labels")?;
    let label_values = labels
        .as_ref()
        .map(|l| l.labels("perceive", "--labels"))
        .transpose()?;
    let heights: Option<BTreeMap<u32, f64>> = match args.heights.as_deref() {
        Some(path) => Some(json::from_json(
            &json::read_text(path)?,
            &path.display().to_string(),
        )?),
        None => None,
    };
    let frame = Frame {
        depth: depth
            .as_ref()
            .map(|d| d.depth("perceive", "--depth"))
            .transpose()?,
        labels: label_values.as_deref(),
        heights: heights.as_ref(),
    };
    let mut seen = look(
        &frame,
        &camera,
        &workspace,
        &gripper,
        prior.as_ref(),
        &settings,
    )?;
    if let Some(path) = args.library.as_deref() {
        seen.name_from(&read_library(path)?, &Identify::default())?;
    }
    if let Some(path) = &args.report {
        json::write_text(path, &to_json(&seen.report()))?;
    }
    if let Some(path) = &args.overlay {
        json::write_text(path, &overlay_svg(&seen, &camera))?;
    }
    eprintln!(
        "{} objects, {} blobs, {} blocking, {} of the prior's objects gone",
        seen.objects.len(),
        seen.blobs.len(),
        seen.blocking().len(),
        seen.gone.len()
    );
    let scene = seen.scene()?;
    write_output(args.output.as_deref(), &to_json(&scene))
}
