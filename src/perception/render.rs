//! Exact depth images of a scene: each pixel's ray cast against the table plane `z = 0` and every
//! object's prism `{(x, y) ∈ P, 0 ≤ z ≤ h}`, upright or moved as a rigid body (a toppled prism in
//! the simulator). Test support, and the simulator's camera.
//!
//! A convex solid is the intersection of half-spaces `n·p ≤ d` (for an upright prism: its edges'
//! half-planes and the slab `0 ≤ z ≤ h`), so the ray `c + s·r` lies in it for `s` in the
//! intersection of one interval per half-space, `(n·r)·s ≤ d − n·c` (Kay and Kajiya's slabs); the
//! first `s` of that interval is the depth, because `r` is scaled to unit camera `z`.

use nalgebra::{Point3, Vector3};

use super::camera::Camera;
use crate::error::Result;
use crate::geometry::{ConvexPolygon, half_planes};
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

/// A convex solid to render: the half-spaces `n·p ≤ d` whose intersection it is (table frame,
/// metres) and its corners, which bound its image.
#[derive(Clone, Debug)]
pub struct Solid {
    /// The object it is.
    pub id: ObjectId,
    /// Outward normals `n` and offsets `d` of its faces' planes.
    pub planes: Vec<(Vector3<f64>, f64)>,
    /// Its corners.
    pub corners: Vec<Point3<f64>>,
}

impl Solid {
    /// The upright prism `{(x, y) ∈ outline, 0 ≤ z ≤ height}` (an outline in the table frame).
    pub fn prism(id: ObjectId, outline: &ConvexPolygon, height: f64) -> Self {
        let mut planes = vec![(Vector3::z(), height), (-Vector3::z(), 0.0)];
        planes.extend(
            half_planes(outline)
                .into_iter()
                .map(|(n, d)| (Vector3::new(n.x, n.y, 0.0), d)),
        );
        let corners = outline
            .vertices()
            .iter()
            .flat_map(|v| [0.0, height].map(|z| Point3::new(v.x, v.y, z)))
            .collect();
        Self {
            id,
            planes,
            corners,
        }
    }

    /// The prism of `outline` (in its own frame, `0 ≤ z ≤ height`) carried by the rigid motion
    /// `p ↦ rotation·p + translation`: a plane `n·q ≤ d` of the own frame becomes
    /// `(R n)·p ≤ d + (R n)·t`.
    pub fn moved_prism(
        id: ObjectId,
        outline: &ConvexPolygon,
        height: f64,
        rotation: &nalgebra::Rotation3<f64>,
        translation: &Vector3<f64>,
    ) -> Self {
        let own = Self::prism(id, outline, height);
        Self {
            id,
            planes: own
                .planes
                .iter()
                .map(|(n, d)| {
                    let normal = rotation * n;
                    (normal, d + normal.dot(translation))
                })
                .collect(),
            corners: own
                .corners
                .iter()
                .map(|c| rotation * c + translation)
                .collect(),
        }
    }
}

/// Where the ray `centre + s·ray` enters the solid of `planes`, if it does at `s > 0`.
fn enters(centre: &Point3<f64>, ray: &Vector3<f64>, planes: &[(Vector3<f64>, f64)]) -> Option<f64> {
    let (mut low, mut high) = (0.0_f64, f64::INFINITY);
    for (normal, d) in planes {
        // rate·s ≤ room
        let rate = normal.x * ray.x + normal.y * ray.y + normal.z * ray.z;
        let room = d - normal.x * centre.x - normal.y * centre.y - normal.z * centre.z;
        if rate.abs() < 1e-15 {
            if room < 0.0 {
                high = -1.0;
            }
        } else if rate > 0.0 {
            high = high.min(room / rate);
        } else {
            low = low.max(room / rate);
        }
    }
    (low <= high && low > 0.0).then_some(low)
}

