//! A blob of depth alone with two plateaus, parted into one blob per plateau when each part is an
//! upright prism of its own (`formulations/perception.md`, "Two plateaus in one blob").
//!
//! Without labels, two objects of different heights make one blob wherever they meet in the image:
//! touching on the table, or apart on it but with the taller one's top, which perspective moves
//! away from the nadir by `h·r/(H − h)`, next to the lower one in the image. A convex prism lying on
//! the table has at most one horizontal face looking up, so two plateaus at heights `h₁ > h₂` are
//! two objects, or one object on another, or a face and a slope of one toppled object.
//!
//! **Parting.** Each plateau's marker is the largest 4-connected set of the blob's pixels within
//! `BAND` of its height. The rest of the blob is flooded from the markers, the flood's level along a
//! path being the lowest height on it, highest level first (a watershed of `−h`): a pixel joins the
//! part whose flood reaches it at the higher level. So a wall goes with the top it hangs from, down
//! to its foot beside the lower plateau, and pixels without depth go last, to whichever part holds
//! them.
//!
//! **Kept only when both parts are upright prisms apart** ([`PartTest`]): each part has one
//! plateau, a footprint of an object's size and a convex image; its top face, the pixels within
//! `BAND` of its top, fills at least `MIN_FILL` of its footprint as the image shows that footprint
//! at the top's height (a slope's most populated band of heights does not); and the two footprints
//! overlap by no more than
//! [`PerceptionSettings::overlap_repair`](super::PerceptionSettings::overlap_repair) (one object on
//! another overlaps the one under it). Otherwise the blob stays whole, and `stacked`.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use nalgebra::Point3;

use super::blob::{Blob, Judged};
use super::blobs::{Mask, Window, components, four_neighbours};
use super::camera::Camera;
use super::report::BlobStatus;
use crate::geometry::{ConvexPolygon, max_separation};

/// A blob's top and, if it has one, its second plateau ([`super::blob::top_of`]).
pub type Measure = (Option<f64>, Option<f64>);

/// Half the width of a plateau's band of heights, metres: half the 5 mm band the top is read from.
const BAND: f64 = 0.0025;
/// The least share of its footprint, as the image shows it at the top's height, that a part's top
/// face must fill to be an upright prism's.
const MIN_FILL: f64 = 0.5;

/// The pixels of `blob` in two parts, one per plateau (`levels`, the higher first), flooded from
/// each plateau's marker highest first; `None` when a plateau has no pixel.
pub fn part(
    pixels: &[usize],
    levels: [f64; 2],
    heights: &[f64],
    width: usize,
) -> Option<[Vec<usize>; 2]> {
    if pixels.is_empty() {
        return None;
    }
    // The blob's box, where the flood runs.
    let window = Window::around(pixels, width);
    let (w, h) = window.size();
    let inside = window.mask().set;
    // The height of the box's pixel `j` (none in the margin beyond the image).
    let height = |j: usize| {
        window
            .image_index(j, width)
            .and_then(|i| heights.get(i).copied())
            .unwrap_or(f64::NAN)
    };
    // 0: not yet reached; 1 and 2: the parts.
    let mut part = vec![0_u8; w * h];
    for (k, &level) in levels.iter().enumerate() {
        let set: Vec<bool> = (0..w * h)
            .map(|j| inside[j] && part[j] == 0 && (height(j) - level).abs() <= BAND)
            .collect();
        let (pieces, count) = components(&Mask {
            width: w,
            height: h,
            set,
        });
        let mut sizes = vec![0_usize; count as usize + 1];
        for &p in &pieces {
            sizes[p as usize] += 1;
        }
        let largest = (1..sizes.len()).max_by_key(|&p| sizes[p])?;
        for (j, &p) in pieces.iter().enumerate() {
            if p as usize == largest {
                part[j] = k as u8 + 1;
            }
        }
    }
    // The flood's level along a path is the lowest height on it: a pixel is reached at the lower of
    // its own height and the level of the neighbour it is reached from, highest level first, ties in
    // the order reached. Pixels without depth are reached last.
    let key = |j: usize| {
        let z = height(j);
        if z.is_finite() {
            (z * 1e6).round() as i64
        } else {
            i64::MIN
        }
    };
    let neighbours = |j: usize| four_neighbours(j, w, h);
    let mut queue = BinaryHeap::new();
    let mut order = 0_u64;
    for j in 0..w * h {
        if part[j] != 0 {
            for n in neighbours(j) {
                if inside[n] && part[n] == 0 {
                    queue.push((key(j).min(key(n)), Reverse(order), n, part[j]));
                    order += 1;
                }
            }
        }
    }
    while let Some((level, _, j, from)) = queue.pop() {
        if part[j] != 0 {
            continue;
        }
        part[j] = from;
        for n in neighbours(j) {
            if inside[n] && part[n] == 0 {
                queue.push((level.min(key(n)), Reverse(order), n, from));
                order += 1;
            }
        }
    }
    let mut parts = [Vec::new(), Vec::new()];
    for &i in pixels {
        match part[window.local(i, width)] {
            1 => parts[0].push(i),
            2 => parts[1].push(i),
            _ => {}
        }
    }
    Some(parts)
}

/// What keeps a parting: each part judged on its own, with its top measured.
pub struct PartTest<'a> {
    /// The heights of the look's pixels above the table.
    pub heights: &'a [f64],
    /// The camera.
    pub camera: &'a Camera,
    /// The deepest overlap of the two footprints allowed, metres.
    pub overlap: f64,
}

