//! # pushmog
//!
//! Plans how a robot with a parallel-jaw gripper clears a table of extruded convex polygons into a bin
//! in as few trips as possible. Objects are grouped into clusters whose summed minimum grasp diameters
//! fit between the jaws, each cluster is pushed tight with *fork pushes* (jaws partly open, jaw line
//! perpendicular to the push), and the tight row is lifted in one multi-object grasp. The metric is
//! objects per trip (OpT). The method follows the Push-MOG paper (Aeron et al., CASE 2023); pushmog keeps
//! its heuristics as baselines and adds optimal planners, a physics simulator and an experiment runner.
//!
//! Modules, in the order data flows through them:
//! - [`geometry`]: convex polygons, minimum grasp diameters, separating lines, sliding and contact.
//! - [`scene`]: objects, the gripper, the workspace and the validated [`Scene`]; the built-in object
//!   library and the seeded scene generator.
//! - [`problem`]: what every planning stage shares, validated once: the grasp model, the fork-push
//!   geometry, the shortest push and the time model.
//! - [`cluster`]: partitions into clusters that fit the jaws (the paper's hierarchical clustering).
//! - [`push`]: fork pushes that bring a cluster together (the paper's pushes toward the central object).
//! - [`grasp`]: jaw poses and the analytic model of what a closing holds; single- and multi-object
//!   planners.
//! - [`exec`]: executors that carry plans out (the ideal one applies them exactly).
//! - [`policy`]: `sog`, `mog`, `push-mog` and the closed loop of the paper's Algorithm 1.
//! - [`plan`]: what a run records, and [`plan::verify`], the independent checker.
//! - [`render`]: SVG drawings of scenes and plans; [`json`]: file formats with precise errors;
//!   [`schema`]: their JSON Schemas by name.
//! - [`time_model`]: seconds per trip and per push, for objectives and picks per hour.
//! - [`stack`]: riders on a pushed row's top: where one may stand, and the search for the spot.
//! - [`perception`]: overhead depth frames and instance labels turned into a validated scene.
//! - [`experiment`]: configurations, the parallel resumable runner, logs, tables and figures.
//!
//! ```
//! use pushmog::scene::{GeneratorSettings, builtin_object_set, generate_scene};
//! let scene = generate_scene(&GeneratorSettings::default(), &builtin_object_set(), 7).unwrap();
//! assert_eq!(scene.objects().len(), 34);
//! ```

pub mod cluster;
pub mod error;
pub mod exec;
#[cfg(feature = "experiment")]
pub mod experiment;
pub mod geometry;
pub mod grasp;
pub mod id;
pub mod json;
pub mod outcome;
pub mod perception;
pub mod plan;
pub mod policy;
pub mod problem;
pub mod push;
pub mod random;
pub mod render;
pub mod scene;
pub mod schema;
pub mod stack;
pub mod stats;
pub mod time_model;

pub use error::{Error, Result};
pub use scene::Scene;

/// The README's code, run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
