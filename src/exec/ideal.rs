//! The ideal executor: pushes move objects exactly to their targets, and a grasp carries exactly what
//! the analytic grasp model predicts for the table as it stands.

use crate::error::Result;
use crate::grasp::{Grasp, GraspModel, Squeeze, squeeze};
use crate::push::Push;
use crate::scene::{ObjectId, Scene};

use super::{Executor, GraspResult, Landing};

/// Applies pushes and grasps exactly.
#[derive(Clone, Debug, Default)]
pub struct Ideal {
    scene: Option<Scene>,
    model: GraspModel,
}

impl Ideal {
    /// An ideal executor judging grasps with `model`.
    pub fn new(model: GraspModel) -> Self {
        Self { scene: None, model }
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
        let carried: Vec<ObjectId> = match squeeze(scene, &grasp.jaws, &self.model) {
            Squeeze::Held { objects, .. } => {
                objects.iter().map(|&i| scene.objects()[i].id).collect()
            }
            _ => Vec::new(),
        };
        self.scene = Some(scene.without(&carried));
        Ok(GraspResult::carried(carried))
    }

    fn observe(&mut self) -> Result<Scene> {
        self.table().cloned()
    }
}
