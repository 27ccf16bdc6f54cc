//! Integration tests of pushmog: one test binary, one module per subject.
#![allow(clippy::unwrap_used)]

mod cli;
mod generator;
mod geometry_properties;
mod scene_json;
mod support;
