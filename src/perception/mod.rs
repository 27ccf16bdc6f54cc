//! From a camera to a scene: overhead depth frames (and optional instance labels) turned into a
//! validated [`Scene`](crate::Scene), with ids kept across looks and a report for every blob.
//!
//! The maths is in `formulations/perception.md`:
//! - the camera ([`Camera`]): OpenCV pinhole conventions, `p_table = R·p_cam + t`, depth = camera `z`;
//! - the table `z = a·x + b·y + c`, fitted by least squares to the pixels that see it
//!   (`table.rs`), so each pixel's height is measured from the table as it is;
//! - the blobs: pixels more than the cut height `c` above the table, a 3×3 opening, 4-connected
//!   components (`blobs.rs`), or given labels grown into that mask;
//! - the footprint (`footprint.rs`): a blob's image hull back-projected onto the top plane `z = h`
//!   and onto the cut plane `z = c` gives two polygons whose intersection is exactly the top face of
//!   an unoccluded convex prism, at any camera tilt (the two-plane theorem); by default
//!   ([`PerceptionSettings::fit_outline`]) each side of the image outline is first fitted to the
//!   pixels on both sides of its edge by a logistic loss (`fit.rs`); with
//!   [`PerceptionSettings::fit_sides`], the image outline is built from lines fitted to the blob's
//!   outermost pixels, with the corner tips that the median cut put back (`sides.rs`);
//! - without labels, a blob with two plateaus is parted into two objects when both parts are
//!   upright prisms apart (`plateaus.rs`, a watershed from the plateaus);
//! - with labels and depth, an object a taller neighbour stands in front of is cut at that
//!   neighbour's edge where the two overlap, and a label the neighbour leaves in pieces is one
//!   object (`hidden.rs`);
//! - every blob gets a [`BlobStatus`]; those that block planning keep [`Perception::scene`] from
//!   giving a scene, so nothing in view is dropped silently;
//! - ids are kept by matching centroids to a prior scene (`track.rs`), and an object the prior holds
//!   keeps the prior's frame, turned by the angle that fits its outline best (`align.rs`);
//! - an object without a prior can be named from a known object set
//!   ([`Perception::name_from`], `identify.rs`): the set's shape that fits its outline best over
//!   every turn gives its name, mass and frame, so its yaw is measured.
//!
//! [`render_depth`] and [`add_noise`] make frames of known scenes: test support, and a camera for
//! the simulator. [`read_npy`] reads NumPy's `.npy` images; [`overlay_svg`] draws a look's blobs
//! over its image.

mod align;
mod blob;
mod blobs;
mod camera;
mod find;
mod fit;
mod footprint;
mod hidden;
mod identify;
mod input;
mod noise;
mod npy;
mod occlusion;
mod overlay;
mod perceive;
mod plateaus;
mod render;
mod report;
mod settings;
mod sides;
mod table;
mod track;

pub use camera::{Camera, DepthUnits, Extrinsics, Intrinsics, KNOWN_SCALES, MAX_CAMERA_TILT};
pub use identify::{Identify, Match, best_shape, name_from_set};
pub use input::{Depth, Frame};
pub use noise::{DepthNoise, add_noise, erode_labels};
pub use npy::{Npy, NpyData, read_npy, write_npy_f32, write_npy_u32};
pub use overlay::overlay_svg;
pub use perceive::perceive;
pub use render::{Rendered, Solid, render_depth, render_solids};
pub use report::{BlobReport, BlobStatus, PastEdge, PastEdgeReport, Perception, PerceptionReport};
pub use settings::PerceptionSettings;
pub use table::TablePlane;
