//! Where the closed loop's observations of the table come from: a scene file, a command that prints
//! one (told the table expected in `$PUSHMOG_PRIOR`), or a depth camera perceived here (`camera.rs`).

use std::path::PathBuf;

use super::camera::{DepthLook, Look, unique};
use crate::error::{Error, Result};
use crate::push::{Push, predict};
use crate::scene::Scene;

/// Where observations of the table come from between trips.
#[derive(Clone, Debug, PartialEq)]
pub enum Observation {
    /// A scene JSON file, read again after each trip (a perception pipeline rewrites it).
    File(PathBuf),
    /// A shell command that prints a scene JSON document (run with `sh -c`); after the first look,
    /// `$PUSHMOG_PRIOR` names a scene file of the table expected (the last one read, each pushed
    /// object where its push was planned to leave it), for the command's tracker.
    Command(String),
    /// A depth camera whose frames a shell command writes, perceived here (`camera.rs`).
    Camera(Box<DepthLook>),
}

impl Observation {
    /// Reads the table once, with no table known before.
    ///
    /// # Errors
    /// I/O, a failing command, or an invalid scene.
    pub fn read(&self) -> Result<Scene> {
        self.read_after(None, &[])
    }

    /// Reads the table once; a camera's look keeps the ids of `last` (the table read before, if
    /// any), each object of `pushes` moved where its push was planned to leave it.
    ///
    /// # Errors
    /// I/O, a failing command, an invalid scene, or a look whose blobs block planning.
    pub fn read_after(&self, last: Option<&Scene>, pushes: &[Push]) -> Result<Scene> {
        self.look_after(last, pushes).map(|look| look.scene)
    }

    /// As [`Observation::read_after`], with what a camera sees past the workspace's edge.
    ///
    /// # Errors
    /// As [`Observation::read_after`].
    pub fn look_after(&self, last: Option<&Scene>, pushes: &[Push]) -> Result<Look> {
        let scene_only = |scene| Look {
            scene,
            past_edge: Vec::new(),
        };
        // The table expected now: the last one read, each pushed object where its push was
        // planned to leave it (as it was read when that prediction is no valid scene).
        let expected = last.map(|scene| predict(scene, pushes).unwrap_or_else(|_| scene.clone()));
        match self {
            Self::Camera(look) => look.read(expected.as_ref()),
            Self::File(path) => crate::json::read_scene(path).map(scene_only),
            Self::Command(command) => {
                // The table expected, for the command's tracker: `$PUSHMOG_PRIOR` names it.
                let prior = expected
                    .map(|scene| {
                        let path = std::env::temp_dir().join(format!(
                            "pushmog-prior-{}-{}.json",
                            std::process::id(),
                            unique()
                        ));
                        crate::json::write_text(&path, &crate::json::to_json(&scene)).map(|()| path)
                    })
                    .transpose()?;
                let mut shell = std::process::Command::new("sh");
                shell.args(["-c", command]);
                if let Some(path) = &prior {
                    shell.env("PUSHMOG_PRIOR", path);
                }
                let output = shell.output();
                if let Some(path) = &prior {
                    let _ = std::fs::remove_file(path);
                }
                let output = output.map_err(|source| Error::Io {
                    path: PathBuf::from(command),
                    source,
                })?;
                if !output.status.success() {
                    return Err(Error::field(
                        "observation command",
                        command.clone(),
                        format!(
                            "exited with {}: {}",
                            output.status,
                            String::from_utf8_lossy(&output.stderr).trim()
                        ),
                    ));
                }
                let text = String::from_utf8_lossy(&output.stdout);
                crate::json::scene_from_json(&text, command).map(scene_only)
            }
        }
    }
}
