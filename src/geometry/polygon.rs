//! The convex polygon type: construction with validation, area, centroid, support function and width.
//!
//! Vertices are stored counter-clockwise (positive signed area) whatever order they were given in, with
//! every turn strictly to the left: no repeated, collinear or reflex vertices.

use nalgebra::{Isometry2, Point2, Vector2};

/// Relative tolerance below which a turn counts as straight: the sine of the angle between two
/// consecutive edges.
const STRAIGHT_TURN_SINE: f64 = 1e-9;

/// Relative tolerance below which two consecutive vertices count as one point (a fraction of the
/// polygon's bounding-box diagonal).
const COINCIDENT_FRACTION: f64 = 1e-12;

/// A convex polygon with its vertices counter-clockwise and strictly convex.
///
/// Built only through [`ConvexPolygon::new`], which checks every property, so code that holds one can
/// trust it.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexPolygon {
    vertices: Vec<Point2<f64>>,
}

/// Why a list of vertices is not a convex polygon. Vertex indices refer to the list as it was given.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PolygonError {
    /// Fewer than three vertices.
    #[error("a polygon needs at least 3 vertices, got {count}")]
    TooFewVertices {
        /// How many were given.
        count: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {index} has a coordinate that is NaN or infinite")]
    NonFinite {
        /// The offending vertex.
        index: usize,
    },
    /// Two consecutive vertices coincide.
    #[error("vertices {first} and {second} coincide")]
    Coincident {
        /// The first of the pair.
        first: usize,
        /// The second of the pair.
        second: usize,
    },
    /// All vertices lie on one line, so the outline encloses no area.
    #[error("the outline has zero area: all its vertices lie on one line")]
    ZeroArea,
    /// A vertex lies on the straight line through its two neighbours.
    #[error("vertex {index} is collinear with its neighbours (remove it)")]
    Collinear {
        /// The offending vertex.
        index: usize,
    },
    /// The outline turns the other way at a vertex.
    #[error("the outline is not convex: it turns the other way at vertex {index}")]
    NotConvex {
        /// The first reflex vertex.
        index: usize,
    },
    /// The outline crosses itself: a bow-tie (turns both ways, no net area) or a star (turns one way
    /// but winds around more than once).
    #[error("the outline intersects itself")]
    SelfIntersecting {
        /// How many full turns the outline makes (0 for a bow-tie, 2 or more for a star).
        windings: u32,
    },
}

impl ConvexPolygon {
    /// Builds a convex polygon from its vertices in either orientation.
    ///
    /// # Errors
    /// A [`PolygonError`] naming the offending vertex when there are fewer than three vertices, a
    /// coordinate is not finite, two consecutive vertices coincide, the outline is collinear (zero area),
    /// a vertex is collinear with its neighbours, the outline is not convex or it intersects itself.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Point2;
    /// use pushmog::geometry::ConvexPolygon;
    /// // Clockwise input is accepted and stored counter-clockwise.
    /// let square = ConvexPolygon::new(vec![
    ///     Point2::new(0.0, 0.0), Point2::new(0.0, 1.0), Point2::new(1.0, 1.0), Point2::new(1.0, 0.0),
    /// ]).unwrap();
    /// assert!((square.area() - 1.0).abs() < 1e-12);
    /// ```
    pub fn new(vertices: Vec<Point2<f64>>) -> Result<Self, PolygonError> {
        let n = vertices.len();
        if n < 3 {
            return Err(PolygonError::TooFewVertices { count: n });
        }
        if let Some(index) = vertices
            .iter()
            .position(|v| !(v.x.is_finite() && v.y.is_finite()))
        {
            return Err(PolygonError::NonFinite { index });
        }
        let (lo, hi) = point_bounds(&vertices);
        let diagonal = (hi - lo).norm();
        for i in 0..n {
            let j = (i + 1) % n;
            if (vertices[j] - vertices[i]).norm() <= COINCIDENT_FRACTION * diagonal {
                return Err(PolygonError::Coincident {
                    first: i,
                    second: j,
                });
            }
        }
        // Turn at each vertex: sine of the angle from the incoming to the outgoing edge.
        let turns: Vec<f64> = (0..n)
            .map(|i| {
                let incoming = vertices[i] - vertices[(i + n - 1) % n];
                let outgoing = vertices[(i + 1) % n] - vertices[i];
                cross(&incoming, &outgoing) / (incoming.norm() * outgoing.norm())
            })
            .collect();
        if turns.iter().all(|s| s.abs() <= STRAIGHT_TURN_SINE) {
            return Err(PolygonError::ZeroArea);
        }
        let signed_area = shoelace(&vertices);
        if signed_area.abs() <= COINCIDENT_FRACTION * diagonal * diagonal {
            // Turns both ways and encloses no net area: a bow-tie.
            return Err(PolygonError::SelfIntersecting { windings: 0 });
        }
        let sense = signed_area.signum();
        // Report the first bad vertex in the order the caller gave.
        for (index, turn) in turns.iter().enumerate() {
            let turn = turn * sense;
            if turn.abs() <= STRAIGHT_TURN_SINE {
                return Err(PolygonError::Collinear { index });
            }
            if turn < 0.0 {
                return Err(PolygonError::NotConvex { index });
            }
        }
        let total_turn: f64 = (0..n)
            .map(|i| {
                let incoming = vertices[i] - vertices[(i + n - 1) % n];
                let outgoing = vertices[(i + 1) % n] - vertices[i];
                cross(&incoming, &outgoing)
                    .abs()
                    .atan2(incoming.dot(&outgoing))
            })
            .sum();
        let windings = (total_turn / std::f64::consts::TAU).round() as u32;
        if windings != 1 {
            return Err(PolygonError::SelfIntersecting { windings });
        }
        let mut vertices = vertices;
        if sense < 0.0 {
            vertices.reverse();
        }
        Ok(Self { vertices })
    }

