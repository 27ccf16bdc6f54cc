//! The simulated table: extruded prisms on a fixed slab under gravity, and a two-finger gripper whose
//! fingers slide on prismatic joints driven by force-limited motors, in rapier3d.
//!
//! Frames: the table top is the plane `z = 0`, gravity points down `−z`. An object's body frame is
//! its polygon's frame at table level, so its collider is the convex hull of the outline at `z = 0`
//! and at `z = height`. The palm is a kinematic body at the fingers' mid-height; its local `x` is the
//! closing axis. Each finger is a dynamic box (plate thickness along `x`, plate length along `y`,
//! finger height along `z`) on a prismatic joint along the palm's `x`.

use rapier3d_f64::math::{Pose, Rotation, Vector};
use rapier3d_f64::prelude::*;

use crate::geometry::ConvexPolygon;
use crate::scene::{Gripper, ObjectId, Pose as PlanarPose};

/// Collider materials, stored in the colliders' user data.
const TABLE: u128 = 0;
const OBJECT: u128 = 1;
const FINGER: u128 = 2;

/// One object as the simulator knows it: its prism and its full spatial pose.
#[derive(Clone, Debug)]
pub(super) struct Prism {
    pub id: ObjectId,
    pub name: Option<String>,
    pub polygon: ConvexPolygon,
    pub height: f64,
    pub mass: f64,
    pub translation: Vector,
    pub rotation: Rotation,
}

impl Prism {
    /// The pose seen from above: position of the body frame and yaw.
    pub fn planar_pose(&self) -> PlanarPose {
        let x_axis = self.rotation * Vector::X;
        PlanarPose::new(
            self.translation.x,
            self.translation.y,
            x_axis.y.atan2(x_axis.x),
        )
    }

    /// How far the object is tilted from upright, radians.
    pub fn tilt(&self) -> f64 {
        (self.rotation * Vector::Z)
            .dot(Vector::Z)
            .clamp(-1.0, 1.0)
            .acos()
    }

    /// The outline seen from above at the planar pose.
    pub fn outline(&self) -> ConvexPolygon {
        self.polygon.transformed(&self.planar_pose().isometry())
    }

    fn points(&self) -> Vec<Vector> {
        self.polygon
            .vertices()
            .iter()
            .flat_map(|v| {
                [
                    Vector::new(v.x, v.y, 0.0),
                    Vector::new(v.x, v.y, self.height),
                ]
            })
            .collect()
    }
}

/// Per-pair friction from the two colliders' materials.
struct Materials {
    finger: f64,
    object: f64,
    table: f64,
}

impl PhysicsHooks for Materials {
    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        let material = |handle: ColliderHandle| {
            context
                .colliders
                .get(handle)
                .map_or(OBJECT, |c| c.user_data)
        };
        let (a, b) = (material(context.collider1), material(context.collider2));
        let friction = if a == FINGER || b == FINGER {
            self.finger
        } else if a == TABLE || b == TABLE {
            self.table
        } else {
            self.object
        };
        if let ModifiableContacts::Rigid(manifold) = &mut context.contacts {
            *manifold.friction = friction;
        }
    }
}

/// A short simulation around one action: the objects within reach, the table, the gripper.
pub(super) struct Stage {
    world: PhysicsWorld,
    hooks: Materials,
    members: Vec<(usize, RigidBodyHandle)>,
    palm: RigidBodyHandle,
    joints: [ImpulseJointHandle; 2],
    fingers: [RigidBodyHandle; 2],
    palm_translation: Vector,
    palm_rotation: Rotation,
    time_step: f64,
}

/// Motion parameters of a stage.
pub(super) struct StageSettings {
    pub friction_finger: f64,
    pub friction_object: f64,
    pub friction_table: f64,
    pub finger_mass: f64,
    pub finger_height: f64,
    pub time_step: f64,
    pub contact_frequency: f64,
}