impl PartTest<'_> {
    /// Whether the two parts, with their tops (and second plateaus) and judgements, are two upright
    /// prisms apart.
    pub fn keeps(&self, parts: [(&Blob, Measure, &Judged); 2]) -> bool {
        let mut prints = Vec::new();
        for (blob, measured, judged) in parts {
            let (Some(top), None, Some(print)) = (measured.0, measured.1, &judged.footprint) else {
                return false;
            };
            // A part too small, or not convex, is a piece of one object (a thin bar's wall).
            if matches!(
                judged.status,
                BlobStatus::TooSmall | BlobStatus::NotConvex | BlobStatus::NoDepth
            ) {
                return false;
            }
            if self.fill(blob, top, print) < MIN_FILL {
                return false;
            }
            prints.push(print);
        }
        max_separation(prints[0], prints[1]).1 >= -self.overlap
    }

    /// The share of `print`, as the image shows it at height `top`, that the blob's pixels within
    /// `BAND` of `top` fill.
    fn fill(&self, blob: &Blob, top: f64, print: &ConvexPolygon) -> f64 {
        let seen: Vec<_> = print
            .vertices()
            .iter()
            .filter_map(|p| self.camera.project(&Point3::new(p.x, p.y, top)))
            .map(|(q, _)| q)
            .collect();
        let n = seen.len();
        if n < 3 {
            return 0.0;
        }
        let area = 0.5
            * (0..n)
                .map(|k| {
                    let (a, b) = (seen[k], seen[(k + 1) % n]);
                    a.x * b.y - b.x * a.y
                })
                .sum::<f64>()
                .abs();
        let on_top = blob
            .pixels
            .iter()
            .filter(|&&i| (self.heights[i] - top).abs() <= BAND)
            .count();
        on_top as f64 / area.max(1.0)
    }
}

/// `blobs` (with `measured`, their tops) with each unlabelled blob of two plateaus parted where
/// `test` keeps the parting ([`PartTest::keeps`]), the parts measured by `measure` and judged by
/// `judge`; each parting is noted in `adjustments`.
pub fn part_blobs(
    blobs: Vec<Blob>,
    measured: Vec<Measure>,
    test: &PartTest,
    measure: impl Fn(&Blob) -> Measure,
    judge: impl Fn(&Blob, Measure) -> Judged,
    adjustments: &mut Vec<String>,
) -> (Vec<Blob>, Vec<Measure>) {
    let width = test.camera.intrinsics.width as usize;
    let mut out = (
        Vec::with_capacity(blobs.len()),
        Vec::with_capacity(blobs.len()),
    );
    for (blob, m) in blobs.into_iter().zip(measured) {
        let parted = match (blob.label, m) {
            (None, (Some(top), Some(lower))) => {
                part(&blob.pixels, [top, lower], test.heights, width)
            }
            _ => None,
        };
        let Some([high, low]) = parted else {
            out.0.push(blob);
            out.1.push(m);
            continue;
        };
        let piece = |pixels: Vec<usize>| Blob {
            label: None,
            pixels,
            given_height: None,
            cut: blob.cut,
            split: false,
        };
        let (high, low) = (piece(high), piece(low));
        let (mh, ml) = (measure(&high), measure(&low));
        let (jh, jl) = (judge(&high, mh), judge(&low, ml));
        if !test.keeps([(&high, mh, &jh), (&low, ml, &jl)]) {
            out.0.push(blob);
            out.1.push(m);
            continue;
        }
        adjustments.push(format!(
            "a blob of two plateaus ({:.1} and {:.1} mm) parted into two objects, in pixels {:?} \
             and {:?}",
            m.0.unwrap_or(0.0) * 1e3,
            m.1.unwrap_or(0.0) * 1e3,
            jh.pixel_box,
            jl.pixel_box
        ));
        out.0.extend([high, low]);
        out.1.extend([mh, ml]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip 25 pixels long and 3 wide: a top at 60 mm (columns 0–9), its wall coming down
    /// toward the lower object (10–14, the last at 20 mm), and a top at 15 mm (15–24).
    fn strip() -> (Vec<f64>, Vec<usize>) {
        let profile = |u: usize| match u {
            0..=9 => 0.060,
            10..=14 => 0.060 - 0.008 * (u - 9) as f64,
            _ => 0.015,
        };
        let heights: Vec<f64> = (0..3 * 25).map(|i| profile(i % 25)).collect();
        (heights, (0..3 * 25).collect())
    }

    #[test]
    fn a_wall_goes_with_the_top_it_hangs_from() {
        let (heights, pixels) = strip();
        let [high, low] = part(&pixels, [0.060, 0.015], &heights, 25).unwrap();
        assert_eq!(high.len() + low.len(), pixels.len());
        assert!(high.iter().all(|&i| i % 25 <= 14), "{high:?}");
        assert!(low.iter().all(|&i| i % 25 >= 15), "{low:?}");
    }

    #[test]
    fn pixels_without_depth_go_to_the_part_around_them() {
        let (mut heights, pixels) = strip();
        heights[25 + 3] = f64::NAN;
        heights[25 + 20] = f64::NAN;
        let [high, low] = part(&pixels, [0.060, 0.015], &heights, 25).unwrap();
        assert!(high.contains(&(25 + 3)) && low.contains(&(25 + 20)));
    }

    #[test]
    fn a_plateau_with_no_pixel_parts_nothing() {
        let (heights, pixels) = strip();
        assert!(part(&pixels, [0.060, 0.040], &heights, 25).is_none());
    }
}
