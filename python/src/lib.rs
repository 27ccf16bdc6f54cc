//! The native half of the `pushmog` Python package (`pushmog._native`). Documents cross this boundary
//! as JSON text in the formats the command line reads and writes, so a Python dict and a CLI file
//! have one schema; the Python half (`python/pushmog/`) turns them into numpy arrays and small
//! classes. Every call that plans, runs or checks releases the GIL while Rust works, so a thread pool
//! plans scenes in parallel.
//!
//! Errors become the Python exceptions of `pushmog._errors`, whose attributes name the culprit
//! (`object`, `field`, `component`, `line`, `column`, `feature`): a bad scene a `SceneError`, a bad
//! setting a `SettingsError`, a document that does not parse a `FormatError` (all `ValueError`s), a
//! file problem a `FileError` (an `OSError`), anything else a `PlanError` (a `RuntimeError`).

use pushmog::exec::{ExecutorKind, SimSettings};
use pushmog::grasp::Grasp;
use pushmog::json::{self, to_json};
use pushmog::plan::{Plan, verify};
use pushmog::policy::{
    Landing, Policy, PolicyKind, PolicySettings, TripContext as Context, TripPlan,
};
use pushmog::push::Push;
use pushmog::render::{RenderOptions, plan_svg, scene_svg};
use pushmog::scene::{
    GeneratorSettings, Object, ObjectSet, ObjectSpec, Workspace, builtin_object_set, generate_scene,
};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

mod fusion;
mod perception;

/// An attribute of a Python exception.
enum Attribute {
    Int(i64),
    Float(f64),
    Text(String),
}

/// A Python exception for a pushmog error (a class of `pushmog._errors`), with the culprit's names
/// as attributes.
fn to_py_err(error: pushmog::Error, context: ErrorContext) -> PyErr {
    use Attribute::{Float, Int, Text};
    use pushmog::Error as E;
    let id = |id: &pushmog::scene::ObjectId| Int(i64::from(id.0));
    let attributes: Vec<(&str, Attribute)> = match &error {
        E::InvalidObject {
            id: object,
            index,
            field,
            ..
        } => vec![
            ("object", id(object)),
            ("index", Int(*index as i64)),
            ("field", Text(field.to_string())),
        ],
        E::DuplicateId { id: object, .. } => {
            vec![("object", id(object)), ("field", Text("id".into()))]
        }
        E::Overlap {
            first,
            second,
            depth,
        } => vec![
            ("object", id(first)),
            ("other", id(second)),
            ("field", Text("pose".into())),
            ("depth", Float(*depth)),
        ],
        E::InvalidField {
            component, field, ..
        } => vec![
            ("component", Text(component.clone())),
            ("field", Text(field.clone())),
        ],
        E::Json {
            path, line, column, ..
        } => vec![
            ("field", Text(path.clone())),
            ("line", Int(*line as i64)),
            ("column", Int(*column as i64)),
        ],
        E::Refused { trip, .. } => vec![("trip", Int(*trip as i64))],
        E::NotCompiled {
            component,
            field,
            feature,
            ..
        } => vec![
            ("component", Text(component.clone())),
            ("field", Text(field.clone())),
            ("feature", Text((*feature).to_string())),
        ],
        _ => Vec::new(),
    };
    let message = error.to_string();
    Python::attach(|py| {
        let err = raise(py, class_of(&error, context), message);
        let value = err.value(py);
        for (name, attribute) in attributes {
            let set = match attribute {
                Int(number) => value.setattr(name, number),
                Float(number) => value.setattr(name, number),
                Text(text) => value.setattr(name, text),
            };
            // An attribute that cannot be set leaves the message, which names the culprit too.
            drop(set);
        }
        err
    })
}

/// What a call was doing when it failed, for the exception class of input errors.
#[derive(Clone, Copy, PartialEq, Eq)]
enum ErrorContext {
    /// Reading or generating a scene: every input error is a `SceneError`.
    Scene,
    /// Reading settings: every input error is a `SettingsError`.
    Settings,
    /// Anything else.
    Other,
}

