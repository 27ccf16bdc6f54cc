//! Steps 1–3 of the model: the open jaws placed, the caught objects slid into a row along the
//! closing axis, the plates closed on it.

use nalgebra::Vector2;

use super::{Body, Friction, JawPose, SLIDE_TIE, Side, Squeeze};
use crate::geometry::{ConvexPolygon, cast_distance, contact_patch, overlap};

/// The row the closing jaws form, before any judgement of friction: which objects are caught, in
/// order from the plate that closes along `+a`, where they end up, and how far each had to slide.
#[derive(Clone, Debug)]
pub(super) struct Row {
    /// Indices (in the bodies) of the caught objects, in row order along `a`.
    pub caught: Vec<usize>,
    /// Their outlines once closed (each slid along the axis onto its predecessor).
    pub outlines: Vec<ConvexPolygon>,
    /// Contacts along the row: the first plate with the first object, each object with the next, the
    /// last object with the other plate; normals point along the row (`+a` side).
    pub contacts: Vec<Side>,
    /// Distance between the plate faces when closed, metres.
    pub width: f64,
}

/// Places the open jaws, slides the caught objects into a row along the axis and closes the plates
/// on it (steps 1–3 of the module docs); `Err` with the refusal when that fails.
pub(super) fn form_row(
    bodies: &[Body<'_>],
    gripper: &crate::scene::Gripper,
    jaws: &JawPose,
    tolerance: f64,
) -> std::result::Result<Row, Squeeze> {
    let axis = jaws.axis();
    let plates = jaws.plates(gripper);
    let between = jaws.between(gripper);
    let reach = jaws.opening / 2.0 + gripper.plate_length;
    let mut caught: Vec<usize> = Vec::new();
    for (index, body) in bodies.iter().enumerate() {
        let outline = body.outline;
        let centroid = outline.centroid();
        if nalgebra::distance(&centroid, &jaws.center) > reach + outline.radius_about(&centroid) {
            continue;
        }
        if plates.iter().any(|p| overlap(p, outline, 0.0)) {
            return Err(Squeeze::PlateHits { object: index });
        }
        if overlap(&between, outline, 0.0) {
            let (low, high) = outline.projection(&axis);
            let middle = jaws.center.coords.dot(&axis);
            let half_gap = jaws.gap(gripper) / 2.0;
            if low < middle - half_gap || high > middle + half_gap {
                return Err(Squeeze::Straddles { object: index });
            }
            caught.push(index);
        }
    }
    if caught.is_empty() {
        return Err(Squeeze::Empty);
    }
    let low = |p: &ConvexPolygon| p.projection(&axis).0;
    caught.sort_by(|&a, &b| low(bodies[a].outline).total_cmp(&low(bodies[b].outline)));

    // Close: slide each object along −a onto the row.
    let mut row: Vec<ConvexPolygon> = vec![bodies[caught[0]].outline.clone()];
    for (k, &index) in caught.iter().enumerate().skip(1) {
        let moving = bodies[index].outline;
        let mut first: Option<(f64, usize)> = None;
        // Latest placed first, so a tie (touching two at once) goes to the row's current end.
        for (j, placed) in row.iter().enumerate().rev() {
            if let Some(d) = cast_distance(moving, &-axis, jaws.opening, placed)
                && first.is_none_or(|(best, _)| d < best - SLIDE_TIE)
            {
                first = Some((d, j));
            }
        }
        // A row: each object lands on the one placed just before it (so none is met twice).
        match first {
            Some((slide, predecessor)) if predecessor == k - 1 => {
                row.push(moving.translated(&(-axis * slide)));
            }
            _ => return Err(Squeeze::NotARow { object: index }),
        }
    }
    // Each plate closes along the axis until it meets the row; it must meet the row's end object first.
    let last = row.len() - 1;
    let meet = |plate: &ConvexPolygon, direction: Vector2<f64>, end: usize| {
        let mut first: Option<(f64, usize)> = None;
        for (k, outline) in row.iter().enumerate() {
            if let Some(d) = cast_distance(plate, &direction, jaws.opening, outline)
                && first.is_none_or(|(best, _)| d < best - SLIDE_TIE)
            {
                first = Some((d, k));
            }
        }
        match first {
            Some((d, k)) if k == end => Ok((d, plate.translated(&(direction * d)))),
            Some((_, k)) => Err(caught[k]),
            None => Err(caught[end]),
        }
    };
    let (left_travel, left_plate) =
        meet(&plates[1], axis, 0).map_err(|object| Squeeze::NotARow { object })?;
    let (right_travel, right_plate) =
        meet(&plates[0], -axis, last).map_err(|object| Squeeze::NotARow { object })?;
    let width = jaws.gap(gripper) - left_travel - right_travel;
    let tolerance = tolerance.max(1e-9);
    let plate_contact = |plate: &ConvexPolygon, object: &ConvexPolygon| {
        contact_patch(plate, object, tolerance).map(|patch| Side {
            ends: patch.ends,
            inward: patch.normal,
            friction: Friction::Jaw,
        })
    };
    let (Some(left_side), Some(right_side)) = (
        plate_contact(&left_plate, &row[0]),
        plate_contact(&right_plate, &row[last]),
    ) else {
        return Err(Squeeze::NotARow { object: caught[0] });
    };
    let mut contacts = vec![left_side];
    for k in 1..row.len() {
        let Some(patch) = contact_patch(&row[k - 1], &row[k], tolerance) else {
            return Err(Squeeze::NotARow { object: caught[k] });
        };
        contacts.push(Side {
            ends: patch.ends,
            inward: patch.normal,
            friction: Friction::Object,
        });
    }
    // The right plate's patch, with its normal turned to point along the row like the others.
    contacts.push(Side {
        inward: -right_side.inward,
        ..right_side
    });
    Ok(Row {
        caught,
        outlines: row,
        contacts,
        width,
    })
}
