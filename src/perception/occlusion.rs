//! Sides of a blob's outline along a neighbour that hides its wall (`formulations/perception.md`,
//! "Sides along a neighbour").
//!
//! Two labelled objects can touch in the image. Where a neighbour `B` presses against the wall of
//! a blob `A` that the camera would see, `B` hides that wall: the boundary between the two in the
//! image is `B`'s top edge, at `B`'s top height `h_B`, and since the two touch, that edge stands
//! right above `A`'s side. Cast at `h_B` that part of `A`'s outline lands on `A`'s side; cast at
//! `A`'s cut it lands inside `A`. This holds whether `B` is lower than `A` (the wall shows above
//! `h_B`, the edge is the line at `h_B` on it) or higher (`B`'s top edge hides part of `A`'s top).
//! Where `A` stands in front instead (its wall faces away from the nadir, `B` behind it), the pixels
//! just outside are `B`'s wall seen over `A`'s top edge, below `B`'s top, and nothing changes.
//!
//! A side of the outline can run along `B` at one end and along the wall's foot at the other: the
//! hull's chord from the top's corner where `B` hides the wall to the wall's cut corner where it
//! shows. That chord is the image of a segment on the wall from the top down to the cut, so each
//! end is cast at its own height, which the blob's own outermost pixels there give: the top (or
//! `h_B`, where `B` is higher) where they stand at the top, their own height on the wall otherwise
//! ([`end_lifts`]).

use nalgebra::{Point2, Vector2};

/// Which blob holds each pixel and each blob's top: what [`end_lifts`] reads around a blob.
pub struct Neighbours<'a> {
    /// Per pixel, one more than the index of the blob that holds it; 0 for none.
    pub owner: &'a [u32],
    /// Per blob, its top height above the table, metres, if known.
    pub tops: &'a [Option<f64>],
    /// The index of the blob judged.
    pub index: usize,
}

/// Per pixel of an image of `size` pixels, one more than the index of the blob (of `blobs`, each
/// its pixel indices) that holds it; 0 for none: [`Neighbours::owner`].
pub fn owners<'a>(blobs: impl Iterator<Item = &'a [usize]>, size: usize) -> Vec<u32> {
    let mut owner = vec![0_u32; size];
    for (k, pixels) in blobs.enumerate() {
        for &i in pixels {
            owner[i] = k as u32 + 1;
        }
    }
    owner
}

/// The heights of the blob's pixels just inside a side of its outline, each with where along the
/// side it lies (0 at its first corner, 1 at its second), in increasing height.
pub type Band = Vec<(f64, f64)>;

/// How far outside a side, pixels, its outside is sampled.
const OUTSIDE: [f64; 2] = [1.0, 2.0];
/// The share of a side, from each end, whose outside decides that end.
const END_SHARE: f64 = 1.0 / 3.0;
/// The least count, and share of the sampled pixels with depth, of a neighbour's pixels outside an
/// end for that neighbour to hide it.
const MIN_PIXELS: usize = 3;
const MIN_SHARE: f64 = 0.5;
/// The shortest side, pixels, whose ends are cast at heights of their own along a neighbour.
const MIN_LENGTH: f64 = 10.0;
/// How close to the neighbour's top, metres, the median height of its pixels there must be for
/// them to be its top (and not its wall seen over the blob's edge): about 2.5 σ of the depth
/// noise at 0.7 m (`noise.rs`).
const TOP_BAND: f64 = 0.003;