/// The name of the exception class in `pushmog._errors` that `error` raises.
fn class_of(error: &pushmog::Error, context: ErrorContext) -> &'static str {
    use pushmog::Error as E;
    match error {
        E::Io { .. } | E::Busy { .. } => "FileError",
        E::InvalidObject { .. }
        | E::DuplicateId { .. }
        | E::Overlap { .. }
        | E::Placement { .. } => "SceneError",
        E::InvalidField { .. } | E::Json { .. } if context == ErrorContext::Scene => "SceneError",
        E::Json { .. } if context == ErrorContext::Settings => "SettingsError",
        E::InvalidField { .. } | E::NotCompiled { .. } => "SettingsError",
        E::Json { .. } => "FormatError",
        _ => "PlanError",
    }
}

/// A `SettingsError`: an unknown name or a value out of range given to a call.
fn settings_error(message: String) -> PyErr {
    Python::attach(|py| raise(py, "SettingsError", message))
}

/// The exception `class` (of `pushmog._errors`) with `message`; the built-in exception it derives
/// from if that module cannot be loaded (the native module used on its own).
fn raise(py: Python<'_>, class: &str, message: String) -> PyErr {
    let made = py
        .import("pushmog._errors")
        .and_then(|module| module.getattr(class))
        .and_then(|class| class.call1((message.clone(),)));
    match made {
        Ok(value) => PyErr::from_value(value),
        Err(_) => match class {
            "FileError" => PyOSError::new_err(message),
            "PlanError" => PyRuntimeError::new_err(message),
            _ => PyValueError::new_err(message),
        },
    }
}

fn check<T>(result: pushmog::Result<T>) -> PyResult<T> {
    result.map_err(|e| to_py_err(e, ErrorContext::Other))
}

/// As [`check`], for settings documents: every input error is a `SettingsError`.
fn check_settings<T>(result: pushmog::Result<T>) -> PyResult<T> {
    result.map_err(|e| to_py_err(e, ErrorContext::Settings))
}

/// As [`check`], for calls that read or generate a scene: every input error is a `SceneError`.
fn check_scene<T>(result: pushmog::Result<T>) -> PyResult<T> {
    result.map_err(|e| to_py_err(e, ErrorContext::Scene))
}

/// A validated scene (objects, gripper, workspace), parsed once and shared by every call.
#[pyclass(module = "pushmog._native", frozen)]
struct Scene {
    scene: pushmog::Scene,
}

#[pymethods]
impl Scene {
    /// Reads and validates a scene JSON document; `source` names it in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, source = "<scene>"))]
    fn from_json(py: Python<'_>, text: &str, source: &str) -> PyResult<Self> {
        let scene = py.detach(|| json::scene_from_json(text, source));
        Ok(Self {
            scene: check_scene(scene)?,
        })
    }

    /// The scene as JSON, in the format `pushmog scene generate` writes.
    fn to_json(&self) -> String {
        to_json(&self.scene)
    }

    /// Minimum grasp diameter d* of every object, in scene order, metres.
    fn grasp_diameters(&self) -> Vec<f64> {
        (0..self.scene.len())
            .map(|i| self.scene.min_grasp_diameter(i))
            .collect()
    }

    /// Ids of the objects wider than the jaw gap (never graspable).
    fn ungraspable(&self) -> Vec<u32> {
        self.scene.ungraspable().iter().map(|id| id.0).collect()
    }

    fn __len__(&self) -> usize {
        self.scene.len()
    }
}

/// What a closed loop remembers between trips: the random stream that picks the next cluster, the
/// jaw poses where grasps carried nothing (not tried again in practically the same place), the
/// object sets of multi-object grasps that carried nothing (given up after two) and the pushes
/// whose fingers came down on an object.
#[pyclass(module = "pushmog._native")]
struct TripContext {
    context: Context,
}

