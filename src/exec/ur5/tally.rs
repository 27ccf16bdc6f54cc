//! What became of each object the closed loop knew: carried to the bin, or lost to planning.
//!
//! The robot cannot see into the bin, so an object counts as carried when it is gone from the look
//! after a grasp that held it: one of the grasp's objects, or a rider put down on its row in the
//! same trip. Any other object gone from a look (pushed off the table, thrown by a grasp, taken
//! along by a neighbour) is *lost*, [`NOT_IN_VIEW`], and the run cannot end cleared while it is;
//! counting it carried would report a table cleared with an object lying beside it.
//!
//! A depth camera also lists the blobs it sees whole past the workspace's edge that would be
//! objects otherwise (`Perception::past_edge`). Each lost object is matched to the nearest of them,
//! nearest pairs first, within [`MATCH_RADIUS`] of where it was last known; a matched object is
//! [`OUTSIDE`], and is offered where it lies to the loop's rule for objects past the edge
//! (`run.reach_past_edge`) under its own id, name and mass. A grasp of such an object carried it
//! when the look after finds it past the edge no more. An object found again on the workspace with
//! its id (the tracker kept it) is no longer lost.

use crate::scene::{Object, ObjectId, Scene};

/// The reason given for an object gone from the look that no grasp held and no camera sees.
pub const NOT_IN_VIEW: &str = "not in view";

/// The reason given for a lost object the camera sees past the workspace's edge.
pub const OUTSIDE: &str = "outside the workspace";

/// How far (metres) from where a lost object was last known a blob past the edge may lie and still
/// be taken for it: the largest reach past the edge the loop allows (`run.reach_past_edge` ≤ 0.2 m)
/// plus an object's size, so that an object pushed or thrown from just inside the edge to as far
/// as the arm may reach is found again.
pub const MATCH_RADIUS: f64 = 0.3;

/// A lost object: where it was last known, and why it cannot be planned for.
#[derive(Clone, Debug, PartialEq)]
struct Lost {
    object: Object,
    reason: &'static str,
}

/// The closed loop's account of the objects it knew (module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Tally {
    lost: Vec<Lost>,
}

impl Tally {
    /// Forgets everything (a new run).
    pub(super) fn clear(&mut self) {
        self.lost.clear();
    }

    /// Takes the look `after` that followed the table `before`: `held` are the objects of a grasp
    /// made in between (empty for a look during a trip) and `past_edge` the objects the camera sees
    /// past the workspace's edge (their ids are not the loop's). Returns the objects carried and
    /// those newly lost.
    pub(super) fn after_look(
        &mut self,
        before: &Scene,
        after: &Scene,
        held: &[ObjectId],
        past_edge: &[Object],
    ) -> (Vec<ObjectId>, Vec<ObjectId>) {
        let seen = |id: ObjectId| after.objects().iter().any(|o| o.id == id);
        // Found again on the workspace under its own id.
        self.lost.retain(|l| !seen(l.object.id));
        let mut carried = Vec::new();
        let mut newly = Vec::new();
        for object in before.objects().iter().filter(|o| !seen(o.id)) {
            if held.contains(&object.id) {
                carried.push(object.id);
            } else {
                newly.push(object.id);
                self.lost.push(Lost {
                    object: object.clone(),
                    reason: NOT_IN_VIEW,
                });
            }
        }
        let matched = self.match_past_edge(past_edge);
        // A lost object a grasp held and the camera no longer sees past the edge was carried.
        let mut k = 0;
        self.lost.retain(|l| {
            let found = matched[k];
            k += 1;
            let taken = !found && held.contains(&l.object.id) && !newly.contains(&l.object.id);
            if taken {
                carried.push(l.object.id);
            }
            !taken
        });
        (carried, newly)
    }

