//! Fork-push geometry: where the fingers go, and whether they can get there.
//!
//! For a push of an object along the unit vector `u`, the jaw line (closing axis) is `n ⊥ u` and the
//! plate centres sit at `g ± n·s/2`, with `s` the fork-push opening (30 % of the stroke). Each finger's
//! footprint is a plate seen from above: `plate_thickness` along `n` and `plate_length` along `u`.
//! The gripper centre `g` moves on the line through the object's centroid along `u`:
//! - **contact** `g_c`: the fingers, swept along `u` from far behind, first touch the object;
//! - **approach** `g_a = g_c − u·d`: where the fingers are lowered, with `d` the approach clearance,
//!   or more when the fingers there would come nearer the pushed object than that in some other
//!   direction (a narrow end that reaches back between the fingers: they touch the object's sides,
//!   and beside its end they would come down on it); `d` then grows in 1 mm steps until they clear;
//! - **end** `g_e = g_c + u·L` for a push of length `L`.
//!
//! Checks: the fingers at `g_a` keep the approach clearance from the pushed object and the finger
//! clearance from every other object, and the fingers swept from `g_a` to `g_e` touch no object
//! other than the one pushed.

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::SkipReason;
use crate::geometry::{ConvexPolygon, cast_distance, overlap};
use crate::scene::{Gripper, ObjectId};

pub use crate::problem::ForkSettings;

/// The gripper's motion for one fork push (all points are the gripper centre in the table frame).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ForkPush {
    /// Where the fingers are lowered, behind the object.
    #[schemars(with = "[f64; 2]")]
    pub approach: Point2<f64>,
    /// Where the fingers first touch the object.
    #[schemars(with = "[f64; 2]")]
    pub contact: Point2<f64>,
    /// Where the push ends; the fingers rise here.
    #[schemars(with = "[f64; 2]")]
    pub end: Point2<f64>,
    /// Direction of the jaw line (closing axis), radians: perpendicular to the push.
    pub jaw_angle: f64,
    /// Distance between the plate centres, metres.
    pub opening: f64,
    /// Height of the fingertips above the table while pushing, metres (chosen so the object slides
    /// rather than tips; absent in plans written before it was planned).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
}

/// The two finger footprints for a gripper centred at `centre` whose fingers face the unit vector
/// `facing` (the push direction, or a flush push's face normal): the jaw line is perpendicular to it.
pub fn finger_footprints(
    gripper: &Gripper,
    opening: f64,
    centre: &Point2<f64>,
    facing: &Vector2<f64>,
) -> [ConvexPolygon; 2] {
    let jaw_line = Vector2::new(-facing.y, facing.x);
    let half_along = gripper.plate_thickness / 2.0;
    let half_across = gripper.plate_length / 2.0;
    [1.0, -1.0].map(|side| {
        ConvexPolygon::rectangle(
            &(centre + jaw_line * (side * opening / 2.0)),
            &jaw_line,
            half_along,
            half_across,
        )
    })
}

/// The fingertip height at which pushing `outline` (an object `height` tall) slides it rather than
/// tips it, or `None` when no height at or above `min_height` does.
///
/// Pushed at height `h` against table friction `μ`, the object is pushed with about `μ·m·g` and tips
/// about an edge of its base when that force's moment `μ·m·g·h` exceeds the weight's, `m·g·r`, with
/// `r` the distance from the centroid to that edge. The fingers do not push exactly along the planned
/// direction (a corner between two fingers is pushed sideways too), so `r` is the distance to the
/// nearest edge of the base, whatever the push direction: the fingertips go at most `(r − margin)/μ`
/// high (the contact resultant cannot sit below them), and at the preferred fraction of the height
/// when that is lower.
pub fn push_height(settings: &ForkSettings, outline: &ConvexPolygon, height: f64) -> Option<f64> {
    let centroid = outline.centroid();
    let lever = outline
        .edges()
        .map(|(a, b)| {
            let edge = b - a;
            let outward = Vector2::new(edge.y, -edge.x).normalize();
            outward.dot(&(a - centroid))
        })
        .fold(f64::INFINITY, f64::min);
    let highest = if settings.table_friction > 0.0 {
        (lever - settings.tip_margin) / settings.table_friction
    } else {
        f64::INFINITY
    };
    let preferred = settings.height_fraction * height;
    let chosen = preferred.min(highest);
    (chosen >= settings.min_height).then_some(chosen)
}