#[pymethods]
impl TripContext {
    #[new]
    #[pyo3(signature = (seed = 0))]
    fn new(seed: u64) -> Self {
        Self {
            context: Context::new(seed),
        }
    }

    /// Records that this grasp (JSON of a trip's `grasp`) carried nothing: its jaws, and its
    /// objects when there were several; with `landed_on`, the object a finger came down on.
    #[pyo3(signature = (grasp, landed_on = None))]
    fn add_failed(&mut self, grasp: &str, landed_on: Option<u32>) -> PyResult<()> {
        let grasp: Grasp = check(json::from_json(grasp, "grasp"))?;
        match landed_on {
            Some(on) => self
                .context
                .record_landing(&grasp, pushmog::scene::ObjectId(on)),
            None => self.context.record_failure(&grasp),
        }
        Ok(())
    }

    /// Forgets the failed grasps that came down on one of `carried` (ids); whether any was.
    fn forget_landings_on(&mut self, carried: Vec<u32>) -> bool {
        let carried: Vec<_> = carried.into_iter().map(pushmog::scene::ObjectId).collect();
        self.context.forget_landings_on(&carried)
    }

    /// The jaw poses recorded as failed, as JSON.
    fn failed(&self) -> String {
        to_json(&self.context.failed)
    }

    /// The object sets of the multi-object grasps recorded as failed, as JSON.
    fn failed_together(&self) -> String {
        to_json(&self.context.failed_together)
    }

    /// Records that during this push (JSON of a trip's push) a finger came down on object `on`.
    fn add_landed(&mut self, push: &str, on: u32) -> PyResult<()> {
        let push: Push = check(json::from_json(push, "push"))?;
        self.context.landed.push(Landing {
            push,
            on: pushmog::scene::ObjectId(on),
        });
        Ok(())
    }

    /// The pushes recorded as landed on an object, as JSON (`push`, `on`).
    fn landed(&self) -> String {
        to_json(&self.context.landed)
    }

    /// Notes the riders a trip (JSON) put down, the trip planned on `scene`.
    fn note_riders(&mut self, scene: &Scene, trip: &str) -> PyResult<()> {
        let trip: TripPlan = check(json::from_json(trip, "trip"))?;
        self.context.note_riders(&scene.scene, &trip);
        Ok(())
    }

    /// Notes what a trip's (JSON) grasp carried: a rider that stayed behind while its row went to
    /// the bin whole is not offered as a rider again.
    fn note_carried(&mut self, trip: &str, carried: Vec<u32>) -> PyResult<()> {
        let trip: TripPlan = check(json::from_json(trip, "trip"))?;
        let carried: Vec<_> = carried.into_iter().map(pushmog::scene::ObjectId).collect();
        self.context.note_carried(&trip, &carried);
        Ok(())
    }

    /// The riders that fell off a row carried whole, not offered again.
    fn fell_off(&self) -> Vec<u32> {
        self.context.fell_off.iter().map(|id| id.0).collect()
    }

    /// Takes in what a look could not plan for, `(id, reason)` pairs: riders reported left standing
    /// on another object are grasped with their rows.
    fn note_lost(&mut self, lost: Vec<(u32, String)>) {
        let lost: Vec<(pushmog::scene::ObjectId, &str)> = lost
            .iter()
            .map(|(id, why)| (pushmog::scene::ObjectId(*id), why.as_str()))
            .collect();
        self.context.note_lost(&lost);
    }
}

/// Objects seen past the workspace's edge, as `Planner.past_edge_trip` takes them.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Seen {
    objects: Vec<ObjectSpec>,
}

/// A policy with its settings, ready to plan.
#[pyclass(module = "pushmog._native", frozen)]
struct Planner {
    policy: Policy,
}

