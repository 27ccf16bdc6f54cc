//! A base for objects whose outline has many vertices, and the collision groups that let it touch
//! only the table.
//!
//! rapier's contact between two faces keeps at most four vertices of each (parry3d 0.31's
//! `PolygonalFeatureMap for ConvexPolyhedron` takes the first four of a face), so the hull of an
//! outline of many short edges, a rounded corner traced vertex by vertex, stood on four points a
//! few millimetres apart: such objects rocked and crept up to 25 mm per trip while nothing touched
//! them (`formulations/grasping.md`, "Outlines of many vertices in the simulator"). Such an object
//! gets a second, massless collider, the prisms of the triangles from the outline's centroid to each
//! edge, which touches only the table: every face rapier compares with the table's has three
//! vertices and the object rests on all of its outline. The convex hull of the prism stays the
//! object's collider for everything else (fingers, other objects) and carries its mass.

use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::prelude::*;

use crate::geometry::ConvexPolygon;

/// Outlines of more vertices than this stand on a base ([`collider`]). Objects of the built-in
/// library (3 to 8 sides) and regular polygons of up to 24 sides, noise-free, moved at most 0.5 mm
/// per trip on the hull alone. The bound is 8 so that every run on the library, and every
/// committed table, stays as it was; giving bases of 5 to 8 vertices their whole outline too
/// changes those runs, and is left for a regeneration of them.
const WHOLE_HULL_UP_TO: usize = 8;

/// The base of an object of outline `polygon` (its own frame, at table level) and `height`; `None`
/// for outlines of at most [`WHOLE_HULL_UP_TO`] vertices, whose hull rests on the table itself.
pub(super) fn collider(polygon: &ConvexPolygon, height: f64) -> Option<ColliderBuilder> {
    let vertices = polygon.vertices();
    if vertices.len() <= WHOLE_HULL_UP_TO {
        return None;
    }
    let centre = polygon.centroid();
    let shapes = (0..vertices.len())
        .map(|i| {
            let corners = [centre, vertices[i], vertices[(i + 1) % vertices.len()]];
            let points: Vec<Vector> = corners
                .iter()
                .flat_map(|v| [Vector::new(v.x, v.y, 0.0), Vector::new(v.x, v.y, height)])
                .collect();
            SharedShape::convex_hull(&points).map(|shape| (Pose::IDENTITY, shape))
        })
        .collect::<Option<Vec<_>>>()?;
    Some(ColliderBuilder::compound(shapes))
}

/// The table is alone in `TABLE_GROUP`; fingers and objects are in every other group and touch
/// everything. The hull of an object that has a base touches everything but the table, and the
/// base touches only the table.
const TABLE_GROUP: Group = Group::GROUP_1;
const BASE_GROUP: Group = Group::GROUP_2;

pub(super) fn table_groups() -> InteractionGroups {
    InteractionGroups::new(TABLE_GROUP, Group::ALL, InteractionTestMode::And)
}

/// Fingers, and objects without a base.
pub(super) fn body_groups() -> InteractionGroups {
    InteractionGroups::new(
        Group::ALL.difference(TABLE_GROUP),
        Group::ALL,
        InteractionTestMode::And,
    )
}

pub(super) fn hull_over_base_groups() -> InteractionGroups {
    let above = Group::ALL.difference(TABLE_GROUP);
    InteractionGroups::new(above, above, InteractionTestMode::And)
}

pub(super) fn base_groups() -> InteractionGroups {
    InteractionGroups::new(BASE_GROUP, TABLE_GROUP, InteractionTestMode::And)
}