    /// Matches the lost objects to `past_edge` (nearest pairs first, within [`MATCH_RADIUS`]),
    /// moving each matched one to where it is seen; returns, per lost object, whether it was.
    fn match_past_edge(&mut self, past_edge: &[Object]) -> Vec<bool> {
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (i, lost) in self.lost.iter().enumerate() {
            let from = lost.object.world_centroid();
            for (j, seen) in past_edge.iter().enumerate() {
                let distance = (seen.world_centroid() - from).norm();
                if distance <= MATCH_RADIUS {
                    pairs.push((distance, i, j));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut matched = vec![false; self.lost.len()];
        let mut used = vec![false; past_edge.len()];
        for (_, i, j) in pairs {
            if matched[i] || used[j] {
                continue;
            }
            (matched[i], used[j]) = (true, true);
            let known = &self.lost[i].object;
            self.lost[i] = Lost {
                object: Object {
                    id: known.id,
                    name: known.name.clone(),
                    mass: known.mass,
                    ..past_edge[j].clone()
                },
                reason: OUTSIDE,
            };
        }
        for (lost, &found) in self.lost.iter_mut().zip(&matched) {
            if !found {
                lost.reason = NOT_IN_VIEW;
            }
        }
        matched
    }

    /// The objects lost to planning, with the reason.
    pub(super) fn lost(&self) -> Vec<(ObjectId, &'static str)> {
        self.lost.iter().map(|l| (l.object.id, l.reason)).collect()
    }

    /// The lost objects the camera saw past the edge at the last look, where it saw them.
    pub(super) fn past_edge(&self) -> Vec<Object> {
        self.lost
            .iter()
            .filter(|l| l.reason == OUTSIDE)
            .map(|l| l.object.clone())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point2, Vector2};

    use crate::geometry::ConvexPolygon;
    use crate::scene::{Gripper, Pose, Workspace};

    fn object(id: u32, x: f64, y: f64) -> Object {
        Object {
            id: ObjectId(id),
            name: None,
            polygon: ConvexPolygon::rectangle(&Point2::origin(), &Vector2::x(), 0.015, 0.01),
            pose: Pose::new(x, y, 0.0),
            height: 0.02,
            mass: None,
        }
    }

    fn table(objects: Vec<Object>) -> Scene {
        Scene::from_parts(Workspace::new(0.4, 0.3), Gripper::default(), objects).unwrap()
    }

    #[test]
    fn only_what_the_grasp_held_is_carried_and_the_rest_is_lost() {
        let mut tally = Tally::default();
        let before = table(vec![
            object(1, 0.1, 0.1),
            object(2, 0.2, 0.1),
            object(3, 0.3, 0.2),
        ]);
        let after = table(vec![object(3, 0.3, 0.2)]);
        let (carried, newly) = tally.after_look(&before, &after, &[ObjectId(1)], &[]);
        assert_eq!(carried, vec![ObjectId(1)]);
        assert_eq!(newly, vec![ObjectId(2)]);
        assert_eq!(tally.lost(), vec![(ObjectId(2), NOT_IN_VIEW)]);
        assert!(tally.past_edge().is_empty());
        // Found again under its id: no longer lost.
        let again = table(vec![object(2, 0.25, 0.1), object(3, 0.3, 0.2)]);
        let (carried, newly) = tally.after_look(&after, &again, &[], &[]);
        assert!(carried.is_empty() && newly.is_empty());
        assert!(tally.lost().is_empty());
    }

    #[test]
    fn an_object_seen_past_the_edge_keeps_its_id_until_a_grasp_takes_it() {
        let mut tally = Tally::default();
        let before = table(vec![object(1, 0.38, 0.1), object(2, 0.1, 0.1)]);
        let after = table(vec![object(2, 0.1, 0.1)]);
        // The camera's ids are its own; a blob far off is no match.
        let outside = vec![object(40, 0.45, 0.12), object(41, 1.2, 0.1)];
        let (carried, newly) = tally.after_look(&before, &after, &[], &outside);
        assert!(carried.is_empty());
        assert_eq!(newly, vec![ObjectId(1)]);
        assert_eq!(tally.lost(), vec![(ObjectId(1), OUTSIDE)]);
        let there = tally.past_edge();
        assert_eq!(there.len(), 1);
        assert_eq!(there[0].id, ObjectId(1));
        assert!((there[0].world_centroid().x - 0.45).abs() < 1e-12);
        // A grasp of object 2 leaves the outside one where it is.
        let empty = table(Vec::new());
        let (carried, _) = tally.after_look(&after, &empty, &[ObjectId(2)], &outside);
        assert_eq!(carried, vec![ObjectId(2)]);
        assert_eq!(tally.lost(), vec![(ObjectId(1), OUTSIDE)]);
        // A grasp of it that fails: still there.
        tally.after_look(&empty, &empty, &[ObjectId(1)], &outside);
        assert_eq!(tally.lost(), vec![(ObjectId(1), OUTSIDE)]);
        // One that carries it: gone from past the edge, so carried.
        let (carried, newly) = tally.after_look(&empty, &empty, &[ObjectId(1)], &outside[1..]);
        assert_eq!(carried, vec![ObjectId(1)]);
        assert!(newly.is_empty() && tally.lost().is_empty());
    }

    #[test]
    fn a_lost_object_no_longer_seen_past_the_edge_without_a_grasp_is_not_in_view() {
        let mut tally = Tally::default();
        let before = table(vec![object(1, 0.38, 0.1)]);
        let empty = table(Vec::new());
        tally.after_look(&before, &empty, &[], &[object(9, 0.42, 0.1)]);
        assert_eq!(tally.lost(), vec![(ObjectId(1), OUTSIDE)]);
        tally.after_look(&empty, &empty, &[], &[]);
        assert_eq!(tally.lost(), vec![(ObjectId(1), NOT_IN_VIEW)]);
        assert!(tally.past_edge().is_empty());
    }
}
