//! The blobs of a look (`formulations/perception.md`, "Blobs"): the depth mask's components, or
//! instance labels grown into that mask, or labels alone; a label in separate pieces is marked.

use std::collections::BTreeMap;

use super::blob::{Blob, above_cut};
use super::blobs::{Mask, Window, components, grow_labels};
use super::camera::Camera;
use super::input::Frame;
use super::settings::PerceptionSettings;

/// The pixels above the cut ([`above_cut`]), without specks ([`Mask::without_specks`]), and the
/// labels of their components.
fn object_mask(heights: &[f64], camera: &Camera, cut: f64) -> (Mask, Vec<u32>) {
    let (width, height) = (
        camera.intrinsics.width as usize,
        camera.intrinsics.height as usize,
    );
    // A pixel with depth is above the cut when its height is (NaN is above nothing); only those
    // without depth look at their neighbours.
    let mut set: Vec<bool> = heights.iter().map(|&h| h > cut).collect();
    for (i, h) in heights.iter().enumerate() {
        if !h.is_finite() {
            set[i] = above_cut(heights, i, width, cut);
        }
    }
    Mask { width, height, set }.without_specks()
}

/// The pixel lists of `labels` (per pixel, 0 for none), one per distinct non-zero value, each in
/// raster order.
fn group(labels: &[u32]) -> BTreeMap<u32, Vec<usize>> {
    let mut groups: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    // Runs of one label, each added at once.
    let mut i = 0;
    while i < labels.len() {
        let label = labels[i];
        let run = labels[i..].iter().take_while(|&&l| l == label).count();
        if label != 0 {
            groups.entry(label).or_default().extend(i..i + run);
        }
        i += run;
    }
    groups
}

/// Whether `pixels` form more than one 4-connected piece of at least 10 pixels (looked at within
/// their box, where all their connections lie).
fn is_split(pixels: &[usize], width: usize) -> bool {
    if pixels.is_empty() {
        return false;
    }
    let window = Window::around(pixels, width);
    let (parts, count) = components(&window.mask());
    if count < 2 {
        return false;
    }
    let mut sizes = vec![0_usize; count as usize + 1];
    for &i in pixels {
        sizes[parts[window.local(i, width)] as usize] += 1;
    }
    sizes.iter().filter(|&&s| s >= 10).count() > 1
}

/// The blobs of a look: components of the depth mask, or labels grown into it, or labels alone.
pub fn find_blobs(
    frame: &Frame,
    heights: Option<&[f64]>,
    camera: &Camera,
    settings: &PerceptionSettings,
) -> Vec<Blob> {
    let width = camera.intrinsics.width as usize;
    let given = |label: u32| frame.heights.and_then(|h| h.get(&label).copied());
    let labelled = |label: u32, pixels: Vec<usize>, cut: f64| Blob {
        label: Some(label),
        split: is_split(&pixels, width),
        pixels,
        given_height: given(label),
        cut,
    };
    let Some(heights) = heights else {
        let labels = frame.labels.unwrap_or(&[]);
        return group(labels)
            .into_iter()
            .map(|(l, pixels)| labelled(l, pixels, 0.0))
            .collect();
    };
    let (mask, mut parts) = object_mask(heights, camera, settings.cut_height);
    let cut = settings.cut_height;
    let mut blobs = Vec::new();
    if let Some(labels) = frame.labels {
        let grown = grow_labels(&mask, labels);
        let mut rest = mask.clone();
        for (i, &l) in grown.iter().enumerate() {
            rest.set[i] = rest.set[i] && l == 0;
        }
        let groups = group(&grown);
        for (l, pixels) in group(labels) {
            match groups.get(&l) {
                Some(grown) => blobs.push(labelled(l, grown.clone(), cut)),
                // A label with nothing above the cut: its own pixels, judged as they are.
                None => blobs.push(labelled(l, pixels, 0.0)),
            }
        }
        parts = components(&rest).0;
    }
    // The mask's pixels that no label claimed, by component.
    for (_, pixels) in group(&parts) {
        blobs.push(Blob {
            label: None,
            pixels,
            given_height: None,
            cut,
            split: false,
        });
    }
    blobs
}
