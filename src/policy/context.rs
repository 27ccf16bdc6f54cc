//! What a run carries from one trip to the next ([`TripContext`]), so that planning a trip depends
//! on the table and this context only.

use serde::{Deserialize, Serialize};

use crate::cluster::ClusterMemory;
use crate::exec::RIDER_LEFT;
use crate::geometry::ConvexPolygon;
use crate::grasp::{Grasp, JawPose};
use crate::plan::TripPlan;
use crate::push::Push;
use crate::random::SeededRng;
use crate::scene::{ObjectId, Scene};

/// What a run remembers from trip to trip: the random stream that picks the next object or cluster,
/// the jaw poses where grasps carried nothing (not tried again in practically the same place, unless
/// the grasp came down on an object since carried away and nothing else can be planned:
/// [`TripContext::forget_landings_on`]), the
/// sets of objects whose multi-object grasps carried nothing (after [`GIVE_UP_AFTER`] such grasps,
/// those objects are taken one at a time), and the pushes whose fingers came down on an object (if
/// the camera cannot see it, the pushed object is not pushed again with the fingers lowered near
/// there), and what the clusterer remembers (the MILP's last optimum). A policy keeps no state
/// between calls: a trip's plan depends on the table and this context only.
#[derive(Clone, Debug)]
pub struct TripContext {
    pub(super) rng: SeededRng,
    /// Jaw poses of grasps that carried nothing.
    pub failed: Vec<JawPose>,
    /// The grasps among `failed` whose jaws came down on an object, with that object.
    pub failed_on: Vec<GraspLanding>,
    /// The objects (sorted) of each multi-object grasp that carried nothing.
    pub failed_together: Vec<Vec<ObjectId>>,
    /// Pushes during whose descent a finger came down on an object.
    pub landed: Vec<Landing>,
    /// The rows trips pushed ahead for later trips' grasps (`pricing.push_ahead`), each its
    /// objects, in the order they were pushed; empty when none waits.
    pub ahead: Vec<Vec<ObjectId>>,
    /// What the clusterer remembers from earlier trips (the MILP's last proven optimum).
    pub clusterings: ClusterMemory,
    /// Riders left standing on their rows after the row's grasp failed, as the last look reported
    /// them ([`TripContext::note_lost`]).
    pub perched: Vec<Perched>,
    /// Every rider put down so far, where and on what ([`TripContext::note_riders`]).
    placed: Vec<Perched>,
    /// Riders that fell off a row their trip carried whole ([`TripContext::note_carried`]): not
    /// offered as riders again.
    pub fell_off: Vec<ObjectId>,
}

/// A rider still standing on the row it was put down on, its row's grasp not having carried it
/// (the executor reports it lost as [`crate::exec::RIDER_LEFT`]). A camera that sees it on top
/// cannot give it a place on the table, but the run knows where it was put and on what.
#[derive(Clone, Debug, PartialEq)]
pub struct Perched {
    /// The rider.
    pub rider: ObjectId,
    /// The objects the trip that placed it meant to grasp: its row.
    pub row: Vec<ObjectId>,
    /// The objects of the row it was put down on.
    pub on: Vec<ObjectId>,
    /// Its outline seen from above where it was put down.
    pub footprint: ConvexPolygon,
}

/// Multi-object grasps of one set of objects that may carry nothing before those objects are no
/// longer grasped together in the run. A failed grasp is not tried again in the same place, but a
/// grasp model that misjudges a set (an object toppled onto a side face, say, seen from above as an
/// upright prism of its outline) may hold it in every other place too: on a held-out scene the
/// pair 12/31 (a triangular prism lying on its side and a pentagon) was grasped together eleven
/// times, each carrying nothing, until the run stopped. One failure can be bad luck (objects move,
/// and the next look sees them anew), so the set is given up after the second.
pub const GIVE_UP_AFTER: usize = 2;

/// A grasp that carried nothing because a finger came down on an object.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspLanding {
    /// The grasp's jaws.
    pub jaws: JawPose,
    /// The object the finger came down on.
    pub on: ObjectId,
}

/// A push during whose descent a finger came down on an object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Landing {
    /// The push.
    pub push: Push,
    /// The object the finger came down on.
    pub on: ObjectId,
}

