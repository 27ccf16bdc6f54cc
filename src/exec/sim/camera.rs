//! The simulator's depth camera: an observation made by rendering what is on the table and
//! perceiving it, instead of reporting each prism's pose with noise.
//!
//! The camera hangs `above` the workspace's centre looking straight down, with square pixels of
//! `pixel` metres on the table and `margin` of table shown around the workspace. Every prism is
//! rendered exactly as it lies (upright, toppled or riding; `perception::render_solids`), the
//! depth gets the noise of `noise` from the simulator's random stream, and `perception::perceive`
//! turns depth and instance labels into objects (`formulations/perception.md`).
//!
//! What the camera model gives and what it does not:
//! - **Geometry from depth.** Outlines, positions and heights are the footprints perceived from the
//!   noisy depth, so the planner sees what the camera measures, errors and all.
//! - **Ids from instance labels.** Each prism's pixels carry its own label, the same at every look:
//!   a segmentation and tracker that never confuse two objects. The perceived object takes that
//!   prism's id, name and mass (the name and mass a library lookup would give). With
//!   `label_erosion` the labels stop that many pixels short of each outline, as a segmenter's masks
//!   do; the depth still shows the whole object.
//! - **What is not planned for** is reported lost with the blob's status: a prism whose blob is
//!   too small, stacked, not convex, over the workspace's edge and so on, and a prism no pixel shows.
//!   A rider left standing on another object is reported as the pose model reports it: with one
//!   label per object its blob is one plateau, which the camera cannot tell from a tall object.
//!   A prism outside the workspace or over its edge that would be an object otherwise is also
//!   reported where it was seen (`Executor::past_edge`, from `Perception::past_edge`), within the
//!   `margin` of table the image shows.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::Sim;
use super::prism::Prism;
use crate::error::Result;
use crate::exec::RIDER_LEFT;
use crate::perception::{
    BlobStatus, Camera, Depth, DepthNoise, Frame, PerceptionSettings, Solid, add_noise,
    erode_labels, perceive, render_solids,
};
use crate::scene::{Object, Scene, Workspace};

/// An overhead depth camera for the simulator (`sim.camera`); without it the simulator reports
/// each object's pose with Gaussian noise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SimCamera {
    /// Height of the optical centre above the table, metres. Default 0.7, the set-up whose
    /// accuracy `formulations/perception.md` measured.
    pub above: f64,
    /// Size of a pixel on the table, metres. Default 0.001 (the same set-up: 1280 × 720 pixels
    /// over about 1.28 m × 0.72 m).
    pub pixel: f64,
    /// Table shown around the workspace on every side, metres. Default 0.05, so that an object
    /// pushed to the workspace's edge does not reach the image's border.
    pub margin: f64,
    /// The depth noise. Default: σ = 0.0025·z² m, 2 % of pixels without depth, half of the edge
    /// pixels flying (`formulations/perception.md`).
    pub noise: DepthNoise,
    /// How the frame is perceived. Default: `perceive`'s defaults.
    pub perception: PerceptionSettings,
    /// The camera's calibration error: perception is given a pose of the camera that differs from
    /// the one it renders from by this much. Default none (left out of written settings).
    #[serde(skip_serializing_if = "CalibrationError::is_zero")]
    pub calibration: CalibrationError,
    /// Pixels by which each object's instance label falls short of its outline on every side
    /// (`perception::erode_labels`), as a segmenter's masks do; two touching objects are then
    /// parted by twice as many unlabelled pixels. Default 0: exact labels (left out of written
    /// settings). At most 10.
    #[serde(skip_serializing_if = "is_zero")]
    pub label_erosion: u32,
}

fn is_zero(value: &u32) -> bool {
    *value == 0
}

/// How far the camera's calibrated pose, which perception uses, lies from the pose it renders
/// from: a hand-eye or marker calibration's error (`formulations/perception.md`, "The simulator's
/// camera"). Fixed for a run, as a calibration is for a cell.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct CalibrationError {
    /// The calibrated optical centre less the true one, metres, table frame.
    pub offset: [f64; 3],
    /// The calibrated orientation turned from the true one about the optical centre, radians,
    /// about the table's x, then y, then z axis.
    pub turn: [f64; 3],
}

impl CalibrationError {
    /// No error: left out of written settings.
    pub fn is_zero(&self) -> bool {
        *self == Self::default()
    }

    /// `camera` as calibrated with this error: `R' = E·R`, `t' = t + offset`, with `E` the turn.
    pub fn calibrated(&self, camera: &Camera) -> Camera {
        let [x, y, z] = self.turn;
        let mut calibrated = camera
            .clone()
            .turned(&nalgebra::Rotation3::from_euler_angles(x, y, z));
        for (value, offset) in calibrated
            .extrinsics
            .translation
            .iter_mut()
            .zip(self.offset)
        {
            *value += offset;
        }
        calibrated
    }
}

impl Default for SimCamera {
    fn default() -> Self {
        Self {
            above: 0.7,
            pixel: 0.001,
            margin: 0.05,
            noise: DepthNoise::default(),
            perception: PerceptionSettings::default(),
            calibration: CalibrationError::default(),
            label_erosion: 0,
        }
    }
}