/// For each side `k` of the counter-clockwise image loop `corners` (corner `k` to `k + 1`), the
/// heights at which its two ends are cast, or `None` for a side that bounds nothing.
///
/// - Without a neighbour's top outside it ([`Neighbours`]), a side is cast at `lifts[k]`, both
///   ends.
/// - At an end of a side at least `MIN_LENGTH` long whose outside holds a neighbour's top `h_B`,
///   the blob's own outermost pixels along that end (`bands[k]`, heights with where along the side
///   they lie) say where its silhouette stands: at its own top, when their median is within
///   `TOP_BAND` of it, the end is cast at the higher of `top` and `h_B` (the blob's top edge, or the
///   neighbour's hiding it); on its wall otherwise, at their tenth percentile within `[cut, top]`.
///   An end with fewer than `MIN_PIXELS` such pixels keeps `lifts[k]`, unless every one of them
///   stands at the top: then it is a top edge all the same.
/// - A shorter side with a neighbour's top outside it bounds nothing: its ends have too few pixels
///   of their own, and cast at two heights its direction on the table would be anything. It is the
///   image of a vertical edge, whose corner the sides next to it give as well, or a chord from where
///   the wall shows to where the neighbour hides it, whose side the sides next to it continue.
/// - So does a shorter side whose band holds fewer than `MIN_PIXELS` pixels, neighbour or not
///   (labels with depth only): one pixel low on the wall, or a flying one, would cast it at the
///   cut, and where a neighbour hides the wall beside it, that cuts the corner off.
pub fn end_lifts(
    corners: &[Point2<f64>],
    lifts: &[f64],
    bands: &[Band],
    (cut, top): (f64, f64),
    heights: &[f64],
    width: usize,
    neighbours: Option<&Neighbours>,
) -> Vec<Option<[f64; 2]>> {
    let n = corners.len();
    (0..n)
        .map(|k| {
            let lift = lifts[k];
            let Some(neighbours) = neighbours else {
                return Some([lift, lift]);
            };
            let (a, b) = (corners[k], corners[(k + 1) % n]);
            let hiding = |part| hiding_top(a, b, part, heights, width, neighbours);
            if (b - a).norm() < MIN_LENGTH {
                // Too few pixels of the blob's own say where a short side stands: one flying
                // pixel or one of the wall, where a neighbour hides the rest, would cast it low
                // and cut the corner off. The sides next to it bound that corner.
                let few = bands[k].len() < MIN_PIXELS;
                return (!few && hiding((0.0, 1.0)).is_none()).then_some([lift, lift]);
            }
            let at = |from: f64, to: f64| {
                let Some(hiding) = hiding((from, to)) else {
                    return lift;
                };
                // The band is in increasing height.
                let own: Vec<f64> = bands[k]
                    .iter()
                    .filter(|(along, _)| (from..=to).contains(along))
                    .map(|&(_, h)| h)
                    .collect();
                // Too few to judge a wall by, but a few that all stand at the top still say the
                // silhouette there is a top edge.
                let at_top = !own.is_empty() && own[0] >= top - TOP_BAND;
                if own.len() < MIN_PIXELS && !at_top {
                    return lift;
                }
                if own[own.len() / 2] >= top - TOP_BAND {
                    top.max(hiding)
                } else {
                    own[own.len() / 10].clamp(cut, top)
                }
            };
            Some([at(0.0, END_SHARE), at(1.0 - END_SHARE, 1.0)])
        })
        .collect()
}

/// The top of the neighbour whose top the pixels just outside the part `(from, to)` (shares of its
/// length from `a`) of the side `a → b` see, if one does.
fn hiding_top(
    a: Point2<f64>,
    b: Point2<f64>,
    part: (f64, f64),
    heights: &[f64],
    width: usize,
    neighbours: &Neighbours,
) -> Option<f64> {
    let (blob, median) = outside(a, b, part, heights, width, neighbours)?;
    let top = neighbours.tops.get(blob).copied().flatten()?;
    ((median - top).abs() <= TOP_BAND).then_some(top)
}

/// The blob most of whose pixels lie just outside the part `(from, to)` of the side `a → b`, when
/// it holds at least `MIN_PIXELS` of them and `MIN_SHARE` of those with depth, and the median
/// height of its pixels there.
fn outside(
    a: Point2<f64>,
    b: Point2<f64>,
    (from, to): (f64, f64),
    heights: &[f64],
    width: usize,
    neighbours: &Neighbours,
) -> Option<(usize, f64)> {
    let edge = b - a;
    let length = edge.norm();
    if length < 1e-9 {
        return None;
    }
    let outward = Vector2::new(edge.y, -edge.x) / length;
    let rows = heights.len() / width;
    let steps = ((to - from) * length / 0.5).ceil().max(1.0) as usize;
    let mut seen: Vec<usize> = Vec::new();
    for s in 0..=steps {
        let t = from + (to - from) * s as f64 / steps as f64;
        for d in OUTSIDE {
            let p = a + edge * t + outward * d;
            let (u, v) = (p.x.round(), p.y.round());
            if u < 0.0 || v < 0.0 || u >= width as f64 || v >= rows as f64 {
                continue;
            }
            let i = v as usize * width + u as usize;
            if heights[i].is_finite() {
                seen.push(i);
            }
        }
    }
    seen.sort_unstable();
    seen.dedup();
    // The most frequent other blob outside, and the heights of its pixels there.
    let mut by_blob: Vec<(usize, f64)> = seen
        .iter()
        .filter_map(|&i| {
            let o = neighbours.owner[i] as usize;
            (o != 0 && o - 1 != neighbours.index).then(|| (o - 1, heights[i]))
        })
        .collect();
    by_blob.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    let mut best: Option<&[(usize, f64)]> = None;
    for group in by_blob.chunk_by(|x, y| x.0 == y.0) {
        if best.is_none_or(|b| group.len() > b.len()) {
            best = Some(group);
        }
    }
    let group = best?;
    if group.len() < MIN_PIXELS || (group.len() as f64) < MIN_SHARE * seen.len() as f64 {
        return None;
    }
    Some((group[0].0, group[group.len() / 2].1))
}

