//! The simulated table: extruded prisms on a fixed slab under gravity, and a two-finger gripper whose
//! fingers slide on prismatic joints driven by force-limited motors, in rapier3d.
//!
//! Frames: the table top is the plane `z = 0`, gravity points down `−z`. An object's body frame is
//! its polygon's frame at table level, so its collider is the convex hull of the outline at `z = 0`
//! and at `z = height` (for outlines of many vertices, it stands on a separate base: `base.rs`). The palm is a kinematic body at the fingers' mid-height; its local `x` is the
//! closing axis. Each finger is a dynamic box (plate thickness along `x`, plate length along `y`,
//! finger height along `z`) on a prismatic joint along the palm's `x`.
//!
//! **Finger drive.** With the coupled drive (the 2F-85's single motor and linkage) one opening `q`
//! drives both fingers: each joint's servo holds its finger at `∓q/2` with the linkage's stiffness
//! `k`, so a finger pressed outward by `d` pushes back with `k·d`. While closing, `q` shrinks at the
//! jaw speed until the mean of the two fingers' forces reaches the grip force; each step it shrinks
//! by at most `(F_grip − F)/k`, so the force approaches the limit without overshoot. Then `q` holds;
//! if an object slips and the force drops, closing resumes, as a force-limited motor does. With
//! independent fingers each finger has its own velocity motor limited to the grip force.
//!
//! **Landing.** While the gripper descends, a finger whose contact with an object has a normal within
//! 60° of vertical has come down on top of it: the descent stops there (a real arm would be stopped or
//! would crush the object), and the caller reports the action as failed.
//!
//! Here the stage is built and stepped; its motions are in `actions.rs`, the objects in `../prism.rs`.

use rapier3d_f64::math::{Pose, Rotation, Vector};
use rapier3d_f64::prelude::*;

use super::base;
use super::prism::Prism;
use super::settings::FingerDrive;
use crate::scene::Gripper;

/// A contact normal with a vertical component above this (cos 60°) means a finger is on top of an
/// object, not beside it.
const LANDING_NORMAL: f64 = 0.5;

/// A contact point counts as touching when the shapes interpenetrate (rapier also reports points a
/// little apart, within its prediction distance, whose normals join the nearest features and so can
/// point anywhere).
const TOUCHING: f64 = 0.0;

/// Collider materials, stored in the colliders' user data.
const TABLE: u128 = 0;
const OBJECT: u128 = 1;
const FINGER: u128 = 2;

mod actions;

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
    members: Members,
    /// Each object's collider and its index in the prisms.
    object_colliders: ObjectColliders,
    palm: RigidBodyHandle,
    joints: [ImpulseJointHandle; 2],
    fingers: [RigidBodyHandle; 2],
    finger_colliders: [ColliderHandle; 2],
    palm_translation: Vector,
    palm_rotation: Rotation,
    time_step: f64,
    /// Longest run-on before the poses are read back, seconds ([`Stage::write_back`]).
    rest_wait: f64,
    /// Half the finger's height: the palm sits this far above the fingertips, metres.
    half_finger: f64,
    drive: Drive,
}

/// The coupled drive's state: the commanded opening and, while closing, its speed and force limit.
struct Drive {
    kind: FingerDrive,
    stiffness: f64,
    damping: f64,
    /// Commanded distance between plate centres, metres.
    opening: f64,
    /// Smallest opening (plates touching), metres.
    shut: f64,
    /// While closing: speed (m/s) and force limit (N).
    closing: Option<(f64, f64)>,
}

