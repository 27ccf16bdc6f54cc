//! One blob judged: its top height, whether it is stacked, its footprint, and the status that the
//! checks give it before tracking (`formulations/perception.md`, "Statuses").

use nalgebra::Point2;

use super::blobs::four_neighbours;
use super::camera::Camera;
use super::footprint::{footprint, footprint_by_edges, image_hull, solidity_behind};
use super::occlusion::{Band, Neighbours, end_lifts, hidden_sides};
use super::report::{BlobStatus, PastEdge};
use super::settings::PerceptionSettings;
use super::table::TablePlane;
use crate::geometry::ConvexPolygon;
use crate::scene::{Object, ObjectId, Pose, Workspace};

/// A blob's pixels and where its top height comes from.
pub struct Blob {
    /// The label it came from, if any.
    pub label: Option<u32>,
    /// Its pixel indices.
    pub pixels: Vec<usize>,
    /// The height given for its label, if any.
    pub given_height: Option<f64>,
    /// The plane its pixels were cut at: the cut height for blobs from depth, 0 for labels alone.
    pub cut: f64,
    /// Whether one label covers separate pieces.
    pub split: bool,
}

/// What judging a blob found.
pub struct Judged {
    /// `[u_min, v_min, u_max, v_max]`.
    pub pixel_box: [usize; 4],
    /// The top height, if known.
    pub top: Option<f64>,
    /// The image hull's solidity.
    pub solidity: f64,
    /// The footprint, if one was found.
    pub footprint: Option<ConvexPolygon>,
    /// The status before tracking and overlaps.
    pub status: BlobStatus,
    /// Whether the blob is outside the workspace or over its edge and would be an object
    /// otherwise: whole in view, in one piece, one plateau, of an object's size and convex.
    pub past_edge: bool,
    /// The blobs that stand in front of it in the image ([`hidden_sides`]), by index.
    pub hidden_by: Vec<usize>,
}

/// The largest count of `sorted` values within a window `width` wide, and that window's median.
fn plateau(sorted: &[f64], width: f64) -> (usize, f64) {
    let (mut best, mut at) = (0, (0, 0));
    let mut end = 0;
    for start in 0..sorted.len() {
        while end < sorted.len() && sorted[end] <= sorted[start] + width {
            end += 1;
        }
        if end - start > best {
            best = end - start;
            at = (start, end);
        }
    }
    (
        best,
        sorted.get((at.0 + at.1) / 2).copied().unwrap_or(f64::NAN),
    )
}

/// The top height and, for a stacked blob, the second plateau's.
///
/// The most populated 5 mm band of heights is one plateau; the most populated band at least
/// `stacked_step` away from it, above or below, is a second one when it holds `stacked_fraction` of
/// the pixels. Walls spread their pixels over every height and make no plateau. The top is the
/// higher plateau.
fn top_height(heights: &[f64], settings: &PerceptionSettings) -> (f64, Option<f64>) {
    let mut sorted: Vec<f64> = heights.to_vec();
    sorted.sort_by(f64::total_cmp);
    let band = 0.005;
    let (_, first) = plateau(&sorted, band);
    let others: Vec<f64> = sorted
        .iter()
        .copied()
        .filter(|&h| (h - first).abs() > settings.stacked_step && h > settings.cut_height + band)
        .collect();
    let (count, second) = plateau(&others, band);
    if (count as f64) < settings.stacked_fraction * sorted.len() as f64 || count == 0 {
        return (first, None);
    }
    (first.max(second), Some(first.min(second)))
}

/// Whether pixel `i` is above `cut`: its height is, or it has none and three of its four
/// neighbours are (a pixel without depth inside a face, not one on a wall below the cut).
pub fn above_cut(heights: &[f64], i: usize, width: usize, cut: f64) -> bool {
    if heights[i].is_finite() {
        return heights[i] > cut;
    }
    four_neighbours(i, width, heights.len() / width)
        .filter(|&j| heights[j] > cut)
        .count()
        >= 3
}

/// The 3×3 median of `pixels` in an image `width` × `height`: every pixel, of the blob or next to
/// it, whose window holds at least 5 of the blob's 9. A pixel at an edge whose depth noise put it on
/// the wrong side of the cut is outvoted by its neighbours, on either side of the edge alike, so the
/// edge stays where it was.
fn majority(pixels: &[usize], width: usize, height: usize) -> Vec<usize> {
    let (w, h) = (width as isize, height as isize);
    super::blobs::Window::around(pixels, width)
        .median()
        .into_iter()
        .filter(|&(u, v)| u >= 0 && v >= 0 && u < w && v < h)
        .map(|(u, v)| (v * w + u) as usize)
        .collect()
}

