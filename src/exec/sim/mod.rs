//! A physics-simulated executor: fork pushes and multi-object grasps carried out by rapier3d on
//! extruded prisms standing on a frictional table under gravity, so that objects per trip come from a
//! physics engine that knows nothing of the planner's models.
//!
//! Each action is simulated on a short-lived *stage* (`world/`) holding the table, the gripper and
//! the objects within `reach` of the action's path; objects further away cannot be touched and keep
//! their poses. Stages are built in a fixed order from the state, so a run is deterministic: the same
//! scene, settings and seed give the same run, bit for bit, on one build.
//!
//! - **Fork push** (the paper's five steps): fingers opened to the fork opening, placed above the
//!   approach point with the jaw line across the push (with actuation noise), lowered until the
//!   fingertips are at `push_height_fraction` of the object's height, moved along the planned path at
//!   `push_speed`, raised.
//! - **Grasp and trip**: jaws opened as planned above the grasp (with actuation noise), lowered to
//!   `grasp_height`, closed at `jaw_speed` with at most `grip_force` per finger until they stop, lifted
//!   by `lift`, left to settle; with riders aboard, carried sideways by `carry` at
//!   `carry_acceleration` and left to settle again; the objects lifted clear of the table are
//!   carried to the bin. Anything dropped stays where physics leaves it.
//! - **Coming to rest**: after every action the stage runs on, the arm still, until nothing on it
//!   moves faster than 5 cm/s or turns faster than 2 rad/s (at most `rest_wait`), so that what
//!   falls lands before its pose is kept (`formulations/grasping.md`, "Objects still moving when an
//!   action ends").
//! - **Place** (riders, `formulations/stacking.md`): the rider picked with its single-object grasp,
//!   lifted clear, carried and turned over the row, put down on its top, let go.
//! - **Perception**: an observation is the true planar poses plus Gaussian noise (seeded). An object
//!   tilted past `topple_angle` that lies flat on a face (three or more corners on the table) is seen
//!   as a new, lower prism: the hull of its corners from above, less those within 0.1 mm of its edges
//!   ([`crate::geometry::hull_polygon`]; a prism on a side face has end faces standing on edge). One
//!   leaning on something, or whose outline has left the workspace, cannot be planned for; they are
//!   reported by [`Executor::lost`] and end the run when nothing else is left. Those past the
//!   workspace's edge are also reported where they lie ([`Executor::past_edge`], their noise drawn
//!   from a stream of their own), for a policy allowed to reach there (`run.reach_past_edge`).
//!   Noise that would make two observed outlines overlap is undone for one of them (a real
//!   segmentation never reports interpenetrating objects).

mod base;
mod camera;
mod observe;
mod place;
mod prism;
#[cfg(test)]
mod rest_check;
#[cfg(test)]
mod ride_check;
mod rollout;
mod settings;
mod world;

use nalgebra::Point2;
use rapier3d_f64::math::{Rotation, Vector};

use self::prism::Prism;
use self::world::{Stage, StageSettings};
use super::{Executor, GraspResult, Landing};
use crate::error::{Error, Result};
use crate::grasp::{Grasp, JawPose};
use crate::plan::Rider;
use crate::push::Push;
use crate::random::SeededRng;
use crate::scene::{Gripper, ObjectId, Pose, Scene, Workspace};

pub use rollout::Rollout;

/// A rider whose base is this high above the table still stands on something, metres.
const RIDING: f64 = 0.005;

impl Sim {
    /// Whether `prism` is a rider still standing upright on something (its row was not carried):
    /// a camera sees it on top, not on the table, so neither observation plans for it.
    fn rider_left_standing(&self, prism: &Prism) -> bool {
        self.placed.contains(&prism.id)
            && prism.tilt() <= self.settings.topple_angle
            && prism.translation.z > RIDING
    }
}
pub use camera::{CalibrationError, SimCamera};
pub use settings::{FingerDrive, SimSettings};

/// Where an action's stage was set: the jaws' centre and the end of its path, with actuation
/// noise, and the top of what stands within reach of that path, metres.
struct Lowered {
    centre: (f64, f64),
    end: (f64, f64),
    top: f64,
}

/// What [`Sim::close_and_release`] saw once the jaws had closed.
#[derive(Clone, Debug, PartialEq)]
pub struct Closing {
    /// Set when the descent came down on an object (nothing was closed then).
    pub landing: Option<Landing>,
    /// Distance between the plate centres once closed, metres.
    pub opening: f64,
    /// Every object within reach of the jaws and its pose seen from above once closed.
    pub poses: Vec<(ObjectId, Pose)>,
}

