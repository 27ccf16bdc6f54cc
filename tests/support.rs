//! Shared helpers: fixture paths, running the command-line binary, small hand-made scenes, generated
//! scenes and whole runs of a preset with plans applied exactly.

use std::path::PathBuf;
use std::process::{Command, Output};

use nalgebra::{Point2, Vector2};
use pushmog::geometry::ConvexPolygon;
use pushmog::scene::{Gripper, Object, ObjectId, Pose, Scene, Workspace};

/// Path of a file under `tests/fixtures`.
pub fn fixture(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(relative)
}

/// Runs the `pushmog` binary with `args`.
pub fn pushmog(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pushmog"))
        .args(args)
        .output()
        .expect("the pushmog binary runs")
}

/// A fresh empty folder under the target directory for one test's files.
pub fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 0.5 m × 0.4 m table of axis-aligned boxes `width` along x and `depth` along y, 30 mm tall, with
/// ids 0, 1, … at the centres `at`.
pub fn boxes(width: f64, depth: f64, at: &[(f64, f64)]) -> Scene {
    let outline =
        ConvexPolygon::rectangle(&Point2::origin(), &Vector2::x(), width / 2.0, depth / 2.0);
    let objects = at
        .iter()
        .enumerate()
        .map(|(k, &(x, y))| Object {
            id: ObjectId(k as u32),
            name: None,
            polygon: outline.clone(),
            pose: Pose::new(x, y, 0.0),
            height: 0.03,
            mass: None,
        })
        .collect();
    Scene::from_parts(Workspace::new(0.5, 0.4), Gripper::default(), objects).unwrap()
}

/// A grasp of object 0 at (0.1, 0.1), jaws open 80 mm: something to ask of an executor before it
/// was given a table.
pub fn stray_grasp() -> pushmog::grasp::Grasp {
    pushmog::grasp::Grasp {
        jaws: pushmog::grasp::JawPose {
            center: nalgebra::Point2::new(0.1, 0.1),
            angle: 0.0,
            opening: 0.08,
        },
        objects: vec![pushmog::scene::ObjectId(0)],
        width: 0.03,
        margin: 0.01,
    }
}

/// Default policy settings with riders on (`formulations/stacking.md`).
pub fn with_riders() -> pushmog::policy::PolicySettings {
    let mut settings = pushmog::policy::PolicySettings::default();
    settings.riders.enabled = true;
    settings
}

/// Generated scene `seed` of the default generator settings and object set.
pub fn scene(seed: u64) -> Scene {
    pushmog::scene::generate_scene(
        &pushmog::scene::GeneratorSettings::default(),
        &pushmog::scene::builtin_object_set(),
        seed,
    )
    .unwrap()
}

/// A whole run of the preset `kind` with default settings on `scene`, plans applied exactly.
pub fn run(kind: pushmog::policy::PolicyKind, scene: &Scene, seed: u64) -> pushmog::plan::Plan {
    let policy =
        pushmog::policy::Policy::new(kind, pushmog::policy::PolicySettings::default()).unwrap();
    let mut executor = policy.ideal();
    policy.run(scene, &mut executor, seed).unwrap()
}

/// A test executor: the ideal executor, whose grasps and places go through `hook`.
pub struct Rigged<H> {
    pub table: pushmog::exec::Ideal,
    pub hook: H,
}

/// What a [`Rigged`] executor does in place of the ideal executor's grasp, and what it reports lost
/// (by default what the ideal executor reports: riders left standing).
pub trait GraspHook {
    fn grasp(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult>;
    fn lost(&self, table: &pushmog::exec::Ideal) -> Vec<(pushmog::scene::ObjectId, &'static str)> {
        use pushmog::exec::Executor;
        table.lost()
    }
    /// Objects seen past the workspace's edge; none by default.
    fn past_edge(&self) -> Vec<Object> {
        Vec::new()
    }
    /// Puts a rider down; the ideal executor's place by default.
    fn place(
        &mut self,
        table: &mut pushmog::exec::Ideal,
        rider: &pushmog::plan::Rider,
    ) -> pushmog::Result<Option<pushmog::exec::Landing>> {
        use pushmog::exec::Executor;
        table.place(rider)
    }
}

impl<H: GraspHook> pushmog::exec::Executor for Rigged<H> {
    fn name(&self) -> &'static str {
        "rigged"
    }
    fn reset(&mut self, scene: &Scene) -> pushmog::Result<()> {
        self.table.reset(scene)
    }
    fn push(
        &mut self,
        push: &pushmog::push::Push,
    ) -> pushmog::Result<Option<pushmog::exec::Landing>> {
        self.table.push(push)
    }
    fn grasp(
        &mut self,
        grasp: &pushmog::grasp::Grasp,
    ) -> pushmog::Result<pushmog::exec::GraspResult> {
        self.hook.grasp(&mut self.table, grasp)
    }
    fn observe(&mut self) -> pushmog::Result<Scene> {
        self.table.observe()
    }
    fn place(
        &mut self,
        rider: &pushmog::plan::Rider,
    ) -> pushmog::Result<Option<pushmog::exec::Landing>> {
        self.hook.place(&mut self.table, rider)
    }
    fn lost(&self) -> Vec<(pushmog::scene::ObjectId, &'static str)> {
        self.hook.lost(&self.table)
    }
    fn past_edge(&self) -> Vec<Object> {
        self.hook.past_edge()
    }
}
