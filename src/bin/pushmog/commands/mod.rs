//! What each subcommand does, in terms of library calls: one file per group of commands.

mod compare;
mod experiment;
mod files;
mod io;
mod perceive;
mod run;
mod scene;

pub use compare::{compare_clustering, compare_pushing, grasp_agreement};
pub use experiment::{experiment, merge, report};
pub use files::{render, schema, verify};
pub(crate) use io::{policy, read_scene, summary};
pub use perceive::perceive;
pub(crate) use perceive::{read_camera, read_library};
pub use run::{cluster, plan, run};
pub use scene::{check, demo, generate, library};
