//! One step of the closing: contacts found, table friction and the jaw motor applied, contact
//! impulses solved by sequential passes, positions advanced.

use nalgebra::{Point2, Vector2};

use super::{
    BAUMGARTE, Contact, GRAVITY, Party, Piece, Plates, SLOP, SPECULATIVE, TIME_STEP,
    WARM_START_RADIUS, World,
};
use crate::geometry::{ConvexPolygon, contact_points, cross};

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

    pub(super) fn step(&mut self) {
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

    pub(super) fn still(&self) -> bool {
        let slow = 0.02 * self.jaw_speed;
        self.plates.rate.abs() < slow
            && self
                .pieces
                .iter()
                .all(|p| p.velocity.norm() < slow && (p.spin * p.friction_radius).abs() < slow)
    }
}
