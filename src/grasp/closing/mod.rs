//! The jaws closing, simulated in the plane: the caught objects and their neighbours slide and turn on
//! the table while the plates close on them, until the squeeze reaches the grip force.
//!
//! A small rigid-body simulation of its own (not the rapier simulator the experiments use as referee):
//! - **Objects** are rigid polygons with their masses and the inertia of a uniform lamina. The table
//!   resists their motion with Coulomb friction through an ellipsoidal limit surface: force up to
//!   `μ_t·m·g`, and torque up to `μ_t·m·g·ρ` with `ρ` the mean distance of the area from the centroid
//!   (uniform pressure).
//! - **Plates** are the 2F-85's coupled fingers: one opening `q` drives both plates symmetrically
//!   about the jaw centre, with the fingers' mass, and a motor that closes at the jaw speed with at
//!   most the grip force per finger.
//! - **Contacts** between polygons (objects with each other and with the plates) carry Coulomb
//!   friction, `μ_jaw` at a plate and `μ_obj` between objects, solved by sequential impulses each step
//!   (10 passes, more for pieces under 10 g; position drift corrected by a fraction of the
//!   penetration).
//!
//! The simulation stops when the jaws have stalled on the objects and everything is still, when the
//! plates shut, or after the time the jaws need to cross their opening. An object is *gripped* when
//! it lies in the chain of contacts that joins the two plates, touching it at two places at least.
//! With `GraspModel::friction_share` set it must also be able to rest under its contacts with that
//! share of their friction (`equilibrium.rs`).
//!
//! Here the bodies, the world and the closing's loop; one step of it in `step.rs`.

use nalgebra::{Isometry2, Point2, Vector2};

use super::body::Body;
use crate::geometry::ConvexPolygon;
use crate::problem::GraspModel;
use crate::scene::Gripper;

use super::equilibrium::{Touch, balanced};
use super::jaws::JawPose;

use crate::problem::GRAVITY;
/// Time step, seconds (the plates move 0.05 mm per step at 0.05 m/s; 0.5 ms gave the same verdicts
/// on the replayed grasps, 2 ms lost some).
const TIME_STEP: f64 = 1e-3;
/// Solver passes per step when every piece weighs at least [`PLAIN_MASS`].
const ITERATIONS: usize = 10;
/// Most solver passes per step. A light piece pressed between two heavy plates converges slowly
/// under sequential impulses (a 0.5 g square against 50 g fingers still bounced after 10 passes,
/// and was held with 20), so passes grow with the square root of the mass ratio up to this.
const MAX_ITERATIONS: usize = 80;
/// Lightest piece solved with [`ITERATIONS`] passes, kilograms (every object of the built-in set
/// weighs more).
const PLAIN_MASS: f64 = 0.01;
/// Fraction of a penetration corrected per step.
const BAUMGARTE: f64 = 0.2;
/// Penetration left alone, metres.
const SLOP: f64 = 5e-5;
/// Contacts are found this far apart (so fast approaches do not tunnel), metres.
const SPECULATIVE: f64 = 5e-4;
/// Mass of one finger, kilograms (a 2F-85 fingertip and pad are tens of grams).
const FINGER_MASS: f64 = 0.05;
/// Extra time allowed after the jaws could have crossed their opening, seconds.
const EXTRA_TIME: f64 = 0.4;
/// A contact within this distance of one of the last step (same pair) continues it, metres.
const WARM_START_RADIUS: f64 = 1e-3;
/// A contact this close counts as touching when judging an object's equilibrium, metres.
const TOUCHING: f64 = 1e-4;
/// Steps everything must stay still before the closing counts as settled.
const STILL_STEPS: usize = 20;

/// A rigid polygon sliding on the table.
#[derive(Clone, Debug)]
struct Piece {
    start: ConvexPolygon,
    start_centroid: Point2<f64>,
    position: Point2<f64>,
    angle: f64,
    velocity: Vector2<f64>,
    spin: f64,
    mass: f64,
    inertia: f64,
    friction_radius: f64,
    /// Impulse of table friction accumulated in the current step: force and torque parts.
    table: (Vector2<f64>, f64),
}

