//! Integration tests of pushmog: one test binary, one module per subject.
#![allow(clippy::unwrap_used)]

mod architecture;
mod baselines;
mod cli;
mod clustering_milp;
mod executors;
mod experiments;
mod fuse;
mod fuzz;
mod generator;
mod geometry_properties;
mod perception;
mod policies;
mod pricing;
mod pushing_socp;
mod records;
mod recovery;
mod riders;
mod scene_json;
mod sim;
mod support;
mod time_model;
mod ur5;
mod ur5_lost;