/// How far the approach point backs off at a time when the fingers would come down too near the
/// pushed object, metres.
const BACK_OFF_STEP: f64 = 0.001;

/// Plans the gripper motion that pushes `world[pushed]` (an object `height` tall) by `distance` along
/// the unit vector `push`, the jaws open to `opening` between the plates' centres: the fork opening
/// ([`Gripper::fork_push_opening`]) for a fork push, or [`Gripper::plate_thickness`] plus a little for
/// the closed gripper pushing as one narrow block, which fits where a fork does not. `world` holds
/// every object's outline where it stands now, `ids` their ids.
///
/// # Errors
/// The [`SkipReason`] when the fingers cannot be placed or moved, or the object would tip.
#[allow(clippy::too_many_arguments)]
pub fn plan_fork(
    gripper: &Gripper,
    settings: &ForkSettings,
    world: &[ConvexPolygon],
    ids: &[ObjectId],
    pushed: usize,
    height: f64,
    push: &Vector2<f64>,
    distance: f64,
    opening: f64,
) -> std::result::Result<ForkPush, SkipReason> {
    plan_fork_facing(
        gripper,
        settings,
        world,
        ids,
        pushed,
        height,
        (push, push),
        distance,
        opening,
    )
}

/// [`plan_fork`] with the fingers facing the unit vector `facing` while they move along `push`: a
/// flush push at an angle to its face's normal keeps the jaw line along the face (`push::flush`).
#[allow(clippy::too_many_arguments)]
pub fn plan_fork_facing(
    gripper: &Gripper,
    settings: &ForkSettings,
    world: &[ConvexPolygon],
    ids: &[ObjectId],
    pushed: usize,
    height: f64,
    (push, facing): (&Vector2<f64>, &Vector2<f64>),
    distance: f64,
    opening: f64,
) -> std::result::Result<ForkPush, SkipReason> {
    let object = &world[pushed];
    let centroid = object.centroid();
    let Some(tip_height) = push_height(settings, object, height) else {
        return Err(SkipReason::WouldTip);
    };
    let reach = object.radius_about(&centroid) + gripper.plate_length + opening + 0.01;
    let far = centroid - push * reach;
    let touch = finger_footprints(gripper, opening, &far, facing)
        .iter()
        .filter_map(|finger| cast_distance(finger, push, 2.0 * reach, object))
        .fold(f64::INFINITY, f64::min);
    if !touch.is_finite() {
        return Err(SkipReason::NoFingerContact);
    }
    let contact = far + push * touch;
    // Back off until the lowered fingers clear the pushed object by the approach clearance in every
    // direction, not only along the push. Moving the fingers back from where they touch it never
    // brings them nearer (convex outlines).
    let margin = settings.finger_clearance;
    let clear_of_object = |back: f64| {
        finger_footprints(gripper, opening, &(contact - push * back), facing)
            .iter()
            .all(|finger| {
                crate::geometry::distance(finger, object) >= settings.approach_clearance - 1e-9
            })
    };
    let mut back = settings.approach_clearance;
    while !clear_of_object(back) {
        back += BACK_OFF_STEP;
        if back > reach {
            return Err(SkipReason::NoRoomForFingers {
                object: ids[pushed],
            });
        }
    }
    let approach = contact - push * back;
    let end = contact + push * distance;
    let travel = back + distance;
    let fingers = finger_footprints(gripper, opening, &approach, facing);
    let swept: Vec<_> = fingers
        .iter()
        .map(|f| f.swept_box(&(push * travel)))
        .collect();
    for (index, other) in world.iter().enumerate() {
        let near = |(lo, hi): (Point2<f64>, Point2<f64>)| {
            let grow = Vector2::new(margin, margin);
            other.box_meets((lo - grow, hi + grow))
        };
        if index == pushed || !swept.iter().any(|b| near(*b)) {
            continue;
        }
        if fingers
            .iter()
            .any(|f| overlap(f, other, 0.0) || crate::geometry::distance(f, other) < margin)
        {
            return Err(SkipReason::NoRoomForFingers { object: ids[index] });
        }
        if fingers
            .iter()
            .any(|f| cast_distance(f, push, travel, other).is_some())
        {
            return Err(SkipReason::FingersHit { object: ids[index] });
        }
    }
    let jaw_line = Vector2::new(-facing.y, facing.x);
    Ok(ForkPush {
        approach,
        contact,
        end,
        jaw_angle: jaw_line.y.atan2(jaw_line.x),
        opening,
        height: Some(tip_height),
    })
}
