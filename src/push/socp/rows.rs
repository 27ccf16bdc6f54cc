//! The rows a cluster may form: the closing axes to try, the half-planes that keep members clear of
//! their neighbours, the cheap test of a perfect row before any program, the judgement of a row
//! after its pushes, and the jaws a row is built for.

use nalgebra::{Point2, Vector2};

use super::Socp;
use crate::geometry::{ConvexPolygon, convex_hull, max_separation};
use crate::grasp::{Body, JawPose, Squeeze, squeeze};
use crate::push::row::Fence;
use crate::push::{Push, predict};
use crate::scene::Scene;

impl Socp {
    pub(super) fn axes(
        &self,
        starts: &[Point2<f64>],
        outlines: &[ConvexPolygon],
    ) -> Vec<Vector2<f64>> {
        let n = self.settings.axes;
        let mut axes: Vec<Vector2<f64>> = (0..n)
            .map(|k| {
                let angle = std::f64::consts::PI * k as f64 / n as f64;
                Vector2::new(angle.cos(), angle.sin())
            })
            .collect();
        // Edge normals: along them an object meets the plates and its neighbours flat.
        for outline in outlines {
            for (a, b) in outline.edges() {
                let edge = b - a;
                axes.push(Vector2::new(edge.y, -edge.x).normalize());
            }
        }
        for (a, p) in starts.iter().enumerate() {
            for q in &starts[a + 1..] {
                let joining = q - p;
                if joining.norm() > 0.0 {
                    axes.push(joining.normalize());
                }
            }
        }
        // Principal axis of the centroids.
        let mean = starts.iter().map(|p| p.coords).sum::<Vector2<f64>>() / starts.len() as f64;
        let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
        for p in starts {
            let d = p.coords - mean;
            xx += d.x * d.x;
            xy += d.x * d.y;
            yy += d.y * d.y;
        }
        let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
        axes.push(Vector2::new(angle.cos(), angle.sin()));
        axes
    }

    /// Half-planes keeping each member clear of the outside objects near the cluster.
    ///
    /// When a line separates an outside object from the hull of the whole cluster, that line (the
    /// axis of largest separation) fences every member: members may move anywhere on the cluster's
    /// side. An object reaching into the cluster's hull is fenced off from each member separately,
    /// along the axis of largest separation between the two.
    pub(super) fn fences(
        &self,
        scene: &Scene,
        members: &[usize],
        outlines: &[ConvexPolygon],
    ) -> Vec<Fence> {
        let points: Vec<Point2<f64>> = members
            .iter()
            .flat_map(|&i| scene.world_polygon(i).vertices().to_vec())
            .collect();
        let hull = ConvexPolygon::new(convex_hull(&points)).ok();
        let mut fences = Vec::new();
        for other in (0..scene.len()).filter(|o| !members.contains(o)) {
            let outline = scene.world_polygon(other);
            let whole = hull
                .as_ref()
                .map(|h| max_separation(outline, h))
                .filter(|&(_, separation)| separation > 0.0);
            for (m, &index) in members.iter().enumerate() {
                let own = scene.world_polygon(index);
                let (normal, separation) = match whole {
                    Some((normal, _)) => {
                        // The member's own gap along the cluster's fence.
                        let gap = own.projection(&normal).0 - outline.projection(&normal).1;
                        (normal, gap)
                    }
                    None => max_separation(outline, own),
                };
                if separation > self.settings.neighbourhood {
                    continue;
                }
                // n·p − h(−n) ≥ max_q n·x + kept gap, with h about the centroid.
                let kept = self.settings.clearance.min(separation.max(0.0));
                let far_side = outline.projection(&normal).1;
                let offset = far_side + kept + outlines[m].support(&-normal);
                // Never demand more than the member already has (rounding).
                let offset = offset.min(normal.dot(&scene.centroid(index).coords));
                fences.push(Fence {
                    member: m,
                    normal,
                    offset,
                });
            }
        }
        fences
    }

