//! Bounding discs of a set of polygons, sorted along x: which of them can come within a distance of
//! a point, without visiting them all.
//!
//! Disc `i` has the polygon's area centroid `c_i` as centre and the largest distance of a vertex
//! from it as radius `r_i`, so the polygon lies inside it. A query for the point `p` and reach `ρ`
//! returns every `i` with `|c_i − p| ≤ ρ + r_i`: a superset of the polygons within `ρ` of `p`, the
//! same test the planners made by scanning every object. Only discs whose centres lie within
//! `ρ + max_i r_i` of `p` along x are tested (a binary search in the sorted order), so a query on a
//! table of `N` objects costs `O(log N + k)` for `k` discs in that strip, instead of `O(N)`.

use nalgebra::Point2;

use super::ConvexPolygon;

/// Bounding discs of polygons, indexed by position.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Discs {
    centres: Vec<Point2<f64>>,
    radii: Vec<f64>,
    /// Positions sorted by centre x.
    order: Vec<usize>,
    /// Centre x in that order.
    xs: Vec<f64>,
    largest: f64,
}

impl Discs {
    /// The bounding discs of `polygons`, about their area centroids.
    pub fn of(polygons: &[ConvexPolygon]) -> Self {
        let centres: Vec<Point2<f64>> = polygons.iter().map(ConvexPolygon::centroid).collect();
        let radii = polygons
            .iter()
            .zip(&centres)
            .map(|(p, c)| p.radius_about(c))
            .collect();
        Self::new(centres, radii)
    }

    /// Discs with these centres and radii (equal lengths).
    pub fn new(centres: Vec<Point2<f64>>, radii: Vec<f64>) -> Self {
        assert_eq!(centres.len(), radii.len(), "one radius per centre");
        let mut order: Vec<usize> = (0..centres.len()).collect();
        order.sort_by(|&a, &b| centres[a].x.total_cmp(&centres[b].x));
        let xs = order.iter().map(|&i| centres[i].x).collect();
        let largest = radii.iter().copied().fold(0.0, f64::max);
        Self {
            centres,
            radii,
            order,
            xs,
            largest,
        }
    }

    /// Number of discs.
    pub fn len(&self) -> usize {
        self.centres.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.centres.is_empty()
    }

    /// Centre of disc `i` (the polygon's area centroid).
    pub fn centre(&self, i: usize) -> Point2<f64> {
        self.centres[i]
    }

    /// Radius of disc `i`.
    pub fn radius(&self, i: usize) -> f64 {
        self.radii[i]
    }

    /// Positions `i`, ascending, of the discs with `|c_i − point| ≤ reach + r_i`.
    pub fn within(&self, point: &Point2<f64>, reach: f64) -> Vec<usize> {
        // The strip is widened by a hair so that rounding in the subtraction never drops a disc the
        // exact test below keeps.
        let half = reach + self.largest + 1e-9 * (1.0 + point.x.abs());
        let start = self.xs.partition_point(|&x| x < point.x - half);
        let end = self.xs.partition_point(|&x| x <= point.x + half);
        let mut found: Vec<usize> = self.order[start..end]
            .iter()
            .copied()
            .filter(|&i| nalgebra::distance(&self.centres[i], point) <= reach + self.radii[i])
            .collect();
        found.sort_unstable();
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SeededRng;

    #[test]
    fn a_query_returns_exactly_what_a_scan_of_every_disc_returns() {
        let mut rng = SeededRng::new(5);
        let n = 300;
        let centres: Vec<Point2<f64>> = (0..n)
            .map(|_| Point2::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)))
            .collect();
        let radii: Vec<f64> = (0..n).map(|_| rng.uniform(0.0, 0.06)).collect();
        let discs = Discs::new(centres.clone(), radii.clone());
        for _ in 0..200 {
            let point = Point2::new(rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2));
            let reach = rng.uniform(0.0, 0.2);
            let scanned: Vec<usize> = (0..n)
                .filter(|&i| nalgebra::distance(&centres[i], &point) <= reach + radii[i])
                .collect();
            assert_eq!(discs.within(&point, reach), scanned);
        }
        assert!(Discs::default().within(&Point2::origin(), 1.0).is_empty());
    }

    #[test]
    fn a_polygon_lies_inside_its_disc() {
        let square = ConvexPolygon::rectangle(
            &Point2::new(0.3, -0.2),
            &nalgebra::Vector2::new(0.6, 0.8),
            0.01,
            0.02,
        );
        let discs = Discs::of(std::slice::from_ref(&square));
        let c = discs.centre(0);
        assert!((c - Point2::new(0.3, -0.2)).norm() < 1e-12);
        assert!((discs.radius(0) - 0.01f64.hypot(0.02)).abs() < 1e-12);
    }
}
