//! How a plan's trips are written: the first trip's scene in full, every later one as its change
//! against the trip before.
//!
//! A run of `n` trips over `m` objects would otherwise repeat every object left on the table in every
//! trip, `O(n·m)` objects in all (a single-object plan of 1000 objects took 178 MB). A later trip's
//! `scene_change` lists the objects of its scene in order, each as
//! - an id alone: the object as it was in the previous trip's scene;
//! - `{"id", "pose"}`: the same object at a new pose;
//! - a whole object: anything else (an object seen for the first time, or with a new outline).
//!
//! Objects of the previous scene not listed are gone. A trip whose workspace or gripper differs from
//! the previous one is written in full. A look during a trip (a new observation after some of its
//! pushes) is written the same way, as its change from the trip's own scene. Reading accepts both
//! forms, so plans written before this format still read; reading then writing gives the same scenes
//! exactly (numbers are not re-derived).

use std::sync::Arc;

use schemars::JsonSchema;
use serde::de::{Error as _, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::shared::{Lookup, SharedScene};
use super::{Fault, Look, LostObject, Trip, TripPlan};
use crate::scene::{ObjectId, ObjectSpec, Pose, SceneSpec};

/// One object of a trip's scene, relative to the previous trip's scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum ObjectChange {
    /// Unchanged since the previous trip.
    Kept(ObjectId),
    /// Moved since the previous trip (pushed, or nudged by physics).
    Moved(Moved),
    /// New, or changed in more than its pose.
    Whole(ObjectSpec),
}

/// An object at a new pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Moved {
    /// The object.
    pub id: ObjectId,
    /// Its new pose.
    pub pose: Pose,
}

/// A trip's scene as written: in full, or as the change from the previous trip's scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TripRecord {
    /// The observation in full (the first trip, or a trip whose workspace or gripper changed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<SceneSpec>,
    /// The observation as a change from the previous trip's scene, object by object in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_change: Option<Vec<ObjectChange>>,
    /// As [`Trip::plan`], its fields written inline.
    #[serde(flatten)]
    pub plan: TripPlan,
    /// As [`Trip::looks`], each scene as a change from the trip's scene.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub looks: Vec<LookRecord>,
    /// As [`Trip::carried`].
    pub carried: Vec<ObjectId>,
    /// As [`Trip::fault`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fault: Option<Fault>,
    /// As [`Trip::lost`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lost: Vec<LostObject>,
}

/// A look during a trip as written: its scene as the change from the trip's scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LookRecord {
    /// As [`super::Look::after_pushes`].
    pub after_pushes: usize,
    /// The observation, object by object in order, as a change from the trip's scene.
    pub scene_change: Vec<ObjectChange>,
}

fn change(previous: &SharedScene, scene: &SharedScene) -> Option<Vec<ObjectChange>> {
    if previous.workspace != scene.workspace || previous.gripper != scene.gripper {
        return None;
    }
    Some(object_changes(previous, scene))
}

/// The objects of `scene`, each as a change from `previous`.
fn object_changes(previous: &SharedScene, scene: &SharedScene) -> Vec<ObjectChange> {
    let mut before = Lookup::new(&previous.objects);
    scene
        .objects
        .iter()
        .map(|object| match before.find(object.id) {
            Some(old) if Arc::ptr_eq(old, object) || **old == **object => {
                ObjectChange::Kept(object.id)
            }
            Some(old)
                if ObjectSpec {
                    pose: object.pose,
                    ..ObjectSpec::clone(old)
                } == **object =>
            {
                ObjectChange::Moved(Moved {
                    id: object.id,
                    pose: object.pose,
                })
            }
            _ => ObjectChange::Whole(ObjectSpec::clone(object)),
        })
        .collect()
}

fn apply(
    previous: &SharedScene,
    changes: Vec<ObjectChange>,
    trip: usize,
) -> std::result::Result<SharedScene, String> {
    let mut before = Lookup::new(&previous.objects);
    let mut earlier = |id: ObjectId| {
        before.find(id).ok_or_else(|| {
            format!(
                "trip {trip}: `scene_change` names object {id}, which the scene it changes does \
                 not hold"
            )
        })
    };
    // A new vector, not one collected in place from `changes`, whose larger buffer it would keep.
    let mut objects = Vec::with_capacity(changes.len());
    for change in changes {
        objects.push(match change {
            ObjectChange::Kept(id) => Arc::clone(earlier(id)?),
            ObjectChange::Moved(Moved { id, pose }) => Arc::new(ObjectSpec {
                pose,
                ..ObjectSpec::clone(earlier(id)?)
            }),
            ObjectChange::Whole(object) => Arc::new(object),
        });
    }
    Ok(SharedScene {
        workspace: previous.workspace.clone(),
        gripper: previous.gripper.clone(),
        objects,
    })
}

