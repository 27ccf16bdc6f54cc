//! One trip checked: its table, clustering, pushes, looks, grasp, riders and rows pushed ahead.

use nalgebra::Point2;

use super::TOLERANCE;
use super::actions::{check_grasp, check_pushes};
use super::riders::check_riders;
use crate::cluster::{Clustering, summed_diameter};
use crate::geometry::{point_bounds, separating_line};
use crate::plan::Trip;
use crate::scene::{ObjectId, Scene};

/// Every violation in one trip.
pub fn verify_trip(trip: &Trip) -> Vec<String> {
    let scene = match Scene::new(trip.scene.to_spec()) {
        Ok(scene) => scene,
        Err(e) => return vec![format!("the trip's scene is invalid: {e}")],
    };
    let mut found = Vec::new();
    check_clustering(&scene, trip, &mut found);
    if !trip.plan.ahead_rows.is_empty() {
        let mut rows: Vec<ObjectId> = trip
            .plan
            .ahead_rows
            .iter()
            .flat_map(|r| r.objects.clone())
            .collect();
        let mut ahead = trip.plan.ahead.clone();
        rows.sort_unstable();
        ahead.sort_unstable();
        if rows != ahead {
            found.push("the rows pushed ahead do not hold exactly the objects pushed ahead".into());
        }
    }
    if let Some(id) = trip
        .plan
        .ahead
        .iter()
        .find(|id| trip.plan.grasp.objects.contains(id))
    {
        found.push(format!(
            "grasp: takes object {id}, which the trip pushed ahead for a later trip"
        ));
    }
    // The pushes up to the first look on the trip's scene, each later run of pushes on the look
    // before it, the grasp after the last run.
    let mut tables = vec![(scene, 0)];
    for (n, look) in trip.looks.iter().enumerate() {
        let start = tables.last().map_or(0, |t| t.1);
        if look.after_pushes < start || look.after_pushes > trip.plan.pushes.len() {
            found.push(format!(
                "look {n}: after push {} is out of order (the trip has {} pushes)",
                look.after_pushes,
                trip.plan.pushes.len()
            ));
            return found;
        }
        if look.scene.workspace != trip.scene.workspace || look.scene.gripper != trip.scene.gripper
        {
            found.push(format!(
                "look {n}: its workspace or gripper is not the trip's"
            ));
        }
        match Scene::new(look.scene.to_spec()) {
            Ok(seen) => tables.push((seen, look.after_pushes)),
            Err(e) => {
                found.push(format!("look {n}: its scene is invalid: {e}"));
                return found;
            }
        }
    }
    let mut world = Vec::new();
    for (k, (table, start)) in tables.iter().enumerate() {
        let end = tables.get(k + 1).map_or(trip.plan.pushes.len(), |t| t.1);
        world = check_pushes(table, trip, *start..end, &mut found);
    }
    if let Some((table, _)) = tables.last() {
        check_grasp(table, &world, trip, &mut found);
        check_riders(table, &world, trip, &mut found);
    }
    found
}

fn check_clustering(scene: &Scene, trip: &Trip, found: &mut Vec<String>) {
    let clusters = &trip.plan.clustering.clusters;
    if clusters.is_empty() {
        if trip.plan.cluster.is_some() {
            found.push("a cluster is chosen from an empty clustering".to_string());
        }
        return;
    }
    if let Some(k) = trip.plan.cluster
        && k >= clusters.len()
    {
        found.push(format!(
            "cluster {k} chosen from {} clusters",
            clusters.len()
        ));
    }
    found.extend(verify_clustering(scene, &trip.plan.clustering));
}

/// Every violation of a clustering of `scene`: not a partition, a cluster over capacity, two clusters
/// no line separates.
pub fn verify_clustering(scene: &Scene, clustering: &Clustering) -> Vec<String> {
    let clusters = &clustering.clusters;
    let mut found = Vec::new();
    let mut seen = vec![0usize; scene.len()];
    let mut indices: Vec<Vec<usize>> = Vec::new();
    for cluster in clusters {
        let mut members = Vec::new();
        for id in cluster {
            match scene.index_of(*id) {
                Some(i) => {
                    seen[i] += 1;
                    members.push(i);
                }
                None => found.push(format!("clustered object {id} is not on the table")),
            }
        }
        indices.push(members);
    }
    for (i, count) in seen.iter().enumerate() {
        if *count != 1 {
            found.push(format!(
                "object {} is in {count} clusters",
                scene.objects()[i].id
            ));
        }
    }
    let gap = scene.gripper().usable_gap();
    for (k, members) in indices.iter().enumerate() {
        let total = summed_diameter(scene, members);
        if members.len() > 1 && total > gap + TOLERANCE {
            found.push(format!(
                "cluster {k}: summed grasp diameters {:.2} mm exceed the {:.2} mm gap",
                total * 1e3,
                gap * 1e3
            ));
        }
    }
    let centroids: Vec<Vec<Point2<f64>>> = indices
        .iter()
        .map(|m| m.iter().map(|&i| scene.centroid(i)).collect())
        .collect();
    // Clusters whose centroid boxes lie more than twice the tolerance apart along x or y are split
    // by an axis-parallel line; only the others need the exact test (a sweep along x).
    let boxes: Vec<(Point2<f64>, Point2<f64>)> = centroids
        .iter()
        .map(|points| point_bounds(points))
        .collect();
    let mut by_x: Vec<usize> = (0..boxes.len()).collect();
    by_x.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut inseparable = Vec::new();
    for (k, &a) in by_x.iter().enumerate() {
        for &b in &by_x[k + 1..] {
            if boxes[b].0.x > boxes[a].1.x + 2.0 * TOLERANCE {
                break;
            }
            if boxes[a].0.y > boxes[b].1.y + 2.0 * TOLERANCE
                || boxes[b].0.y > boxes[a].1.y + 2.0 * TOLERANCE
            {
                continue;
            }
            if separating_line(&centroids[a], &centroids[b], TOLERANCE).is_none() {
                inseparable.push((a.min(b), a.max(b)));
            }
        }
    }
    inseparable.sort_unstable();
    for (a, b) in inseparable {
        found.push(format!("clusters {a} and {b} are not separable by a line"));
    }
    // Riders the clustering chose: each a cluster of its own, on a row of two or more that is a
    // cluster, one rider per row and one row per rider.
    for (k, ride) in clustering.riders.iter().enumerate() {
        let mut row = ride.row.clone();
        row.sort_unstable();
        let is_cluster = |members: &[ObjectId]| {
            clusters.iter().any(|c| {
                let mut c = c.clone();
                c.sort_unstable();
                c == members
            })
        };
        if !is_cluster(&[ride.rider]) {
            found.push(format!(
                "rider {k} (object {}) is not a cluster of its own",
                ride.rider
            ));
        }
        if row.len() < 2 || !is_cluster(&row) {
            found.push(format!(
                "rider {k} (object {}) rides on no row of the clustering",
                ride.rider
            ));
        }
        let twice = clustering.riders[..k].iter().any(|other| {
            other.rider == ride.rider || {
                let mut r = other.row.clone();
                r.sort_unstable();
                r == row
            }
        });
        if twice {
            found.push(format!(
                "rider {k} (object {}): a second ride for the same rider or row",
                ride.rider
            ));
        }
    }
    found
}
