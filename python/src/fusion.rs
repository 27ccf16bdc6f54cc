//! Looks fused across the boundary (`pushmog::policy::LookFusion`): a loop run from Python, such as
//! the MuJoCo example's, plans on the mean of the looks of objects that stood still, as `pushmog
//! run` does with `run.fuse_looks`. Pushes and trips cross as JSON.

use pushmog::grasp::Noise;
use pushmog::json;
use pushmog::policy::TripPlan;
use pushmog::push::Push;
use pyo3::prelude::*;

use crate::{Scene, check, check_settings};

/// The poses of each object since it was last touched; `fuse` gives a look with the still objects
/// at their mean.
#[pyclass(module = "pushmog._native")]
pub struct LookFusion {
    fusion: pushmog::policy::LookFusion,
}

#[pymethods]
impl LookFusion {
    /// A camera whose looks err by `position` metres per axis and `yaw` radians (each 0 to 0.05,
    /// as the grasp judge's `multi.noise`).
    #[new]
    fn new(position: f64, yaw: f64) -> PyResult<Self> {
        let noise = Noise {
            perception_position: position,
            perception_yaw: yaw,
            ..Noise::default()
        };
        check_settings(noise.validate())?;
        Ok(Self {
            fusion: pushmog::policy::LookFusion::new(position, yaw),
        })
    }

    /// The look `scene` with every object that stood still at the mean of its looks.
    fn fuse(&mut self, scene: &Scene) -> Scene {
        Scene {
            scene: self.fusion.fuse(scene.scene.clone()),
        }
    }

    /// Notes a push made (JSON of a trip's push).
    fn pushed(&mut self, push: &str) -> PyResult<()> {
        let push: Push = check(json::from_json(push, "push"))?;
        self.fusion.pushed(&push);
        Ok(())
    }

    /// Notes that a trip's jaws came down open (JSON of the trip): its riders' picks, then its
    /// grasp.
    fn trip_grasped(&mut self, trip: &str) -> PyResult<()> {
        let trip: TripPlan = check(json::from_json(trip, "trip"))?;
        self.fusion.trip_grasped(&trip);
        Ok(())
    }
}
