//! pushmog's analytic model of closing parallel jaws on objects lying on a table.
//!
//! Given a [`JawPose`]:
//! 1. **Placement.** If either open plate overlaps an object, the jaws cannot be lowered
//!    ([`Squeeze::PlateHits`]). Objects overlapping the region between the plates are *caught*; a
//!    caught object must lie between the planes of the two plate faces, or a plate would close past
//!    part of it ([`Squeeze::Straddles`]).
//! 2. **Closing.** Caught objects slide along the closing axis `a` without turning until they touch:
//!    sorted by their lowest point along `a`, each is moved along `−a` until it meets an object already
//!    placed (a shape cast). The result must be a single row: each object meets exactly one
//!    predecessor and is met by at most one successor, and only the first and last touch the plates.
//!    Anything else (an object that meets nothing, two objects side by side) is
//!    [`Squeeze::NotARow`].
//! 3. **Plates.** Each plate (a rectangle `plate_length` long across the axis) closes along the axis
//!    until it meets the row, and must meet the row's end object first. Its contact is computed like any
//!    other: a vertex on the plate's face pushes along the axis, but a plate's corner on an object's
//!    slanted edge pushes along that edge's normal.
//! 4. **Friction in the plane.** Each object in the row is held between two contacts, a plate or a
//!    neighbour. By Nguyen's two-contact condition the object is held when some pair of points, one on
//!    each contact patch, is joined by a segment within the friction cone (half-angle `atan μ`) of both
//!    inward contact normals. A plate's normal is `±a`; between objects the normal is that of the edge in
//!    contact. `μ` is `friction_jaw` at a plate and `friction_object` between objects. Patches are
//!    sampled at 5 points. An object that fails slips out of the row ([`Squeeze::Slips`]): three
//!    equal equilateral triangles are refused here for all plausible `μ`.
//! 5. **Lifting.** With grip force `N`, each plate carries half the row's weight `W`, which needs
//!    `μ_jaw N ≥ W/2`; the interface after the first `k` objects carries `|W/2 − W_k|` and needs at most
//!    `μ_obj N |n·a|`. Masses come from the objects, or from `density × area × height`.
//!
//! The row's predicted width is its extent along `a` after closing. `formulations/references.md` lists
//! the sources of these conditions (Nguyen 1988; the necessary conditions of the public MOG code).

use nalgebra::{Isometry2, Point2, Vector2};

pub use super::body::Body;
use super::jaws::JawPose;
use crate::geometry::{distance, overlap};
pub use crate::problem::{GraspModel, Mechanics};
use crate::scene::Scene;

mod row;

use row::{Row, form_row};

/// Slides equal to within this (metres) are a tie, won by the object placed last.
const SLIDE_TIE: f64 = 1e-9;

use crate::problem::GRAVITY;

/// Objects this far beyond the plates' reach still take part in a planar closing (they may be
/// pushed by what the jaws push), metres.
const NEIGHBOURHOOD: f64 = 0.02;

/// What closing the jaws does, by the model.
#[derive(Clone, Debug, PartialEq)]
pub enum Squeeze {
    /// The row is held: scene indices from one plate to the other, and the closed gap in metres.
    Held {
        /// Scene indices of the objects carried, in row order.
        objects: Vec<usize>,
        /// Distance between the plate faces when closed, metres.
        width: f64,
    },
    /// Nothing lies between the plates.
    Empty,
    /// An open plate lands on this object (scene index).
    PlateHits {
        /// Scene index.
        object: usize,
    },
    /// This object (scene index) reaches past a plate face beside the plate.
    Straddles {
        /// Scene index.
        object: usize,
    },
    /// The caught objects do not form one row; this one is out of line (scene index).
    NotARow {
        /// Scene index.
        object: usize,
    },
    /// Friction cannot keep this object (scene index) in the row.
    Slips {
        /// Scene index.
        object: usize,
    },
    /// This object (scene index) turns or slides out of the row while the jaws close (planar
    /// mechanics).
    Turns {
        /// Scene index.
        object: usize,
    },

    /// The grip force cannot carry the row's weight.
    TooHeavy,
}

/// Which friction coefficient a contact has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Friction {
    /// A plate on an object.
    Jaw,
    /// Two objects.
    Object,
}

