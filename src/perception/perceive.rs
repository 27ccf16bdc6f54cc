//! The look itself: depth to table points, the table fit, the blobs (`find.rs`), each blob judged,
//! ids kept from the prior, small overlaps cut apart, and the report.

use nalgebra::{Point2, Point3, Vector2};

use super::align::in_prior_frame;
use super::blob::{Blob, Judged, judge, past_edge_objects, position, top_of};
use super::camera::Camera;
use super::find::find_blobs;
use super::hidden::{cut_hidden, joined_behind};
use super::input::{Frame, check_workspace_in_view, depth_in_metres};
use super::occlusion::{Neighbours, owners};
use super::plateaus::{PartTest, part_blobs};
use super::report::{BlobReport, BlobStatus, Perception};
use super::settings::PerceptionSettings;
use super::table::{TablePlane, fit_table};
use super::track::match_prior;
use crate::error::{Error, Result};
use crate::geometry::{ConvexPolygon, clip, max_separation, tidy_polygon};
use crate::id::ObjectId;
use crate::scene::{Gripper, Object, Pose, Scene, Workspace};

/// Turns one look into objects and a report per blob (`formulations/perception.md`).
///
/// `prior` is the last look or the scene predicted after the trip's pushes; its ids are kept.
///
/// # Errors
/// Invalid input, each error naming its field: an invalid camera, workspace or settings; image
/// sizes that differ; a 16-bit image without a scale or with a scale far from what the camera's
/// height implies; a workspace corner out of view; a frame with neither depth nor labels; a fitted
/// table further from the calibrated one than the settings allow.
pub fn perceive(
    frame: &Frame,
    camera: &Camera,
    workspace: &Workspace,
    gripper: &Gripper,
    prior: Option<&Scene>,
    settings: &PerceptionSettings,
) -> Result<Perception> {
    camera.validate()?;
    workspace.validate()?;
    settings.validate()?;
    check_workspace_in_view(camera, workspace)?;
    let depth = depth_in_metres(frame, camera)?;
    if depth.is_none() && frame.labels.is_none() {
        return Err(Error::field(
            "frame",
            "depth",
            "a look needs a depth image, instance labels, or both",
        ));
    }
    let mut adjustments = Vec::new();
    let (table, heights) = match &depth {
        Some(depth) => {
            let (table, heights) = table_and_heights(depth, camera, workspace, settings)?;
            (table, Some(heights))
        }
        None => (TablePlane::calibrated(), None),
    };
    let blobs = find_blobs(frame, heights.as_deref(), camera, settings);
    let measured: Vec<(Option<f64>, Option<f64>)> = blobs
        .iter()
        .map(|b| top_of(b, heights.as_deref(), settings))
        .collect();
    // Depth alone: a blob with two plateaus may be two objects that meet in the image.
    let (blobs, measured) = match heights.as_deref() {
        Some(h) => part_blobs(
            blobs,
            measured,
            &PartTest {
                heights: h,
                camera,
                overlap: settings.overlap_repair,
            },
            |b| top_of(b, Some(h), settings),
            |b, m| judge(b, m, Some(h), None, camera, &table, workspace, settings),
            &mut adjustments,
        ),
        None => (blobs, measured),
    };
    // With labels two blobs can touch, and one may hide the other's wall (`occlusion.rs`).
    let owner = (frame.labels.is_some() && heights.is_some()).then(|| {
        owners(
            blobs.iter().map(|b| b.pixels.as_slice()),
            frame.labels.map_or(0, <[u32]>::len),
        )
    });
    let tops: Vec<Option<f64>> = measured.iter().map(|m| m.0).collect();
    // A label in pieces with a taller object standing across it is one object, partly hidden.
    let mut blobs = blobs;
    if let Some(owner) = &owner {
        let width = camera.intrinsics.width as usize;
        for (index, blob) in blobs.iter_mut().enumerate() {
            if let (true, Some(top)) = (blob.split, tops[index])
                && joined_behind(blob, index, top, owner, &tops, width)
            {
                blob.split = false;
                adjustments.push(format!(
                    "label {} is in pieces with a taller object across it: one object, partly \
                     hidden",
                    blob.label.unwrap_or(0)
                ));
            }
        }
    }
    let mut judged: Vec<Judged> = blobs
        .iter()
        .zip(&measured)
        .enumerate()
        .map(|(index, (b, &m))| {
            let neighbours = owner.as_deref().map(|owner| Neighbours {
                owner,
                tops: &tops,
                index,
            });
            judge(
                b,
                m,
                heights.as_deref(),
                neighbours.as_ref(),
                camera,
                &table,
                workspace,
                settings,
            )
        })
        .collect();
    cut_hidden(&mut judged, &mut adjustments);
    let mut reports: Vec<BlobReport> = blobs
        .iter()
        .zip(&judged)
        .map(|(b, j)| BlobReport {
            label: b.label,
            pixels: b.pixels.len(),
            pixel_box: j.pixel_box,
            position: position(&j.footprint),
            top_height: j.top,
            solidity: j.solidity,
            status: j.status.clone(),
            id: None,
            hidden_by: j.hidden_by.clone(),
        })
        .collect();
    let past_edge = past_edge_objects(&blobs, &judged);
    let mut prints: Vec<Option<ConvexPolygon>> = judged.into_iter().map(|j| j.footprint).collect();
    let gone = assign_ids(&mut reports, &prints, &blobs, prior, settings);
    separate(&mut reports, &mut prints, settings, &mut adjustments);
    let objects = objects_of(&reports, &prints, workspace, prior, &mut adjustments);
    if table.points > 0 {
        adjustments.push(format!(
            "table fitted to {} points: {:+.1} mm at the workspace's centre, tilted {:.2}°, \
             residual {:.2} mm",
            table.points,
            table.offset * 1e3,
            table.tilt.to_degrees(),
            table.residual * 1e3
        ));
    }
    Ok(Perception {
        objects,
        blobs: reports,
        table,
        gone,
        adjustments,
        past_edge,
        workspace: workspace.clone(),
        gripper: gripper.clone(),
    })
}