#[pymethods]
impl Planner {
    /// `policy` is a policy (`sog`, `mog`, `push-mog`, `push-mog-milp`, `push-mog-socp`,
    /// `push-mog-opt`) or a named preset (`presets()`); `settings` a JSON document of policy
    /// settings (missing fields keep their defaults, or the preset's).
    #[new]
    #[pyo3(signature = (policy, settings = None))]
    fn new(policy: &str, settings: Option<&str>) -> PyResult<Self> {
        let (kind, settings) = check_settings(pushmog::policy::preset::resolve(
            policy, settings, "settings",
        ))?;
        Ok(Self {
            policy: check(Policy::new(kind, settings))?,
        })
    }

    /// The effective settings, as JSON.
    fn settings(&self) -> String {
        to_json(self.policy.settings())
    }

    /// The preset's name.
    fn policy(&self) -> &'static str {
        self.policy.kind().name()
    }

    /// Plans the next trip on `scene` as it is. Returns JSON `{"trip": …, "status": …,
    /// "seconds": …}`: `trip` is `null` when there is none, and then `status` says why in words
    /// and `no_trip` says why typed (`Policy::plan_trip`'s `NoTrip`).
    #[pyo3(signature = (scene, context = None))]
    fn plan_trip(
        &self,
        py: Python<'_>,
        scene: &Scene,
        context: Option<&Bound<'_, TripContext>>,
    ) -> PyResult<String> {
        let planned = match context {
            Some(context) => {
                let mut context = context.borrow_mut();
                let context = &mut context.context;
                py.detach(|| self.policy.plan_trip_with(&scene.scene, context))
            }
            None => py.detach(|| self.policy.plan_trip(&scene.scene)),
        };
        let planned = check(planned)?;
        let status = planned.status();
        let (trip, no_trip) = match planned.trip {
            Ok(trip) => (Some(trip), None),
            Err(no_trip) => (None, Some(no_trip)),
        };
        let mut answer = serde_json::json!({
            "trip": trip,
            "status": status,
            "seconds": planned.stats.seconds,
        });
        if let Some(no_trip) = no_trip {
            answer["no_trip"] = serde_json::json!(no_trip);
        }
        Ok(to_json(&answer))
    }

    /// The rest of a trip whose pushes have been made, planned on `scene`, a new look at the table
    /// (`Policy::correct_trip`): `trip` is the trip's plan as JSON (as `plan_trip` gave it, or as
    /// the last call of this gave it); `may_push` allows corrective pushes. Returns JSON `{"trip":
    /// …, "seconds": …}`, `trip` `null` when nothing on the table can be grasped.
    #[pyo3(signature = (scene, trip, context = None, may_push = true))]
    fn correct_trip(
        &self,
        py: Python<'_>,
        scene: &Scene,
        trip: &str,
        context: Option<&Bound<'_, TripContext>>,
        may_push: bool,
    ) -> PyResult<String> {
        let trip: TripPlan = check(json::from_json(trip, "trip"))?;
        let fresh = Context::new(0);
        let borrowed = context.map(|c| c.borrow());
        let context = borrowed.as_ref().map_or(&fresh, |c| &c.context);
        let started = std::time::Instant::now();
        let corrected = py.detach(|| {
            self.policy
                .correct_trip(&scene.scene, &trip, context, may_push)
        });
        let seconds = started.elapsed().as_secs_f64();
        let corrected = check(corrected)?;
        Ok(to_json(
            &serde_json::json!({ "trip": corrected, "seconds": seconds }),
        ))
    }

    /// A single-object grasp of one of `seen` (JSON `{"objects": […]}` in the scene file's form, lying
    /// past the edge of `scene`'s workspace) within the policy's `run.reach_past_edge`
    /// (`Policy::past_edge_trip`), not at a jaw pose the context records as failed. Returns JSON
    /// `{"scene": …, "trip": …, "seconds": …}`: the table it was planned on (the workspace grown by
    /// the reach) and the trip, or both `null` when there is none.
    #[pyo3(signature = (scene, seen, context = None))]
    fn past_edge_trip(
        &self,
        py: Python<'_>,
        scene: &Scene,
        seen: &str,
        context: Option<&Bound<'_, TripContext>>,
    ) -> PyResult<String> {
        let seen: Seen = check(json::from_json(seen, "seen"))?;
        let seen = seen
            .objects
            .into_iter()
            .enumerate()
            .map(|(index, spec)| check_scene(Object::from_spec(spec, index)))
            .collect::<PyResult<Vec<Object>>>()?;
        let avoid = context.map_or(Vec::new(), |c| c.borrow().context.failed.clone());
        let table = &scene.scene;
        let started = std::time::Instant::now();
        let taken = py.detach(|| {
            self.policy
                .past_edge_trip(table.workspace(), table.gripper(), &seen, &avoid)
        });
        let seconds = started.elapsed().as_secs_f64();
        let answer = match check(taken)? {
            Some((table, trip)) => {
                serde_json::json!({ "scene": table, "trip": trip, "seconds": seconds })
            }
            None => serde_json::json!({ "scene": null, "trip": null, "seconds": seconds }),
        };
        Ok(to_json(&answer))
    }

    /// Clears `scene` in a closed loop with the `ideal` executor (plans applied exactly) or the
    /// `sim` one (rapier3d physics; `sim_settings` JSON, `noiseless` turns noise off). Returns the
    /// run record as JSON, as `pushmog plan` and `pushmog run --plan` write it.
    #[pyo3(signature = (scene, executor = "ideal", seed = 0, sim_settings = None, noiseless = false))]
    fn run(
        &self,
        py: Python<'_>,
        scene: &Scene,
        executor: &str,
        seed: u64,
        sim_settings: Option<&str>,
        noiseless: bool,
    ) -> PyResult<String> {
        let kind: ExecutorKind = executor.parse().map_err(|_| {
            settings_error(format!(
                "unknown executor `{executor}`; available: ideal, sim"
            ))
        })?;
        let mut settings = match sim_settings {
            // Read for the simulator only, as before: the ideal executor has no settings.
            Some(text) if kind == ExecutorKind::Sim => {
                check_settings(json::from_json::<SimSettings>(text, "sim_settings"))?
            }
            _ => SimSettings::default(),
        };
        if noiseless {
            settings = SimSettings::noiseless_from(&settings);
        }
        // Built as the command line builds it, so a run here equals `pushmog run`.
        let mut executor = check(kind.build(self.policy.problem(), settings, seed))?;
        let plan = py.detach(|| self.policy.run(&scene.scene, executor.as_mut(), seed));
        Ok(to_json(&check(plan)?))
    }
}

