//! Riders: single objects placed on the top of a pushed row just before the row's grasp, so that
//! they travel on the row without taking jaw width (the Push-MOG paper's future work, vertical
//! stacking). This module holds the quasi-static checks and the placement search; the rider's choice
//! and price are in `policy/riders.rs`, a rider left standing on its row in `policy/perched.rs`, and
//! the place action in each executor. The maths, its assumptions and what was measured are in
//! `formulations/stacking.md`.
//!
//! With the row's closing axis `u`, the arm's horizontal acceleration `a` and gravity `g`:
//! - **Support** ([`Support`]): the row's top is the set of its members' top faces `T_j` at the top
//!   height (within `height_tolerance` of the tallest). A rider of footprint `F` rests on the faces
//!   it meets; it stands when its centroid `c` lies in `hull(∪ F ∩ T_j)` at least `m` from every
//!   edge, `m = max(support_margin, (a/g)·h/2)`; the second term is the tipping bound of a uniform
//!   prism of height `h`, whose centroid is `h/2` above its base.
//! - **Clear of the pads**: along `u`, `F` lies within the row's extent `[lo, hi]` inset by
//!   `pad_margin`, so that no pad can touch it; along the plates it may overhang. Given the row's
//!   closing ([`Row::closing`], each member's motion `M_j` as the jaws close), the same holds where
//!   the pads end, `[lo', hi']`, for `M_j F` with `j` the member under the rider's centroid (every
//!   member it rests on when the centroid lies over a gap).
//! - **No sliding**: `μ_object ≥ slide_factor · a/g`.
//! - **Lifting** ([`plates_carry`]): the plates carry the row and its riders by friction,
//!   `μ_jaw · N ≥ (Σ m_row + Σ m_riders)·g / 2`.
//!
//! The search ([`place_rider`]) tries `yaws` turns of the rider. For each, the strip of centroid
//! positions that keeps `F` clear of the pads is linear in the translation, and so is the support
//! hull inset by `t`; bisection on `t` finds the largest inset for which they meet, and the centroid
//! of that meeting is the candidate. With a closing there is one strip per face, shifted by its
//! member's motion along `u`, and one for all faces. The best candidate is then checked exactly
//! against the faces it meets and, with a closing, against the closed pads.

mod closed;
mod placement;
mod support;

pub use placement::{
    NoPlacement, Placement, StackSettings, place_rider, plates_carry, standing_margin,
};
pub use support::{Row, Support};

pub use crate::problem::GRAVITY;

/// The tipping bound: how far a uniform prism of `height` must keep its centroid from the edge of
/// its support so that a horizontal acceleration `acceleration` does not tip it, metres:
/// `(a/g)·h/2` (moments about the edge: the inertial force `m·a` at height `h/2` against the weight
/// `m·g` at lever `d`).
pub fn tipping_bound(height: f64, acceleration: f64) -> f64 {
    acceleration / GRAVITY * height / 2.0
}
