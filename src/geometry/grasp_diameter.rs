//! Minimum grasp diameter of a convex polygon: the narrowest jaw opening at which a parallel-jaw gripper
//! holds the object in a stable two-contact grasp.
//!
//! # Which jaw contacts are stable
//! Parallel jaws touch a convex polygon on its two supporting lines perpendicular to the closing axis
//! `u`. The contacts can be (a) two parallel edges, (b) a vertex opposite an edge, or (c) two vertices.
//! With friction coefficient μ, two contacts `p1`, `p2` with inward normals `n1`, `n2` are in force
//! closure when each normal makes an angle of at most `atan μ` with the line `p1 p2` (Nguyen 1988). A
//! jaw plate's normal is `±u`, so a grasp is robust for any μ ≥ 0 when the line joining the contacts is
//! parallel to `u`: for an edge contact, the perpendicular from the opposite contact lands on the edge.
//!
//! The candidate set used by the public multi-object-grasping code (see `formulations/references.md`)
//! keeps exactly such configurations: (a) parallel edges at their distance; (b) a vertex whose
//! perpendicular foot lands on the opposite edge, with both edges at the vertex within 90° of that
//! perpendicular; (c) two vertices whose joining segment is within 90° of the edges at both. The
//! smallest such distance is the object's *minimum grasp diameter* `d*`.
//!
//! # Why this equals the minimum width
//! Let `w(θ)` be the width of the polygon along `u(θ) = (cos θ, sin θ)`. Every stable configuration above
//! is a configuration of the two supporting lines, so `d* ≥ min_θ w(θ)`. Conversely, `w` is piecewise of
//! the form `|q − p| cos(θ − φ)` between the angles at which a supporting vertex changes, so it is
//! concave on each piece and its minimum sits where a supporting line is flush with an edge (a piece
//! boundary). At that minimum, the perpendicular from the opposite vertex lands on the edge: if its foot
//! fell beyond an end `b` of the edge, turning the lines about `b` and the vertex would make them
//! narrower (the width `|v − b| cos(θ − φ)` has non-zero slope when `v − b` is not parallel to `u`),
//! contradicting minimality. So the minimum width is a stable configuration of kind (a) or (b), and
//! `d* = min_θ w(θ)`.
//!
//! # Algorithm
//! Rotating calipers: for each edge, the furthest vertex from the edge's line is found by a pointer that
//! only moves forward around the polygon, so all `n` edge widths take `O(n)` time in total.

use nalgebra::{Point2, Vector2};

use super::polygon::{ConvexPolygon, cross};

/// The narrowest stable two-jaw grasp of one convex polygon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GraspDiameter {
    /// The jaw opening in metres at which both jaws touch: the polygon's minimum width.
    pub diameter: f64,
    /// Unit closing axis, the inward normal of the flush edge (pointing from that edge into the polygon),
    /// in the polygon's frame.
    pub axis: Vector2<f64>,
    /// Index of the edge one jaw lies flush against (from vertex `edge` to vertex `edge + 1`).
    pub edge: usize,
    /// Index of the vertex the other jaw touches (on a tie between two vertices of a parallel edge, the
    /// first one reached counter-clockwise).
    pub vertex: usize,
}

impl GraspDiameter {
    /// The two jaw contact points `[on the flush edge, on the opposite side]`, in the polygon's frame,
    /// joined by a segment parallel to [`GraspDiameter::axis`]. They sit in the middle of the stretch
    /// where the flush edge and the opposite supporting vertex (or parallel edge) face each other, the
    /// contact least sensitive to a sideways error.
    pub fn contacts(&self, polygon: &ConvexPolygon) -> [Point2<f64>; 2] {
        let start = polygon.vertex(self.edge);
        let along = polygon.vertex(self.edge + 1) - start;
        let length = along.norm();
        let tangent = along / length;
        // Vertices on the far supporting line (one, or two for a parallel edge).
        let tolerance = 1e-9 * length.max(self.diameter);
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in polygon.vertices() {
            if (v - start).dot(&self.axis) >= self.diameter - tolerance {
                let s = (v - start).dot(&tangent);
                low = low.min(s);
                high = high.max(s);
            }
        }
        // The facing stretch is never empty at the minimum width (module docs); clamp for rounding.
        let middle = ((low.max(0.0) + high.min(length)) / 2.0).clamp(0.0, length);
        let on_edge = start + tangent * middle;
        [on_edge, on_edge + self.axis * self.diameter]
    }
}

