//! What a look found: the objects, one report per blob with its status, the fitted table, the prior's
//! objects that are gone, and the adjustments made. Nothing in view is dropped silently.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::identify::{Identify, name_from_set};
use super::table::TablePlane;
use crate::error::{Error, Result};
use crate::id::ObjectId;
use crate::scene::{Gripper, Object, ObjectSet, ObjectSpec, Scene, Workspace};

/// What became of one blob. The first four are notices; every other status blocks
/// [`Perception::scene`], because planning on such a scene could act on an object it does not see.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum BlobStatus {
    /// An object, matched to the prior's object of the same id (or with no prior given).
    Object,
    /// An object the prior does not hold; it got a fresh id.
    New,
    /// Smaller than the smallest object the settings accept: noise, a crumb, a cable.
    TooSmall,
    /// Wholly outside the workspace: not this table's business.
    OutsideWorkspace,
    /// The blob reaches the image's border, so part of it may be out of view.
    TouchesImageBorder,
    /// The footprint lies partly inside and partly outside the workspace.
    StraddlesWorkspaceEdge,
    /// Wider than the largest object the settings accept.
    TooLarge,
    /// Taller than the tallest object the settings accept.
    TooTall,
    /// The blob is far from convex (its solidity is below the settings' bound): most likely
    /// objects that touch, which a prior or labels would split.
    NotConvex,
    /// The blob holds the centroids of several of the prior's objects.
    Merged {
        /// Those objects.
        ids: Vec<ObjectId>,
    },
    /// Two top heights in one blob: an object standing on another.
    Stacked {
        /// The upper and the lower plateau's heights above the table, metres.
        heights: [f64; 2],
    },
    /// One instance label covers separate pieces.
    SplitLabel,
    /// Too few pixels of the blob have depth, and no height was given.
    NoDepth,
    /// Its footprint overlaps another object's by more than the settings repair.
    Overlap {
        /// The other object.
        with: ObjectId,
    },
}

impl BlobStatus {
    /// Whether this status keeps [`Perception::scene`] from giving a scene.
    pub fn blocks(&self) -> bool {
        !matches!(
            self,
            Self::Object | Self::New | Self::TooSmall | Self::OutsideWorkspace
        )
    }
}

/// One blob as found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct BlobReport {
    /// The instance label it came from, when labels were given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<u32>,
    /// Its pixel count.
    pub pixels: usize,
    /// `[u_min, v_min, u_max, v_max]`, pixels.
    pub pixel_box: [usize; 4],
    /// Its footprint's centroid in the table frame, metres, when one was found.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 2]>,
    /// Its top above the fitted table, metres, when measured or given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top_height: Option<f64>,
    /// Pixel count over the area of its image hull (about 1 for a convex blob).
    pub solidity: f64,
    /// What became of it.
    #[serde(flatten)]
    pub status: BlobStatus,
    /// The object it became, if it became one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<ObjectId>,
    /// The blobs (indices into the look's `blobs`) that stand in front of it in the image, taller
    /// than it: where they do, its footprint is only what shows, and it may go on beneath them
    /// (`formulations/perception.md`, "Hidden by a taller neighbour"). Absent when none; labels
    /// with depth only.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hidden_by: Vec<usize>,
}

/// What a look found, as the report file holds it (`pushmog schema perception-report`): everything
/// of a [`Perception`] but the objects, which the scene file holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PerceptionReport {
    /// One report per blob, objects and rejections alike.
    pub blobs: Vec<BlobReport>,
    /// The fitted table.
    pub table: TablePlane,
    /// The prior's objects that no blob matched.
    pub gone: Vec<ObjectId>,
    /// What was changed to make the objects a valid scene.
    pub adjustments: Vec<String>,
    /// The blobs outside the workspace or over its edge that would be objects otherwise
    /// ([`Perception::past_edge`]); absent when none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub past_edge: Vec<PastEdgeReport>,
}

/// A blob outside the workspace or over its edge that would be an object otherwise (whole in view,
/// one piece, one plateau, an object's size, convex), as an object where it lies.
#[derive(Clone, Debug, PartialEq)]
pub struct PastEdge {
    /// The index of its report in `blobs`.
    pub blob: usize,
    /// Its footprint about its centroid, yaw 0, with its label as id (0 without labels).
    pub object: Object,
}