    /// A rectangle centred on `center` with half-extents `half_along` along the unit vector `axis` and
    /// `half_across` across it (both positive and finite; a jaw plate, a finger, a swept band).
    pub fn rectangle(
        center: &Point2<f64>,
        axis: &Vector2<f64>,
        half_along: f64,
        half_across: f64,
    ) -> ConvexPolygon {
        let along = axis * half_along;
        let across = Vector2::new(-axis.y, axis.x) * half_across;
        ConvexPolygon {
            vertices: vec![
                center - along - across,
                center + along - across,
                center + along + across,
                center - along + across,
            ],
        }
    }

    /// The vertices, counter-clockwise.
    pub fn vertices(&self) -> &[Point2<f64>] {
        &self.vertices
    }

    /// The number of vertices (equal to the number of edges).
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Always `false`: a polygon has at least three vertices. Present for API symmetry with `len`.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Vertex `i` modulo the number of vertices.
    pub fn vertex(&self, i: usize) -> Point2<f64> {
        self.vertices[i % self.vertices.len()]
    }

    /// The edges as `(start, end)` pairs, counter-clockwise; edge `i` runs from vertex `i` to `i + 1`.
    pub fn edges(&self) -> impl Iterator<Item = (Point2<f64>, Point2<f64>)> + '_ {
        (0..self.len()).map(|i| (self.vertex(i), self.vertex(i + 1)))
    }

    /// Enclosed area in square metres.
    pub fn area(&self) -> f64 {
        shoelace(&self.vertices)
    }

    /// Area centroid (centre of mass of a uniform lamina), in the polygon's frame.
    pub fn centroid(&self) -> Point2<f64> {
        // Triangle fan from the first vertex, which keeps the sums well conditioned far from the origin.
        let origin = self.vertices[0];
        let mut weighted = Vector2::zeros();
        let mut twice_area = 0.0;
        for i in 1..self.len() - 1 {
            let a = self.vertices[i] - origin;
            let b = self.vertices[i + 1] - origin;
            let w = cross(&a, &b);
            twice_area += w;
            weighted += (a + b) * w;
        }
        origin + weighted / (3.0 * twice_area)
    }

    /// Mean squared distance of the area from the centroid, square metres: the squared radius of
    /// gyration of a uniform lamina (its moment of inertia is this times its mass).
    pub fn gyration_squared(&self) -> f64 {
        let c = self.centroid();
        let mut moment = 0.0;
        let mut area = 0.0;
        for i in 0..self.len() {
            let a = self.vertex(i) - c;
            let b = self.vertex(i + 1) - c;
            let w = cross(&a, &b);
            area += w / 2.0;
            // Second moment of the triangle (c, a, b) about c.
            moment += w / 12.0 * (a.dot(&a) + a.dot(&b) + b.dot(&b));
        }
        moment / area
    }

    /// Mean distance of the area from the centroid, metres (the lever arm of table friction when a
    /// uniformly supported object spins in place), by a 64-point rule on each fan triangle.
    pub fn mean_radius(&self) -> f64 {
        let c = self.centroid();
        let mut weighted = 0.0;
        let mut area = 0.0;
        const SPLIT: usize = 8;
        for i in 0..self.len() {
            let a = self.vertex(i) - c;
            let b = self.vertex(i + 1) - c;
            let w = cross(&a, &b) / 2.0;
            area += w;
            // The triangle (0, a, b) cut into SPLIT² equal triangles; each counts at its centroid.
            let (da, db) = (a / SPLIT as f64, b / SPLIT as f64);
            let mut sum = 0.0;
            for p in 0..SPLIT {
                for q in 0..SPLIT - p {
                    let corner = da * p as f64 + db * q as f64;
                    sum += (corner + (da + db) / 3.0).norm();
                    if p + q + 1 < SPLIT {
                        sum += (corner + (da + db) * 2.0 / 3.0).norm();
                    }
                }
            }
            weighted += w * sum / (SPLIT * SPLIT) as f64;
        }
        weighted / area
    }

    /// The polygon moved by a rigid transform (rotation then translation).
    pub fn transformed(&self, pose: &Isometry2<f64>) -> ConvexPolygon {
        ConvexPolygon {
            vertices: self.vertices.iter().map(|v| pose * v).collect(),
        }
    }

    /// The polygon moved by a translation.
    pub fn translated(&self, offset: &Vector2<f64>) -> ConvexPolygon {
        ConvexPolygon {
            vertices: self.vertices.iter().map(|v| v + offset).collect(),
        }
    }

    /// Support function `h(d) = max_v v·d`, in metres times the length of `direction`.
    pub fn support(&self, direction: &Vector2<f64>) -> f64 {
        self.vertices
            .iter()
            .map(|v| v.coords.dot(direction))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The vertex furthest along `direction` (the first such vertex on ties).
    pub fn support_point(&self, direction: &Vector2<f64>) -> Point2<f64> {
        let mut best = self.vertices[0];
        for v in &self.vertices[1..] {
            if v.coords.dot(direction) > best.coords.dot(direction) {
                best = *v;
            }
        }
        best
    }

    /// The interval `[min, max]` of `v·direction` over the polygon.
    pub fn projection(&self, direction: &Vector2<f64>) -> (f64, f64) {
        self.vertices
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                let t = v.coords.dot(direction);
                (lo.min(t), hi.max(t))
            })
    }

    /// Width in metres between the two supporting lines perpendicular to `direction` (any length but
    /// zero): the jaw opening that just touches the polygon when the jaws close along `direction`.
    pub fn width(&self, direction: &Vector2<f64>) -> f64 {
        let unit = direction.normalize();
        let (lo, hi) = self.projection(&unit);
        hi - lo
    }

    /// Axis-aligned bounding box as `(min corner, max corner)`.
    pub fn bounding_box(&self) -> (Point2<f64>, Point2<f64>) {
        point_bounds(&self.vertices)
    }

    /// The bounding box of this polygon swept along `offset` (its start and end positions together).
    pub fn swept_box(&self, offset: &Vector2<f64>) -> (Point2<f64>, Point2<f64>) {
        let (lo, hi) = self.bounding_box();
        (
            Point2::new(lo.x.min(lo.x + offset.x), lo.y.min(lo.y + offset.y)),
            Point2::new(hi.x.max(hi.x + offset.x), hi.y.max(hi.y + offset.y)),
        )
    }

    /// Whether this polygon's bounding box meets the box `[lo, hi]` (a cheap test before exact ones).
    pub fn box_meets(&self, (lo, hi): (Point2<f64>, Point2<f64>)) -> bool {
        let (a, b) = self.bounding_box();
        a.x <= hi.x && lo.x <= b.x && a.y <= hi.y && lo.y <= b.y
    }

    /// The largest distance in metres from `center` to a vertex: the radius of the smallest circle
    /// around `center` that holds the polygon.
    pub fn radius_about(&self, center: &Point2<f64>) -> f64 {
        self.vertices
            .iter()
            .map(|v| (v - center).norm())
            .fold(0.0, f64::max)
    }

    /// Whether `point` lies inside or on the boundary (within `tolerance` metres).
    pub fn contains_point(&self, point: &Point2<f64>, tolerance: f64) -> bool {
        self.edges().all(|(a, b)| {
            let edge = b - a;
            cross(&edge, &(point - a)) / edge.norm() >= -tolerance
        })
    }
}