/// The image outline fitted to the pixels on both sides of the edge of a blob whose pixels above
/// its cut are `above` (`fit.rs`), from the median hull's corners `corners`, where it agrees with
/// them ([`super::sides::agrees`]); `None` otherwise.
fn fitted_outline(
    corners: &[Point2<f64>],
    above: &[usize],
    heights: &[f64],
    size: (usize, usize),
) -> Option<Vec<Point2<f64>>> {
    super::fit::fit_outline(corners, size, above, |i| heights[i].is_finite())
        .filter(|fitted| super::sides::agrees(fitted, corners))
}

/// For each edge of the counter-clockwise image loop `corners`, its [`Band`]: the heights of the
/// blob's pixels whose centres lie within `SILHOUETTE_BAND` pixels inside the edge and along it.
fn silhouette_bands(
    corners: &[Point2<f64>],
    pixels: &[usize],
    heights: &[f64],
    width: usize,
) -> Vec<Band> {
    // The pixels by row, so that each edge looks only at the rows it spans.
    let first = pixels.iter().map(|&i| i / width).min().unwrap_or(0);
    let last = pixels.iter().map(|&i| i / width).max().unwrap_or(0);
    let mut rows: Vec<Vec<usize>> = vec![Vec::new(); last - first + 1];
    for &i in pixels {
        rows[i / width - first].push(i);
    }
    let n = corners.len();
    (0..n)
        .map(|k| {
            let (a, b) = (corners[k], corners[(k + 1) % n]);
            let edge = b - a;
            let length = edge.norm();
            if length < 1e-9 {
                return Vec::new();
            }
            let outward = nalgebra::Vector2::new(edge.y, -edge.x) / length;
            // Every pixel near the edge lies within the band's width of its rows.
            let (low, high) = (
                a.y.min(b.y) - SILHOUETTE_BAND,
                a.y.max(b.y) + SILHOUETTE_BAND,
            );
            let from = (low.ceil().max(first as f64) as usize).saturating_sub(first);
            let to = (high.floor().max(0.0) as usize)
                .min(last)
                .saturating_sub(first);
            let mut band: Band = rows
                .get(from..=to)
                .unwrap_or(&[])
                .iter()
                .flatten()
                .filter_map(|&i| {
                    let p = Point2::new((i % width) as f64, (i / width) as f64);
                    let inside = outward.dot(&(a - p));
                    let along = edge.dot(&(p - a)) / (length * length);
                    let near =
                        (0.0..=SILHOUETTE_BAND).contains(&inside) && (0.0..=1.0).contains(&along);
                    (near && heights[i].is_finite()).then_some((along, heights[i]))
                })
                .collect();
            band.sort_by(|x, y| x.1.total_cmp(&y.1));
            band
        })
        .collect()
}

/// For each edge of the image loop whose silhouette bands are `bands` ([`silhouette_bands`]), the
/// height at which the blob's silhouette stands along it: the tenth percentile of the band's
/// heights, kept within `[cut, top]`; the cut for an edge with no such pixel. Along a wall the
/// camera sees, the outermost pixels stand just above the cut, so the edge is the cut's, as in the
/// two-plane method. Along a top whose wall a neighbour hides they stand at the top, and so does
/// the edge. Where a wall shows only narrowly (an edge seen almost end-on, or near the nadir), the
/// edge stands in between, off by at most that narrow wall's width.
fn silhouette_heights(bands: &[Band], (cut, top): (f64, f64)) -> Vec<f64> {
    bands
        .iter()
        .map(|band| {
            band.get(band.len() / 10)
                .map_or(cut, |&(_, h)| h.clamp(cut, top))
        })
        .collect()
}

/// How far inside an edge of the image hull, pixels, the pixels lie whose heights say where the
/// silhouette along it stands: the outermost row (the hull's offset puts its edges about half a
/// pixel outside their centres).
const SILHOUETTE_BAND: f64 = 1.5;

/// The pixel box of `pixels`, and whether it touches the image's border.
fn pixel_box(pixels: &[usize], width: usize, height: usize) -> ([usize; 4], bool) {
    let mut b = [usize::MAX, usize::MAX, 0, 0];
    for &i in pixels {
        let (u, v) = (i % width, i / width);
        b = [b[0].min(u), b[1].min(v), b[2].max(u), b[3].max(v)];
    }
    let border = b[0] == 0 || b[1] == 0 || b[2] + 1 == width || b[3] + 1 == height;
    (b, border)
}

