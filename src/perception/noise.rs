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
