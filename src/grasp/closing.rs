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

use nalgebra::{Isometry2, Point2, Vector2};

use super::body::Body;
use crate::geometry::{ConvexPolygon, contact_points, cross};
use crate::problem::GraspModel;
use crate::scene::Gripper;

use super::equilibrium::{Touch, balanced};
use super::jaws::JawPose;

/// Standard gravity, m/s².
const GRAVITY: f64 = 9.81;
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
        let to_origin = Isometry2::translation(-self.start_centroid.x, -self.start_centroid.y);
        let placed = Isometry2::new(self.position.coords, self.angle);
        self.start.transformed(&(placed * to_origin))
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

impl World {
    fn velocity_at(&self, party: Party, point: &Point2<f64>) -> Vector2<f64> {
        match party {
            Party::Piece(i) => {
                let p = &self.pieces[i];
                let r = point - p.position;
                p.velocity + Vector2::new(-r.y, r.x) * p.spin
            }
            Party::Plate(side) => self.plates.axis * (side * self.plates.rate / 2.0),
        }
    }

    /// Inverse effective mass of `party` for an impulse along `direction` at `point`.
    fn inverse_mass(&self, party: Party, point: &Point2<f64>, direction: &Vector2<f64>) -> f64 {
        match party {
            Party::Piece(i) => {
                let p = &self.pieces[i];
                let r = point - p.position;
                let arm = cross(&r, direction);
                1.0 / p.mass + arm * arm / p.inertia
            }
            Party::Plate(side) => {
                let j = side / 2.0 * self.plates.axis.dot(direction);
                j * j / Plates::MASS
            }
        }
    }

    fn apply(&mut self, party: Party, point: &Point2<f64>, impulse: Vector2<f64>) {
        match party {
            Party::Piece(i) => {
                let p = &mut self.pieces[i];
                let r = point - p.position;
                p.velocity += impulse / p.mass;
                p.spin += cross(&r, &impulse) / p.inertia;
            }
            Party::Plate(side) => {
                self.plates.rate += side / 2.0 * self.plates.axis.dot(&impulse) / Plates::MASS;
            }
        }
    }

    fn contacts(&self, margin: f64) -> Vec<Contact> {
        let outlines: Vec<ConvexPolygon> = self.pieces.iter().map(Piece::outline).collect();
        let boxes: Vec<(Point2<f64>, Point2<f64>)> =
            outlines.iter().map(ConvexPolygon::bounding_box).collect();
        let near = |a: (Point2<f64>, Point2<f64>), b: (Point2<f64>, Point2<f64>)| {
            a.0.x <= b.1.x + margin
                && b.0.x <= a.1.x + margin
                && a.0.y <= b.1.y + margin
                && b.0.y <= a.1.y + margin
        };
        let mut found = Vec::new();
        let mut add = |a: Party, b: Party, first: &ConvexPolygon, second: &ConvexPolygon| {
            let friction = if matches!(a, Party::Plate(_)) {
                self.friction_jaw
            } else {
                self.friction_object
            };
            for c in contact_points(first, second, margin) {
                found.push(Contact {
                    a,
                    b,
                    point: c.point,
                    normal: c.normal,
                    separation: c.separation,
                    friction,
                    normal_impulse: 0.0,
                    tangent_impulse: 0.0,
                    normal_mass: 0.0,
                    tangent_mass: 0.0,
                });
            }
        };
        for side in [-1.0, 1.0] {
            let plate = self.plates.outline(side);
            let plate_box = plate.bounding_box();
            for (i, outline) in outlines.iter().enumerate() {
                if near(plate_box, boxes[i]) {
                    add(Party::Plate(side), Party::Piece(i), &plate, outline);
                }
            }
        }
        for i in 0..outlines.len() {
            for j in i + 1..outlines.len() {
                if near(boxes[i], boxes[j]) {
                    add(Party::Piece(i), Party::Piece(j), &outlines[i], &outlines[j]);
                }
            }
        }
        found
    }

    /// Table friction on every piece: the impulse that would stop it, held within the limit surface.
    fn table_friction(&mut self) {
        let limit_per_mass = self.friction_table * GRAVITY * TIME_STEP;
        for p in &mut self.pieces {
            let limit = limit_per_mass * p.mass;
            let (force, torque) = p.table;
            let wanted = (force - p.velocity * p.mass, torque - p.spin * p.inertia);
            let size = (wanted.0.norm_squared() + (wanted.1 / p.friction_radius).powi(2)).sqrt();
            let scale = if size > limit { limit / size } else { 1.0 };
            let next = (wanted.0 * scale, wanted.1 * scale);
            p.velocity += (next.0 - force) / p.mass;
            p.spin += (next.1 - torque) / p.inertia;
            p.table = next;
        }
    }

    /// The jaws' motor: close at the jaw speed with at most the grip force per finger.
    fn motor(&mut self) {
        let plates = &mut self.plates;
        let limit = self.grip_force * TIME_STEP;
        let wanted =
            (plates.motor + (-self.jaw_speed - plates.rate) * Plates::MASS).clamp(-limit, limit);
        plates.rate += (wanted - plates.motor) / Plates::MASS;
        plates.motor = wanted;
    }

