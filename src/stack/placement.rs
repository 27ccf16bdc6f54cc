//! Where a rider goes on a row's top: the search over its turns and translations, and the checks
//! that decide whether it rides (`formulations/stacking.md`).

use std::f64::consts::TAU;

use nalgebra::{Isometry2, Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::closed::{Closed, carriers};
use super::support::{Row, Support};
use super::{GRAVITY, tipping_bound};
use crate::geometry::{ConvexPolygon, clip, half_planes, tidy_polygon};
use crate::scene::Pose;

/// What the rider checks allow.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct StackSettings {
    /// Top faces within this of the tallest member's top count as one support, metres. Default
    /// 2 mm.
    pub height_tolerance: f64,
    /// Least distance from the rider's centroid to the edge of what it rests on, covering where it
    /// is seen and where it is put, metres. Default 5 mm. The tipping bound is applied when larger.
    /// The rider choice also keeps riders off rows with a member's centroid farther than half the
    /// plate length less this margin from the plates' centre line (`policy::riders`).
    pub support_margin: f64,
    /// Least distance, along the closing axis, from the rider's footprint to the row's outer faces
    /// (where the pads close), metres. Default 5 mm.
    pub pad_margin: f64,
    /// Keep that margin also where the pads end once the jaws have closed, the rider carried by the
    /// member under its centroid as the grasp model's planar closing moves the row (`Row::closing`;
    /// `formulations/stacking.md`, "Where the pads end"), not only from the row as it stands.
    /// Default true; left out of written settings when on (logs written before it existed judged
    /// the pads as the row stands, as their `git_commit` says).
    #[serde(skip_serializing_if = "is_true")]
    pub pads_after_closing: bool,
    /// Turns of the rider tried, evenly over a full turn. Default 24 (15° apart).
    pub yaws: usize,
    /// The arm's horizontal acceleration while carrying, m/s². Default 1.2, the time model's
    /// `travel_acceleration`.
    pub acceleration: f64,
    /// Object–object friction must be at least this many times `acceleration / g`. Default 1.5.
    pub slide_factor: f64,
}

fn is_true(value: &bool) -> bool {
    *value
}

impl Default for StackSettings {
    fn default() -> Self {
        Self {
            height_tolerance: 0.002,
            support_margin: 0.005,
            pad_margin: 0.005,
            pads_after_closing: true,
            yaws: 24,
            acceleration: 1.2,
            slide_factor: 1.5,
        }
    }
}

/// Where a rider rests.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// The rider's pose on the table (its frame's origin and yaw), seen from above.
    pub pose: Pose,
    /// The height of its base above the table, metres: the row's top.
    pub base: f64,
    /// The distance from its centroid to the nearest edge of its support polygon (the hull of
    /// the parts of the top faces it covers), metres.
    pub margin: f64,
    /// The row members it rests on, as positions in the row.
    pub resting_on: Vec<usize>,
}

/// Why a rider cannot ride on a row.
#[derive(Clone, Debug, PartialEq)]
pub enum NoPlacement {
    /// The row is empty.
    NoTop,
    /// Object–object friction is below `slide_factor · a/g`: the rider would slide.
    Slides {
        /// The friction needed.
        needed: f64,
    },
    /// At no turn does the rider's footprint fit between the pads with their margins.
    TooWide,
    /// The rider fits between the pads as the row stands, but where the jaws leave the row once
    /// closed (`Row::closing`) a pad would come within its margin of the rider wherever it has room.
    PadsClose,
    /// The best placement leaves the centroid too near the edge of its support.
    NoRoom {
        /// The best margin found, metres (negative: the centroid outside).
        best: f64,
        /// The margin needed, metres.
        needed: f64,
    },
}

/// A candidate: the turn, the centroid's position and the inset of the top's hull reached there.
struct Candidate {
    yaw: f64,
    centroid: Point2<f64>,
    inset: f64,
}

