//! A scene as a run record holds it: objects that did not change since the trip before are shared
//! with that trip, not copied.
//!
//! A run of `n` trips over `m` objects sees `O(n·m)` objects in all. Copied, that is about 250 bytes
//! each (a 5000-object single-object run held 5.7 GB); shared, each trip costs one pointer per object
//! on its table plus the objects that moved. The JSON form is the [`SceneSpec`] form, byte for byte.

use std::collections::HashMap;
use std::sync::Arc;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::scene::{Gripper, ObjectId, ObjectSpec, SceneSpec, Workspace};

/// A recorded scene: a [`SceneSpec`] whose objects may be shared with other recorded scenes.
#[derive(Clone, Debug, PartialEq)]
pub struct SharedScene {
    /// The rectangle to clear.
    pub workspace: Workspace,
    /// The gripper.
    pub gripper: Gripper,
    /// The objects on the table, in the scene's order.
    pub objects: Vec<Arc<ObjectSpec>>,
}

impl SharedScene {
    /// `scene`, sharing each object that is equal to the object of the same id in `earlier`.
    pub fn sharing(scene: SceneSpec, earlier: Option<&SharedScene>) -> Self {
        // Collected into a new vector: collecting from `scene.objects.into_iter()` would reuse its
        // buffer, sized for whole objects, and keep it for the life of the record.
        let mut objects = Vec::with_capacity(scene.objects.len());
        match earlier {
            None => objects.extend(scene.objects.into_iter().map(Arc::new)),
            Some(earlier) => {
                let mut lookup = Lookup::new(&earlier.objects);
                objects.extend(scene.objects.into_iter().map(
                    |object| match lookup.find(object.id) {
                        Some(old) if **old == object => Arc::clone(old),
                        _ => Arc::new(object),
                    },
                ));
            }
        }
        Self {
            workspace: scene.workspace,
            gripper: scene.gripper,
            objects,
        }
    }

    /// The scene as a plain [`SceneSpec`] (a copy of every object).
    pub fn to_spec(&self) -> SceneSpec {
        SceneSpec {
            workspace: self.workspace.clone(),
            gripper: self.gripper.clone(),
            objects: self.objects.iter().map(|o| ObjectSpec::clone(o)).collect(),
        }
    }

    /// The objects' ids, in order.
    pub fn ids(&self) -> impl Iterator<Item = ObjectId> + '_ {
        self.objects.iter().map(|o| o.id)
    }
}

impl From<SceneSpec> for SharedScene {
    fn from(scene: SceneSpec) -> Self {
        Self::sharing(scene, None)
    }
}

/// Finds an earlier scene's objects by id. Tables keep their order from trip to trip, less what
/// was carried, so a forward walk finds nearly every object; a map is built on the first miss.
pub(super) struct Lookup<'a> {
    objects: &'a [Arc<ObjectSpec>],
    next: usize,
    map: Option<HashMap<ObjectId, usize>>,
}

impl<'a> Lookup<'a> {
    pub(super) fn new(objects: &'a [Arc<ObjectSpec>]) -> Self {
        Self {
            objects,
            next: 0,
            map: None,
        }
    }

    /// The earlier object with this id, if there is one.
    pub(super) fn find(&mut self, id: ObjectId) -> Option<&'a Arc<ObjectSpec>> {
        // A few objects ahead covers the ones carried away since.
        for k in self.next..(self.next + 4).min(self.objects.len()) {
            if self.objects[k].id == id {
                self.next = k + 1;
                return Some(&self.objects[k]);
            }
        }
        let objects = self.objects;
        let map = self
            .map
            .get_or_insert_with(|| objects.iter().enumerate().map(|(k, o)| (o.id, k)).collect());
        let k = *map.get(&id)?;
        self.next = k + 1;
        Some(&objects[k])
    }
}

/// The JSON form of a scene, borrowed.
#[derive(Serialize)]
struct SpecRef<'a> {
    workspace: &'a Workspace,
    gripper: &'a Gripper,
    objects: Objects<'a>,
}

struct Objects<'a>(&'a [Arc<ObjectSpec>]);

impl Serialize for Objects<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.0.iter().map(|o| &**o))
    }
}

impl Serialize for SharedScene {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        SpecRef {
            workspace: &self.workspace,
            gripper: &self.gripper,
            objects: Objects(&self.objects),
        }
        .serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for SharedScene {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        SceneSpec::deserialize(deserializer).map(Self::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_json_form_is_the_scene_specs_and_unchanged_objects_are_shared() {
        let spec: SceneSpec = crate::json::from_json(
            r#"{"workspace": {"min": [0, 0], "max": [1, 1]},
                "objects": [
                  {"id": 1, "vertices": [[0,0],[0.02,0],[0,0.02]], "height": 0.03,
                   "pose": {"x": 0.2, "y": 0.2, "yaw": 0}},
                  {"id": 2, "vertices": [[0,0],[0.02,0],[0,0.02]], "height": 0.03,
                   "pose": {"x": 0.5, "y": 0.5, "yaw": 0}, "mass": 0.1}]}"#,
            "test",
        )
        .unwrap();
        let shared = SharedScene::from(spec.clone());
        assert_eq!(
            serde_json::to_string(&shared).unwrap(),
            serde_json::to_string(&spec).unwrap()
        );
        assert_eq!(shared.to_spec(), spec);
        let mut next = spec.clone();
        next.objects.remove(0);
        next.objects[0].pose.x += 0.01;
        next.objects.push(spec.objects[0].clone());
        let later = SharedScene::sharing(next.clone(), Some(&shared));
        assert_eq!(later.to_spec(), next);
        assert!(!Arc::ptr_eq(&later.objects[0], &shared.objects[1]));
        assert!(Arc::ptr_eq(&later.objects[1], &shared.objects[0]));
    }
}