impl Piece {
    fn new(body: &Body<'_>) -> Self {
        let centroid = body.outline.centroid();
        Self {
            start: body.outline.clone(),
            start_centroid: centroid,
            position: centroid,
            angle: 0.0,
            velocity: Vector2::zeros(),
            spin: 0.0,
            mass: body.mass,
            inertia: body.mass * body.outline.gyration_squared(),
            friction_radius: body.outline.mean_radius(),
            table: (Vector2::zeros(), 0.0),
        }
    }

    fn outline(&self) -> ConvexPolygon {
        self.start.transformed(&self.motion())
    }

    /// Its motion so far: from where it started to where it is.
    fn motion(&self) -> Isometry2<f64> {
        let to_origin = Isometry2::translation(-self.start_centroid.x, -self.start_centroid.y);
        Isometry2::new(self.position.coords, self.angle) * to_origin
    }
}

/// The coupled plates.
#[derive(Clone, Debug)]
struct Plates {
    center: Point2<f64>,
    axis: Vector2<f64>,
    /// Distance between plate centres, metres.
    opening: f64,
    /// Its rate of change, m/s (negative while closing).
    rate: f64,
    half_thickness: f64,
    half_length: f64,
    shut: f64,
    /// Motor impulse accumulated in the current step.
    motor: f64,
}

impl Plates {
    /// Generalised mass of the opening: both fingers move at half its rate.
    const MASS: f64 = FINGER_MASS / 2.0;

    /// The plate on `side` (−1: the one at `−a`, +1: the one at `+a`).
    fn outline(&self, side: f64) -> ConvexPolygon {
        ConvexPolygon::rectangle(
            &(self.center + self.axis * (side * self.opening / 2.0)),
            &self.axis,
            self.half_thickness,
            self.half_length,
        )
    }
}

/// One side of a contact.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Party {
    Piece(usize),
    /// A plate: −1 at `−a`, +1 at `+a`.
    Plate(f64),
}

#[derive(Clone, Copy, Debug)]
struct Contact {
    a: Party,
    b: Party,
    point: Point2<f64>,
    /// From `a` into `b`.
    normal: Vector2<f64>,
    separation: f64,
    friction: f64,
    normal_impulse: f64,
    tangent_impulse: f64,
    /// Inverse effective masses along the normal and the tangent (fixed within a step, while
    /// nothing moves).
    normal_mass: f64,
    tangent_mass: f64,
}

impl Contact {
    /// The contact's normal pointing into `party`, if it is one of the two.
    fn normal_into(&self, party: Party) -> Option<Vector2<f64>> {
        if self.b == party {
            Some(self.normal)
        } else if self.a == party {
            Some(-self.normal)
        } else {
            None
        }
    }
}

/// The state of a closing: pieces, plates and the physical constants.
struct World {
    pieces: Vec<Piece>,
    plates: Plates,
    /// The contacts of the last step, with the impulses they carried.
    last: Vec<Contact>,
    friction_jaw: f64,
    friction_object: f64,
    friction_table: f64,
    /// Share of friction an object may use to rest once pressed ([`GraspModel::friction_share`]).
    friction_share: Option<f64>,
    grip_force: f64,
    jaw_speed: f64,
    /// Solver passes per step.
    iterations: usize,
}

mod step;
#[cfg(test)]
mod tests;

/// What a simulated closing ends with.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Closed {
    /// Bodies (indices into the slice given) gripped by the plates, in order along the axis.
    pub gripped: Vec<usize>,
    /// Distance between the plate centres at the end, metres.
    pub opening: f64,
    /// The motor ended at its force limit (the jaws squeeze with the grip force).
    pub squeezing: bool,
    /// Outlines of all the bodies at the end.
    pub outlines: Vec<ConvexPolygon>,
    /// Each body's motion in the table frame, from where it lay to where it ended.
    pub motions: Vec<Isometry2<f64>>,
    /// Normals of the contacts between consecutive gripped bodies (from each to the next).
    pub interfaces: Vec<Vector2<f64>>,
}

