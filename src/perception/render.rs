//! Exact depth images of a scene: each pixel's ray cast against the table plane `z = 0` and every
//! object's prism `{(x, y) ∈ P, 0 ≤ z ≤ h}`. Test support, and the simulator's camera.
//!
//! A prism is the intersection of its edges' half-planes and the slab `0 ≤ z ≤ h`, so the ray
//! `c + s·r` lies in it for `s` in the intersection of one interval per half-plane (Kay and Kajiya's
//! slabs); the first `s` of that interval is the depth, because `r` is scaled to unit camera `z`.

use nalgebra::{Point3, Vector3};

use super::camera::Camera;
use crate::error::Result;
use crate::geometry::half_planes;
use crate::id::ObjectId;
use crate::scene::Scene;

/// A rendered frame: depth in metres (NaN where the ray meets nothing) and, per pixel, `k + 1` for
/// the `k`-th object of `ids` that it sees, 0 for the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Rendered {
    /// Row-major depth, metres (camera `z`).
    pub depth: Vec<f32>,
    /// Row-major labels: 0 for the table or nothing, `k + 1` for `ids[k]`.
    pub labels: Vec<u32>,
    /// The object each label names.
    pub ids: Vec<ObjectId>,
}

/// Where the ray `centre + s·ray` enters the prism of `planes` and `height`, if it does at `s > 0`.
fn enters(
    centre: &Point3<f64>,
    ray: &Vector3<f64>,
    planes: &[(nalgebra::Vector2<f64>, f64)],
    height: f64,
) -> Option<f64> {
    let (mut low, mut high) = (0.0_f64, f64::INFINITY);
    let mut slab = |rate: f64, room: f64| {
        // rate·s ≤ room
        if rate.abs() < 1e-15 {
            if room < 0.0 {
                high = -1.0;
            }
        } else if rate > 0.0 {
            high = high.min(room / rate);
        } else {
            low = low.max(room / rate);
        }
    };
    slab(ray.z, height - centre.z);
    slab(-ray.z, centre.z);
    for (normal, d) in planes {
        slab(
            normal.x * ray.x + normal.y * ray.y,
            d - normal.x * centre.x - normal.y * centre.y,
        );
    }
    (low <= high && low > 0.0).then_some(low)
}

/// The depth and labels `camera` sees of `scene`, exactly.
///
/// # Errors
/// An invalid camera.
pub fn render_depth(scene: &Scene, camera: &Camera) -> Result<Rendered> {
    camera.validate()?;
    let (width, height) = (
        camera.intrinsics.width as usize,
        camera.intrinsics.height as usize,
    );
    let centre = camera.centre();
    let mut depth = vec![f32::NAN; width * height];
    let mut labels = vec![0_u32; width * height];
    let mut best = vec![f64::INFINITY; width * height];
    let rays = camera.rays();
    for (b, ray) in best.iter_mut().zip(&rays) {
        if ray.z < 0.0 {
            *b = -centre.z / ray.z;
        }
    }
    for (k, object) in scene.objects().iter().enumerate() {
        let outline = scene.world_polygon(k);
        let planes = half_planes(outline);
        // The image box of the prism's corners bounds the pixels whose rays can meet it.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for vertex in outline.vertices() {
            for z in [0.0, object.height] {
                if let Some((pixel, _)) = camera.project(&Point3::new(vertex.x, vertex.y, z)) {
                    lo = [lo[0].min(pixel.x), lo[1].min(pixel.y)];
                    hi = [hi[0].max(pixel.x), hi[1].max(pixel.y)];
                }
            }
        }
        let range = |low: f64, high: f64, size: usize| {
            let first = (low.floor() - 1.0).max(0.0) as usize;
            let last = ((high.ceil() + 1.0).max(0.0) as usize).min(size.saturating_sub(1));
            first..=last
        };
        if lo[0] > hi[0] {
            continue;
        }
        for v in range(lo[1], hi[1], height) {
            for u in range(lo[0], hi[0], width) {
                let i = v * width + u;
                if let Some(s) = enters(&centre, &rays[i], &planes, object.height)
                    && s < best[i]
                {
                    best[i] = s;
                    labels[i] = k as u32 + 1;
                }
            }
        }
    }
    for (d, b) in depth.iter_mut().zip(&best) {
        if b.is_finite() {
            *d = *b as f32;
        }
    }
    Ok(Rendered {
        depth,
        labels,
        ids: scene.objects().iter().map(|o| o.id).collect(),
    })
}