/// The longest chord of `polygon`, metres.
fn extent(polygon: &ConvexPolygon) -> f64 {
    let v = polygon.vertices();
    v.iter()
        .flat_map(|a| v.iter().map(move |b| nalgebra::distance(a, b)))
        .fold(0.0, f64::max)
}

/// How far `polygon` reaches outside `workspace` (0 inside), and whether all of it is outside.
fn outside(polygon: &ConvexPolygon, workspace: &Workspace) -> (f64, bool) {
    let reach = polygon
        .vertices()
        .iter()
        .map(|p| workspace.outside_by(p))
        .fold(0.0, f64::max);
    let (lo, hi) = polygon.bounding_box();
    let apart = hi.x < workspace.min[0]
        || hi.y < workspace.min[1]
        || lo.x > workspace.max[0]
        || lo.y > workspace.max[1];
    (reach, apart)
}

/// A blob's top height (its given one, or the higher plateau of its heights when enough of its
/// pixels have depth) and, for a stacked blob, the lower plateau's.
pub fn top_of(
    blob: &Blob,
    heights: Option<&[f64]>,
    settings: &PerceptionSettings,
) -> (Option<f64>, Option<f64>) {
    let known: Vec<f64> = heights.map_or(Vec::new(), |h| {
        blob.pixels
            .iter()
            .map(|&i| h[i])
            .filter(|h| h.is_finite())
            .collect()
    });
    match blob.given_height {
        Some(h) => (Some(h), None),
        None if known.len() as f64 >= settings.min_depth_fraction * blob.pixels.len() as f64
            && !known.is_empty() =>
        {
            let (top, second) = top_height(&known, settings);
            (Some(top), second)
        }
        None => (None, None),
    }
}

/// Judges one blob against `heights` (per pixel above the fitted table, NaN for none), with its
/// top and lower plateau from [`top_of`], and the blobs around it where labels let them touch.
#[allow(clippy::too_many_arguments)]
pub fn judge(
    blob: &Blob,
    (top, stacked): (Option<f64>, Option<f64>),
    heights: Option<&[f64]>,
    neighbours: Option<&Neighbours>,
    camera: &Camera,
    table: &TablePlane,
    workspace: &Workspace,
    settings: &PerceptionSettings,
) -> Judged {
    let (width, height) = (
        camera.intrinsics.width as usize,
        camera.intrinsics.height as usize,
    );
    let (pixel_box, border) = pixel_box(&blob.pixels, width, height);
    // Blobs from depth are cut again at half their top: a flying pixel, mixed between the table
    // and the top, then lies above the cut as often outside the edge as below it inside.
    // `above`: the pixels above the cut before the median, where the cut was made again.
    let (pixels, above, cut) = match (heights, top) {
        (Some(h), Some(top)) if blob.given_height.is_none() && 0.5 * top > blob.cut => {
            let cut = 0.5 * top;
            let above: Vec<usize> = blob
                .pixels
                .iter()
                .copied()
                .filter(|&i| above_cut(h, i, width, cut))
                .collect();
            (majority(&above, width, height), Some(above), cut)
        }
        _ => (blob.pixels.clone(), None, blob.cut),
    };
    let mut hull = image_hull(&pixels, width, settings.fit_sides);
    // With depth, the outline's sides are fitted to the pixels on both sides of its edge, from the
    // median hull (`fit.rs`); the hull is kept where the fit strays from it.
    if settings.fit_outline
        && blob.given_height.is_none()
        && let (Some(h), Some(image)) = (heights, hull.as_mut())
        && let Some(fitted) = fitted_outline(
            &image.corners,
            above.as_deref().unwrap_or(&blob.pixels),
            h,
            (width, height),
        )
    {
        image.corners = fitted;
    }
    let mut solidity = hull.as_ref().map_or(0.0, |h| h.solidity);
    // With labels, a neighbour in front may hide part of the blob: its pixels inside the blob's
    // hull are no notch of the blob's own.
    if let Some(n) = neighbours
        && solidity < settings.min_solidity
    {
        solidity = solidity_behind(&pixels, width, |i| {
            n.owner[i] != 0 && n.owner[i] as usize - 1 != n.index
        });
    }
    // A top measured from depth at or below the cut height (a flat thing, or a label lying on the
    // table) stands on nothing the mask holds: no footprint, so the blob is too small.
    let lowest_top = match blob.given_height {
        Some(_) => cut,
        None => cut.max(settings.cut_height),
    };
    let mut hidden_by = Vec::new();
    let print = match (&hull, top) {
        (Some(hull), Some(top)) if top > lowest_top => match heights {
            // With depth, each edge of the hull is back-projected at the height its silhouette
            // stands at: the cut where a wall shows, the top where a neighbour hides it.
            Some(h) if blob.given_height.is_none() => {
                let bands = silhouette_bands(&hull.corners, &pixels, h, width);
                let lifts = silhouette_heights(&bands, (cut, top));
                let lifts = end_lifts(
                    &hull.corners,
                    &lifts,
                    &bands,
                    (cut, top),
                    h,
                    width,
                    neighbours,
                );
                // Where a taller neighbour stands in front, this blob goes on beneath it; the two
                // are cut apart at the neighbour's edge once every blob is judged (`hidden.rs`).
                if let Some(n) = neighbours {
                    hidden_by = hidden_sides(&hull.corners, top, h, width, n)
                        .into_iter()
                        .flatten()
                        .collect();
                    hidden_by.sort_unstable();
                    hidden_by.dedup();
                }
                footprint_by_edges(hull, camera, table, top, &lifts)
            }
            _ => footprint(hull, camera, table, top, cut),
        },
        _ => None,
    };
    let measured = Measured {
        top,
        stacked,
        solidity,
        border,
    };
    let status = status(blob, &print, &measured, workspace, settings);
    // Judged again on a workspace that holds the footprint, so that the workspace's tests drop out.
    let past_edge = matches!(
        status,
        BlobStatus::OutsideWorkspace | BlobStatus::StraddlesWorkspaceEdge
    ) && print.as_ref().is_some_and(|p| {
        let (lo, hi) = p.bounding_box();
        let holding = Workspace {
            min: [lo.x - 1.0, lo.y - 1.0],
            max: [hi.x + 1.0, hi.y + 1.0],
        };
        self::status(blob, &print, &measured, &holding, settings) == BlobStatus::Object
    });
    Judged {
        pixel_box,
        top,
        solidity,
        footprint: print,
        status,
        past_edge,
        hidden_by,
    }
}

