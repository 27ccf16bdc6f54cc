//! A blob's footprint on the table by the two-plane construction (`formulations/perception.md`).
//!
//! The blob is the image of the object's part above the cut plane `z = c` (its top face at `z = h`
//! and the walls between). Its image hull, back-projected onto the top plane, is the hull of the top
//! face `P` and of `P` shrunk about the camera's nadir by `(H − h)/(H − c)`; back-projected onto the
//! cut plane it is the hull of `P` and of `P` grown by the inverse ratio. Taking the nadir as origin,
//! their support functions are `max(h_P, k·h_P)` and `max(h_P, h_P/k)` with `k < 1`, whose minimum is
//! `h_P` in every direction, so their intersection is exactly `P` for an unoccluded convex prism at
//! any camera tilt.
//!
//! The image hull is that of the blob's row extremes (pixel centres). Centres lie about half a pixel
//! inside the region they sample, and noise at the edge puts some outside it, so the hull is moved
//! by the offset δ that gives it the blob's pixel count as its area (a mitred offset has area
//! `A + P·δ + K·δ²`, `K = Σ tan(φ/2)` over the exterior angles; δ between −1.5 and 1 pixel): the
//! area-matched sub-pixel correction.
//!
//! A blob's solidity is the share of the pixels at least two pixels inside its centre hull that
//! belong to it: 1 for a convex blob whatever the noise at its edge, less where two objects leave
//! a notch between them.

use nalgebra::{Point2, Vector2};

use super::camera::Camera;
use super::sides::{agrees, area_matching_offset, column_ends, fitted_outline, row_ends};
use super::table::TablePlane;
use crate::geometry::{ConvexPolygon, clip, convex_hull, loop_area, tidy_polygon};

/// A blob's image hull, before back-projection.
#[derive(Clone, Debug)]
pub struct ImageHull {
    /// The hull's corners, pixels, counter-clockwise in `(u, v)`.
    pub corners: Vec<Point2<f64>>,
    /// The share of the pixels two or more pixels inside the centre hull that belong to the blob:
    /// 1 for a convex blob, less for a merged or bitten one.
    pub solidity: f64,
}

/// The hull of the pixels `pixels` (indices into rows of `width`), with the area-matched correction;
/// with `fit_sides`, the outline of its fitted sides where it agrees with that (`sides.rs`).
/// `None` when the pixels lie on one line.
pub fn image_hull(pixels: &[usize], width: usize, fit_sides: bool) -> Option<ImageHull> {
    let ends = row_ends(pixels, width);
    let hull = convex_hull(&ends);
    if hull.len() < 3 {
        return None;
    }
    let count = pixels.len() as f64;
    let delta = area_matching_offset(&hull, count);
    let offset_hull = offset(&hull, delta);
    // Sides fitted to the blob's boundary pixels, the median's cut tips put back; the hull itself
    // where the two disagree (`sides.rs`).
    let corners = if fit_sides {
        let mut boundary = ends;
        boundary.extend(column_ends(pixels, width));
        fitted_outline(&hull, &boundary, count)
            .filter(|fitted| agrees(fitted, &offset_hull))
            .unwrap_or(offset_hull)
    } else {
        offset_hull
    };
    Some(ImageHull {
        corners,
        solidity: solidity(pixels, width, &hull, 2.0),
    })
}

/// The solidity of `pixels` (indices into rows of `width`) as [`image_hull`] measures it, but with
/// the pixels for which `hidden` holds counted as the blob's too: those where a neighbour in front
/// hides it (`occlusion.rs`). 1 when the pixels lie on one line.
pub fn solidity_behind(pixels: &[usize], width: usize, hidden: impl Fn(usize) -> bool) -> f64 {
    let hull = convex_hull(&row_ends(pixels, width));
    if hull.len() < 3 {
        return 1.0;
    }
    solidity_with(pixels, width, &hull, 2.0, hidden)
}

/// The share of the pixel centres at least `depth` inside the counter-clockwise convex loop `hull`
/// that are among `pixels`; 1 when no centre is that deep.
fn solidity(pixels: &[usize], width: usize, hull: &[Point2<f64>], depth: f64) -> f64 {
    solidity_with(pixels, width, hull, depth, |_| false)
}