/// Executes plans in the physics simulator.
#[derive(Clone, Debug)]
pub struct Sim {
    settings: SimSettings,
    seed: u64,
    rng: SeededRng,
    prisms: Vec<Prism>,
    workspace: Option<Workspace>,
    gripper: Gripper,
    lost: Vec<(ObjectId, &'static str)>,
    /// Objects of `lost` outside the workspace, as the last look saw them past its edge.
    past_edge: Vec<crate::scene::Object>,
    /// The camera's error for the objects past the edge: a stream of its own, so that the main
    /// stream, and every run, is the same whether or not anything lies there.
    past_edge_rng: SeededRng,
    /// Objects put down on a row as riders and not carried since.
    placed: Vec<ObjectId>,
}

impl Sim {
    /// The simulator's seed for a run whose policy has seed `run_seed`: distinct from the policy's
    /// random stream, fixed by it (`pushmog run --seed` and the Python `Planner.run` use it).
    pub fn seed_for_run(run_seed: u64) -> u64 {
        run_seed ^ 0x5157_5349_4d00_0000
    }

    /// A simulator with these settings; `seed` drives perception and actuation noise.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(settings: SimSettings, seed: u64) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            settings,
            seed,
            rng: SeededRng::new(seed),
            prisms: Vec::new(),
            workspace: None,
            gripper: Gripper::default(),
            lost: Vec::new(),
            past_edge: Vec::new(),
            past_edge_rng: SeededRng::new(seed ^ PAST_EDGE_STREAM),
            placed: Vec::new(),
        })
    }

    /// The effective settings.
    pub fn settings(&self) -> &SimSettings {
        &self.settings
    }

    /// Where every prism standing upright on the table is, without the camera's noise: the ground
    /// truth against which a look, or looks fused, can be measured.
    pub fn true_poses(&self) -> Vec<(ObjectId, Pose)> {
        self.prisms
            .iter()
            .filter(|prism| prism.tilt() <= self.settings.topple_angle)
            .map(|prism| (prism.id, prism.planar_pose()))
            .collect()
    }

    fn stage_settings(&self) -> StageSettings {
        StageSettings {
            friction_finger: self.settings.friction_finger,
            friction_object: self.settings.friction_object,
            friction_table: self.settings.friction_table,
            finger_mass: self.settings.finger_mass,
            finger_height: self.settings.finger_height,
            time_step: self.settings.time_step,
            rest_wait: self.settings.rest_wait,
            contact_frequency: self.settings.contact_frequency,
            fingers: self.settings.fingers,
            linkage_stiffness: self.settings.linkage_stiffness,
        }
    }

    /// Objects on the table within `reach` of the segment from `a` to `b` (planar), in state order.
    fn near(&self, a: (f64, f64), b: (f64, f64)) -> Vec<usize> {
        let reach = self.settings.reach;
        (0..self.prisms.len())
            .filter(|&i| {
                let p = &self.prisms[i];
                let (x, y) = (p.translation.x, p.translation.y);
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let length2 = dx * dx + dy * dy;
                let t = if length2 > 0.0 {
                    (((x - a.0) * dx + (y - a.1) * dy) / length2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (cx, cy) = (a.0 + t * dx, a.1 + t * dy);
                (x - cx).hypot(y - cy) <= reach
            })
            .collect()
    }

    /// Actuation noise: an offset in the plane and a yaw error.
    fn actuation(&mut self) -> (f64, f64, f64) {
        let s = &self.settings;
        let (sp, sy) = (s.actuation_position, s.actuation_yaw);
        (
            sp * self.rng.normal(),
            sp * self.rng.normal(),
            sy * self.rng.normal(),
        )
    }

    /// The grasp's first half: open jaws lowered over the grasp (with actuation noise) and closed until
    /// they stop; `Err` when the descent came down on an object (the action is then abandoned).
    fn lower_and_close(&mut self, grasp: &Grasp) -> std::result::Result<Stage, Landing> {
        let tip = self.settings.grasp_height;
        self.lower_and_close_at(&grasp.jaws, None, Self::tallest, tip)
            .map(|(stage, _)| stage)
    }

    /// Open jaws lowered over `jaws` (with actuation noise) until the fingertips are `tip` above the
    /// table, then closed until they stop, on a stage of the prisms within reach of the path from
    /// the jaws to `end` (with the same noise; `None`: the jaws alone). The jaws come down from 5 mm
    /// above `top` of those prisms. `Err` when the descent came down on an object (the action is
    /// then abandoned).
    fn lower_and_close_at(
        &mut self,
        jaws: &JawPose,
        end: Option<Point2<f64>>,
        top: fn(&Self, &[usize]) -> f64,
        tip: f64,
    ) -> std::result::Result<(Stage, Lowered), Landing> {
        let (ex, ey, eyaw) = self.actuation();
        let centre = (jaws.center.x + ex, jaws.center.y + ey);
        let end = end.map_or(centre, |p| (p.x + ex, p.y + ey));
        let members = self.near(centre, end);
        let top = top(self, &members);
        let above = top + 0.005;
        let s = &self.settings;
        let mut stage = Stage::new(
            &self.prisms,
            &members,
            &self.gripper,
            &self.stage_settings(),
            centre,
            above,
            jaws.angle + eyaw,
            jaws.opening,
        );
        if let Some(index) = stage.descend(above - tip, s.vertical_speed) {
            return Err(self.abandon(stage, above, index));
        }
        let timeout = jaws.opening / s.jaw_speed + 0.5;
        stage.close(s.jaw_speed, s.grip_force, timeout);
        Ok((stage, Lowered { centre, end, top }))
    }

    /// Lowers the open jaws as for `grasp`, closes them, notes where every object within reach is,
    /// then opens the jaws again and rises without lifting anything. For studying what a closing does
    /// (and for tests): the table keeps whatever the closing did to it.
    ///
    /// # Errors
    /// When [`Executor::reset`] was not called.
    pub fn close_and_release(&mut self, grasp: &Grasp) -> Result<Closing> {
        if self.workspace.is_none() {
            return Err(Error::misuse(
                "sim executor",
                "act before reset(): no table was given",
            ));
        }
        let mut stage = match self.lower_and_close(grasp) {
            Ok(stage) => stage,
            Err(landing) => {
                return Ok(Closing {
                    landing: Some(landing),
                    opening: grasp.jaws.opening,
                    poses: Vec::new(),
                });
            }
        };
        stage.wait(0.05);
        let opening = stage.opening();
        let poses = stage
            .poses()
            .into_iter()
            .map(|(index, pose)| (self.prisms[index].id, pose))
            .collect();
        stage.open(grasp.jaws.opening, self.settings.jaw_speed);
        let height = stage.tip_height();
        let above = self.tallest(&(0..self.prisms.len()).collect::<Vec<_>>()) + 0.005;
        stage.travel(
            Vector::new(0.0, 0.0, above - height),
            self.settings.vertical_speed,
        );
        stage.wait(0.05);
        stage.write_back(&mut self.prisms);
        Ok(Closing {
            landing: None,
            opening,
            poses,
        })
    }

    /// Ends an action whose descent stopped on prism `index`: the gripper rises back to `above` and
    /// the objects stay as physics left them.
    fn abandon(&mut self, mut stage: Stage, above: f64, index: usize) -> Landing {
        let height = stage.tip_height();
        stage.travel(
            Vector::new(0.0, 0.0, above - height),
            self.settings.vertical_speed,
        );
        stage.wait(0.05);
        stage.write_back(&mut self.prisms);
        Landing {
            object: self.prisms[index].id,
        }
    }

    /// The highest point of these prisms above the table, metres, riders standing on others
    /// included.
    fn top_of(&self, members: &[usize]) -> f64 {
        members
            .iter()
            .map(|&i| self.prisms[i].translation.z.max(0.0) + self.prisms[i].height)
            .fold(0.0, f64::max)
    }

    fn tallest(&self, members: &[usize]) -> f64 {
        members
            .iter()
            .map(|&i| self.prisms[i].height)
            .fold(0.0, f64::max)
    }
}

impl Sim {
    /// The table's workspace, or misuse before [`Executor::reset`] gave a table.
    fn table(&self) -> Result<&crate::scene::Workspace> {
        self.workspace
            .as_ref()
            .ok_or_else(|| Error::misuse("sim executor", "act before reset(): no table was given"))
    }
}

impl Executor for Sim {
    fn name(&self) -> &'static str {
        "sim"
    }

    fn reset(&mut self, scene: &Scene) -> Result<()> {
        self.rng = SeededRng::new(self.seed);
        self.past_edge_rng = SeededRng::new(self.seed ^ PAST_EDGE_STREAM);
        self.workspace = Some(scene.workspace().clone());
        self.gripper = scene.gripper().clone();
        self.lost.clear();
        self.past_edge.clear();
        self.placed.clear();
        self.prisms = scene
            .objects()
            .iter()
            .map(|o| {
                let mass = o
                    .mass
                    .unwrap_or(self.settings.density * o.polygon.area() * o.height);
                Prism {
                    id: o.id,
                    name: o.name.clone(),
                    polygon: o.polygon.clone(),
                    height: o.height,
                    mass,
                    translation: Vector::new(o.pose.x, o.pose.y, 0.0),
                    rotation: Rotation::from_rotation_z(o.pose.yaw),
                }
            })
            .collect();
        Ok(())
    }

    fn push(&mut self, push: &Push) -> Result<Option<Landing>> {
        self.table()?;
        let Some(target) = self.prisms.iter().position(|p| p.id == push.object) else {
            return Ok(None);
        };
        let (ex, ey, eyaw) = self.actuation();
        let fork = &push.fork;
        let start = (fork.approach.x + ex, fork.approach.y + ey);
        let end = (fork.end.x + ex, fork.end.y + ey);
        let members = self.near(start, end);
        let tip = fork
            .height
            .unwrap_or(self.settings.push_height_fraction * self.prisms[target].height);
        let above = self.tallest(&members) + 0.005;
        let mut stage = Stage::new(
            &self.prisms,
            &members,
            &self.gripper,
            &self.stage_settings(),
            start,
            above,
            fork.jaw_angle + eyaw,
            fork.opening,
        );
        let speed = self.settings.vertical_speed;
        if let Some(index) = stage.descend(above - tip, speed) {
            return Ok(Some(self.abandon(stage, above, index)));
        }
        stage.travel(
            Vector::new(end.0 - start.0, end.1 - start.1, 0.0),
            self.settings.push_speed,
        );
        stage.travel(Vector::new(0.0, 0.0, above - tip), speed);
        stage.wait(0.05);
        stage.write_back(&mut self.prisms);
        Ok(None)
    }

    fn grasp(&mut self, grasp: &Grasp) -> Result<GraspResult> {
        self.table()?;
        let s = self.settings.clone();

        let mut stage = match self.lower_and_close(grasp) {
            Ok(stage) => stage,
            Err(landing) => {
                return Ok(GraspResult {
                    carried: Vec::new(),
                    landing: Some(landing),
                });
            }
        };
        stage.wait(0.05);
        stage.travel(Vector::new(0.0, 0.0, s.lift), s.vertical_speed);
        stage.wait(s.settle);
        // With riders aboard, the row goes sideways toward the bin at the arm's acceleration,
        // which is what may tip or slide a rider.
        let centre = (grasp.jaws.center.x, grasp.jaws.center.y);
        let aboard = !self.placed.is_empty()
            && self
                .near(centre, centre)
                .iter()
                .any(|&i| self.placed.contains(&self.prisms[i].id));
        if aboard && s.carry > 0.0 {
            let along = grasp.jaws.angle + std::f64::consts::FRAC_PI_2;
            let offset = Vector::new(along.cos(), along.sin(), 0.0) * s.carry;
            stage.carry(offset, s.carry_speed, s.carry_acceleration);
            stage.wait(s.settle);
        }
        stage.write_back(&mut self.prisms);
        // Carried: lifted clear of the table (its lowest point at least half the lift up).
        let clear = 0.5 * s.lift;
        let mut carried = Vec::new();
        self.prisms.retain(|p| {
            let lowest = p
                .polygon
                .vertices()
                .iter()
                .flat_map(|v| [0.0, p.height].map(|z| (p.rotation * Vector::new(v.x, v.y, z)).z))
                .fold(f64::INFINITY, f64::min)
                + p.translation.z;
            if lowest > clear {
                carried.push(p.id);
                false
            } else {
                true
            }
        });
        self.placed.retain(|id| !carried.contains(id));
        // Anything else that left the stage upward and fell is back on the table by now.
        Ok(GraspResult::carried(carried))
    }

    /// As [`Sim::put_down`] (`place.rs`).
    fn place(&mut self, rider: &Rider) -> Result<Option<Landing>> {
        self.put_down(rider)
    }

    /// As [`Sim::observation`] (`observe.rs`).
    fn observe(&mut self) -> Result<Scene> {
        self.past_edge.clear();
        match self.settings.camera.clone() {
            Some(camera) => self.camera_observation(&camera),
            None => self.observation(),
        }
    }

    fn lost(&self) -> Vec<(ObjectId, &'static str)> {
        self.lost.clone()
    }

    /// Without the depth camera (`SimSettings::camera`), every object lost outside the workspace
    /// that stands upright or lies flat, seen with the same error as those inside; with it, the
    /// prisms whose blobs perception found outside the workspace or over its edge and would have
    /// taken for objects otherwise (`Perception::past_edge`), as perceived.
    fn past_edge(&self) -> Vec<crate::scene::Object> {
        self.past_edge.clone()
    }
}

/// Mixed into the seed of the stream that draws the camera's error past the workspace's edge.
const PAST_EDGE_STREAM: u64 = 0x0070_6173_7445_6467;
