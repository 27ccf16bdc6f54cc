//! Where the pads end once the jaws have closed on a row (`formulations/stacking.md`, "Where the
//! pads end"): the closed row's extent along the closing axis, how far each member moves along it,
//! and whether a rider carried by its member keeps the pad margin there.

use nalgebra::{Isometry2, Point2, Vector2};

use super::support::Row;
use crate::geometry::ConvexPolygon;

/// The pads' closed places `[lo, hi]` along the closing axis, each member's motion as the jaws
/// close, and its centroid's shift along the axis on the way, metres.
pub(super) struct Closed<'a> {
    pub lo: f64,
    pub hi: f64,
    pub shifts: Vec<f64>,
    motions: &'a [Isometry2<f64>],
    axis: Vector2<f64>,
}

impl<'a> Closed<'a> {
    /// `row` closed by `motions`, one per member.
    pub fn of(row: &Row, motions: &'a [Isometry2<f64>]) -> Self {
        let (lo, hi) = row.closed_extent();
        let shifts = row
            .outlines
            .iter()
            .zip(motions)
            .map(|(outline, motion)| {
                let centroid = outline.centroid();
                row.axis.dot(&((motion * centroid) - centroid))
            })
            .collect();
        Self {
            lo,
            hi,
            shifts,
            motions,
            axis: row.axis,
        }
    }

    /// Whether `footprint`, carried by each of the members `carriers` in turn (turning with it as
    /// well), stays at least `pad` inside the closed pads.
    pub fn clear_of_pads(&self, footprint: &ConvexPolygon, carriers: &[usize], pad: f64) -> bool {
        carriers.iter().all(|&j| {
            let (front, back) = footprint
                .transformed(&self.motions[j])
                .projection(&self.axis);
            front >= self.lo + pad - 1e-12 && back <= self.hi - pad + 1e-12
        })
    }
}

/// The members that carry a rider resting on `resting_on` when the row closes under it: the one
/// whose face holds its centroid, which bears most of its weight and so holds it by friction while
/// the others slide under it; all of them when the centroid lies over a gap between faces.
pub(super) fn carriers(row: &Row, centroid: &Point2<f64>, resting_on: &[usize]) -> Vec<usize> {
    let under: Vec<usize> = resting_on
        .iter()
        .copied()
        .filter(|&j| row.outlines[j].contains_point(centroid, 0.0))
        .collect();
    if under.is_empty() {
        resting_on.to_vec()
    } else {
        under
    }
}
