//! The ideal executor: pushes move objects exactly to their targets, a rider is put down exactly at
//! its place, and a grasp carries exactly what the analytic grasp model predicts for the table as it
//! stands, with every rider standing on what it carries.

use crate::error::Result;
use crate::grasp::{Grasp, GraspModel, Squeeze, squeeze};
use crate::push::Push;
use crate::scene::{ObjectId, Scene};

use super::{Executor, GraspResult, Landing, RIDER_LEFT};
use crate::plan::Rider;

/// Applies pushes and grasps exactly.
#[derive(Clone, Debug, Default)]
pub struct Ideal {
    scene: Option<Scene>,
    model: GraspModel,
    /// Riders put down and not yet carried, each with the objects it rests on.
    riding: Vec<(ObjectId, Vec<ObjectId>)>,
}

impl Ideal {
    /// An ideal executor judging grasps with `model`.
    pub fn new(model: GraspModel) -> Self {
        Self {
            scene: None,
            model,
            riding: Vec::new(),
        }
    }

    fn table(&self) -> Result<&Scene> {
        self.scene.as_ref().ok_or_else(|| {
            crate::Error::misuse("ideal executor", "act before reset(): no table was given")
        })
    }
}

impl Executor for Ideal {
    fn name(&self) -> &'static str {
        "ideal"
    }

    fn reset(&mut self, scene: &Scene) -> Result<()> {
        self.scene = Some(scene.clone());
        self.riding.clear();
        Ok(())
    }

    fn push(&mut self, push: &Push) -> Result<Option<Landing>> {
        let scene = self.table()?;
        let mut objects = scene.objects().to_vec();
        if let Some(object) = objects.iter_mut().find(|o| o.id == push.object) {
            let moved = push.displacement();
            object.pose.x += moved.x;
            object.pose.y += moved.y;
        }
        self.scene = Some(scene.with_objects(objects)?);
        Ok(None)
    }

    fn grasp(&mut self, grasp: &Grasp) -> Result<GraspResult> {
        let scene = self.table()?;
        let mut carried: Vec<ObjectId> = match squeeze(scene, &grasp.jaws, &self.model) {
            Squeeze::Held { objects, .. } => {
                objects.iter().map(|&i| scene.objects()[i].id).collect()
            }
            _ => Vec::new(),
        };
        self.scene = Some(scene.without(&carried));
        // Riders go with what they stand on.
        let (aboard, left): (Vec<_>, Vec<_>) = std::mem::take(&mut self.riding)
            .into_iter()
            .partition(|(_, on)| !on.is_empty() && on.iter().all(|id| carried.contains(id)));
        self.riding = left;
        carried.extend(aboard.into_iter().map(|(rider, _)| rider));
        Ok(GraspResult::carried(carried))
    }

    fn place(&mut self, rider: &Rider) -> Result<Option<Landing>> {
        let scene = self.table()?;
        if scene.index_of(rider.object).is_none() {
            return Err(crate::Error::misuse(
                "ideal executor",
                format!("no object {} on the table to place", rider.object),
            ));
        }
        self.scene = Some(scene.without(&[rider.object]));
        self.riding.push((rider.object, rider.on.clone()));
        Ok(None)
    }

    fn observe(&mut self) -> Result<Scene> {
        self.table().cloned()
    }

    /// Riders whose row was not carried: they stand on other objects, where nothing plans for
    /// them.
    fn lost(&self) -> Vec<(ObjectId, &'static str)> {
        self.riding
            .iter()
            .map(|(rider, _)| (*rider, RIDER_LEFT))
            .collect()
    }
}
