//! One object on the table: an extruded convex polygon with an id, a pose and a height.

use nalgebra::{Isometry2, Point2, Vector2};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::geometry::ConvexPolygon;
pub use crate::id::ObjectId;

/// A planar pose: where an object's own frame sits on the table.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Pose {
    /// x of the object's frame origin in the table frame, metres.
    pub x: f64,
    /// y of the object's frame origin in the table frame, metres.
    pub y: f64,
    /// Rotation of the object's frame about the table normal, radians, counter-clockwise.
    pub yaw: f64,
}

impl Pose {
    /// A pose from its parts (metres, metres, radians).
    pub fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self { x, y, yaw }
    }

    /// The rigid transform from the object's frame to the table frame.
    pub fn isometry(&self) -> Isometry2<f64> {
        Isometry2::new(Vector2::new(self.x, self.y), self.yaw)
    }

    /// Whether all three numbers are finite.
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.yaw.is_finite()
    }
}

/// An object as stored in JSON: the raw form before validation.
///
/// `vertices` are in the object's own frame (metres), in either orientation; they are written back
/// counter-clockwise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    /// Unique id within the scene.
    pub id: ObjectId,
    /// Optional label, e.g. the object library's name for the shape.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Outline in the object's own frame, metres, `[x, y]` pairs; at least 3, convex.
    pub vertices: Vec<[f64; 2]>,
    /// Extrusion height in metres.
    pub height: f64,
    /// Pose of the object's frame on the table.
    pub pose: Pose,
    /// Mass in kilograms, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
}

/// A validated object: its outline is a [`ConvexPolygon`] in the object's own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Unique id within the scene.
    pub id: ObjectId,
    /// Optional label.
    pub name: Option<String>,
    /// Outline in the object's own frame, metres.
    pub polygon: ConvexPolygon,
    /// Pose of the object's frame on the table.
    pub pose: Pose,
    /// Extrusion height in metres.
    pub height: f64,
    /// Mass in kilograms, when known.
    pub mass: Option<f64>,
}

impl Object {
    /// The outline in the table frame.
    pub fn world_polygon(&self) -> ConvexPolygon {
        self.polygon.transformed(&self.pose.isometry())
    }

    /// The area centroid in the table frame, metres.
    pub fn world_centroid(&self) -> Point2<f64> {
        self.pose.isometry() * self.polygon.centroid()
    }

    /// The raw JSON form.
    pub fn to_spec(&self) -> ObjectSpec {
        ObjectSpec {
            id: self.id,
            name: self.name.clone(),
            vertices: self.polygon.vertices().iter().map(|v| [v.x, v.y]).collect(),
            height: self.height,
            pose: self.pose,
            mass: self.mass,
        }
    }
}
