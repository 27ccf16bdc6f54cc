//! The grasp model's settings: which mechanics judge a closing and the physical constants it uses
//! (friction, grip force, density). The model itself lives in `grasp` (`grasp/model.rs`,
//! `grasp/closing/`, `formulations/grasping.md`); this is the part every stage must agree on.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Which mechanics judge a closing.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Mechanics {
    /// Objects slide along the closing axis without turning; each is held by Nguyen's two-contact
    /// condition on its own (the model of the first pushmog releases, kept as a baseline).
    Analytic,
    /// The closing simulated in the plane (`closing/`): objects slide and turn on the table while
    /// the coupled plates close on them; every caught object must end squeezed in the chain between
    /// the plates, and that chain must lift.
    #[default]
    Planar,
}

/// Settings of the grasp model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct GraspModel {
    /// Which mechanics judge the closing. Default `planar`.
    pub mechanics: Mechanics,
    /// Coulomb friction between a plate and an object. Default 0.4 (the plates' value in the public
    /// multi-object grasping simulation, `formulations/references.md`).
    pub friction_jaw: f64,
    /// Coulomb friction between two objects. Default 0.4: the paper wraps the objects' faces in
    /// frictional tape, so object–object contacts are taken as grippy as plate contacts.
    pub friction_object: f64,
    /// Grip force of the closed jaws, newtons. Default 20 (the Robotiq 2F-85's lowest setting).
    pub grip_force: f64,
    /// Coulomb friction between an object and the table (`planar` only). Default 0.3: plastic or wood
    /// on a laminate table (handbook values 0.2–0.4).
    pub friction_table: f64,
    /// Closing speed of the jaws, m/s (`planar` only). Default 0.05 (within the 2F-85's
    /// 0.02–0.15 m/s).
    pub jaw_speed: f64,
    /// Density used when an object has no mass, kg/m³. Default 1000 (solid plastic or dense wood).
    pub density: f64,
    /// Objects closer than this count as touching, metres. Default 1e-6.
    pub contact_tolerance: f64,
    /// `planar` only: when set, an object the closing ends up pressing counts as gripped only if its
    /// contact forces can balance within this share of each contact's friction coefficient (0 to 1;
    /// `equilibrium.rs`), so objects left at the edge of a friction cone are not trusted. Default
    /// unset (not checked). At 0.9 the pairs still accepted held more often in noisy simulator
    /// replays (94.6 % against 89.8 % for all), but simulated objects per trip fell
    /// (`formulations/grasping.md`, "Friction to spare").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_share: Option<f64>,
}

impl Default for GraspModel {
    fn default() -> Self {
        Self {
            mechanics: Mechanics::Planar,
            friction_jaw: 0.4,
            friction_object: 0.4,
            grip_force: 20.0,
            friction_table: 0.3,
            jaw_speed: 0.05,
            density: 1000.0,
            contact_tolerance: 1e-6,
            friction_share: None,
        }
    }
}

impl GraspModel {
    /// The analytic model with friction high enough never to let anything slip or drop: it then only
    /// asks whether the objects form one row between the jaws (the geometric "fits the jaws" test).
    pub fn unlimited_friction() -> Self {
        Self {
            mechanics: Mechanics::Analytic,
            friction_jaw: 1e9,
            friction_object: 1e9,
            ..Self::default()
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        // Friction may be set huge (the "fits the jaws" test sets it to 1e9), never negative.
        let checks: [(&str, f64, (f64, f64), &str); 7] = [
            (
                "friction_jaw",
                self.friction_jaw,
                (0.0, 1e9),
                "Coulomb friction",
            ),
            (
                "friction_object",
                self.friction_object,
                (0.0, 1e9),
                "Coulomb friction",
            ),
            (
                "friction_table",
                self.friction_table,
                (0.0, 2.0),
                "Coulomb friction of dry solids",
            ),
            ("grip_force", self.grip_force, (0.1, 1000.0), "N"),
            (
                "jaw_speed",
                self.jaw_speed,
                (0.005, 0.5),
                "m/s; the 2F-85 closes at 0.02–0.15 m/s, and the closing is simulated step by step",
            ),
            (
                "density",
                self.density,
                (100.0, 20_000.0),
                "kg/m³, from foam to tungsten",
            ),
            (
                "contact_tolerance",
                self.contact_tolerance,
                (0.0, 0.001),
                "m",
            ),
        ];
        for (field, value, range, why) in checks {
            crate::error::in_range("grasp_model", field, value, range, why)?;
        }
        if let Some(share) = self.friction_share
            && !(share.is_finite() && share > 0.0 && share <= 1.0)
        {
            return Err(Error::field(
                "grasp_model",
                "friction_share",
                format!(
                    "must be above 0 and at most 1 (a share of the friction coefficient), got {share}"
                ),
            ));
        }
        Ok(())
    }
}

impl GraspModel {
    /// The mass of an object: its own, or `density × area × height`.
    pub fn mass_of(&self, object: &crate::scene::Object) -> f64 {
        object
            .mass
            .unwrap_or(self.density * object.polygon.area() * object.height)
    }
}