    fn solve_contact(&mut self, contact: &mut Contact) {
        let (a, b, point, normal) = (contact.a, contact.b, contact.point, contact.normal);
        let relative = self.velocity_at(b, &point) - self.velocity_at(a, &point);
        let normal_mass = contact.normal_mass;
        let target = if contact.separation > 0.0 {
            -contact.separation / TIME_STEP
        } else {
            BAUMGARTE * (-contact.separation - SLOP).max(0.0) / TIME_STEP
        };
        let accumulated =
            (contact.normal_impulse + (target - relative.dot(&normal)) / normal_mass).max(0.0);
        let delta = accumulated - contact.normal_impulse;
        contact.normal_impulse = accumulated;
        self.apply(a, &point, -normal * delta);
        self.apply(b, &point, normal * delta);
        // Friction along the tangent, within the cone of the normal impulse.
        let tangent = Vector2::new(-normal.y, normal.x);
        let relative = self.velocity_at(b, &point) - self.velocity_at(a, &point);
        let tangent_mass = contact.tangent_mass;
        let bound = contact.friction * contact.normal_impulse;
        let accumulated =
            (contact.tangent_impulse - relative.dot(&tangent) / tangent_mass).clamp(-bound, bound);
        let delta = accumulated - contact.tangent_impulse;
        contact.tangent_impulse = accumulated;
        self.apply(a, &point, -tangent * delta);
        self.apply(b, &point, tangent * delta);
    }

    fn step(&mut self) {
        let mut contacts = self.contacts(SPECULATIVE);
        // Warm start: a contact of the same pair near where one was last step starts from the
        // impulses it carried then, so static friction holds from step to step.
        for contact in &mut contacts {
            let previous = self.last.iter().find(|c| {
                c.a == contact.a
                    && c.b == contact.b
                    && (c.point - contact.point).norm_squared() < WARM_START_RADIUS.powi(2)
            });
            if let Some(previous) = previous {
                contact.normal_impulse = previous.normal_impulse;
                contact.tangent_impulse = previous.tangent_impulse;
                let (a, b, point) = (contact.a, contact.b, contact.point);
                let tangent = Vector2::new(-contact.normal.y, contact.normal.x);
                let impulse =
                    contact.normal * contact.normal_impulse + tangent * contact.tangent_impulse;
                self.apply(a, &point, -impulse);
                self.apply(b, &point, impulse);
            }
        }
        for contact in &mut contacts {
            let (a, b, point, normal) = (contact.a, contact.b, contact.point, contact.normal);
            let tangent = Vector2::new(-normal.y, normal.x);
            contact.normal_mass =
                self.inverse_mass(a, &point, &normal) + self.inverse_mass(b, &point, &normal);
            contact.tangent_mass =
                self.inverse_mass(a, &point, &tangent) + self.inverse_mass(b, &point, &tangent);
        }
        for p in &mut self.pieces {
            p.table = (Vector2::zeros(), 0.0);
        }
        self.plates.motor = 0.0;
        for _ in 0..self.iterations {
            self.table_friction();
            self.motor();
            for contact in &mut contacts {
                self.solve_contact(contact);
            }
        }
        for p in &mut self.pieces {
            p.position += p.velocity * TIME_STEP;
            p.angle += p.spin * TIME_STEP;
        }
        let plates = &mut self.plates;
        plates.opening += plates.rate * TIME_STEP;
        if plates.opening <= plates.shut {
            plates.opening = plates.shut;
            plates.rate = plates.rate.max(0.0);
        }
        self.last = contacts;
    }

    fn still(&self) -> bool {
        let slow = 0.02 * self.jaw_speed;
        self.plates.rate.abs() < slow
            && self
                .pieces
                .iter()
                .all(|p| p.velocity.norm() < slow && (p.spin * p.friction_radius).abs() < slow)
    }
}

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
        interfaces,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, side: f64) -> ConvexPolygon {
        let h = side / 2.0;
        ConvexPolygon::new(vec![
            Point2::new(x - h, y - h),
            Point2::new(x + h, y - h),
            Point2::new(x + h, y + h),
            Point2::new(x - h, y + h),
        ])
        .unwrap_or_else(|e| panic!("{e}"))
    }

    fn close(outlines: &[ConvexPolygon], centre: (f64, f64)) -> Closed {
        let bodies: Vec<Body<'_>> = outlines
            .iter()
            .map(|o| Body {
                outline: o,
                mass: 1000.0 * o.area() * 0.03,
            })
            .collect();
        let jaws = JawPose {
            center: Point2::new(centre.0, centre.1),
            angle: 0.0,
            opening: 0.085,
        };
        let caught: Vec<usize> = (0..outlines.len()).collect();
        simulate_closing(
            &bodies,
            &caught,
            &Gripper::default(),
            &jaws,
            &GraspModel::default(),
        )
    }

    #[test]
    fn an_off_centre_cube_is_pushed_to_the_centre_and_gripped() {
        let closed = close(&[square(0.2, 0.15, 0.03)], (0.215, 0.15));
        assert!(closed.squeezing);
        assert_eq!(closed.gripped, vec![0]);
        let centre = closed.outlines[0].centroid();
        assert!((centre.x - 0.215).abs() < 5e-4, "{centre:?}");
        assert!((closed.opening - 0.04).abs() < 5e-4, "{}", closed.opening);
    }

    #[test]
    fn a_half_gram_square_is_gripped() {
        // 5 mm × 5 mm × 20 mm of water density: 0.5 g against 50 g fingers.
        let outline = square(0.05, 0.05, 0.005);
        let bodies = [Body {
            outline: &outline,
            mass: 0.0005,
        }];
        let jaws = JawPose {
            center: Point2::new(0.05, 0.05),
            angle: 0.0,
            opening: 0.025,
        };
        let closed = simulate_closing(
            &bodies,
            &[0],
            &Gripper::default(),
            &jaws,
            &GraspModel::default(),
        );
        assert!(closed.squeezing);
        assert_eq!(closed.gripped, vec![0]);
    }

    #[test]
    fn two_aligned_cubes_are_gripped_together() {
        let closed = close(
            &[square(0.2, 0.15, 0.03), square(0.231, 0.151, 0.03)],
            (0.215, 0.15),
        );
        assert!(closed.squeezing);
        assert_eq!(closed.gripped, vec![0, 1]);
    }
}