/// Motion parameters of a stage.
pub(super) struct StageSettings {
    pub friction_finger: f64,
    pub friction_object: f64,
    pub friction_table: f64,
    pub finger_mass: f64,
    pub finger_height: f64,
    pub time_step: f64,
    /// Longest run-on after the action for the objects to come to rest, seconds.
    pub rest_wait: f64,
    pub contact_frequency: f64,
    pub fingers: FingerDrive,
    pub linkage_stiffness: f64,
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
        let hooks = ActiveHooks::MODIFY_SOLVER_CONTACTS;
        let mut world = world_with_table(settings, palm, hooks);
        let (handles, object_colliders) = add_objects(&mut world, prisms, members, hooks);
        let palm_rotation = Rotation::from_rotation_z(yaw);
        let palm_translation =
            Vector::new(palm.0, palm.1, tip_height + settings.finger_height / 2.0);
        let palm_body = world.bodies.insert(
            RigidBodyBuilder::kinematic_position_based()
                .pose(Pose::from_parts(palm_translation, palm_rotation)),
        );
        let stiffness = settings.linkage_stiffness;
        // Critically damped servo of one finger on the linkage.
        let damping = 2.0 * (stiffness * settings.finger_mass).sqrt();
        let (fingers, finger_colliders, joints) = add_fingers(
            &mut world,
            (gripper, settings),
            palm_body,
            (palm_translation, palm_rotation),
            opening,
            (stiffness, damping, hooks),
        );
        Self {
            world,
            hooks: Materials {
                finger: settings.friction_finger,
                object: settings.friction_object,
                table: settings.friction_table,
            },
            members: handles,
            object_colliders,
            palm: palm_body,
            joints,
            fingers,
            finger_colliders,
            palm_translation,
            palm_rotation,
            time_step: settings.time_step,
            rest_wait: settings.rest_wait,
            half_finger: settings.finger_height / 2.0,
            drive: Drive {
                kind: settings.fingers,
                stiffness,
                damping,
                opening,
                shut: gripper.plate_thickness,
                closing: None,
            },
        }
    }

    fn step(&mut self) {
        self.drive_fingers();
        self.world.step_with_events(&self.hooks, &());
    }

    /// The coupled drive's update before a step: shrink the commanded opening toward the force limit
    /// and move both servo targets with it.
    fn drive_fingers(&mut self) {
        if self.drive.kind != FingerDrive::Coupled {
            return;
        }
        let Some((speed, force)) = self.drive.closing else {
            return;
        };
        let squeeze = self.squeeze();
        let step = if squeeze < force {
            (speed * self.time_step)
                .min((force - squeeze) / self.drive.stiffness)
                .min(self.drive.opening - self.drive.shut)
                .max(0.0)
        } else {
            0.0
        };
        self.drive.opening -= step;
        let velocity = step / self.time_step / 2.0;
        let (opening, stiffness, damping) =
            (self.drive.opening, self.drive.stiffness, self.drive.damping);
        for (side, handle) in [-1.0, 1.0].into_iter().zip(self.joints) {
            if let Some(joint) = self.world.impulse_joints.get_mut(handle, true) {
                joint.data.set_motor(
                    JointAxis::LinX,
                    side * opening / 2.0,
                    -side * velocity,
                    stiffness,
                    damping,
                );
            }
        }
    }

    /// Each finger's position along the closing axis, relative to the palm, metres.
    fn finger_offsets(&self) -> [f64; 2] {
        let palm = self
            .world
            .bodies
            .get(self.palm)
            .map_or(self.palm_translation, |b| b.translation());
        let axis = self.palm_rotation * Vector::X;
        self.fingers.map(|h| {
            self.world
                .bodies
                .get(h)
                .map_or(0.0, |b| (b.translation() - palm).dot(axis))
        })
    }

    /// The coupled drive's squeeze: the mean force with which the linkage holds the fingers against
    /// whatever pushes them outward, newtons (0 for independent fingers).
    pub fn squeeze(&self) -> f64 {
        if self.drive.kind != FingerDrive::Coupled {
            return 0.0;
        }
        let [left, right] = self.finger_offsets();
        let half = self.drive.opening / 2.0;
        self.drive.stiffness * ((-half - left) + (right - half)) / 2.0
    }

    /// The member (index into the prisms) a finger rests on top of, if any.
    fn landed_on(&self) -> Option<usize> {
        for finger in self.finger_colliders {
            for pair in self.world.contact_pairs_with(finger) {
                let other = if pair.collider1 == finger {
                    pair.collider2
                } else {
                    pair.collider1
                };
                let Some(&(_, index)) = self.object_colliders.iter().find(|(h, _)| *h == other)
                else {
                    continue;
                };
                let on_top = pair.manifolds().iter().any(|m| {
                    m.data.normal.z.abs() > LANDING_NORMAL
                        && m.points.iter().any(|p| p.dist < TOUCHING)
                });
                if on_top {
                    return Some(index);
                }
            }
        }
        None
    }
}

/// Each member's prism index and its body.
type Members = Vec<(usize, RigidBodyHandle)>;
/// Each object's hull collider and its prism index.
type ObjectColliders = Vec<(ColliderHandle, usize)>;