impl Friction {
    /// The coefficient of this kind of contact under `model`.
    pub fn of(self, model: &GraspModel) -> f64 {
        match self {
            Self::Jaw => model.friction_jaw,
            Self::Object => model.friction_object,
        }
    }
}

/// One contact of the row: a patch (segment ends) and a unit normal.
#[derive(Clone, Copy, Debug)]
pub(super) struct Side {
    /// Ends of the contact segment (equal for a point contact).
    pub ends: [Point2<f64>; 2],
    /// Unit normal, pointing into the object the contact pushes.
    pub inward: Vector2<f64>,
    /// Which coefficient applies.
    pub friction: Friction,
}

impl Squeeze {
    /// The same verdict with every object index `i` replaced by `to(i)` (from positions in a list of
    /// bodies to scene indices).
    pub fn map_objects(self, to: impl Fn(usize) -> usize) -> Self {
        match self {
            Self::Held { objects, width } => Self::Held {
                objects: objects.into_iter().map(&to).collect(),
                width,
            },
            Self::PlateHits { object } => Self::PlateHits { object: to(object) },
            Self::Straddles { object } => Self::Straddles { object: to(object) },
            Self::NotARow { object } => Self::NotARow { object: to(object) },
            Self::Slips { object } => Self::Slips { object: to(object) },
            Self::Turns { object } => Self::Turns { object: to(object) },
            Self::Empty => Self::Empty,
            Self::TooHeavy => Self::TooHeavy,
        }
    }
}

/// Predicts what closing `jaws` does in `scene`; object indices in the answer are scene indices.
pub fn squeeze(scene: &Scene, jaws: &JawPose, model: &GraspModel) -> Squeeze {
    let (near, bodies) = nearby_bodies(
        scene,
        model,
        &jaws.center,
        squeeze_reach(jaws, scene.gripper()),
    );
    squeeze_bodies(&bodies, scene.gripper(), jaws, model).map_objects(|k| near[k])
}

/// How far from the jaw centre (beyond an object's own radius) a squeeze looks: an object further
/// away is neither caught nor pushed by the closing ([`form_row`] looks at `opening/2 + plate
/// length`, the planar closing [`NEIGHBOURHOOD`] further).
pub(super) fn squeeze_reach(jaws: &JawPose, gripper: &crate::scene::Gripper) -> f64 {
    jaws.opening / 2.0 + gripper.plate_length + NEIGHBOURHOOD
}

/// The objects of `scene` whose bounding discs come within `reach` of `point` (scene indices,
/// ascending) and their bodies. A squeeze of these bodies equals one of the whole scene when
/// `reach` is at least [`squeeze_reach`], with indices into the list.
pub(super) fn nearby_bodies<'a>(
    scene: &'a Scene,
    model: &GraspModel,
    point: &Point2<f64>,
    reach: f64,
) -> (Vec<usize>, Vec<Body<'a>>) {
    let near = scene.near(point, reach);
    let bodies = near
        .iter()
        .map(|&i| Body {
            outline: scene.world_polygon(i),
            mass: model.mass_of(&scene.objects()[i]),
        })
        .collect();
    (near, bodies)
}

/// [`row_of`] on `scene`, looking only at the objects within reach: scene indices.
pub(super) fn row_in_scene(
    scene: &Scene,
    jaws: &JawPose,
    model: &GraspModel,
) -> std::result::Result<Vec<usize>, Squeeze> {
    let reach = jaws.opening / 2.0 + scene.gripper().plate_length;
    let (near, bodies) = nearby_bodies(scene, model, &jaws.center, reach);
    match row_of(&bodies, scene.gripper(), jaws, model) {
        Ok(caught) => Ok(caught.into_iter().map(|k| near[k]).collect()),
        Err(refusal) => Err(refusal.map_objects(|k| near[k])),
    }
}

