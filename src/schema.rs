//! The JSON Schemas of pushmog's file formats, by name, for the command line (`pushmog schema`) and
//! the Python package (`pushmog.schema`). A format whose feature is not built is absent.

use serde_json::Value;

fn of<T: schemars::JsonSchema>() -> Value {
    serde_json::to_value(schemars::schema_for!(T)).unwrap_or(Value::Null)
}

/// Builds one format's schema.
type Builder = fn() -> Value;

/// Every format of this build: its name and its schema.
const FORMATS: &[(&str, Builder)] = &[
    ("scene", crate::json::scene_schema),
    ("object-set", crate::json::object_set_schema),
    ("policy", of::<crate::policy::PolicySettings>),
    #[cfg(feature = "sim")]
    ("sim", of::<crate::exec::SimSettings>),
    #[cfg(feature = "experiment")]
    ("experiment", of::<crate::experiment::ExperimentConfig>),
    #[cfg(feature = "robot")]
    ("robot", of::<crate::exec::ur5::RobotConfig>),
    ("plan", of::<crate::plan::Plan>),
    ("trip", of::<crate::policy::TripPlan>),
    ("camera", of::<crate::perception::Camera>),
    (
        "perception-report",
        of::<crate::perception::PerceptionReport>,
    ),
    (
        "perception-settings",
        of::<crate::perception::PerceptionSettings>,
    ),
];

/// The names of the formats of this build.
pub fn names() -> Vec<&'static str> {
    FORMATS.iter().map(|(name, _)| *name).collect()
}

/// The JSON Schema of the format `name` (see [`names`]); `None` for a name this build does not know.
pub fn named(name: &str) -> Option<Value> {
    FORMATS
        .iter()
        .find(|(known, _)| *known == name)
        .map(|(_, schema)| schema())
}