/// Minimum grasp diameter of a convex polygon by rotating calipers, in `O(n)`.
///
/// # Example
/// ```
/// use nalgebra::Point2;
/// use pushmog::geometry::{ConvexPolygon, min_grasp_diameter};
/// let rectangle = ConvexPolygon::new(vec![
///     Point2::new(0.0, 0.0), Point2::new(0.04, 0.0), Point2::new(0.04, 0.025), Point2::new(0.0, 0.025),
/// ]).unwrap();
/// assert!((min_grasp_diameter(&rectangle).diameter - 0.025).abs() < 1e-12);
/// ```
pub fn min_grasp_diameter(polygon: &ConvexPolygon) -> GraspDiameter {
    let n = polygon.len();
    let height = |edge: usize, vertex: usize| {
        let a = polygon.vertex(edge);
        let along = polygon.vertex(edge + 1) - a;
        cross(&along, &(polygon.vertex(vertex) - a)) / along.norm()
    };
    // Furthest vertex from edge 0: heights rise then fall around a convex polygon.
    let mut far = 1;
    while height(0, far + 1) > height(0, far) {
        far += 1;
    }
    let mut best = (f64::INFINITY, 0, far % n);
    for edge in 0..n {
        // Moving to the next edge can only move the furthest vertex forward; each pointer step is
        // taken at most n times over the whole loop.
        while height(edge, far + 1) > height(edge, far) {
            far += 1;
        }
        let h = height(edge, far);
        if h < best.0 {
            best = (h, edge, far % n);
        }
    }
    let (diameter, edge, vertex) = best;
    let along = polygon.vertex(edge + 1) - polygon.vertex(edge);
    let axis = Vector2::new(-along.y, along.x).normalize();
    GraspDiameter {
        diameter,
        axis,
        edge,
        vertex,
    }
}

/// Every stable edge-flush grasp of a polygon: for each edge, the jaw flush with it and the other jaw on
/// the furthest vertex, kept when the perpendicular from that vertex lands on the edge (kinds (a) and
/// (b) of the module docs). The narrowest is [`min_grasp_diameter`]. `O(n²)`, for the handful of
/// vertices of an object.
pub fn edge_grasps(polygon: &ConvexPolygon) -> Vec<GraspDiameter> {
    let n = polygon.len();
    let mut grasps = Vec::new();
    for edge in 0..n {
        let start = polygon.vertex(edge);
        let along = polygon.vertex(edge + 1) - start;
        let length = along.norm();
        let axis = Vector2::new(-along.y, along.x) / length;
        let (mut vertex, mut diameter) = (0, f64::NEG_INFINITY);
        for k in 0..n {
            let h = (polygon.vertex(k) - start).dot(&axis);
            if h > diameter {
                (vertex, diameter) = (k, h);
            }
        }
        let tangent = along / length;
        let tolerance = 1e-9 * length.max(diameter);
        let lands_on_edge = polygon.vertices().iter().any(|v| {
            let s = (v - start).dot(&tangent);
            (v - start).dot(&axis) >= diameter - tolerance
                && s >= -tolerance
                && s <= length + tolerance
        });
        if lands_on_edge {
            grasps.push(GraspDiameter {
                diameter,
                axis,
                edge,
                vertex,
            });
        }
    }
    grasps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equilateral_triangle_diameter_is_its_height() {
        let side = 0.03;
        let t = ConvexPolygon::new(vec![
            Point2::new(0.0, 0.0),
            Point2::new(side, 0.0),
            Point2::new(side / 2.0, side * 3f64.sqrt() / 2.0),
        ])
        .unwrap();
        let g = min_grasp_diameter(&t);
        assert!((g.diameter - side * 3f64.sqrt() / 2.0).abs() < 1e-12);
        // The contacts are the middle of the base and the apex.
        let [foot, apex] = g.contacts(&t);
        assert!(t.contains_point(&foot, 1e-12));
        assert!((apex - t.vertex(g.vertex)).norm() < 1e-12);
    }

    #[test]
    fn edge_grasps_include_the_narrowest() {
        let rectangle = ConvexPolygon::new(vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.04, 0.0),
            Point2::new(0.04, 0.02),
            Point2::new(0.0, 0.02),
        ])
        .unwrap();
        let all = edge_grasps(&rectangle);
        assert_eq!(all.len(), 4);
        let narrowest = all.iter().map(|g| g.diameter).fold(f64::INFINITY, f64::min);
        assert!((narrowest - min_grasp_diameter(&rectangle).diameter).abs() < 1e-15);
        // An obtuse triangle: the apex's perpendicular misses both short sides.
        let obtuse = ConvexPolygon::new(vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.046, 0.0),
            Point2::new(0.012, 0.008),
        ])
        .unwrap();
        assert_eq!(edge_grasps(&obtuse).len(), 1);
    }

    #[test]
    fn square_contacts_are_mid_edge() {
        let square = ConvexPolygon::new(vec![
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(1.0, 1.0),
            Point2::new(0.0, 1.0),
        ])
        .unwrap();
        let g = min_grasp_diameter(&square);
        let [a, b] = g.contacts(&square);
        assert!((a - Point2::new(0.5, 0.0)).norm() < 1e-12, "{a}");
        assert!((b - Point2::new(0.5, 1.0)).norm() < 1e-12, "{b}");
    }
}