/// Simulates `jaws` closing on `bodies` (all bodies that can take part: those caught between the
/// plates and their neighbours), under the model's friction, grip force and jaw speed.
pub(super) fn simulate_closing(
    bodies: &[Body<'_>],
    caught: &[usize],
    gripper: &Gripper,
    jaws: &JawPose,
    model: &GraspModel,
) -> Closed {
    let axis = jaws.axis();
    let mut world = World {
        pieces: bodies.iter().map(Piece::new).collect(),
        plates: Plates {
            center: jaws.center,
            axis,
            opening: jaws.opening,
            rate: 0.0,
            half_thickness: gripper.plate_thickness / 2.0,
            half_length: gripper.plate_length / 2.0,
            shut: gripper.plate_thickness,
            motor: 0.0,
        },
        friction_jaw: model.friction_jaw,
        friction_object: model.friction_object,
        friction_table: model.friction_table,
        friction_share: model.friction_share,
        grip_force: model.grip_force,
        jaw_speed: model.jaw_speed,
        last: Vec::new(),
        iterations: ITERATIONS,
    };
    let lightest = world
        .pieces
        .iter()
        .map(|p| p.mass)
        .fold(f64::INFINITY, f64::min);
    if lightest.is_finite() && lightest > 0.0 {
        let passes = (ITERATIONS as f64 * (PLAIN_MASS / lightest).sqrt()).ceil();
        world.iterations = (passes as usize).clamp(ITERATIONS, MAX_ITERATIONS);
    }
    // Skip the free travel before a plate first reaches a caught object.
    let middle = jaws.center.coords.dot(&axis);
    let half_face = jaws.opening / 2.0 - gripper.plate_thickness / 2.0;
    let free = caught
        .iter()
        .map(|&i| {
            let (lo, hi) = bodies[i].outline.projection(&axis);
            (lo - (middle - half_face)).min(middle + half_face - hi)
        })
        .fold(f64::INFINITY, f64::min);
    if free.is_finite() && free > SPECULATIVE {
        world.plates.opening -= 2.0 * (free - SPECULATIVE);
    }
    world.plates.rate = -model.jaw_speed;
    let limit = (world.plates.opening - world.plates.shut) / model.jaw_speed + EXTRA_TIME;
    let steps = (limit / TIME_STEP).ceil() as usize;
    let mut still = 0;
    for _ in 0..steps {
        world.step();

        if world.plates.opening <= world.plates.shut {
            break;
        }
        still = if world.still() { still + 1 } else { 0 };
        if still >= STILL_STEPS {
            break;
        }
    }
    let squeezing = world.plates.motor.abs() >= 0.99 * model.grip_force * TIME_STEP;
    finish(&world, squeezing)
}

/// The gripped chain of the final state: the pieces that carry the squeeze. A piece squeezed in the
/// chain is pressed with the grip force from both sides; one that merely touches carries little.
fn finish(world: &World, squeezing: bool) -> Closed {
    let outlines: Vec<ConvexPolygon> = world.pieces.iter().map(Piece::outline).collect();
    let motions: Vec<Isometry2<f64>> = world.pieces.iter().map(Piece::motion).collect();
    let n = world.pieces.len();
    let mut pressed = vec![0.0; n];
    for c in &world.last {
        for party in [c.a, c.b] {
            if let Party::Piece(i) = party {
                pressed[i] += c.normal_impulse;
            }
        }
    }
    let threshold = world.grip_force * TIME_STEP;
    let axis = world.plates.axis;
    let rests = |i: usize| {
        let Some(share) = world.friction_share else {
            return true;
        };
        let touches: Vec<Touch> = world
            .last
            .iter()
            .filter(|c| c.normal_impulse > 0.0 || c.separation <= TOUCHING)
            .filter_map(|c| {
                Some(Touch {
                    point: c.point,
                    normal: c.normal_into(Party::Piece(i))?,
                    friction: c.friction,
                })
            })
            .collect();
        balanced(&world.pieces[i].position, &touches, share)
    };
    let mut gripped: Vec<usize> = (0..n)
        .filter(|&i| squeezing && pressed[i] >= threshold && rests(i))
        .collect();
    gripped.sort_by(|&i, &j| {
        world.pieces[i]
            .position
            .coords
            .dot(&axis)
            .total_cmp(&world.pieces[j].position.coords.dot(&axis))
    });
    let interfaces = gripped
        .windows(2)
        .filter_map(|pair| {
            world
                .last
                .iter()
                .find(|c| {
                    (c.a, c.b) == (Party::Piece(pair[0]), Party::Piece(pair[1]))
                        || (c.a, c.b) == (Party::Piece(pair[1]), Party::Piece(pair[0]))
                })
                .and_then(|c| c.normal_into(Party::Piece(pair[1])))
        })
        .collect();
    Closed {
        gripped,
        opening: world.plates.opening,
        squeezing,
        outlines,
        motions,
        interfaces,
    }
}
