//! The top of a row: which faces a rider can rest on, and the row's extent along the closing axis.

use nalgebra::{Isometry2, Point2, Vector2};

use crate::geometry::{ConvexPolygon, convex_hull};

/// The objects a grasp takes, as they stand: each one's outline on the table and its height, and
/// the grasp's closing axis.
#[derive(Clone, Debug)]
pub struct Row {
    /// Each member's outline in the table frame, metres.
    pub outlines: Vec<ConvexPolygon>,
    /// Each member's height, metres.
    pub heights: Vec<f64>,
    /// The closing axis, a unit vector.
    pub axis: Vector2<f64>,
    /// Where the jaws, closing, leave each member: its motion in the table frame from where it
    /// stands (by the grasp model's planar closing, `grasp::closed_motions`). `None`: the row is
    /// taken to stay as it stands.
    pub closing: Option<Vec<Isometry2<f64>>>,
}

impl Row {
    /// The row's extent along the closing axis: the smallest and largest `axis · p` over its
    /// members, metres. The pads close onto these two faces.
    pub fn extent(&self) -> (f64, f64) {
        self.outlines
            .iter()
            .map(|o| o.projection(&self.axis))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
                (lo.min(a), hi.max(b))
            })
    }

    /// The row's extent along the closing axis once the jaws have closed on it (where the pads
    /// end), metres; as it stands without a closing.
    pub fn closed_extent(&self) -> (f64, f64) {
        let Some(motions) = &self.closing else {
            return self.extent();
        };
        self.outlines
            .iter()
            .zip(motions)
            .map(|(o, m)| o.transformed(m).projection(&self.axis))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
                (lo.min(a), hi.max(b))
            })
    }
}

/// The top of a row on which riders may rest.
#[derive(Clone, Debug)]
pub struct Support {
    /// The height of the top, metres: the tallest member's.
    pub height: f64,
    /// The members whose top faces are at that height (within the tolerance), as positions in the
    /// row.
    pub members: Vec<usize>,
    /// Their top faces, in the table frame.
    pub faces: Vec<ConvexPolygon>,
    /// The hull of those faces: no rider's support polygon reaches beyond it.
    pub hull: ConvexPolygon,
}

impl Support {
    /// The top of `row`: the faces within `height_tolerance` of the tallest member's top. A rider
    /// bridging faces of unequal height would rest on the higher ones only, tilted; the tolerance
    /// is what the objects' own compliance takes up. `None` for an empty row.
    pub fn of(row: &Row, height_tolerance: f64) -> Option<Self> {
        let height = row
            .heights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let members: Vec<usize> = (0..row.heights.len())
            .filter(|&j| row.heights[j] >= height - height_tolerance)
            .collect();
        let faces: Vec<ConvexPolygon> = members.iter().map(|&j| row.outlines[j].clone()).collect();
        let points: Vec<Point2<f64>> = faces
            .iter()
            .flat_map(|f| f.vertices().iter().copied())
            .collect();
        let hull = ConvexPolygon::new(convex_hull(&points)).ok()?;
        Some(Self {
            height,
            members,
            faces,
            hull,
        })
    }
}