/// Generates a seeded scene of `objects` objects from an object set (JSON; default the built-in
/// set) on a `width` × `depth` workspace.
#[pyfunction]
#[pyo3(signature = (objects, seed, object_set = None, width = 0.6, depth = 0.45))]
fn generate(
    py: Python<'_>,
    objects: usize,
    seed: u64,
    object_set: Option<&str>,
    width: f64,
    depth: f64,
) -> PyResult<Scene> {
    let set = match object_set {
        Some(text) => check(json::from_json::<ObjectSet>(text, "object_set"))?,
        None => builtin_object_set(),
    };
    let settings = GeneratorSettings {
        objects,
        workspace: Workspace::new(width, depth),
        ..GeneratorSettings::default()
    };
    let scene = py.detach(|| generate_scene(&settings, &set, seed));
    Ok(Scene {
        scene: check_scene(scene)?,
    })
}

/// The built-in object set, as JSON.
#[pyfunction]
fn builtin_objects() -> String {
    to_json(&builtin_object_set())
}

/// Checks a run record (JSON) with the independent verifier; returns the violations found, each
/// as text (none: the plan is consistent).
#[pyfunction]
fn verify_plan(py: Python<'_>, plan: &str) -> PyResult<Vec<String>> {
    let plan: Plan = check(json::from_json(plan, "plan"))?;
    Ok(py.detach(|| verify(&plan).iter().map(ToString::to_string).collect()))
}