/// As [`solidity`], with the pixels for which `also` holds counted among `pixels`.
fn solidity_with(
    pixels: &[usize],
    width: usize,
    hull: &[Point2<f64>],
    depth: f64,
    also: impl Fn(usize) -> bool,
) -> f64 {
    let n = hull.len();
    let planes: Vec<(Vector2<f64>, f64)> = (0..n)
        .map(|k| {
            let edge = hull[(k + 1) % n] - hull[k];
            let normal = Vector2::new(edge.y, -edge.x) / edge.norm();
            (normal, normal.dot(&hull[k].coords) - depth)
        })
        .collect();
    let (lo, hi) = crate::geometry::point_bounds(hull);
    let window = super::blobs::Window::around(pixels, width);
    let (mut inside, mut held) = (0_usize, 0_usize);
    for v in lo.y.ceil().max(0.0) as usize..=hi.y.floor().max(0.0) as usize {
        for u in lo.x.ceil().max(0.0) as usize..=hi.x.floor().max(0.0) as usize {
            let p = Point2::new(u as f64, v as f64);
            if planes.iter().all(|(normal, d)| normal.dot(&p.coords) <= *d) {
                inside += 1;
                held += usize::from(window.holds(u as isize, v as isize) || also(v * width + u));
            }
        }
    }
    if inside == 0 {
        1.0
    } else {
        held as f64 / inside as f64
    }
}

/// The counter-clockwise convex loop `hull` with every edge moved outward by `delta`.
pub(super) fn offset(hull: &[Point2<f64>], delta: f64) -> Vec<Point2<f64>> {
    let n = hull.len();
    let normal = |k: usize| {
        let edge = hull[(k + 1) % n] - hull[k];
        Vector2::new(edge.y, -edge.x) / edge.norm()
    };
    (0..n)
        .map(|k| {
            let (before, after) = (normal((k + n - 1) % n), normal(k));
            // The corner moves along the bisector so that both edges move by `delta`.
            hull[k] + (before + after) * (delta / (1.0 + before.dot(&after)))
        })
        .collect()
}

/// The image loop `corners` back-projected onto the fitted table lifted by `lift`, as a convex
/// polygon in the table frame.
fn back_project(
    corners: &[Point2<f64>],
    camera: &Camera,
    table: &TablePlane,
    lift: f64,
) -> Option<ConvexPolygon> {
    let centre = camera.centre();
    let points: Option<Vec<Point2<f64>>> = corners
        .iter()
        .map(|c| {
            table
                .meet(&centre, &camera.ray(c.x, c.y), lift)
                .map(|p| Point2::new(p.x, p.y))
        })
        .collect();
    tidy_polygon(&points?)
}

/// The footprint of a blob whose top is `top` above the table and whose pixels are those above
/// `cut`: the intersection of the image hull back-projected onto both planes.
pub fn footprint(
    hull: &ImageHull,
    camera: &Camera,
    table: &TablePlane,
    top: f64,
    cut: f64,
) -> Option<ConvexPolygon> {
    footprint_by_edges(
        hull,
        camera,
        table,
        top,
        &vec![Some([cut, cut]); hull.corners.len()],
    )
}