/// Predicts what closing `jaws` does to `bodies` (which need not form a valid scene); object indices
/// in the answer are positions in `bodies`.
pub fn squeeze_bodies(
    bodies: &[Body<'_>],
    gripper: &crate::scene::Gripper,
    jaws: &JawPose,
    model: &GraspModel,
) -> Squeeze {
    let row = match form_row(bodies, gripper, jaws, model.contact_tolerance) {
        Ok(row) => row,
        Err(refusal) => return refusal,
    };
    match model.mechanics {
        Mechanics::Analytic => {
            if let Err(refusal) = judge_rigid(&row, model) {
                return refusal;
            }
            let normals: Vec<Vector2<f64>> = row.contacts[1..row.contacts.len() - 1]
                .iter()
                .map(|c| c.inward)
                .collect();
            if let Err(refusal) = judge_lifting(&row.caught, &normals, bodies, &jaws.axis(), model)
            {
                return refusal;
            }
            Squeeze::Held {
                width: row.width,
                objects: row.caught,
            }
        }
        Mechanics::Planar => judge_planar(&row, bodies, gripper, jaws, model),
    }
}

/// Steps 1–3 alone (the jaws placed, the caught objects slid into a row, the plates meeting it):
/// the caught objects (positions in `bodies`) in row order, or the refusal. No friction, no
/// simulation: the cheap test a candidate passes before the mechanics judge it.
pub(super) fn row_of(
    bodies: &[Body<'_>],
    gripper: &crate::scene::Gripper,
    jaws: &JawPose,
    model: &GraspModel,
) -> std::result::Result<Vec<usize>, Squeeze> {
    form_row(bodies, gripper, jaws, model.contact_tolerance).map(|row| row.caught)
}

/// The planar judgement: the closing simulated with turning objects (`closing/`); every caught
/// object must end gripped, and the gripped row must lift.
fn judge_planar(
    row: &Row,
    bodies: &[Body<'_>],
    gripper: &crate::scene::Gripper,
    jaws: &JawPose,
    model: &GraspModel,
) -> Squeeze {
    let (near, closed) = close_planar(row, bodies, gripper, jaws, model);
    let gripped: Vec<usize> = closed.gripped.iter().map(|&k| near[k]).collect();
    if let Some(&lost) = row.caught.iter().find(|i| !gripped.contains(i)) {
        return Squeeze::Turns { object: lost };
    }
    if !closed.squeezing {
        return Squeeze::Slips {
            object: row.caught[0],
        };
    }
    if let Err(refusal) = judge_lifting(&gripped, &closed.interfaces, bodies, &jaws.axis(), model) {
        return refusal;
    }
    Squeeze::Held {
        width: closed.opening - gripper.plate_thickness,
        objects: gripped,
    }
}

/// The planar closing (`closing/`) of `row`'s jaws on the caught objects and every object the
/// closing might push (those within reach of the jaws): positions in `bodies` of the simulated
/// ones, and the closing.
fn close_planar(
    row: &Row,
    bodies: &[Body<'_>],
    gripper: &crate::scene::Gripper,
    jaws: &JawPose,
    model: &GraspModel,
) -> (Vec<usize>, super::closing::Closed) {
    let reach = jaws.opening / 2.0 + gripper.plate_length + NEIGHBOURHOOD;
    let near: Vec<usize> = (0..bodies.len())
        .filter(|&i| {
            let outline = bodies[i].outline;
            let centroid = outline.centroid();
            row.caught.contains(&i)
                || nalgebra::distance(&centroid, &jaws.center)
                    <= reach + outline.radius_about(&centroid)
        })
        .collect();
    let local: Vec<Body<'_>> = near.iter().map(|&i| bodies[i]).collect();
    let caught: Vec<usize> = row
        .caught
        .iter()
        .filter_map(|i| near.iter().position(|j| j == i))
        .collect();
    let closed = super::closing::simulate_closing(&local, &caught, gripper, jaws, model);
    (near, closed)
}

/// Where closing `jaws` in `scene` leaves each of `objects` (scene indices), by the planar
/// closing: each one's motion in the table frame from where it lies. `None` under the analytic
/// mechanics (it slides the row together but does not say where the coupled plates leave it), when
/// the jaws do not form a row, or when an object of `objects` does not take part in the closing.
pub fn closed_motions(
    scene: &Scene,
    jaws: &JawPose,
    model: &GraspModel,
    objects: &[usize],
) -> Option<Vec<Isometry2<f64>>> {
    if model.mechanics != Mechanics::Planar {
        return None;
    }
    let (listed, bodies) = nearby_bodies(
        scene,
        model,
        &jaws.center,
        squeeze_reach(jaws, scene.gripper()),
    );
    let row = form_row(&bodies, scene.gripper(), jaws, model.contact_tolerance).ok()?;
    let (near, closed) = close_planar(&row, &bodies, scene.gripper(), jaws, model);
    objects
        .iter()
        .map(|object| {
            let body = listed.iter().position(|i| i == object)?;
            let k = near.iter().position(|&j| j == body)?;
            Some(closed.motions[k])
        })
        .collect()
}

/// The analytic model's judgement of friction in the plane (step 4): each object is held between its
/// two contacts by Nguyen's two-contact condition, objects judged one by one.
fn judge_rigid(row: &Row, model: &GraspModel) -> std::result::Result<(), Squeeze> {
    for k in 0..row.outlines.len() {
        let before = row.contacts[k];
        let after = Side {
            inward: -row.contacts[k + 1].inward,
            ..row.contacts[k + 1]
        };
        if !two_contacts_hold(&before, &after, model) {
            return Err(Squeeze::Slips {
                object: row.caught[k],
            });
        }
    }
    Ok(())
}

/// Lifting against gravity (step 5): the plates carry the row's weight by friction, and every
/// interface (unit normals between consecutive objects of `row`) carries the weight on one side of
/// it.
fn judge_lifting(
    row: &[usize],
    interfaces: &[Vector2<f64>],
    bodies: &[Body<'_>],
    axis: &Vector2<f64>,
    model: &GraspModel,
) -> std::result::Result<(), Squeeze> {
    let masses: Vec<f64> = row.iter().map(|&i| bodies[i].mass).collect();
    let weight: f64 = masses.iter().sum::<f64>() * GRAVITY;
    let force = model.grip_force;
    if model.friction_jaw * force < weight / 2.0 {
        return Err(Squeeze::TooHeavy);
    }
    let mut carried_left = 0.0;
    for (k, normal) in interfaces.iter().enumerate() {
        carried_left += masses[k] * GRAVITY;
        let shear = (weight / 2.0 - carried_left).abs();
        if shear > model.friction_object * force * normal.dot(axis).abs() {
            return Err(Squeeze::TooHeavy);
        }
    }
    Ok(())
}

/// The scene indices of the objects caught between the open plates, or `None` when a plate would land
/// on an object.
pub fn caught_objects(scene: &Scene, jaws: &JawPose) -> Option<Vec<usize>> {
    let gripper = scene.gripper();
    let plates = jaws.plates(gripper);
    let between = jaws.between(gripper);
    let reach = jaws.opening / 2.0 + gripper.plate_length;
    let mut caught = Vec::new();
    for index in scene.near(&jaws.center, reach) {
        let outline = scene.world_polygon(index);
        if plates.iter().any(|p| overlap(p, outline, 0.0)) {
            return None;
        }
        if overlap(&between, outline, 0.0) {
            caught.push(index);
        }
    }
    Some(caught)
}

/// Clearance between the open plates and the nearest object not in `held`, capped at `cap` metres.
pub(super) fn plate_clearance(scene: &Scene, jaws: &JawPose, held: &[usize], cap: f64) -> f64 {
    let plates = jaws.plates(scene.gripper());
    let mut clearance = cap;
    for index in scene.near(&jaws.center, jaws.opening / 2.0 + cap + 0.05) {
        if held.contains(&index) {
            continue;
        }
        let outline = scene.world_polygon(index);
        for plate in &plates {
            clearance = clearance.min(distance(plate, outline));
        }
    }
    clearance
}

/// Nguyen's condition over sampled points of two contact patches.
fn two_contacts_hold(first: &Side, second: &Side, model: &GraspModel) -> bool {
    let samples = |side: &Side| -> Vec<Point2<f64>> {
        let [a, b] = side.ends;
        (0..5).map(|k| a + (b - a) * (k as f64 / 4.0)).collect()
    };
    let within = |v: Vector2<f64>, normal: Vector2<f64>, friction: f64| {
        let length = v.norm();
        length > 0.0
            && v.dot(&normal) >= length * normal.norm() / (1.0 + friction * friction).sqrt()
    };
    for p in samples(first) {
        for q in samples(second) {
            if within(q - p, first.inward, first.friction.of(model))
                && within(p - q, second.inward, second.friction.of(model))
            {
                return true;
            }
        }
    }
    false
}
