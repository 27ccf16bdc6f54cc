//! Candidate jaws of the multi-object planner: a grid of centres over the targets' hull, closing
//! angles from the targets' edges, and for each angle the centre that fits the targets best; and a
//! candidate moved to the middle of what it catches (`centre_along_axis`).

use nalgebra::{Point2, Vector2};

use super::MultiObject;
use crate::geometry::{ConvexPolygon, convex_hull, point_bounds};
use crate::grasp::JawPose;
use crate::grasp::model::row_in_scene;
use crate::scene::Scene;

impl MultiObject {
    fn centres(&self, scene: &Scene, targets: &[usize]) -> Vec<Point2<f64>> {
        let outline: Vec<Point2<f64>> = targets
            .iter()
            .flat_map(|&i| scene.world_polygon(i).vertices().to_vec())
            .collect();
        let hull = ConvexPolygon::new(convex_hull(&outline)).ok();
        let (lo, hi) = point_bounds(&outline);
        let [nx, ny] = self.settings.grid;
        let mut centres = Vec::new();
        for ix in 0..nx {
            for iy in 0..ny {
                let p = Point2::new(
                    lo.x + (hi.x - lo.x) * (ix as f64 + 0.5) / nx as f64,
                    lo.y + (hi.y - lo.y) * (iy as f64 + 0.5) / ny as f64,
                );
                if hull.as_ref().is_none_or(|h| h.contains_point(&p, 0.0)) {
                    centres.push(p);
                }
            }
        }
        for (k, &a) in targets.iter().enumerate() {
            centres.push(scene.centroid(a));
            for &b in &targets[k + 1..] {
                centres.push(nalgebra::center(&scene.centroid(a), &scene.centroid(b)));
            }
        }
        centres
    }

    /// Every jaw pose to evaluate: grid centres × angles, the centre aligned with the targets for
    /// every angle, and the caller's hints.
    pub(super) fn candidates(
        &self,
        scene: &Scene,
        targets: &[usize],
        hints: &[JawPose],
    ) -> Vec<JawPose> {
        let opening = self.settings.opening_fraction * scene.gripper().stroke;
        let angles = self.angles(scene, targets);
        let mut poses: Vec<JawPose> = hints.to_vec();
        for &angle in &angles {
            poses.push(JawPose {
                center: aligned_centre(scene, targets, angle),
                angle,
                opening,
            });
        }
        for center in self.centres(scene, targets) {
            for &angle in &angles {
                poses.push(JawPose {
                    center,
                    angle,
                    opening,
                });
            }
        }
        poses
    }

    /// `jaws` moved along their closing axis to the middle of `caught`'s extent along it (scene
    /// indices, sorted), with the moved plates' clearance (`clearance`, `pushed` objects kept
    /// further from), when the move catches the same objects, stands apart from every jaw pose in
    /// `avoid` and keeps the plates clear enough; `None` otherwise (`centre_along_axis`).
    pub(super) fn centred(
        &self,
        scene: &Scene,
        jaws: &JawPose,
        caught: &[usize],
        avoid: &[JawPose],
        pushed: &[usize],
    ) -> Option<(JawPose, f64)> {
        let axis = jaws.axis();
        let (low, high) = caught
            .iter()
            .map(|&i| scene.world_polygon(i).projection(&axis))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
                (lo.min(a), hi.max(b))
            });
        let shift = (low + high) / 2.0 - jaws.center.coords.dot(&axis);
        if !shift.is_finite() || shift.abs() < 1e-6 {
            return None;
        }
        let moved = JawPose {
            center: jaws.center + axis * shift,
            ..*jaws
        };
        let mut same = row_in_scene(scene, &moved, self.problem.grasp_model()).ok()?;
        same.sort_unstable();
        if same != caught || avoid.iter().any(|a| a.same_place(&moved)) {
            return None;
        }
        let (clearance, enough) = self.clearance(scene, &moved, pushed);
        enough.then_some((moved, clearance))
    }

    fn angles(&self, scene: &Scene, targets: &[usize]) -> Vec<f64> {
        let n = self.settings.angles;
        let mut angles: Vec<f64> = (0..n)
            .map(|k| std::f64::consts::PI * k as f64 / n as f64)
            .collect();
        let half_turn = |v: Vector2<f64>| v.y.atan2(v.x).rem_euclid(std::f64::consts::PI);
        for (k, &a) in targets.iter().enumerate() {
            let object = &scene.objects()[a];
            angles.push(half_turn(
                object.pose.isometry() * scene.grasp_diameter(a).axis,
            ));
            for &b in &targets[k + 1..] {
                let joining = scene.centroid(b) - scene.centroid(a);
                if joining.norm() > 0.0 {
                    angles.push(half_turn(joining));
                }
            }
        }
        angles
    }
}

/// The jaw centre that fits the targets best for closing along `angle`: the middle of their extent
/// along the axis, and the middle of the band across it that all of them cover (or the mean of their
/// middles when there is none).
fn aligned_centre(scene: &Scene, targets: &[usize], angle: f64) -> Point2<f64> {
    let axis = Vector2::new(angle.cos(), angle.sin());
    let across = Vector2::new(-axis.y, axis.x);
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut band_low, mut band_high) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut middles = 0.0;
    for &i in targets {
        let outline = scene.world_polygon(i);
        let (a, b) = outline.projection(&axis);
        low = low.min(a);
        high = high.max(b);
        let (c, d) = outline.projection(&across);
        band_low = band_low.max(c);
        band_high = band_high.min(d);
        middles += (c + d) / 2.0;
    }
    let along = (low + high) / 2.0;
    let side = if band_low <= band_high {
        (band_low + band_high) / 2.0
    } else {
        middles / targets.len() as f64
    };
    Point2::from(axis * along + across * side)
}