/// An empty world under gravity with the solver's settings, and the table: a wide fixed slab whose
/// top is z = 0, centred under the palm.
fn world_with_table(
    settings: &StageSettings,
    palm: (f64, f64),
    hooks: ActiveHooks,
) -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    world.integration_parameters.dt = settings.time_step;
    world
        .integration_parameters
        .contact_softness
        .natural_frequency = settings.contact_frequency;
    // Coulomb friction at every contact point. rapier's default (`Simplified`) adds a "twist"
    // constraint per manifold that removes rotation in the contact plane: an object pushed off
    // its centre by one finger then slides without turning (a 26 × 44 mm block pushed 6–13 mm
    // off centre kept its yaw to 0.01°, where MuJoCo turned it 28°), and pushes looked exact.
    // Per-point Coulomb friction resists turning only through where the contacts are, as the
    // limit surface of `formulations/grasping.md` does.
    world.integration_parameters.friction_model = FrictionModel::Coulomb;
    let table = world
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(palm.0, palm.1, -0.05)));
    world.colliders.insert_with_parent(
        ColliderBuilder::cuboid(1.0, 1.0, 0.05)
            .collision_groups(base::table_groups())
            .user_data(TABLE)
            .active_hooks(hooks),
        table,
        &mut world.bodies,
    );
    world
}

/// Each member's prism as a dynamic body (its hull, and a base under outlines of many vertices):
/// the bodies by prism index, and each hull collider with its prism index.
fn add_objects(
    world: &mut PhysicsWorld,
    prisms: &[Prism],
    members: &[usize],
    hooks: ActiveHooks,
) -> (Members, ObjectColliders) {
    let mut handles = Vec::with_capacity(members.len());
    let mut object_colliders = Vec::with_capacity(members.len());
    for &index in members {
        let prism = &prisms[index];
        let body = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(Pose::from_parts(prism.translation, prism.rotation))
                .can_sleep(false),
        );
        let volume = prism.polygon.area() * prism.height;
        let base = base::collider(&prism.polygon, prism.height);
        let groups = if base.is_some() {
            base::hull_over_base_groups()
        } else {
            base::body_groups()
        };
        if let Some(collider) = ColliderBuilder::convex_hull(&prism.points()) {
            let handle = world.colliders.insert_with_parent(
                collider
                    .density(prism.mass / volume)
                    .collision_groups(groups)
                    .user_data(OBJECT)
                    .active_hooks(hooks),
                body,
                &mut world.bodies,
            );
            object_colliders.push((handle, index));
        }
        if let Some(base) = base {
            world.colliders.insert_with_parent(
                base.density(0.0)
                    .collision_groups(base::base_groups())
                    .user_data(OBJECT)
                    .active_hooks(hooks),
                body,
                &mut world.bodies,
            );
        }
        handles.push((index, body));
    }
    (handles, object_colliders)
}

/// The two fingers, boxes on prismatic joints along the palm's `x`, held `opening` apart by their
/// drives: the finger bodies, their colliders and their joints.
fn add_fingers(
    world: &mut PhysicsWorld,
    (gripper, settings): (&Gripper, &StageSettings),
    palm_body: RigidBodyHandle,
    (palm_translation, palm_rotation): (Vector, Rotation),
    opening: f64,
    (stiffness, damping, hooks): (f64, f64, ActiveHooks),
) -> (
    [RigidBodyHandle; 2],
    [ColliderHandle; 2],
    [ImpulseJointHandle; 2],
) {
    let half = [
        gripper.plate_thickness / 2.0,
        gripper.plate_length / 2.0,
        settings.finger_height / 2.0,
    ];
    let volume = 8.0 * half[0] * half[1] * half[2];
    let mut fingers = Vec::with_capacity(2);
    let mut finger_colliders = Vec::with_capacity(2);
    let mut joints = Vec::with_capacity(2);
    for side in [-1.0, 1.0] {
        let offset = palm_rotation * Vector::new(side * opening / 2.0, 0.0, 0.0);
        let finger = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(Pose::from_parts(palm_translation + offset, palm_rotation))
                .can_sleep(false),
        );
        finger_colliders.push(
            world.colliders.insert_with_parent(
                ColliderBuilder::cuboid(half[0], half[1], half[2])
                    .density(settings.finger_mass / volume)
                    .collision_groups(base::body_groups())
                    .user_data(FINGER)
                    .active_hooks(hooks),
                finger,
                &mut world.bodies,
            ),
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
            .contacts_enabled(false);
        // Both drives hold the fingers at the opening until told to close; the coupled servo is
        // the linkage itself, as strong as the arm needs (200 N, ten times the grip).
        let joint = match settings.fingers {
            FingerDrive::Coupled => joint.motor_position(side * opening / 2.0, stiffness, damping),
            FingerDrive::Independent => joint.motor_position(side * opening / 2.0, 2000.0, 100.0),
        }
        .motor_max_force(200.0);
        joints.push(world.impulse_joints.insert(palm_body, finger, joint, true));
        fingers.push(finger);
    }
    (
        [fingers[0], fingers[1]],
        [finger_colliders[0], finger_colliders[1]],
        [joints[0], joints[1]],
    )
}