/// The table fitted to the pixels inside the workspace, and every pixel's height above it.
fn table_and_heights(
    depth: &[f64],
    camera: &Camera,
    workspace: &Workspace,
    settings: &PerceptionSettings,
) -> Result<(TablePlane, Vec<f64>)> {
    let centre = camera.centre();
    let k = &camera.intrinsics;
    let width = k.width as usize;
    let rotation = camera.rotation();
    let point = |i: usize| {
        let (u, v) = ((i % width) as f64, (i / width) as f64);
        let ray = rotation * nalgebra::Vector3::new((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
        centre + ray * depth[i]
    };
    // Every fourth pixel (every index divisible by 4) of every fourth row: a sixteenth of the image
    // is plenty for three numbers.
    let sample: Vec<Point3<f64>> = (0..depth.len() / width)
        .step_by(4)
        .flat_map(|v| ((v * width).next_multiple_of(4)..(v + 1) * width).step_by(4))
        .map(point)
        .filter(|p| p.z.is_finite() && workspace.outside_by(&Point2::new(p.x, p.y)) == 0.0)
        .collect();
    let middle = (
        0.5 * (workspace.min[0] + workspace.max[0]),
        0.5 * (workspace.min[1] + workspace.max[1]),
    );
    let table = fit_table(&sample, settings.table_start, middle).ok_or_else(|| {
        Error::field(
            "table",
            "depth",
            format!(
                "fewer than 3 pixels in the workspace lie within {} m of the calibrated table; \
                 check the extrinsics and the depth scale",
                settings.table_start
            ),
        )
    })?;
    if table.offset.abs() > settings.max_table_offset || table.tilt > settings.max_table_tilt {
        return Err(Error::field(
            "table",
            "extrinsics",
            format!(
                "the table fitted to the depth lies {:+.1} mm from the calibrated one at the \
                 workspace's centre and is tilted {:.2}° to it (limits {:.1} mm and {:.2}°): \
                 the calibration is off",
                table.offset * 1e3,
                table.tilt.to_degrees(),
                settings.max_table_offset * 1e3,
                settings.max_table_tilt.to_degrees()
            ),
        ));
    }
    // The height of t + z·r above the plane is g·t − c + z·(g·r) with g = (−a, −b, 1), and
    // g·r = q·((u − cx)/fx, (v − cy)/fy, 1) with q = Rᵀ·g: two multiplications and two additions
    // a pixel.
    let [a, b, c] = table.coefficients;
    let g = nalgebra::Vector3::new(-a, -b, 1.0);
    let q = rotation.transpose() * g;
    let base = g.dot(&centre.coords) - c;
    let mut heights = Vec::with_capacity(depth.len());
    for v in 0..k.height {
        let row = q.z + q.y * (f64::from(v) - k.cy) / k.fy;
        let along = q.x / k.fx;
        let start = row - along * k.cx;
        let line = &depth[v as usize * width..(v as usize + 1) * width];
        heights.extend(
            line.iter()
                .enumerate()
                .map(|(u, &z)| base + z * (start + along * u as f64)),
        );
    }
    Ok((table, heights))
}

/// Gives each blob that is an object its id: the prior's when matched (`Object`), a fresh one
/// otherwise (`New` with a prior; the label or the next number without one). Blobs holding the
/// centroids of several prior objects become `Merged`. Returns the prior's ids that are gone.
fn assign_ids(
    reports: &mut [BlobReport],
    prints: &[Option<ConvexPolygon>],
    blobs: &[Blob],
    prior: Option<&Scene>,
    settings: &PerceptionSettings,
) -> Vec<ObjectId> {
    let has_print = |k: usize| prints[k].is_some();
    let mut taken = vec![None; reports.len()];
    let mut gone = Vec::new();
    if let Some(prior) = prior {
        // Blobs that hold two or more of the prior's objects are merged; those objects are in view,
        // not gone.
        let mut held = Vec::new();
        for k in (0..reports.len()).filter(|&k| has_print(k)) {
            let one_or_many = matches!(
                reports[k].status,
                BlobStatus::Object | BlobStatus::NotConvex
            );
            let Some(print) = prints[k].as_ref().filter(|_| one_or_many) else {
                continue;
            };
            let inside: Vec<ObjectId> = (0..prior.len())
                .filter(|&j| print.contains_point(&prior.centroid(j), 0.0))
                .map(|j| prior.objects()[j].id)
                .collect();
            if inside.len() > 1 {
                held.extend(inside.iter().copied());
                reports[k].status = BlobStatus::Merged { ids: inside };
            }
        }
        let seen: Vec<usize> = (0..reports.len())
            .filter(|&k| has_print(k) && reports[k].status == BlobStatus::Object)
            .collect();
        let centres: Vec<Point2<f64>> = seen
            .iter()
            .filter_map(|&k| prints[k].as_ref().map(|p| p.centroid()))
            .collect();
        let (ids, missing) = match_prior(&centres, prior, settings.track_gate);
        gone = missing
            .into_iter()
            .filter(|id| !held.contains(id))
            .collect();
        for (&k, id) in seen.iter().zip(ids) {
            taken[k] = id;
        }
    }
    let seen: Vec<usize> = (0..reports.len())
        .filter(|&k| has_print(k) && reports[k].status == BlobStatus::Object)
        .collect();
    // Fresh ids follow the prior's largest id and every label, so they never repeat one.
    let prior_ids = prior
        .into_iter()
        .flat_map(|p| p.objects().iter().map(|o| o.id.0));
    let labels = blobs.iter().filter_map(|b| b.label);
    let mut next = prior_ids.chain(labels).max().map_or(1, |m| m + 1);
    for &k in &seen {
        if reports[k].status != BlobStatus::Object {
            continue;
        }
        let id = match (taken[k], prior, blobs[k].label) {
            (Some(id), _, _) => id,
            (None, Some(_), _) => {
                reports[k].status = BlobStatus::New;
                next += 1;
                ObjectId(next - 1)
            }
            (None, None, Some(label)) => ObjectId(label),
            (None, None, None) => {
                next += 1;
                ObjectId(next - 1)
            }
        };
        reports[k].id = Some(id);
    }
    gone
}

/// Cuts apart footprints that overlap by at most `overlap_repair` along the line halfway through
/// the overlap; larger overlaps become `Overlap`.
fn separate(
    reports: &mut [BlobReport],
    prints: &mut [Option<ConvexPolygon>],
    settings: &PerceptionSettings,
    adjustments: &mut Vec<String>,
) {
    let objects: Vec<usize> = (0..reports.len())
        .filter(|&k| reports[k].id.is_some())
        .collect();
    for (a, &i) in objects.iter().enumerate() {
        for &j in &objects[a + 1..] {
            let (Some(first), Some(second)) = (prints[i].clone(), prints[j].clone()) else {
                continue;
            };
            let (normal, gap) = max_separation(&first, &second);
            if gap >= 0.0 {
                continue;
            }
            let (id_i, id_j) = (reports[i].id, reports[j].id);
            if -gap > settings.overlap_repair {
                reports[j].status = BlobStatus::Overlap {
                    with: id_i.unwrap_or(ObjectId(0)),
                };
                reports[j].id = None;
                continue;
            }
            let middle = first.support(&normal) + 0.5 * gap;
            let cut = |p: &ConvexPolygon, n: Vector2<f64>, d: f64| {
                tidy_polygon(&clip(p.vertices(), &n, d))
            };
            prints[i] = cut(&first, normal, middle - 1e-6);
            prints[j] = cut(&second, -normal, -(middle + 1e-6));
            adjustments.push(format!(
                "objects {} and {} overlapped by {:.2} mm: cut apart halfway",
                id_i.map_or(0, |d| d.0),
                id_j.map_or(0, |d| d.0),
                -gap * 1e3
            ));
        }
    }
}

/// The objects of the blobs that have ids, each footprint trimmed to the workspace where it reaches
/// past the edge by less than the trim (an adjustment). An object the prior holds keeps the prior's
/// frame, name and mass (`align.rs`); another is given its outline about its centroid, yaw 0.
fn objects_of(
    reports: &[BlobReport],
    prints: &[Option<ConvexPolygon>],
    workspace: &Workspace,
    prior: Option<&Scene>,
    adjustments: &mut Vec<String>,
) -> Vec<Object> {
    let mut objects = Vec::new();
    for (report, print) in reports.iter().zip(prints) {
        let (Some(id), Some(print), Some(top)) = (report.id, print, report.top_height) else {
            continue;
        };
        let mut points = print.vertices().to_vec();
        let walls = [
            (Vector2::new(-1.0, 0.0), -workspace.min[0]),
            (Vector2::new(0.0, -1.0), -workspace.min[1]),
            (Vector2::new(1.0, 0.0), workspace.max[0]),
            (Vector2::new(0.0, 1.0), workspace.max[1]),
        ];
        for (normal, d) in walls {
            points = clip(&points, &normal, d);
        }
        let Some(trimmed) = tidy_polygon(&points) else {
            continue;
        };
        if (trimmed.area() - print.area()).abs() > 1e-12 {
            adjustments.push(format!("object {id}: trimmed to the workspace's edge"));
        }
        let before = prior.and_then(|p| p.index_of(id).map(|k| &p.objects()[k]));
        let object = match before {
            Some(before) => {
                let (pose, polygon) = in_prior_frame(&trimmed, before);
                Object {
                    id,
                    name: before.name.clone(),
                    polygon,
                    pose,
                    height: top,
                    mass: before.mass,
                }
            }
            None => {
                let centre = trimmed.centroid();
                Object {
                    id,
                    name: None,
                    polygon: trimmed.translated(&-centre.coords),
                    pose: Pose::new(centre.x, centre.y, 0.0),
                    height: top,
                    mass: None,
                }
            }
        };
        objects.push(object);
    }
    objects
}