/// As [`footprint`], each edge `k` of the image hull (from corner `k` to `k + 1`) back-projected
/// with its two ends on the planes `lifts[k]` above the table instead of the cut plane: the
/// heights at which the silhouette stands at those ends. Where the blob's edge shows a wall, that is
/// the cut; where a neighbour hides the wall, the top's edge or the neighbour's is the silhouette,
/// and its own height puts it back where it is (`formulations/perception.md`, "Why touching objects
/// come out small" and "Sides along a neighbour"). An edge without lifts bounds nothing. The
/// footprint is also kept within the hull back-projected onto the top plane, and onto the highest
/// lift where one stands above the top.
pub fn footprint_by_edges(
    hull: &ImageHull,
    camera: &Camera,
    table: &TablePlane,
    top: f64,
    lifts: &[Option<[f64; 2]>],
) -> Option<ConvexPolygon> {
    let corners = &hull.corners;
    let n = corners.len();
    if lifts.len() != n {
        return None;
    }
    let mut print = back_project(corners, camera, table, top)?;
    let highest = lifts
        .iter()
        .flatten()
        .flatten()
        .copied()
        .fold(top, f64::max);
    if highest > top {
        // A neighbour's top edge hides part of this top: the top plane's cast may lie inside the
        // footprint there, so the bound is the hull of both casts.
        let higher = back_project(corners, camera, table, highest)?;
        let mut both = print.vertices().to_vec();
        both.extend_from_slice(higher.vertices());
        print = tidy_polygon(&both)?;
    }
    let centre = camera.centre();
    let meet = |c: &Point2<f64>, lift: f64| {
        table
            .meet(&centre, &camera.ray(c.x, c.y), lift)
            .map(|p| Point2::new(p.x, p.y))
    };
    // The loop keeps one turning sense on every plane below the camera (each is a central
    // projection of the image): the blob lies left of each edge when the loop turns
    // counter-clockwise on the table, right of it otherwise.
    let on_top: Option<Vec<Point2<f64>>> = corners.iter().map(|c| meet(c, top)).collect();
    let left = loop_area(&on_top?) > 0.0;
    for (k, lift) in lifts.iter().enumerate() {
        let Some([from, to]) = *lift else {
            continue;
        };
        let (a, b) = (meet(&corners[k], from)?, meet(&corners[(k + 1) % n], to)?);
        let along = b - a;
        if along.norm() < 1e-12 {
            continue;
        }
        // Outward: to the right of the edge for a counter-clockwise loop.
        let right = Vector2::new(along.y, -along.x).normalize();
        let normal = if left { right } else { -right };
        print = tidy_polygon(&clip(print.vertices(), &normal, normal.dot(&a.coords)))?;
    }
    Some(print)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::cross;
    use crate::perception::camera::Camera;

    fn turns_left(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> bool {
        cross(&(b - a), &(c - a)) > 0.0
    }

    #[test]
    fn the_offset_moves_each_edge_of_a_square_by_delta() {
        let square = [
            Point2::new(0.0, 0.0),
            Point2::new(2.0, 0.0),
            Point2::new(2.0, 2.0),
            Point2::new(0.0, 2.0),
        ];
        assert!(turns_left(&square[0], &square[1], &square[2]));
        let grown = offset(&square, 0.5);
        assert!((loop_area(&grown) - 9.0).abs() < 1e-12);
        assert!((grown[0] - Point2::new(-0.5, -0.5)).norm() < 1e-12);
    }

    #[test]
    fn a_filled_square_of_pixels_has_its_own_area_and_full_solidity() {
        let width = 20;
        let pixels: Vec<usize> = (5..15)
            .flat_map(|v| (3..13).map(move |u| v * width + u))
            .collect();
        let hull = image_hull(&pixels, width, false).unwrap();
        // 100 pixels: the centre hull is 9 × 9, grown by half a pixel it is 10 × 10.
        assert!((loop_area(&hull.corners) - 100.0).abs() < 1e-9);
        assert!((hull.solidity - 1.0).abs() < 1e-9);
    }

    /// The two-plane theorem: the exact image hull of a convex prism's part above the cut,
    /// back-projected onto the top and the cut planes, meets in the top face itself, for random
    /// prisms and cameras up to 40° from straight down.
    #[test]
    fn the_two_planes_give_the_footprint_exactly() {
        use crate::geometry::point_distance;
        use crate::random::SeededRng;
        use nalgebra::Point3;
        let mut rng = SeededRng::new(2);
        for trial in 0..300 {
            let centre = Point2::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
            let points: Vec<Point2<f64>> = (0..3 + rng.index(8))
                .map(|_| {
                    let (r, a) = (
                        rng.uniform(0.005, 0.06),
                        rng.uniform(0.0, std::f64::consts::TAU),
                    );
                    centre + Vector2::new(a.cos(), a.sin()) * r
                })
                .collect();
            let Some(top) = tidy_polygon(&points) else {
                continue;
            };
            let height = rng.uniform(0.005, 0.15);
            let cut = rng.uniform(0.05, 0.95) * height;
            let camera = Camera::looking_down(
                640,
                480,
                1.2,
                rng.uniform(-0.2, 0.2),
                rng.uniform(-0.2, 0.2),
                rng.uniform(0.4, 1.2),
            )
            .tilted(rng.uniform(-0.7, 0.7));
            let seen: Vec<Point2<f64>> = top
                .vertices()
                .iter()
                .flat_map(|v| [height, cut].map(|z| Point3::new(v.x, v.y, z)))
                .map(|p| camera.project(&p).expect("in front of the camera").0)
                .collect();
            let hull = ImageHull {
                corners: convex_hull(&seen),
                solidity: 1.0,
            };
            let table = TablePlane::calibrated();
            let print = footprint(&hull, &camera, &table, height, cut).expect("a footprint");
            for v in print.vertices() {
                assert!(
                    point_distance(&top, v) < 1e-9,
                    "trial {trial}: {v} is off the top face"
                );
            }
            for v in top.vertices() {
                assert!(
                    point_distance(&print, v) < 1e-9,
                    "trial {trial}: corner {v} is missing"
                );
            }
        }
    }
}