/// A [`PastEdge`] in the report file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PastEdgeReport {
    /// The index of its report in `blobs`.
    pub blob: usize,
    /// Its footprint about its centroid, yaw 0, with its label as id (0 without labels), in the
    /// scene file's form.
    pub object: ObjectSpec,
}

/// The result of `perceive`.
#[derive(Clone, Debug, PartialEq)]
pub struct Perception {
    /// The objects seen, in the table frame: each in the frame of the prior's object it is (or of
    /// the set's shape [`Perception::name_from`] matched), else its outline about its centroid, yaw 0.
    pub objects: Vec<Object>,
    /// One report per blob, objects and rejections alike.
    pub blobs: Vec<BlobReport>,
    /// The fitted table.
    pub table: TablePlane,
    /// The prior's objects that no blob matched.
    pub gone: Vec<ObjectId>,
    /// What was changed to make the objects a valid scene (overlaps cut apart, edges trimmed).
    pub adjustments: Vec<String>,
    /// The blobs outside the workspace or over its edge that would be objects otherwise, each as
    /// an object where it lies ([`PastEdge`]). A closed loop may take such an object by itself
    /// (`run.reach_past_edge`); they are not part of [`Perception::scene`].
    pub past_edge: Vec<PastEdge>,
    /// The workspace the scene is for.
    pub workspace: Workspace,
    /// The gripper the scene is for.
    pub gripper: Gripper,
}

impl Perception {
    /// The report file's content.
    pub fn report(&self) -> PerceptionReport {
        PerceptionReport {
            blobs: self.blobs.clone(),
            table: self.table,
            gone: self.gone.clone(),
            adjustments: self.adjustments.clone(),
            past_edge: self
                .past_edge
                .iter()
                .map(|p| PastEdgeReport {
                    blob: p.blob,
                    object: p.object.to_spec(),
                })
                .collect(),
        }
    }

    /// Names the objects seen without a prior (no name) from `set`: each takes the frame, name and
    /// mass of the set's shape that fits its outline best, when one fits well enough
    /// (`identify.rs`); an adjustment says which shape and how well, or that none fitted.
    /// Objects the prior named keep their names. Returns how many were named.
    ///
    /// # Errors
    /// A shape of the set whose outline is not convex (named).
    pub fn name_from(&mut self, set: &ObjectSet, rule: &Identify) -> Result<usize> {
        let mut named = 0;
        for object in self.objects.iter_mut().filter(|o| o.name.is_none()) {
            let note = match name_from_set(object, set, rule)? {
                Some(found) => {
                    named += 1;
                    format!(
                        "object {}: named {} from the set {} (IoU {:.3})",
                        object.id, set.objects[found.shape].name, set.name, found.iou
                    )
                }
                None => format!(
                    "object {}: no shape of the set {} fits it; left unnamed, yaw 0",
                    object.id, set.name
                ),
            };
            self.adjustments.push(note);
        }
        Ok(named)
    }

    /// The blobs whose status blocks planning.
    pub fn blocking(&self) -> Vec<&BlobReport> {
        self.blobs.iter().filter(|b| b.status.blocks()).collect()
    }

    /// The validated scene of the objects seen.
    ///
    /// # Errors
    /// An [`Error::InvalidField`] on `blobs` listing every blocking blob (its pixel box, position and
    /// status), or the scene's own validation error.
    pub fn scene(&self) -> Result<Scene> {
        let blocking = self.blocking();
        if !blocking.is_empty() {
            let list: Vec<String> = blocking
                .iter()
                .map(|b| {
                    let at = b.position.map_or(String::new(), |p| {
                        format!(" at ({:.3}, {:.3}) m", p[0], p[1])
                    });
                    format!(
                        "blob in pixels {:?}{at}: {}",
                        b.pixel_box,
                        serde_json::to_value(&b.status)
                            .map(|v| v.to_string())
                            .unwrap_or_default()
                    )
                })
                .collect();
            return Err(Error::field(
                "perception",
                "blobs",
                format!(
                    "{} blob(s) keep the look from being planned on: {}",
                    blocking.len(),
                    list.join("; ")
                ),
            ));
        }
        Scene::from_parts(
            self.workspace.clone(),
            self.gripper.clone(),
            self.objects.clone(),
        )
    }
}