/// An SVG drawing of a scene: workspace, objects, ids, scale bar.
#[pyfunction]
#[pyo3(signature = (scene, title = "scene", pixels_per_metre = 1500.0))]
fn scene_to_svg(scene: &Scene, title: &str, pixels_per_metre: f64) -> PyResult<String> {
    let options = options(pixels_per_metre)?;
    Ok(scene_svg(&scene.scene, &options, title))
}

/// An SVG drawing of a run record (JSON): clusters, pushes and jaws of every trip.
#[pyfunction]
#[pyo3(signature = (plan, title = "plan", pixels_per_metre = 1500.0))]
fn plan_to_svg(py: Python<'_>, plan: &str, title: &str, pixels_per_metre: f64) -> PyResult<String> {
    let options = options(pixels_per_metre)?;
    let plan: Plan = check(json::from_json(plan, "plan"))?;
    check(py.detach(|| plan_svg(&plan, &options, title)))
}

fn options(pixels_per_metre: f64) -> PyResult<RenderOptions> {
    if !(pixels_per_metre.is_finite() && pixels_per_metre > 0.0) {
        return Err(settings_error(format!(
            "pixels_per_metre must be a positive number, got {pixels_per_metre}"
        )));
    }
    Ok(RenderOptions {
        pixels_per_metre,
        ..RenderOptions::default()
    })
}

/// The JSON Schema of a format by name (`pushmog::schema::names`).
#[pyfunction]
fn schema(name: &str) -> PyResult<String> {
    pushmog::schema::named(name)
        .map(|value| to_json(&value))
        .ok_or_else(|| {
            settings_error(format!(
                "unknown schema `{name}`; available: {}",
                pushmog::schema::names().join(", ")
            ))
        })
}

/// The names of the six policies.
#[pyfunction]
fn policies() -> Vec<&'static str> {
    PolicyKind::ALL.iter().map(|kind| kind.name()).collect()
}

/// The named presets: `(name, policy, what it is)`.
#[pyfunction]
fn presets() -> Vec<(&'static str, &'static str, &'static str)> {
    pushmog::policy::preset::PRESETS
        .iter()
        .map(|p| (p.name, p.kind.name(), p.about))
        .collect()
}

/// Default settings, as JSON: `policy` or `sim` (the rapier simulator's physical parameters).
#[pyfunction]
fn defaults(name: &str) -> PyResult<String> {
    match name {
        "policy" => Ok(to_json(&PolicySettings::default())),
        "sim" => Ok(to_json(&SimSettings::default())),
        "perception" => Ok(to_json(&pushmog::perception::PerceptionSettings::default())),
        "noise" => Ok(to_json(&pushmog::perception::DepthNoise::default())),
        _ => Err(settings_error(format!(
            "unknown settings `{name}`; available: policy, sim, perception, noise"
        ))),
    }
}

/// The version of the Rust crate this package was built from.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("RIDER_LEFT", pushmog::exec::RIDER_LEFT)?;
    module.add_class::<Scene>()?;
    module.add_class::<TripContext>()?;
    module.add_class::<Planner>()?;
    module.add_class::<fusion::LookFusion>()?;
    module.add_function(wrap_pyfunction!(generate, module)?)?;
    module.add_function(wrap_pyfunction!(builtin_objects, module)?)?;
    module.add_function(wrap_pyfunction!(verify_plan, module)?)?;
    module.add_function(wrap_pyfunction!(scene_to_svg, module)?)?;
    module.add_function(wrap_pyfunction!(plan_to_svg, module)?)?;
    module.add_function(wrap_pyfunction!(schema, module)?)?;
    module.add_function(wrap_pyfunction!(policies, module)?)?;
    module.add_function(wrap_pyfunction!(presets, module)?)?;
    module.add_function(wrap_pyfunction!(defaults, module)?)?;
    module.add_function(wrap_pyfunction!(version, module)?)?;
    module.add_function(wrap_pyfunction!(perception::perceive, module)?)?;
    module.add_function(wrap_pyfunction!(perception::render, module)?)?;
    Ok(())
}