/// For each side `k` of the counter-clockwise image loop `corners`, the neighbour that hides the
/// blob beyond it, if one does: a neighbour whose pixels just outside a third of the side (the
/// whole side, for one shorter than `MIN_LENGTH`) stand, by their median, more than
/// `TOP_BAND` above the blob's `top`. A ray meets the higher surface first, so there the neighbour
/// is in front, and the side is the neighbour's silhouette, not the blob's: where the blob ends
/// beneath it the pixels do not say (`formulations/perception.md`, "Hidden by a taller
/// neighbour").
pub fn hidden_sides(
    corners: &[Point2<f64>],
    top: f64,
    heights: &[f64],
    width: usize,
    neighbours: &Neighbours,
) -> Vec<Option<usize>> {
    let n = corners.len();
    (0..n)
        .map(|k| {
            let (a, b) = (corners[k], corners[(k + 1) % n]);
            let parts: &[(f64, f64)] = if (b - a).norm() < MIN_LENGTH {
                &[(0.0, 1.0)]
            } else {
                &[
                    (0.0, END_SHARE),
                    (END_SHARE, 1.0 - END_SHARE),
                    (1.0 - END_SHARE, 1.0),
                ]
            };
            parts.iter().find_map(|&part| {
                outside(a, b, part, heights, width, neighbours)
                    .filter(|&(_, median)| median > top + TOP_BAND)
                    .map(|(blob, _)| blob)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 × 20 image: blob 0 on the left half (its pixels at 20 mm, but those of column 9 in
    /// `wall_rows`, at 11 mm: a wall it shows there), a neighbour (blob 1) on the right half in
    /// `neighbour_rows`, at `right` metres; the side between them runs from (9.5, 1) to (9.5, 19).
    fn halves(
        right: f64,
        neighbour_rows: std::ops::Range<usize>,
        wall_rows: std::ops::Range<usize>,
    ) -> (Vec<f64>, Vec<u32>, Vec<Band>) {
        let width = 20;
        let mut heights = vec![0.0; width * width];
        let mut owner = vec![0_u32; width * width];
        for v in 0..width {
            for u in 0..width {
                let i = v * width + u;
                if u < 10 {
                    heights[i] = if u == 9 && wall_rows.contains(&v) {
                        0.011
                    } else {
                        0.02
                    };
                    owner[i] = 1;
                } else if neighbour_rows.contains(&v) {
                    heights[i] = right;
                    owner[i] = 2;
                }
            }
        }
        // The band of the side: column 9, rows 1 to 19.
        let mut band: Band = (1..=19)
            .map(|v| ((v as f64 - 1.0) / 18.0, heights[v * width + 9]))
            .collect();
        band.sort_by(|x, y| x.1.total_cmp(&y.1));
        (heights, owner, vec![band, Vec::new()])
    }

    const SIDE: [Point2<f64>; 2] = [Point2::new(9.5, 1.0), Point2::new(9.5, 19.0)];

    /// The ends of the first side of `side` on a [`halves`] image, every side lifted to `lift`,
    /// the blob's cut and top at 10 and 20 mm; with labels (`owner`, and each blob's top) or
    /// without.
    fn first_ends(
        side: &[Point2<f64>],
        lift: f64,
        bands: &[Band],
        heights: &[f64],
        labels: Option<(&[u32], &[Option<f64>])>,
    ) -> Option<[f64; 2]> {
        let neighbours = labels.map(|(owner, tops)| Neighbours {
            owner,
            tops,
            index: 0,
        });
        end_lifts(
            side,
            &vec![lift; side.len()],
            bands,
            (0.01, 0.02),
            heights,
            20,
            neighbours.as_ref(),
        )[0]
    }

    #[test]
    fn a_chord_along_a_neighbour_stands_at_the_top_where_it_hides_the_wall_and_at_the_wall_where_it_shows()
     {
        // The side runs down the image (v growing), so its outside is to the right (u growing)
        // for a counter-clockwise loop in (u, v). The neighbour's top, level with the blob's, is
        // outside along the whole side; the blob's wall shows at the second end only.
        let (heights, owner, bands) = halves(0.02, 0..20, 13..20);
        let tops = [Some(0.02), Some(0.02)];
        let ends = first_ends(&SIDE, 0.011, &bands, &heights, Some((&owner, &tops)));
        assert_eq!(ends, Some([0.02, 0.011]));
        // Without neighbours nothing changes.
        let alone = first_ends(&SIDE, 0.011, &bands, &heights, None);
        assert_eq!(alone, Some([0.011, 0.011]));
    }

    #[test]
    fn a_taller_neighbour_hiding_the_top_stands_the_end_at_its_own_top() {
        // Only the first third has the neighbour outside; its top, 30 mm, hides the blob's 20 mm
        // top there.
        let (heights, owner, bands) = halves(0.03, 0..7, 0..0);
        let tops = [Some(0.02), Some(0.03)];
        let ends = first_ends(&SIDE, 0.02, &bands, &heights, Some((&owner, &tops)));
        assert_eq!(ends, Some([0.03, 0.02]));
    }

    #[test]
    fn a_neighbours_wall_seen_over_the_edge_changes_nothing_and_a_short_side_bounds_nothing() {
        // The neighbour's pixels outside stand 10 mm under its top: its wall, not its top.
        let (heights, owner, bands) = halves(0.03, 0..20, 13..20);
        let tops = [Some(0.02), Some(0.04)];
        let ends = first_ends(&SIDE, 0.011, &bands, &heights, Some((&owner, &tops)));
        assert_eq!(ends, Some([0.011, 0.011]));
        // A side of 5 pixels with a neighbour's top outside it bounds nothing.
        let tops = [Some(0.02), Some(0.03)];
        let short = [Point2::new(9.5, 1.0), Point2::new(9.5, 6.0)];
        let ends = first_ends(&short, 0.011, &bands, &heights, Some((&owner, &tops)));
        assert_eq!(ends, None);
    }

    #[test]
    fn a_short_side_with_too_few_pixels_of_its_own_bounds_nothing_where_labels_are_given() {
        // No neighbour outside: the table. The 5-pixel side's band holds one pixel, low on the
        // wall (a flying pixel, or the last of a wall a neighbour hides further on).
        let (heights, owner, _) = halves(0.02, 0..0, 0..0);
        let tops = [Some(0.02), None];
        let labels = Some((owner.as_slice(), tops.as_slice()));
        let short = [Point2::new(9.5, 1.0), Point2::new(9.5, 6.0)];
        let lone: Vec<Band> = vec![vec![(0.5, 0.011)], Vec::new()];
        assert_eq!(first_ends(&short, 0.011, &lone, &heights, labels), None);
        // Three pixels of its own say where it stands; without labels nothing changes.
        let three: Vec<Band> = vec![vec![(0.2, 0.011), (0.5, 0.011), (0.8, 0.012)], Vec::new()];
        assert_eq!(
            first_ends(&short, 0.011, &three, &heights, labels),
            Some([0.011, 0.011])
        );
        assert_eq!(
            first_ends(&short, 0.011, &lone, &heights, None),
            Some([0.011, 0.011])
        );
    }

    #[test]
    fn an_end_along_a_neighbour_with_two_pixels_of_its_own_both_at_the_top_is_a_top_edge() {
        // The neighbour, level with the blob, lies outside the whole side; the blob shows its
        // wall at the first end (three pixels low on it) and has two pixels at its top at the
        // second, a sharp corner's tip beside the neighbour.
        let (heights, owner, _) = halves(0.02, 0..20, 0..0);
        let tops = [Some(0.02), Some(0.02)];
        let cast = |second: [(f64, f64); 2]| {
            let mut band: Band = vec![(0.05, 0.011), (0.1, 0.012), (0.2, 0.011)];
            band.extend(second);
            band.sort_by(|x, y| x.1.total_cmp(&y.1));
            let bands = [band, Vec::new()];
            first_ends(&SIDE, 0.011, &bands, &heights, Some((&owner, &tops)))
        };
        assert_eq!(cast([(0.9, 0.0195), (0.95, 0.02)]), Some([0.011, 0.02]));
        // One of the two on the wall: too few to say, and the side keeps its height.
        assert_eq!(cast([(0.9, 0.012), (0.95, 0.02)]), Some([0.011, 0.011]));
    }
}