/// Trip `k` of `trips` in its written form.
fn record(trips: &[Trip], k: usize) -> TripRecord {
    let trip = &trips[k];
    let scene_change = k
        .checked_sub(1)
        .and_then(|p| change(&trips[p].scene, &trip.scene));
    TripRecord {
        scene: scene_change.is_none().then(|| trip.scene.to_spec()),
        scene_change,
        plan: trip.plan.clone(),
        looks: trip
            .looks
            .iter()
            .map(|look| LookRecord {
                after_pushes: look.after_pushes,
                scene_change: object_changes(&trip.scene, &look.scene),
            })
            .collect(),
        carried: trip.carried.clone(),
        fault: trip.fault,
        lost: trip.lost.clone(),
    }
}

impl super::Plan {
    /// The plan as indented JSON, as [`crate::json::to_json`] writes it, with the trips written one
    /// at a time so that a long plan is never held whole as a JSON tree.
    pub fn to_json(&self) -> String {
        let head = super::Plan {
            policy: self.policy.clone(),
            executor: self.executor.clone(),
            seed: self.seed,
            settings: self.settings.clone(),
            trips: Vec::new(),
            failed_attempts: self.failed_attempts.clone(),
            status: self.status.clone(),
            seconds: self.seconds,
        };
        let trips = &self.trips;
        crate::json::to_json_listing(&head, "trips", (0..trips.len()).map(|k| record(trips, k)))
    }
}

/// Writes `trips` in the compact form (`#[serde(serialize_with)]` of [`super::Plan::trips`]), one
/// record at a time.
///
/// # Errors
/// The serializer's.
pub fn serialize<S: Serializer>(trips: &[Trip], serializer: S) -> Result<S::Ok, S::Error> {
    serializer.collect_seq((0..trips.len()).map(|k| record(trips, k)))
}

/// The trip a record describes, after `previous`.
fn trip(
    k: usize,
    record: TripRecord,
    previous: Option<&Trip>,
) -> std::result::Result<Trip, String> {
    let scene = match (record.scene, record.scene_change, previous) {
        (Some(scene), None, previous) => SharedScene::sharing(scene, previous.map(|p| &p.scene)),
        (None, Some(changes), Some(previous)) => apply(&previous.scene, changes, k)?,
        (None, Some(_), None) => {
            return Err(
                "trip 0: the first trip needs its `scene` in full, not a `scene_change`".into(),
            );
        }
        (Some(_), Some(_), _) => {
            return Err(format!(
                "trip {k}: give `scene` or `scene_change`, not both"
            ));
        }
        (None, None, _) => return Err(format!("trip {k}: needs `scene` or `scene_change`")),
    };
    let looks = record
        .looks
        .into_iter()
        .map(|look| {
            Ok(Look {
                after_pushes: look.after_pushes,
                scene: apply(&scene, look.scene_change, k)?,
            })
        })
        .collect::<std::result::Result<Vec<Look>, String>>()?;
    Ok(Trip {
        scene,
        plan: record.plan,
        looks,
        carried: record.carried,
        fault: record.fault,
        lost: record.lost,
    })
}

/// Reads trips in either form (`#[serde(deserialize_with)]` of [`super::Plan::trips`]), each
/// record as it comes, so that a long plan is never held in its written form.
///
/// # Errors
/// A trip with neither or both of `scene` and `scene_change`, a first trip given as a change, or a
/// change naming an object the previous scene does not hold.
pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<Trip>, D::Error> {
    struct Trips;
    impl<'de> Visitor<'de> for Trips {
        type Value = Vec<Trip>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a list of trips")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<Trip>, A::Error> {
            let mut trips: Vec<Trip> = Vec::with_capacity(seq.size_hint().unwrap_or(0));
            while let Some(record) = seq.next_element::<TripRecord>()? {
                let next = trip(trips.len(), record, trips.last()).map_err(A::Error::custom)?;
                trips.push(next);
            }
            Ok(trips)
        }
    }
    deserializer.deserialize_seq(Trips)
}