impl SimCamera {
    /// Checks each field's range.
    ///
    /// # Errors
    /// [`crate::Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let checks = [
            (
                "camera.above",
                self.above,
                (0.2, 3.0),
                "m; a depth camera over a table",
            ),
            (
                "camera.pixel",
                self.pixel,
                (1e-4, 0.01),
                "m per pixel on the table",
            ),
            (
                "camera.margin",
                self.margin,
                (0.0, 0.5),
                "m of table around the workspace",
            ),
            (
                "camera.noise.sigma_per_square_metre",
                self.noise.sigma_per_square_metre,
                (0.0, 0.1),
                "per metre; the default is 0.0025",
            ),
            (
                "camera.noise.dropped",
                self.noise.dropped,
                (0.0, 0.5),
                "a fraction of the pixels",
            ),
            (
                "camera.noise.flying",
                self.noise.flying,
                (0.0, 1.0),
                "a probability",
            ),
            (
                "camera.noise.edge_jump",
                self.noise.edge_jump,
                (1e-4, 0.1),
                "m of depth step",
            ),
            (
                "camera.label_erosion",
                f64::from(self.label_erosion),
                (0.0, 10.0),
                "pixels a segmenter's mask falls short of the outline",
            ),
        ];
        for (field, value, range, why) in checks {
            crate::error::in_range("sim", field, value, range, why)?;
        }
        let calibration = &self.calibration;
        for (part, values, why) in [
            ("offset", calibration.offset, "m; a calibration's error"),
            ("turn", calibration.turn, "rad; a calibration's error"),
        ] {
            for (k, value) in values.into_iter().enumerate() {
                let field = format!("camera.calibration.{part}[{k}]");
                crate::error::in_range("sim", &field, value, (-0.1, 0.1), why)?;
            }
        }
        self.perception.validate()
    }

    /// The camera over `workspace`.
    pub fn over(&self, workspace: &Workspace) -> Camera {
        let size = |low: f64, high: f64| ((high - low + 2.0 * self.margin) / self.pixel).ceil();
        let width = size(workspace.min[0], workspace.max[0]);
        let height = size(workspace.min[1], workspace.max[1]);
        let fov = 2.0 * (0.5 * width * self.pixel / self.above).atan();
        Camera::looking_down(
            width as u32,
            height as u32,
            fov,
            0.5 * (workspace.min[0] + workspace.max[0]),
            0.5 * (workspace.min[1] + workspace.max[1]),
            self.above,
        )
    }
}

/// The words a lost object's report gives for a blob that is not planned for.
fn reason(status: &BlobStatus) -> &'static str {
    match status {
        BlobStatus::Object | BlobStatus::New => "seen",
        BlobStatus::TooSmall => "seen too small",
        BlobStatus::OutsideWorkspace => "outside the workspace",
        BlobStatus::TouchesImageBorder => "seen at the image's border",
        BlobStatus::StraddlesWorkspaceEdge => "seen over the workspace's edge",
        BlobStatus::TooLarge => "seen too large",
        BlobStatus::TooTall => "seen too tall",
        BlobStatus::NotConvex => "seen not convex",
        BlobStatus::Merged { .. } => "seen merged with another",
        BlobStatus::Stacked { .. } => "seen stacked",
        BlobStatus::SplitLabel => "seen in pieces",
        BlobStatus::NoDepth => "seen without depth",
        BlobStatus::Overlap { .. } => "seen overlapping another",
    }
}

impl Sim {
    /// The table as `camera` sees it now (module docs), and what it cannot plan for in `self.lost`.
    ///
    /// # Errors
    /// Misuse before a table was given.
    pub(super) fn camera_observation(&mut self, camera: &SimCamera) -> Result<Scene> {
        let workspace = self.table()?.clone();
        self.lost.clear();
        let solids: Vec<Solid> = self.prisms.iter().map(Prism::solid).collect();
        let view = camera.over(&workspace);
        let rendered = render_solids(&solids, &view)?;
        let width = view.intrinsics.width as usize;
        let depth = add_noise(&rendered.depth, width, &camera.noise, &mut self.rng);
        // Label `id + 1` for each prism: the same at every look, 0 for the table.
        let labels: Vec<u32> = rendered
            .labels
            .iter()
            .map(|&l| {
                if l == 0 {
                    0
                } else {
                    rendered.ids[l as usize - 1].0 + 1
                }
            })
            .collect();
        let labels = erode_labels(&labels, width, camera.label_erosion as usize);
        let frame = Frame {
            depth: Some(Depth::Metres(&depth)),
            labels: Some(&labels),
            heights: None,
        };
        // Rendered from where the camera is, perceived with where its calibration says it is.
        let seen = perceive(
            &frame,
            &camera.calibration.calibrated(&view),
            &workspace,
            &self.gripper,
            None,
            &camera.perception,
        )?;
        let mut objects = Vec::new();
        for prism in &self.prisms {
            let label = prism.id.0 + 1;
            if self.rider_left_standing(prism) {
                self.lost.push((prism.id, RIDER_LEFT));
                continue;
            }
            let Some(k) = seen.blobs.iter().position(|b| b.label == Some(label)) else {
                self.lost.push((prism.id, "not in view"));
                continue;
            };
            let blob = &seen.blobs[k];
            let object = blob
                .id
                .and_then(|id| seen.objects.iter().find(|o| o.id == id));
            match object {
                Some(object) => objects.push(Object {
                    id: prism.id,
                    name: prism.name.clone(),
                    mass: Some(prism.mass),
                    ..object.clone()
                }),
                None => {
                    self.lost.push((prism.id, reason(&blob.status)));
                    if let Some(there) = seen.past_edge.iter().find(|p| p.blob == k) {
                        self.past_edge.push(Object {
                            id: prism.id,
                            name: prism.name.clone(),
                            mass: Some(prism.mass),
                            ..there.object.clone()
                        });
                    }
                }
            }
        }
        Scene::from_parts(workspace, self.gripper.clone(), objects)
    }
}
