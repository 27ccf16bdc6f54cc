//! A look drawn over its image, as SVG: each blob's pixel box with its status, green for objects,
//! grey for notices, red for what blocks planning, and each object's footprint as the camera sees
//! its top.

use std::fmt::Write as _;

use nalgebra::Point3;

use super::camera::Camera;
use super::report::Perception;

/// The SVG of `seen` in the image coordinates of `camera` (one unit per pixel).
pub fn overlay_svg(seen: &Perception, camera: &Camera) -> String {
    let (width, height) = (camera.intrinsics.width, camera.intrinsics.height);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"-0.5 -0.5 {width} {height}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect x=\"-0.5\" y=\"-0.5\" width=\"{width}\" height=\"{height}\" fill=\"#f4f4f4\"/>\n"
    );
    for object in &seen.objects {
        let corners: Vec<String> = object
            .world_polygon()
            .vertices()
            .iter()
            .filter_map(|v| camera.project(&Point3::new(v.x, v.y, object.height)))
            .map(|(p, _)| format!("{:.1},{:.1}", p.x, p.y))
            .collect();
        let _ = writeln!(
            svg,
            "<polygon points=\"{}\" fill=\"#2a9d4a\" fill-opacity=\"0.35\" stroke=\"#1b6e33\"/>",
            corners.join(" ")
        );
    }
    for blob in &seen.blobs {
        let [u0, v0, u1, v1] = blob.pixel_box;
        let status = serde_json::to_value(&blob.status)
            .ok()
            .and_then(|v| v.get("status").and_then(|s| s.as_str()).map(str::to_string))
            .unwrap_or_default();
        let colour = if blob.status.blocks() {
            "#d62828"
        } else if blob.id.is_some() {
            "#1b6e33"
        } else {
            "#888888"
        };
        let label = match blob.id {
            Some(id) => format!("{id} {status}"),
            None => status,
        };
        let _ = writeln!(
            svg,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"{colour}\" \
             stroke-width=\"{}\"/>\n<text x=\"{}\" y=\"{}\" fill=\"{colour}\">{label}</text>",
            u0 as f64 - 0.5,
            v0 as f64 - 0.5,
            u1 - u0 + 1,
            v1 - v0 + 1,
            if blob.status.blocks() { 2 } else { 1 },
            u0,
            v0.saturating_sub(3).max(10),
        );
    }
    svg.push_str("</svg>\n");
    svg
}
