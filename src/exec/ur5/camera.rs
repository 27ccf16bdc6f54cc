//! The closed loop's look through a depth camera: a shell command writes one depth frame (and, if
//! it has them, instance labels) as NumPy files, and `perception::perceive` turns them into the
//! table, with the scene expected after the pushes made since the last look as its prior
//! (`formulations/perception.md`).
//!
//! The command runs with `sh -c`, with `PUSHMOG_DEPTH` naming the `.npy` file it must write (float
//! metres, or uint16 in the camera's `depth.scale` units) and `PUSHMOG_LABELS` naming one it may
//! write (integer labels, 0 for none). The prior keeps the ids of the objects the planner knows:
//! the last table read, each pushed object moved to where its push was planned to leave it
//! (`Observation::read_after`). A look
//! in which any blob blocks planning (objects merged, stacked, over the workspace's edge, …) is an
//! error that lists them, so the robot stops rather than plan on a table it cannot see. An object
//! over the edge blocks so too: a plan made without it could bring a plate down on it. Objects seen
//! whole past the edge do not block; the look lists them (`Perception::past_edge`), for the tally
//! of lost objects (`tally.rs`).

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::perception::{Camera, Frame, Identify, PerceptionSettings, perceive, read_npy};
use crate::scene::{Object, ObjectSet, Scene};

/// One look at the table: the scene to plan on, and what the camera sees past the workspace's edge.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    /// The table, validated.
    pub scene: Scene,
    /// The blobs seen whole past the workspace's edge that would be objects otherwise, as objects
    /// where they lie; their ids are the camera's (labels or new ids), not the loop's. Empty for
    /// observations without a camera.
    pub past_edge: Vec<Object>,
}

/// A depth camera read by a shell command, for the table the robot works on.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthLook {
    /// The calibrated camera (`pushmog schema camera`).
    pub camera: Camera,
    /// The shell command that writes the frame to `$PUSHMOG_DEPTH` (and labels to `$PUSHMOG_LABELS`).
    pub command: String,
    /// A scene whose workspace and gripper the looks are for (its objects are not used).
    pub table: Scene,
    /// How frames are perceived.
    pub settings: PerceptionSettings,
    /// The cell's object set, if known: objects seen without a prior (those of the first look, and
    /// any new one) are named from it (`Perception::name_from`).
    pub library: Option<ObjectSet>,
}

impl DepthLook {
    /// One look: the command run, its frame read and perceived with `prior` (the table expected
    /// now, if one is known), whose ids it keeps.
    ///
    /// # Errors
    /// The command failing or writing no depth, a frame the camera refuses, or blobs that block.
    pub fn read(&self, prior: Option<&Scene>) -> Result<Look> {
        let folder =
            std::env::temp_dir().join(format!("pushmog-look-{}-{}", std::process::id(), unique()));
        std::fs::create_dir_all(&folder).map_err(|source| Error::Io {
            path: folder.clone(),
            source,
        })?;
        let result = self.look_in(&folder, prior);
        let _ = std::fs::remove_dir_all(&folder);
        result
    }

    fn look_in(&self, folder: &Path, prior: Option<&Scene>) -> Result<Look> {
        let (depth_path, labels_path) = (folder.join("depth.npy"), folder.join("labels.npy"));
        let output = std::process::Command::new("sh")
            .args(["-c", &self.command])
            .env("PUSHMOG_DEPTH", &depth_path)
            .env("PUSHMOG_LABELS", &labels_path)
            .output()
            .map_err(|source| Error::Io {
                path: PathBuf::from(&self.command),
                source,
            })?;
        if !output.status.success() {
            return Err(Error::field(
                "camera command",
                self.command.clone(),
                format!(
                    "exited with {}: {}",
                    output.status,
                    String::from_utf8_lossy(&output.stderr).trim()
                ),
            ));
        }
        if !depth_path.exists() {
            return Err(Error::field(
                "camera command",
                self.command.clone(),
                "wrote no depth frame to $PUSHMOG_DEPTH",
            ));
        }
        let depth = read_npy(&bytes(&depth_path)?, &depth_path.display().to_string())?;
        let labels = if labels_path.exists() {
            let npy = read_npy(&bytes(&labels_path)?, &labels_path.display().to_string())?;
            Some(npy.labels("camera command", "$PUSHMOG_LABELS")?)
        } else {
            None
        };
        let frame = Frame {
            depth: Some(depth.depth("camera command", "$PUSHMOG_DEPTH")?),
            labels: labels.as_deref(),
            heights: None,
        };
        let mut seen = perceive(
            &frame,
            &self.camera,
            self.table.workspace(),
            self.table.gripper(),
            prior,
            &self.settings,
        )?;
        if let Some(set) = &self.library {
            seen.name_from(set, &Identify::default())?;
        }
        Ok(Look {
            scene: seen.scene()?,
            past_edge: seen.past_edge.into_iter().map(|p| p.object).collect(),
        })
    }
}

fn bytes(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// A number not handed out before in this process.
pub(super) fn unique() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}