/// What the pixels say about a blob, before its footprint is judged.
#[derive(Clone, Copy)]
struct Measured {
    top: Option<f64>,
    stacked: Option<f64>,
    solidity: f64,
    border: bool,
}

/// The first status that applies, in the order of `formulations/perception.md`.
fn status(
    blob: &Blob,
    print: &Option<ConvexPolygon>,
    measured: &Measured,
    workspace: &Workspace,
    settings: &PerceptionSettings,
) -> BlobStatus {
    let Measured {
        top,
        stacked,
        solidity,
        border,
    } = *measured;
    let Some(top) = top else {
        return BlobStatus::NoDepth;
    };
    let Some(print) = print else {
        return BlobStatus::TooSmall;
    };
    if print.area() < settings.min_area {
        return BlobStatus::TooSmall;
    }
    let (reach, apart) = outside(print, workspace);
    if apart {
        return BlobStatus::OutsideWorkspace;
    }
    if border {
        return BlobStatus::TouchesImageBorder;
    }
    if blob.split {
        return BlobStatus::SplitLabel;
    }
    if let Some(lower) = stacked {
        return BlobStatus::Stacked {
            heights: [top, lower],
        };
    }
    if top > settings.max_height {
        return BlobStatus::TooTall;
    }
    if extent(print) > settings.max_extent {
        return BlobStatus::TooLarge;
    }
    if solidity < settings.min_solidity {
        return BlobStatus::NotConvex;
    }
    if reach > settings.edge_trim {
        return BlobStatus::StraddlesWorkspaceEdge;
    }
    BlobStatus::Object
}

/// The centroid of a footprint as the report's position.
pub fn position(print: &Option<ConvexPolygon>) -> Option<[f64; 2]> {
    print.as_ref().map(|p| {
        let c: Point2<f64> = p.centroid();
        [c.x, c.y]
    })
}

/// The blobs judged objects but for the workspace's edge ([`Judged::past_edge`]), as objects
/// where they lie (`Perception::past_edge`).
pub fn past_edge_objects(blobs: &[Blob], judged: &[Judged]) -> Vec<PastEdge> {
    let mut objects = Vec::new();
    for (k, (blob, judged)) in blobs.iter().zip(judged).enumerate() {
        let (true, Some(print), Some(top)) = (judged.past_edge, &judged.footprint, judged.top)
        else {
            continue;
        };
        let centre = print.centroid();
        objects.push(PastEdge {
            blob: k,
            object: Object {
                id: ObjectId(blob.label.unwrap_or(0)),
                name: None,
                polygon: print.translated(&-centre.coords),
                pose: Pose::new(centre.x, centre.y, 0.0),
                height: top,
                mass: None,
            },
        });
    }
    objects
}