/// The z-component of the cross product of two plane vectors.
pub fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Signed area by the shoelace formula, positive for counter-clockwise outlines, computed about the
/// first vertex.
fn shoelace(vertices: &[Point2<f64>]) -> f64 {
    let origin = vertices[0];
    let mut twice = 0.0;
    for i in 1..vertices.len() - 1 {
        twice += cross(&(vertices[i] - origin), &(vertices[i + 1] - origin));
    }
    twice / 2.0
}

/// Smallest axis-parallel box around `points`: lower and upper corners (infinite, inverted, for none).
pub fn point_bounds(points: &[Point2<f64>]) -> (Point2<f64>, Point2<f64>) {
    let mut lo = Point2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in points {
        lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    (lo, hi)
}

#[cfg(test)]
mod moment_tests {
    use super::*;

    #[test]
    fn moments_of_a_square_match_closed_forms() {
        let s = 0.03;
        let square = ConvexPolygon::new(vec![
            Point2::new(0.1, 0.2),
            Point2::new(0.1 + s, 0.2),
            Point2::new(0.1 + s, 0.2 + s),
            Point2::new(0.1, 0.2 + s),
        ])
        .unwrap_or_else(|e| panic!("{e}"));
        assert!((square.gyration_squared() - s * s / 6.0).abs() < 1e-15);
        // Mean distance from the centre of a unit square: (√2 + ln(1 + √2)) / 6.
        let exact = s * (2f64.sqrt() + (1.0 + 2f64.sqrt()).ln()) / 6.0;
        assert!(
            (square.mean_radius() - exact).abs() < 0.005 * exact,
            "{} vs {exact}",
            square.mean_radius()
        );
    }
}

/// The axis-aligned square with lower-left corner `(x, y)` and the given side, for tests.
#[cfg(test)]
pub(crate) fn square(x: f64, y: f64, side: f64) -> ConvexPolygon {
    let half = side / 2.0;
    ConvexPolygon::rectangle(&Point2::new(x + half, y + half), &Vector2::x(), half, half)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(points: &[(f64, f64)]) -> Result<ConvexPolygon, PolygonError> {
        ConvexPolygon::new(points.iter().map(|&(x, y)| Point2::new(x, y)).collect())
    }

    #[test]
    fn clockwise_input_is_stored_counter_clockwise() {
        let p = poly(&[(0.0, 0.0), (0.0, 1.0), (2.0, 1.0), (2.0, 0.0)]).unwrap();
        assert!(p.area() > 0.0);
        assert!((p.area() - 2.0).abs() < 1e-12);
        assert!((p.centroid() - Point2::new(1.0, 0.5)).norm() < 1e-12);
    }

    #[test]
    fn each_defect_is_named() {
        assert_eq!(
            poly(&[(0.0, 0.0), (1.0, 0.0)]),
            Err(PolygonError::TooFewVertices { count: 2 })
        );
        assert_eq!(
            poly(&[(0.0, 0.0), (1.0, f64::NAN), (0.0, 1.0)]),
            Err(PolygonError::NonFinite { index: 1 })
        );
        assert_eq!(
            poly(&[(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)]),
            Err(PolygonError::ZeroArea)
        );
        assert_eq!(
            poly(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (1.0, 1.0)]),
            Err(PolygonError::Collinear { index: 1 })
        );
        assert_eq!(
            poly(&[(0.0, 0.0), (2.0, 0.0), (1.0, 0.5), (2.0, 2.0), (0.0, 2.0)]),
            Err(PolygonError::NotConvex { index: 2 })
        );
        assert!(matches!(
            poly(&[(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]),
            Err(PolygonError::SelfIntersecting { .. })
        ));
        assert_eq!(
            poly(&[(0.0, 0.0), (1.0, 0.0), (1.0, 0.0), (0.0, 1.0)]),
            Err(PolygonError::Coincident {
                first: 1,
                second: 2
            })
        );
    }

    #[test]
    fn a_pentagram_is_self_intersecting() {
        let star: Vec<(f64, f64)> = (0..5)
            .map(|k| {
                let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
                (a.cos(), a.sin())
            })
            .collect();
        assert_eq!(
            poly(&star),
            Err(PolygonError::SelfIntersecting { windings: 2 })
        );
    }
}