/// The depth and labels `camera` sees of `scene`, exactly.
///
/// # Errors
/// An invalid camera.
pub fn render_depth(scene: &Scene, camera: &Camera) -> Result<Rendered> {
    let solids: Vec<Solid> = scene
        .objects()
        .iter()
        .enumerate()
        .map(|(k, object)| Solid::prism(object.id, scene.world_polygon(k), object.height))
        .collect();
    render_solids(&solids, camera)
}

/// The depth and labels `camera` sees of convex `solids` standing on the table plane `z = 0`,
/// exactly; label `k + 1` is `solids[k]`.
///
/// # Errors
/// An invalid camera.
pub fn render_solids(solids: &[Solid], camera: &Camera) -> Result<Rendered> {
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
    for (k, solid) in solids.iter().enumerate() {
        // The image box of the solid's corners bounds the pixels whose rays can meet it.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for corner in &solid.corners {
            if let Some((pixel, _)) = camera.project(corner) {
                lo = [lo[0].min(pixel.x), lo[1].min(pixel.y)];
                hi = [hi[0].max(pixel.x), hi[1].max(pixel.y)];
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
                if let Some(s) = enters(&centre, &rays[i], &solid.planes)
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
        ids: solids.iter().map(|s| s.id).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point2, Rotation3, Vector2};

    fn camera() -> Camera {
        Camera::looking_down(200, 160, 2.0 * (100.0_f64 / 700.0).atan(), 0.1, 0.08, 0.7)
    }

    #[test]
    fn a_prism_turned_about_z_and_moved_renders_as_its_outline_placed_upright() {
        let own = ConvexPolygon::new(vec![
            Point2::new(-0.02, -0.01),
            Point2::new(0.025, -0.015),
            Point2::new(0.01, 0.02),
        ])
        .unwrap();
        let (yaw, at) = (0.7, Vector3::new(0.11, 0.07, 0.0));
        let placed = own.transformed(&nalgebra::Isometry2::new(Vector2::new(at.x, at.y), yaw));
        let upright =
            render_solids(&[Solid::prism(ObjectId(3), &placed, 0.03)], &camera()).unwrap();
        let rotation = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw);
        let moved = Solid::moved_prism(ObjectId(3), &own, 0.03, &rotation, &at);
        let turned = render_solids(&[moved], &camera()).unwrap();
        let seen = upright.labels.iter().filter(|&&l| l == 1).count();
        assert!(seen > 500, "{seen} pixels");
        for (a, b) in upright.depth.iter().zip(&turned.depth) {
            assert!(
                (a - b).abs() < 1e-6 || (a.is_nan() && b.is_nan()),
                "{a} {b}"
            );
        }
    }

    #[test]
    fn a_box_lying_on_its_side_shows_its_width_as_its_height() {
        // 40 × 20 mm box 30 mm tall, turned a quarter about x: its own y becomes z, so it lies 20 mm
        // tall and 30 mm deep, resting on the table when lifted by half its own y extent.
        let own = ConvexPolygon::rectangle(&Point2::origin(), &Vector2::x(), 0.02, 0.01);
        let rotation = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        let solid = Solid::moved_prism(
            ObjectId(0),
            &own,
            0.03,
            &rotation,
            &Vector3::new(0.1, 0.08, 0.01),
        );
        let lowest = solid
            .corners
            .iter()
            .map(|c| c.z)
            .fold(f64::INFINITY, f64::min);
        assert!(lowest.abs() < 1e-12, "{lowest}");
        let rendered = render_solids(&[solid], &camera()).unwrap();
        // The ray through the pixel above (0.1, 0.065), inside the box's top face, meets it at z = 0.02.
        let camera = camera();
        let (pixel, _) = camera.project(&Point3::new(0.1, 0.065, 0.02)).unwrap();
        let i = pixel.y.round() as usize * 200 + pixel.x.round() as usize;
        assert_eq!(rendered.labels[i], 1);
        assert!(
            (f64::from(rendered.depth[i]) - 0.68).abs() < 1e-6,
            "{}",
            rendered.depth[i]
        );
    }
}