    /// Whether the grasp model holds a perfect row along `axis`: the members in `order`, centroids on
    /// one line, neighbours `gap` apart, jaws centred on it. A cheap stand-in, solved before any
    /// program, for whether rows along `axis` can be held.
    pub(super) fn proxy_held(
        &self,
        outlines: &[ConvexPolygon],
        masses: &[f64],
        order: &[usize],
        axis: &Vector2<f64>,
        gripper: &crate::scene::Gripper,
    ) -> bool {
        let mut placed = Vec::with_capacity(order.len());
        let mut at = 0.0;
        for (j, &m) in order.iter().enumerate() {
            if j > 0 {
                at += outlines[order[j - 1]].support(axis)
                    + outlines[m].support(&-axis)
                    + self.settings.gap;
            }
            placed.push(outlines[m].translated(&(axis * at)));
        }
        let (Some(&first), Some(&last)) = (order.first(), order.last()) else {
            return false;
        };
        let low = -outlines[first].support(&-axis);
        let high = at + outlines[last].support(axis);
        let jaws = JawPose {
            center: Point2::from(axis * ((low + high) / 2.0)),
            angle: axis.y.atan2(axis.x),
            opening: gripper.stroke,
        };
        let bodies: Vec<Body<'_>> = placed
            .iter()
            .zip(order)
            .map(|(outline, &m)| Body {
                outline,
                mass: masses[m],
            })
            .collect();
        matches!(
            self.memory.squeeze(&bodies, gripper, &jaws, self.problem.grasp_model()),
            Squeeze::Held { objects, .. } if objects.len() == order.len()
        )
    }

    /// Whether every member is carried when the jaws close at `jaws` after the pushes: by the grasp
    /// model alone, or under noise by the judge (`robust_rows`).
    pub(super) fn row_is_held(
        &self,
        scene: &Scene,
        members: &[usize],
        pushes: &[Push],
        jaws: &JawPose,
    ) -> bool {
        let Ok(after) = predict(scene, pushes) else {
            return false;
        };
        match self.judge.as_ref().filter(|_| self.settings.robust_rows) {
            Some(judge) => {
                let pushed: Vec<usize> = pushes
                    .iter()
                    .filter_map(|p| after.index_of(p.object))
                    .collect();
                judge.carries(&after, jaws, &pushed, members)
            }
            None => matches!(squeeze(&after, jaws, self.problem.grasp_model()),
                Squeeze::Held { objects, .. } if members.iter().all(|m| objects.contains(m))),
        }
    }
}

/// The jaws the row was built for: closing along `axis`, centred on the row's extent along it and on
/// its centre line across, fully open.
pub(super) fn intended_grasp(
    axis: &Vector2<f64>,
    targets: &[Point2<f64>],
    outlines: &[ConvexPolygon],
    centre_line: f64,
    stroke: f64,
) -> JawPose {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for (target, outline) in targets.iter().zip(outlines) {
        let at = target.coords.dot(axis);
        low = low.min(at - outline.support(&-axis));
        high = high.max(at + outline.support(axis));
    }
    let across = Vector2::new(-axis.y, axis.x);
    JawPose {
        center: Point2::from(axis * ((low + high) / 2.0) + across * centre_line),
        angle: axis.y.atan2(axis.x),
        opening: stroke,
    }
}

/// Up to `limit` orderings of `items`, the given order first (Heap's algorithm).
pub(super) fn permutations(items: &[usize], limit: usize) -> Vec<Vec<usize>> {
    let mut current = items.to_vec();
    let mut out = vec![current.clone()];
    let n = current.len();
    let mut counters = vec![0usize; n];
    let mut i = 0;
    while i < n && out.len() < limit {
        if counters[i] < i {
            if i % 2 == 0 {
                current.swap(0, i);
            } else {
                current.swap(counters[i], i);
            }
            out.push(current.clone());
            counters[i] += 1;
            i = 0;
        } else {
            counters[i] = 0;
            i += 1;
        }
    }
    out
}
