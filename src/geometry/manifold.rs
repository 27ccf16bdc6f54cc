//! Contact points of two convex polygons, for the planar closing simulation.
//!
//! The reference face is the edge of either polygon whose outward normal separates the two the most
//! (the separating-axis test over both polygons' edge normals). The other polygon's edge that faces
//! it most squarely (the incident edge) is clipped to the reference face's extent, and every clipped
//! point no further than `margin` from the face's line is a contact: one point for a vertex on a face,
//! two for touching faces.

use nalgebra::{Point2, Vector2};

use super::polygon::ConvexPolygon;

/// One contact point between two polygons.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// Where the polygons touch, midway between their boundaries.
    pub point: Point2<f64>,
    /// Unit normal pointing from the first polygon into the second.
    pub normal: Vector2<f64>,
    /// Distance between the boundaries along the normal, metres (negative when they interpenetrate).
    pub separation: f64,
}

/// The outward unit normal of edge `i` (from vertex `i` to `i + 1`) of a counter-clockwise polygon.
fn edge_normal(vertices: &[Point2<f64>], i: usize) -> Vector2<f64> {
    let a = vertices[i];
    let b = vertices[(i + 1) % vertices.len()];
    let d = b - a;
    Vector2::new(d.y, -d.x).normalize()
}

/// The edge of `reference` whose normal separates `other` the most, and that separation.
fn best_face(reference: &[Point2<f64>], other: &[Point2<f64>]) -> (usize, f64) {
    let mut best = (0, f64::NEG_INFINITY);
    for i in 0..reference.len() {
        let normal = edge_normal(reference, i);
        let separation = other
            .iter()
            .map(|v| normal.dot(&(v - reference[i])))
            .fold(f64::INFINITY, f64::min);
        if separation > best.1 {
            best = (i, separation);
        }
    }
    best
}

/// The contact points of `first` and `second` no more than `margin` metres apart (at most two);
/// empty when they are further apart.
pub fn contact_points(
    first: &ConvexPolygon,
    second: &ConvexPolygon,
    margin: f64,
) -> Vec<ContactPoint> {
    let (a, b) = (first.vertices(), second.vertices());
    let (face_a, separation_a) = best_face(a, b);
    if separation_a > margin {
        return Vec::new();
    }
    let (face_b, separation_b) = best_face(b, a);
    if separation_b > margin {
        return Vec::new();
    }
    // Prefer the first polygon's face unless the second's is clearly better (stable choice).
    let flip = separation_b > separation_a + 1e-6;
    let (reference, incident, face) = if flip { (b, a, face_b) } else { (a, b, face_a) };
    let normal = edge_normal(reference, face);
    let v1 = reference[face];
    let v2 = reference[(face + 1) % reference.len()];
    // The incident edge: the one whose normal points most against the reference normal.
    let incident_edge = (0..incident.len())
        .min_by(|&i, &j| {
            edge_normal(incident, i)
                .dot(&normal)
                .total_cmp(&edge_normal(incident, j).dot(&normal))
        })
        .unwrap_or(0);
    let mut points = [
        incident[incident_edge],
        incident[(incident_edge + 1) % incident.len()],
    ];
    // Clip the incident edge to the reference face's extent along its tangent.
    let tangent = (v2 - v1).normalize();
    let (low, high) = (tangent.dot(&v1.coords), tangent.dot(&v2.coords));
    for (bound, keep_above) in [(low, true), (high, false)] {
        let s = points.map(|p| tangent.dot(&p.coords) - bound);
        let inside = |d: f64| if keep_above { d >= 0.0 } else { d <= 0.0 };
        match (inside(s[0]), inside(s[1])) {
            (true, true) => {}
            (false, false) => return Vec::new(),
            (a_in, _) => {
                let t = s[0] / (s[0] - s[1]);
                let cut = points[0] + (points[1] - points[0]) * t;
                if a_in {
                    points[1] = cut;
                } else {
                    points[0] = cut;
                }
            }
        }
    }
    let sign = if flip { -1.0 } else { 1.0 };
    let mut contacts: Vec<ContactPoint> = Vec::with_capacity(2);
    for p in points {
        let separation = normal.dot(&(p - v1));
        if separation <= margin {
            let point = p - normal * (separation / 2.0);
            if contacts
                .iter()
                .all(|c| (c.point - point).norm_squared() > 1e-16)
            {
                contacts.push(ContactPoint {
                    point,
                    normal: normal * sign,
                    separation,
                });
            }
        }
    }
    contacts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polygon(points: &[(f64, f64)]) -> ConvexPolygon {
        ConvexPolygon::new(points.iter().map(|&(x, y)| Point2::new(x, y)).collect())
            .unwrap_or_else(|e| panic!("{e}"))
    }

    fn square(x: f64, y: f64, side: f64) -> ConvexPolygon {
        polygon(&[(x, y), (x + side, y), (x + side, y + side), (x, y + side)])
    }

    #[test]
    fn touching_faces_give_two_points_and_a_vertex_gives_one() {
        let a = square(0.0, 0.0, 1.0);
        let b = square(0.99, 0.5, 1.0);
        let contacts = contact_points(&a, &b, 0.0);
        assert_eq!(contacts.len(), 2);
        for c in &contacts {
            assert!((c.normal - Vector2::x()).norm() < 1e-12);
            assert!((c.separation + 0.01).abs() < 1e-12);
        }
        let ys: Vec<f64> = contacts.iter().map(|c| c.point.y).collect();
        assert!(ys.iter().any(|y| (y - 0.5).abs() < 1e-12));
        assert!(ys.iter().any(|y| (y - 1.0).abs() < 1e-12));
        // A diamond's corner pressing into the square's top face.
        let diamond = polygon(&[(0.5, 0.99), (1.0, 1.5), (0.5, 2.0), (0.0, 1.5)]);
        let contacts = contact_points(&a, &diamond, 0.0);
        assert_eq!(contacts.len(), 1);
        assert!((contacts[0].normal - Vector2::y()).norm() < 1e-12);
        // Swapped, the normal turns round.
        let swapped = contact_points(&diamond, &a, 0.0);
        assert_eq!(swapped.len(), 1);
        assert!((swapped[0].normal + Vector2::y()).norm() < 1e-12);
        // Apart by more than the margin: nothing.
        assert!(contact_points(&a, &square(1.1, 0.0, 1.0), 0.05).is_empty());
        assert_eq!(contact_points(&a, &square(1.1, 0.0, 1.0), 0.2).len(), 2);
    }
}