/// Places `rider` (its outline in its own frame, its height) on `row`'s top with the most room, or
/// says why it cannot ride. `friction_object` is the rider–row friction coefficient.
pub fn place_rider(
    row: &Row,
    rider: &ConvexPolygon,
    rider_height: f64,
    friction_object: f64,
    settings: &StackSettings,
) -> Result<Placement, NoPlacement> {
    let support = Support::of(row, settings.height_tolerance).ok_or(NoPlacement::NoTop)?;
    let needed_friction = settings.slide_factor * settings.acceleration / GRAVITY;
    if friction_object < needed_friction {
        return Err(NoPlacement::Slides {
            needed: needed_friction,
        });
    }
    let needed = settings
        .support_margin
        .max(tipping_bound(rider_height, settings.acceleration));
    let (lo, hi) = row.extent();
    let closed = row.closing.as_ref().map(|motions| Closed::of(row, motions));
    let pad = settings.pad_margin;
    let hull = half_planes(&support.hull);
    let mut candidates = Vec::new();
    let mut fits_between_pads = false;
    for k in 0..settings.yaws.max(1) {
        let yaw = TAU * k as f64 / settings.yaws.max(1) as f64;
        let footprint = about_centroid(rider, yaw);
        let (front, back) = footprint.projection(&row.axis);
        let strip = (lo + pad - front, hi - pad - back);
        if strip.0 > strip.1 {
            continue;
        }
        fits_between_pads = true;
        // With the closing: one strip per face the rider may rest on (the pads' closed places
        // seen from that member, which carries the rider with it), and one for a rider carried by
        // any of them.
        let strips: Vec<(f64, f64)> = match &closed {
            None => vec![strip],
            Some(closed) => {
                let mut strips: Vec<(f64, f64)> = support
                    .members
                    .iter()
                    .map(|&j| {
                        (
                            strip.0.max(closed.lo - closed.shifts[j] + pad - front),
                            strip.1.min(closed.hi - closed.shifts[j] - pad - back),
                        )
                    })
                    .collect();
                let all = strips
                    .iter()
                    .fold(strip, |all, s| (all.0.max(s.0), all.1.min(s.1)));
                strips.push(all);
                strips.retain(|strip| strip.0 <= strip.1);
                strips
            }
        };
        for strip in strips {
            if let Some((inset, centroid)) = deepest(&support.hull, &hull, &row.axis, strip) {
                candidates.push(Candidate {
                    yaw,
                    centroid,
                    inset,
                });
            }
        }
    }
    if !fits_between_pads {
        return Err(NoPlacement::TooWide);
    }
    candidates.sort_by(|a, b| b.inset.total_cmp(&a.inset));
    let mut best = f64::NEG_INFINITY;
    let mut pads_close = closed.is_some() && candidates.is_empty();
    for candidate in &candidates {
        if candidate.inset < needed {
            break;
        }
        let footprint = about_centroid(rider, candidate.yaw).translated(&candidate.centroid.coords);
        let (margin, resting_on) = resting(&support, &footprint, &candidate.centroid);
        let resting_on: Vec<usize> = resting_on.into_iter().map(|f| support.members[f]).collect();
        if margin < needed {
            best = best.max(margin);
            continue;
        }
        if let Some(closed) = &closed
            && !closed.clear_of_pads(
                &footprint,
                &carriers(row, &candidate.centroid, &resting_on),
                pad,
            )
        {
            pads_close = true;
            continue;
        }
        let offset = Isometry2::rotation(candidate.yaw) * rider.centroid().coords;
        let origin = candidate.centroid - offset;
        return Ok(Placement {
            pose: Pose::new(origin.x, origin.y, candidate.yaw),
            base: support.height,
            margin,
            resting_on,
        });
    }
    if pads_close && best < needed {
        return Err(NoPlacement::PadsClose);
    }
    if best == f64::NEG_INFINITY {
        best = candidates.first().map_or(f64::NEG_INFINITY, |c| c.inset);
    }
    Err(NoPlacement::NoRoom { best, needed })
}