impl TripContext {
    /// A fresh context; `seed` drives the random choices.
    pub fn new(seed: u64) -> Self {
        Self {
            rng: SeededRng::new(seed),
            failed: Vec::new(),
            failed_on: Vec::new(),
            failed_together: Vec::new(),
            landed: Vec::new(),
            ahead: Vec::new(),
            clusterings: ClusterMemory::default(),
            perched: Vec::new(),
            placed: Vec::new(),
            fell_off: Vec::new(),
        }
    }

    /// Notes a grasp that carried nothing: its jaws, and its objects when there were several.
    pub fn record_failure(&mut self, grasp: &Grasp) {
        self.failed.push(grasp.jaws);
        if grasp.objects.len() >= 2 {
            let mut objects = grasp.objects.clone();
            objects.sort_unstable();
            self.failed_together.push(objects);
        }
    }

    /// Notes a grasp that carried nothing because a finger came down on the object `on`.
    pub fn record_landing(&mut self, grasp: &Grasp, on: ObjectId) {
        self.record_failure(grasp);
        self.failed_on.push(GraspLanding {
            jaws: grasp.jaws,
            on,
        });
    }

    /// Forgets the failed grasps that came down on one of `carried`, objects known to have left the
    /// table for the bin, so that their places may be tried again; whether any was forgotten. An
    /// object merely no longer seen (lost outside the workspace, toppled, seen stacked) may still
    /// lie where the fingers came down, so only carried objects count. The run calls this only
    /// when nothing could be planned otherwise: while other grasps remain, the place that failed is
    /// still passed over.
    pub fn forget_landings_on(&mut self, carried: &[ObjectId]) -> bool {
        let (gone, kept): (Vec<GraspLanding>, Vec<GraspLanding>) = self
            .failed_on
            .iter()
            .partition(|landing| carried.contains(&landing.on));
        for landing in &gone {
            if let Some(k) = self.failed.iter().position(|jaws| *jaws == landing.jaws) {
                self.failed.remove(k);
            }
        }
        self.failed_on = kept;
        !gone.is_empty()
    }

    /// Notes the riders that `trip`, planned on `scene`, put down: where, on what and in which
    /// row, in case a look finds one left standing there.
    pub fn note_riders(&mut self, scene: &Scene, trip: &TripPlan) {
        for rider in &trip.riders {
            if let Some(i) = scene.index_of(rider.object) {
                self.placed.retain(|p| p.rider != rider.object);
                self.placed.push(Perched {
                    rider: rider.object,
                    row: trip.grasp.objects.clone(),
                    on: rider.on.clone(),
                    footprint: scene.objects()[i]
                        .polygon
                        .transformed(&rider.place.isometry()),
                });
            }
        }
    }

    /// Notes what `trip`'s grasp carried: a rider it put down that stayed behind though the row
    /// it rode on went to the bin whole fell off a row held in the jaws, and is not offered as a
    /// rider again (`formulations/stacking.md`, "Riders that fell off"). A rider left by a row not
    /// carried whole is the row's failure, not its own, and may ride again.
    pub fn note_carried(&mut self, trip: &TripPlan, carried: &[ObjectId]) {
        if !trip.grasp.objects.iter().all(|id| carried.contains(id)) {
            return;
        }
        for rider in &trip.riders {
            if !carried.contains(&rider.object) && !self.fell_off.contains(&rider.object) {
                self.fell_off.push(rider.object);
            }
        }
    }

    /// Takes in what a look could not plan for (the executor's [`crate::exec::Executor::lost`]):
    /// the riders it reports left standing on another object ([`RIDER_LEFT`]) are
    /// [`TripContext::perched`] until the next look.
    pub fn note_lost(&mut self, lost: &[(ObjectId, &str)]) {
        self.perched = self
            .placed
            .iter()
            .filter(|p| lost.contains(&(p.rider, RIDER_LEFT)))
            .cloned()
            .collect();
    }

    /// Whether `grasp` takes two or more objects that are still to be grasped together.
    pub(super) fn together(&self, grasp: &Grasp) -> bool {
        grasp.objects.len() >= 2 && !self.given_up(&grasp.objects)
    }

    /// Whether these objects are no longer to be grasped together: [`GIVE_UP_AFTER`] grasps of
    /// exactly them carried nothing.
    pub fn given_up(&self, objects: &[ObjectId]) -> bool {
        let mut objects = objects.to_vec();
        objects.sort_unstable();
        self.failed_together
            .iter()
            .filter(|set| **set == objects)
            .count()
            >= GIVE_UP_AFTER
    }
}