impl Stage {
    /// Builds the stage with `prisms[i]` for `i` in `members`, the palm at `palm` (fingertips at
    /// `tip_height` above the table) with its closing axis at `yaw`, the fingers `opening` apart
    /// between plate centres.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        prisms: &[Prism],
        members: &[usize],
        gripper: &Gripper,
        settings: &StageSettings,
        palm: (f64, f64),
        tip_height: f64,
        yaw: f64,
        opening: f64,
    ) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        world.integration_parameters.dt = settings.time_step;
        world
            .integration_parameters
            .contact_softness
            .natural_frequency = settings.contact_frequency;
        let hooks = ActiveHooks::MODIFY_SOLVER_CONTACTS;
        // The table: a wide fixed slab whose top is z = 0.
        let table = world
            .bodies
            .insert(RigidBodyBuilder::fixed().translation(Vector::new(palm.0, palm.1, -0.05)));
        world.colliders.insert_with_parent(
            ColliderBuilder::cuboid(1.0, 1.0, 0.05)
                .user_data(TABLE)
                .active_hooks(hooks),
            table,
            &mut world.bodies,
        );
        let mut handles = Vec::with_capacity(members.len());
        for &index in members {
            let prism = &prisms[index];
            let body = world.bodies.insert(
                RigidBodyBuilder::dynamic()
                    .pose(Pose::from_parts(prism.translation, prism.rotation))
                    .can_sleep(false),
            );
            let volume = prism.polygon.area() * prism.height;
            if let Some(collider) = ColliderBuilder::convex_hull(&prism.points()) {
                world.colliders.insert_with_parent(
                    collider
                        .density(prism.mass / volume)
                        .user_data(OBJECT)
                        .active_hooks(hooks),
                    body,
                    &mut world.bodies,
                );
            }
            handles.push((index, body));
        }
        let palm_rotation = Rotation::from_rotation_z(yaw);
        let palm_translation =
            Vector::new(palm.0, palm.1, tip_height + settings.finger_height / 2.0);
        let palm_body = world.bodies.insert(
            RigidBodyBuilder::kinematic_position_based()
                .pose(Pose::from_parts(palm_translation, palm_rotation)),
        );
        let half = [
            gripper.plate_thickness / 2.0,
            gripper.plate_length / 2.0,
            settings.finger_height / 2.0,
        ];
        let volume = 8.0 * half[0] * half[1] * half[2];
        let mut fingers = Vec::with_capacity(2);
        let mut joints = Vec::with_capacity(2);
        for side in [-1.0, 1.0] {
            let offset = palm_rotation * Vector::new(side * opening / 2.0, 0.0, 0.0);
            let finger = world.bodies.insert(
                RigidBodyBuilder::dynamic()
                    .pose(Pose::from_parts(palm_translation + offset, palm_rotation))
                    .can_sleep(false),
            );
            world.colliders.insert_with_parent(
                ColliderBuilder::cuboid(half[0], half[1], half[2])
                    .density(settings.finger_mass / volume)
                    .user_data(FINGER)
                    .active_hooks(hooks),
                finger,
                &mut world.bodies,
            );
            let limits = if side < 0.0 {
                [-gripper.stroke / 2.0, -gripper.plate_thickness / 2.0]
            } else {
                [gripper.plate_thickness / 2.0, gripper.stroke / 2.0]
            };
            let joint = PrismaticJointBuilder::new(Vector::X)
                .local_anchor1(Vector::ZERO)
                .local_anchor2(Vector::ZERO)
                .limits(limits)
                .motor_model(MotorModel::ForceBased)
                .motor_position(side * opening / 2.0, 2000.0, 100.0)
                .motor_max_force(200.0)
                .contacts_enabled(false);
            joints.push(world.impulse_joints.insert(palm_body, finger, joint, true));
            fingers.push(finger);
        }
        Self {
            world,
            hooks: Materials {
                finger: settings.friction_finger,
                object: settings.friction_object,
                table: settings.friction_table,
            },
            members: handles,
            palm: palm_body,
            joints: [joints[0], joints[1]],
            fingers: [fingers[0], fingers[1]],
            palm_translation,
            palm_rotation,
            time_step: settings.time_step,
        }
    }

    fn step(&mut self) {
        self.world.step_with_events(&self.hooks, &());
    }

    /// Lets the world run with the palm still, seconds.
    pub fn wait(&mut self, seconds: f64) {
        let steps = (seconds / self.time_step).ceil() as usize;
        for _ in 0..steps {
            self.move_palm_to(self.palm_translation);
            self.step();
        }
    }

    fn move_palm_to(&mut self, translation: Vector) {
        self.palm_translation = translation;
        if let Some(palm) = self.world.bodies.get_mut(self.palm) {
            palm.set_next_kinematic_position(Pose::from_parts(translation, self.palm_rotation));
        }
    }

    /// Moves the palm in a straight line by `offset` at `speed`, simulating each step.
    pub fn travel(&mut self, offset: Vector, speed: f64) {
        let distance = offset.length();
        if distance == 0.0 {
            return;
        }
        let steps = (distance / (speed * self.time_step)).ceil().max(1.0) as usize;
        let start = self.palm_translation;
        for k in 1..=steps {
            self.move_palm_to(start + offset * (k as f64 / steps as f64));
            self.step();
        }
    }

    /// Closes the jaws at `speed` with at most `force` per finger, until they stop moving (or are shut);
    /// returns the final opening between plate centres.
    pub fn close(&mut self, speed: f64, force: f64, timeout: f64) -> f64 {
        for (side, handle) in [-1.0, 1.0].into_iter().zip(self.joints) {
            if let Some(joint) = self.world.impulse_joints.get_mut(handle, true) {
                joint
                    .data
                    .set_motor_velocity(JointAxis::LinX, -side * speed, 1000.0);
                joint.data.set_motor_max_force(JointAxis::LinX, force);
            }
        }
        let steps = (timeout / self.time_step).ceil() as usize;
        let mut still = 0;
        let mut last = self.opening();
        for _ in 0..steps {
            self.move_palm_to(self.palm_translation);
            self.step();
            let now = self.opening();
            // Stopped: under a tenth of the commanded speed for 0.05 s.
            if (last - now).abs() < 0.1 * speed * self.time_step {
                still += 1;
                if still as f64 * self.time_step >= 0.05 {
                    break;
                }
            } else {
                still = 0;
            }
            last = now;
        }
        self.opening()
    }

    /// Current distance between the plate centres, metres.
    pub fn opening(&self) -> f64 {
        let position = |h: RigidBodyHandle| {
            self.world
                .bodies
                .get(h)
                .map_or(Vector::ZERO, |b| b.translation())
        };
        (position(self.fingers[1]) - position(self.fingers[0])).length()
    }

    /// Writes the simulated poses back into `prisms`.
    pub fn write_back(&self, prisms: &mut [Prism]) {
        for &(index, handle) in &self.members {
            if let Some(body) = self.world.bodies.get(handle) {
                prisms[index].translation = body.translation();
                prisms[index].rotation = *body.rotation();
            }
        }
    }
}
