//! The rectangular area of the table the robot clears.

use nalgebra::{Point2, Vector2};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Largest magnitude of a workspace coordinate, metres. Geometry is computed to micrometres (contact
/// and overlap tolerances of 1 µm and below); at 1000 m a double still resolves 1e-13 m, and no table
/// a gripper reaches is larger. Object poses and vertices are bounded through the workspace.
pub const MAX_COORDINATE: f64 = 1000.0;

/// An axis-aligned rectangle of the table frame, metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Workspace {
    /// Lower-left corner `[x, y]`, metres.
    pub min: [f64; 2],
    /// Upper-right corner `[x, y]`, metres.
    pub max: [f64; 2],
}

impl Default for Workspace {
    /// 0.5 m × 0.4 m with its corner at the origin: a table area in easy reach of a UR5 (the Push-MOG
    /// paper does not give its workspace size).
    fn default() -> Self {
        Self::new(0.5, 0.4)
    }
}

impl Workspace {
    /// A `width × depth` rectangle (metres) with its lower-left corner at the origin.
    pub fn new(width: f64, depth: f64) -> Self {
        Self {
            min: [0.0, 0.0],
            max: [width, depth],
        }
    }

    /// Extent along x, metres.
    pub fn width(&self) -> f64 {
        self.max[0] - self.min[0]
    }

    /// Extent along y, metres.
    pub fn depth(&self) -> f64 {
        self.max[1] - self.min[1]
    }

    /// Length of the diagonal, metres.
    pub fn diagonal(&self) -> f64 {
        self.width().hypot(self.depth())
    }

    /// The lower-left corner.
    pub fn min_corner(&self) -> Point2<f64> {
        Point2::new(self.min[0], self.min[1])
    }

    /// The upper-right corner.
    pub fn max_corner(&self) -> Point2<f64> {
        Point2::new(self.max[0], self.max[1])
    }

    /// The gaps between the box `(low, high)` and the edges, metres, in the order left, bottom,
    /// right, top (negative where the box reaches past an edge).
    pub fn room(&self, (low, high): (Point2<f64>, Point2<f64>)) -> [f64; 4] {
        [
            low.x - self.min[0],
            low.y - self.min[1],
            self.max[0] - high.x,
            self.max[1] - high.y,
        ]
    }

    /// How far `point` may move along `direction` before it leaves the rectangle, metres:
    /// the distance to the first edge the ray from `point` crosses, in units of `direction`'s length
    /// (infinite for a zero direction). Negative when `point` is already past that edge.
    pub fn room_along(&self, point: &Point2<f64>, direction: &Vector2<f64>) -> f64 {
        // Distance from coordinate p, moving at u per metre, to the interval [lo, hi]'s end.
        let reach = |p: f64, u: f64, lo: f64, hi: f64| {
            if u > 1e-12 {
                (hi - p) / u
            } else if u < -1e-12 {
                (lo - p) / u
            } else {
                f64::INFINITY
            }
        };
        reach(point.x, direction.x, self.min[0], self.max[0]).min(reach(
            point.y,
            direction.y,
            self.min[1],
            self.max[1],
        ))
    }

    /// How far `point` lies outside the rectangle, metres (0 inside).
    pub fn outside_by(&self, point: &Point2<f64>) -> f64 {
        let dx = (self.min[0] - point.x).max(point.x - self.max[0]).max(0.0);
        let dy = (self.min[1] - point.y).max(point.y - self.max[1]).max(0.0);
        dx.hypot(dy)
    }

    /// Checks that the corners are finite and the rectangle has positive size.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming `min` or `max`.
    pub fn validate(&self) -> Result<()> {
        for (field, corner) in [("min", self.min), ("max", self.max)] {
            if !corner
                .iter()
                .all(|c| c.is_finite() && c.abs() <= MAX_COORDINATE)
            {
                return Err(Error::field(
                    "workspace",
                    field,
                    format!(
                        "coordinates must be finite and within ±{MAX_COORDINATE} m (a table, not a \
                         site; lengths are in metres), got {corner:?}"
                    ),
                ));
            }
        }
        if self.width() <= 0.0 || self.depth() <= 0.0 {
            return Err(Error::field(
                "workspace",
                "max",
                format!(
                    "must lie above and right of `min` {:?}, got {:?}",
                    self.min, self.max
                ),
            ));
        }
        Ok(())
    }
}
