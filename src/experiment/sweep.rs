//! What an experiment sweeps over every run (`[sweep]`): bin distances, frictions and named
//! variants, the last laid over a configuration's own simulator and policy settings key by key
//! (`[[sweep.variants]]`, `experiments/README.md`).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::exec::SimSettings;
use crate::policy::PolicySettings;

/// Values swept over every run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    /// Distances to the bin, metres; empty keeps the policies' own.
    #[serde(default)]
    pub bin_distance: Vec<f64>,
    /// Coulomb friction at the simulator's finger pads and between objects (`friction_finger` and
    /// `friction_object` together); empty keeps the executor's settings. The planners' grasp models
    /// keep their own friction: this varies the world, not what the planner believes. When given,
    /// at least one value.
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "crate::json::non_empty_list"
    )]
    pub friction: Vec<f64>,
    /// Named variants of every run, each changing simulator and policy settings together; empty
    /// keeps them as they are.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub variants: Vec<Variant>,
}

impl SweepConfig {
    /// Bin distances that are lengths, frictions that are coefficients, a friction sweep and
    /// variants' simulator settings only in the simulator (`simulated`), and each variant labelled,
    /// no label twice; errors name `component`'s field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub(super) fn check(&self, simulated: bool, component: &str) -> Result<()> {
        let refuse =
            |field: &str, reason: String| Err(Error::field(component.to_string(), field, reason));
        if self
            .bin_distance
            .iter()
            .any(|d| !(d.is_finite() && *d >= 0.0))
        {
            return refuse("sweep.bin_distance", "must be non-negative metres".into());
        }
        if self.friction.iter().any(|f| !(f.is_finite() && *f >= 0.0)) {
            return refuse(
                "sweep.friction",
                "must be non-negative friction coefficients".into(),
            );
        }
        if !self.friction.is_empty() && !simulated {
            return refuse(
                "sweep.friction",
                "sweeps the simulator's friction: needs `executor.kind = \"sim\"`".into(),
            );
        }
        for (k, variant) in self.variants.iter().enumerate() {
            if variant.label.trim().is_empty() {
                return refuse(
                    "sweep.variants.label",
                    format!("variant {} needs a label", k + 1),
                );
            }
            if self.variants[..k].iter().any(|v| v.label == variant.label) {
                return refuse(
                    "sweep.variants.label",
                    format!("two variants are labelled `{}`", variant.label),
                );
            }
            if !variant.sim.is_empty() && !simulated {
                return refuse(
                    "sweep.variants.sim",
                    format!(
                        "variant `{}` changes the simulator's settings: needs `executor.kind = \"sim\"`",
                        variant.label
                    ),
                );
            }
        }
        Ok(())
    }

    /// The sweep's points in run order: bin distance, then friction, then variant (`None` where
    /// that value is not swept).
    pub(super) fn points(&self) -> Vec<(Option<f64>, Option<f64>, Option<usize>)> {
        let variants = each_or_none((0..self.variants.len()).collect());
        let mut points = Vec::new();
        for bin_distance in each_or_none(self.bin_distance.clone()) {
            for friction in each_or_none(self.friction.clone()) {
                points.extend(variants.iter().map(|&v| (bin_distance, friction, v)));
            }
        }
        points
    }
}

/// Each swept value, or a single `None` when nothing is swept.
fn each_or_none<T>(swept: Vec<T>) -> Vec<Option<T>> {
    if swept.is_empty() {
        vec![None]
    } else {
        swept.into_iter().map(Some).collect()
    }
}

/// One variant of every run: settings laid over the executor's simulator settings and over every
/// policy's settings (tables are merged key by key, so `{ riders = { checks = { acceleration =
/// 2.0 } } }` changes that one value). What a variant changes in the simulator is the world; what
/// it changes in the policies is what the planners believe and how the time model charges. A
/// swept friction or bin distance is applied after the variant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Variant {
    /// The variant's name in tables and logs.
    pub label: String,
    /// Simulator settings changed (any subset of the executor's `settings`).
    #[serde(default)]
    pub sim: serde_json::Map<String, serde_json::Value>,
    /// Policy settings changed in every policy (any subset).
    #[serde(default)]
    pub policies: serde_json::Map<String, serde_json::Value>,
}

impl Variant {
    /// `base` with this variant's simulator settings laid over it.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the variant when its settings do not fit the simulator's.
    pub fn sim_settings(&self, base: &SimSettings) -> Result<SimSettings> {
        with_overrides(base, &self.sim, &self.label, "sim")
    }

    /// `base` with this variant's policy settings laid over it.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the variant when its settings do not fit a policy's.
    pub fn policy_settings(&self, base: &PolicySettings) -> Result<PolicySettings> {
        with_overrides(base, &self.policies, &self.label, "policies")
    }
}

/// `settings` with `over` laid onto them and read back; errors name `field` of the variant `label`.
fn with_overrides<T>(
    settings: &T,
    over: &serde_json::Map<String, serde_json::Value>,
    label: &str,
    field: &str,
) -> Result<T>
where
    T: Clone + Serialize + serde::de::DeserializeOwned,
{
    if over.is_empty() {
        return Ok(settings.clone());
    }
    let refuse = |e: serde_json::Error| {
        Error::field(format!("sweep variant `{label}`"), field, e.to_string())
    };
    let mut value = serde_json::to_value(settings).map_err(refuse)?;
    crate::json::lay_over(&mut value, over);
    serde_json::from_value(value).map_err(refuse)
}
