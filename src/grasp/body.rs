//! An object as the grasp model and the closing simulation see it: a leaf both depend on.

use crate::geometry::ConvexPolygon;

/// An object as the grasp model sees it: its outline on the table and its mass.
#[derive(Clone, Copy, Debug)]
pub struct Body<'a> {
    /// Outline in the table frame.
    pub outline: &'a ConvexPolygon,
    /// Mass, kilograms.
    pub mass: f64,
}