/// Whether the plates carry a row of `row_masses` with riders of `rider_masses` by friction: each
/// plate, pressing with `grip_force` at friction `friction_jaw`, takes half the weight.
pub fn plates_carry(
    friction_jaw: f64,
    grip_force: f64,
    row_masses: &[f64],
    rider_masses: &[f64],
) -> bool {
    let weight: f64 = row_masses.iter().chain(rider_masses).sum::<f64>() * GRAVITY;
    friction_jaw * grip_force >= weight / 2.0
}

/// `outline` turned by `yaw` about its centroid and moved so that the centroid is at the origin.
fn about_centroid(outline: &ConvexPolygon, yaw: f64) -> ConvexPolygon {
    let turned = outline.transformed(&Isometry2::rotation(yaw));
    let centroid = turned.centroid();
    turned.translated(&-centroid.coords)
}

/// The largest `t` for which the hull inset by `t` meets the strip `strip.0 ≤ axis·x ≤ strip.1`,
/// by bisection, and the centroid of that meeting; `None` when the strip misses the hull.
fn deepest(
    hull: &ConvexPolygon,
    planes: &[(Vector2<f64>, f64)],
    axis: &Vector2<f64>,
    strip: (f64, f64),
) -> Option<(f64, Point2<f64>)> {
    let region = |t: f64| {
        let mut points = hull.vertices().to_vec();
        for (normal, d) in planes {
            points = clip(&points, normal, d - t);
        }
        points = clip(&points, axis, strip.1);
        clip(&points, &-axis, -strip.0)
    };
    let mut inside = region(0.0);
    if inside.is_empty() {
        return None;
    }
    let (mut low, mut high) = (0.0, hull.width(axis).max(hull.width(&axis.yx())));
    for _ in 0..40 {
        let t = 0.5 * (low + high);
        let points = region(t);
        if points.is_empty() {
            high = t;
        } else {
            low = t;
            inside = points;
        }
    }
    // The mean of the region's distinct corners: at the deepest inset the region has shrunk to a
    // point or a segment, whose middle this is.
    let mut corners: Vec<Point2<f64>> = Vec::with_capacity(inside.len());
    for p in inside {
        if corners.iter().all(|c| nalgebra::distance(c, &p) > 1e-9) {
            corners.push(p);
        }
    }
    let sum = corners.iter().fold(Vector2::zeros(), |s, p| s + p.coords);
    Some((low, Point2::from(sum / corners.len() as f64)))
}

/// How far the centroid of `footprint` lies inside the hull of the parts of the faces `tops` that
/// the footprint covers, metres (negative outside, `-∞` when it covers none): check 1 of
/// `formulations/stacking.md` without its margin.
pub fn standing_margin(tops: &[ConvexPolygon], footprint: &ConvexPolygon) -> f64 {
    let support = Support {
        height: 0.0,
        members: (0..tops.len()).collect(),
        faces: tops.to_vec(),
        hull: footprint.clone(),
    };
    resting(&support, footprint, &footprint.centroid()).0
}

/// The margin of `centroid` inside the hull of the parts of the top faces that `footprint` covers
/// (negative outside), and which faces those are.
fn resting(
    support: &Support,
    footprint: &ConvexPolygon,
    centroid: &Point2<f64>,
) -> (f64, Vec<usize>) {
    let mut contact = Vec::new();
    let mut faces = Vec::new();
    for (f, face) in support.faces.iter().enumerate() {
        let mut points = footprint.vertices().to_vec();
        for (normal, d) in half_planes(face) {
            points = clip(&points, &normal, d);
        }
        if points.len() >= 3 {
            faces.push(f);
            contact.extend(points);
        }
    }
    // Clipping leaves points on the footprint's edges nearly in line; the tidy hull drops them.
    let Some(polygon) = tidy_polygon(&contact) else {
        return (f64::NEG_INFINITY, faces);
    };
    let margin = half_planes(&polygon)
        .iter()
        .map(|(normal, d)| d - normal.dot(&centroid.coords))
        .fold(f64::INFINITY, f64::min);
    (margin, faces)
}

#[cfg(test)]
#[path = "placement_tests.rs"]
mod tests;
