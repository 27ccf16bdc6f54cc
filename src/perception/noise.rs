//! A depth camera's errors, added to an exact frame: test support, and the simulator's camera.
//!
//! - Each depth `z` gets Gaussian noise of standard deviation `σ(z) = a·z²`, the growth with
//!   the square of range that a structured-light or stereo camera's disparity error gives (with
//!   `a = 0.0025 m⁻¹`, σ = 1.2 mm at 0.7 m).
//! - A fraction of pixels return nothing (NaN), at random.
//! - At a depth edge (a 4-neighbour more than `edge_jump` farther or nearer), a pixel is a
//!   "flying pixel" with probability `flying`: its depth is a random mix of its own and the
//!   neighbour's, as when one pixel's footprint straddles the edge.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::blobs::four_neighbours;
use crate::random::SeededRng;

/// The noise of [`add_noise`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct DepthNoise {
    /// `a` in `σ(z) = a·z²`, per metre.
    pub sigma_per_square_metre: f64,
    /// Fraction of pixels that return nothing.
    pub dropped: f64,
    /// Probability that a pixel at a depth edge is a flying pixel.
    pub flying: f64,
    /// A depth difference between 4-neighbours that makes an edge, metres.
    pub edge_jump: f64,
}

impl Default for DepthNoise {
    /// `a = 0.0025 m⁻¹`, 2 % dropped, half of the edge pixels flying, edges of 5 mm and more: the
    /// noise issue 40's measurements were made with (`formulations/perception.md`).
    fn default() -> Self {
        Self {
            sigma_per_square_metre: 0.0025,
            dropped: 0.02,
            flying: 0.5,
            edge_jump: 0.005,
        }
    }
}

/// `depth` (row-major, `width` per row, metres, NaN for nothing) with the noise of `noise`, drawn
/// from `rng`.
pub fn add_noise(depth: &[f32], width: usize, noise: &DepthNoise, rng: &mut SeededRng) -> Vec<f32> {
    let height = depth.len() / width.max(1);
    let mut out = depth.to_vec();
    for v in 0..height {
        for u in 0..width {
            let i = v * width + u;
            let z = depth[i];
            if !z.is_finite() {
                continue;
            }
            let mut value = f64::from(z);
            // The neighbour across the largest jump, if that is an edge.
            let mut jump: Option<f64> = None;
            for n in four_neighbours(i, width, height) {
                let other = f64::from(depth[n]);
                if other.is_finite()
                    && (other - value).abs() > noise.edge_jump
                    && jump.is_none_or(|j| (other - value).abs() > (j - value).abs())
                {
                    jump = Some(other);
                }
            }
            if let Some(other) = jump
                && rng.unit() < noise.flying
            {
                value += rng.unit() * (other - value);
            }
            value += noise.sigma_per_square_metre * value * value * rng.normal();
            out[i] = if rng.unit() < noise.dropped {
                f32::NAN
            } else {
                value as f32
            };
        }
    }
    out
}

/// `labels` (row-major, `width` per row, 0 for none) with each label shrunk by `r` pixels: a pixel
/// keeps its label only when every pixel of the `(2r + 1)²` square about it (clipped to the image)
/// carries the same label, as a segmenter whose masks stop short of the objects' outlines. Two
/// touching objects are then parted by a strip of `2r` unlabelled pixels. `r = 0` changes nothing.
pub fn erode_labels(labels: &[u32], width: usize, r: usize) -> Vec<u32> {
    if r == 0 || width == 0 {
        return labels.to_vec();
    }
    let height = labels.len() / width;
    // Separable: whether the row's ±r pixels all carry the pixel's label, then the same down the
    // column of those answers.
    let mut rows = vec![false; labels.len()];
    for v in 0..height {
        for u in 0..width {
            let i = v * width + u;
            let l = labels[i];
            rows[i] =
                (u.saturating_sub(r)..=(u + r).min(width - 1)).all(|x| labels[v * width + x] == l);
        }
    }
    (0..labels.len())
        .map(|i| {
            let (u, v) = (i % width, i / width);
            let l = labels[i];
            let kept = (v.saturating_sub(r)..=(v + r).min(height - 1)).all(|y| {
                let k = y * width + u;
                rows[k] && labels[k] == l
            });
            if kept { l } else { 0 }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::erode_labels;

    #[test]
    fn erosion_keeps_what_a_square_of_one_label_surrounds() {
        // A 6 × 4 image: label 1 in columns 0–2, label 2 in columns 3–5.
        let width = 6;
        let labels: Vec<u32> = (0..24).map(|i| if i % width < 3 { 1 } else { 2 }).collect();
        assert_eq!(erode_labels(&labels, width, 0), labels);
        let eroded = erode_labels(&labels, width, 1);
        // The image's border clips the square; the seam between the labels is cleared on both
        // sides.
        let expected: Vec<u32> = (0..24)
            .map(|i| match i % width {
                0 | 1 => 1,
                4 | 5 => 2,
                _ => 0,
            })
            .collect();
        assert_eq!(eroded, expected);
    }

    /// The square of `r` about each pixel, checked pixel by pixel.
    fn brute(labels: &[u32], width: usize, r: usize) -> Vec<u32> {
        let height = labels.len() / width;
        (0..labels.len())
            .map(|i| {
                let (u, v) = (i % width, i / width);
                let l = labels[i];
                let same = (v.saturating_sub(r)..=(v + r).min(height - 1)).all(|y| {
                    (u.saturating_sub(r)..=(u + r).min(width - 1))
                        .all(|x| labels[y * width + x] == l)
                });
                if same { l } else { 0 }
            })
            .collect()
    }

    #[test]
    fn erosion_matches_the_square_checked_pixel_by_pixel() {
        let mut rng = crate::random::SeededRng::new(7);
        let (width, height) = (37, 23);
        // Blocks of random labels, so that runs of one label are a few pixels long.
        let labels: Vec<u32> = (0..width * height)
            .map(|i| {
                let (u, v) = (i % width / 4, i / width / 3);
                ((u * 31 + v * 17) % 5) as u32
            })
            .map(|l| if rng.unit() < 0.05 { 0 } else { l })
            .collect();
        for r in 0..4 {
            assert_eq!(
                erode_labels(&labels, width, r),
                brute(&labels, width, r),
                "r = {r}"
            );
        }
    }
}
