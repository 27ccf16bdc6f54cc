//! Objects a taller neighbour hides in part: cut apart from it where they overlap, and joined when
//! it leaves their label in pieces (`formulations/perception.md`, "Hidden by a taller neighbour").
//!
//! Where a neighbour `T`'s pixels just outside blob `A`'s outline stand above `A`'s top, a ray meets
//! `T` first: `T` stands in front, and that stretch of `A`'s outline is `T`'s silhouette. Cast as
//! `A`'s own, it can land inside `T`'s footprint. Two objects do not overlap, and `T`, the taller,
//! shows its whole top; so where the two footprints overlap, `A` alone yields: it is cut at `T`'s
//! edge, along the axis that separates them best, instead of halfway or, past
//! [`PerceptionSettings::overlap_repair`](super::PerceptionSettings::overlap_repair), being
//! reported as `overlap`. Footprints that do not overlap are left as they are.
//!
//! A taller object standing across a lower one in the image can leave the lower one's label in
//! pieces. Joined through the taller blobs' pixels, such pieces make one: the label is one object
//! seen in parts ([`joined_behind`]), not a split label.

use super::blob::{Blob, Judged};
use super::blobs::{Window, components};
use super::report::BlobStatus;
use crate::geometry::{ConvexPolygon, clip, max_separation, tidy_polygon};

/// How much higher than a blob, metres, a neighbour's top must stand to be taller than it: the
/// `TOP_BAND` of `occlusion.rs`.
const TALLER: f64 = 0.003;

/// Each object of `judged` that a taller neighbour hides, cut where its footprint overlaps that
/// neighbour's; each cut noted in `adjustments`.
pub fn cut_hidden(judged: &mut [Judged], adjustments: &mut Vec<String>) {
    let cut: Vec<(usize, ConvexPolygon)> = (0..judged.len())
        .filter_map(|i| Some((i, yielded(judged, i)?)))
        .collect();
    for (i, print) in cut {
        let before = judged[i]
            .footprint
            .as_ref()
            .map_or(0.0, ConvexPolygon::area);
        adjustments.push(format!(
            "the blob in pixels {:?} cut where a taller blob in front of it overlapped it: {:.0} mm² \
             of its footprint",
            judged[i].pixel_box,
            (before - print.area()) * 1e6
        ));
        judged[i].footprint = Some(print);
    }
}

/// Blob `i`'s footprint cut at the edge of each neighbour in front of it that it overlaps; `None`
/// when nothing is cut.
fn yielded(judged: &[Judged], i: usize) -> Option<ConvexPolygon> {
    let a = &judged[i];
    if a.status != BlobStatus::Object || a.hidden_by.is_empty() {
        return None;
    }
    let mut print = a.footprint.clone()?;
    let mut changed = false;
    for &t in &a.hidden_by {
        let Some(theirs) = &judged[t].footprint else {
            continue;
        };
        let (normal, gap) = max_separation(&print, theirs);
        if gap >= 0.0 {
            continue;
        }
        // `theirs` begins at `support + gap` along `normal`.
        let edge = print.support(&normal) + gap;
        print = tidy_polygon(&clip(print.vertices(), &normal, edge))?;
        changed = true;
    }
    changed.then_some(print)
}

/// Whether the pieces of a blob whose label is split (`blob`, index `index`, top `top`) are joined
/// by the pixels of taller blobs in front of it (`owner` and `tops` as in
/// [`Neighbours`](super::occlusion::Neighbours)): then a taller object stands across it in the
/// image, and its label is one object seen in pieces, not a segmentation fault.
pub fn joined_behind(
    blob: &Blob,
    index: usize,
    top: f64,
    owner: &[u32],
    tops: &[Option<f64>],
    width: usize,
) -> bool {
    if blob.pixels.is_empty() {
        return false;
    }
    let window = Window::around(&blob.pixels, width);
    let mut mask = window.mask();
    let taller = |o: u32| {
        o != 0 && o as usize - 1 != index && tops[o as usize - 1].is_some_and(|t| t > top + TALLER)
    };
    for (j, set) in mask.set.iter_mut().enumerate() {
        let in_front = window
            .image_index(j, width)
            .is_some_and(|i| i < owner.len() && taller(owner[i]));
        *set = *set || in_front;
    }
    // Counted as the split itself is: pieces of 10 pixels or more.
    let (parts, count) = components(&mask);
    let mut sizes = vec![0_usize; count as usize + 1];
    for &i in &blob.pixels {
        sizes[parts[window.local(i, width)] as usize] += 1;
    }
    sizes.iter().filter(|&&s| s >= 10).count() <= 1
}
