//! Named presets beyond the six policies: one of them with settings of its own laid over the
//! defaults, so that a configuration measured in `experiments/` can be asked for by name from the
//! command line (`pushmog run --policy push-mog-time-riders`), Python (`Planner("…")`) and
//! experiment files (`name = "…"`).
//!
//! - `push-mog-time`: `push-mog-opt` with `experiments/push-mog-time.json`: the expected-time
//!   objective, rows pushed ahead, flush pushes, the edge and friction margins, pairs up to 15 cm
//!   and fused looks (`formulations/picks-per-hour.md`).
//! - `push-mog-time-riders`: the same with riders (`formulations/stacking.md`).
//! - `push-mog-opt-riders`: `push-mog-opt` with riders and nothing else changed.
//!
//! Settings given with a preset are laid over its own key by key (tables merged, anything else
//! replaced). A plan or log records the policy it ran (`push-mog-opt`) and every setting, so a run
//! of a preset reads back as the same policy with those settings written out.

use super::{PolicyKind, PolicySettings};
use crate::error::{Error, Result};

/// The settings file that `push-mog-time` names, kept in `experiments/` beside the configurations
/// that measured it, embedded here so that the library needs no file at run time.
const PUSH_MOG_TIME: &str = include_str!("../../experiments/push-mog-time.json");

/// Riders on (`riders.enabled`), the checks at their defaults.
const RIDERS: &str = r#"{ "riders": { "enabled": true } }"#;

/// A named preset: a policy and the settings laid over its defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Preset {
    /// The name it is asked for by.
    pub name: &'static str,
    /// The policy it runs.
    pub kind: PolicyKind,
    /// What it is, in a line.
    pub about: &'static str,
    /// JSON documents of policy settings, laid over the defaults in order.
    layers: &'static [&'static str],
}

/// Every preset, in table order.
pub const PRESETS: [Preset; 3] = [
    Preset {
        name: "push-mog-time",
        kind: PolicyKind::PushMogOpt,
        about: "push-mog-opt priced in robot time: expected-time objective, rows pushed ahead, \
                flush pushes, edge and friction margins, fused looks",
        layers: &[PUSH_MOG_TIME],
    },
    Preset {
        name: "push-mog-time-riders",
        kind: PolicyKind::PushMogOpt,
        about: "push-mog-time with riders put down on pushed rows",
        layers: &[PUSH_MOG_TIME, RIDERS],
    },
    Preset {
        name: "push-mog-opt-riders",
        kind: PolicyKind::PushMogOpt,
        about: "push-mog-opt with riders put down on pushed rows",
        layers: &[RIDERS],
    },
];

impl Preset {
    /// The preset called `name`, if there is one.
    pub fn named(name: &str) -> Option<&'static Preset> {
        PRESETS.iter().find(|p| p.name == name)
    }

    /// Its settings as a JSON document (only what it sets, not the defaults).
    ///
    /// # Errors
    /// [`Error::InvalidField`] if an embedded document does not parse (a build error, tested).
    pub fn settings_json(&self) -> Result<serde_json::Value> {
        let mut settings = serde_json::Value::Object(serde_json::Map::new());
        for layer in self.layers {
            let value: serde_json::Value = crate::json::from_json(layer, self.name)?;
            let serde_json::Value::Object(over) = value else {
                return Err(Error::field(self.name, "settings", "not a table"));
            };
            crate::json::lay_over(&mut settings, &over);
        }
        Ok(settings)
    }

    /// Its settings with `over` (a table of policy settings, if any) laid over them, as policy
    /// settings; `source` names `over` in errors.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field of `over` that does not fit.
    pub fn settings(
        &self,
        over: Option<&serde_json::Map<String, serde_json::Value>>,
        source: &str,
    ) -> Result<PolicySettings> {
        let mut settings = self.settings_json()?;
        if let Some(over) = over {
            crate::json::lay_over(&mut settings, over);
        }
        crate::json::from_json(&settings.to_string(), source)
    }
}

/// The names every policy entry point takes: the six policies, then the presets.
pub fn policy_names() -> Vec<&'static str> {
    PolicyKind::ALL
        .iter()
        .map(|k| k.name())
        .chain(PRESETS.iter().map(|p| p.name))
        .collect()
}

/// The policy called `name` (one of the six, or a preset) and its settings: `over` (a JSON document
/// of policy settings, if any; `source` names it in errors) laid over the preset's, or read as the
/// policy's when `name` is one of the six.
///
/// # Errors
/// [`Error::InvalidField`] for an unknown name (listing the names) or settings that do not fit.
pub fn resolve(
    name: &str,
    over: Option<&str>,
    source: &str,
) -> Result<(PolicyKind, PolicySettings)> {
    if let Some(preset) = Preset::named(name) {
        let over = match over {
            Some(text) => {
                // Read as settings first, so that a wrong key is refused naming its path.
                crate::json::from_json::<PolicySettings>(text, source)?;
                match crate::json::from_json::<serde_json::Value>(text, source)? {
                    serde_json::Value::Object(map) => Some(map),
                    _ => return Err(Error::field(source, "settings", "must be a table")),
                }
            }
            None => None,
        };
        return Ok((preset.kind, preset.settings(over.as_ref(), source)?));
    }
    let kind: PolicyKind = name.parse().map_err(|_| {
        Error::field(
            "policy",
            "name",
            format!(
                "unknown policy `{name}`; choose one of {}",
                policy_names().join(", ")
            ),
        )
    })?;
    let settings = match over {
        Some(text) => crate::json::from_json::<PolicySettings>(text, source)?,
        None => PolicySettings::default(),
    };
    Ok((kind, settings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_reads_and_validates() {
        for preset in PRESETS {
            let settings = preset
                .settings(None, preset.name)
                .unwrap_or_else(|e| panic!("{}: {e}", preset.name));
            settings
                .validate()
                .unwrap_or_else(|e| panic!("{}: {e}", preset.name));
            assert!(PolicyKind::ALL.iter().all(|k| k.name() != preset.name));
        }
    }

    #[test]
    fn the_riders_presets_are_their_policies_with_riders_on_and_nothing_else() {
        let time = Preset::named("push-mog-time").map(|p| p.settings(None, "t"));
        let time = time.unwrap_or_else(|| panic!("push-mog-time")).unwrap();
        let riders = resolve("push-mog-time-riders", None, "r").unwrap().1;
        assert!(!time.riders.enabled && riders.riders.enabled);
        let mut same = riders.clone();
        same.riders.enabled = false;
        assert_eq!(same, time);
        let (kind, opt) = resolve("push-mog-opt-riders", None, "o").unwrap();
        assert_eq!(kind, PolicyKind::PushMogOpt);
        let mut defaults = PolicySettings::default();
        defaults.riders.enabled = true;
        assert_eq!(opt, defaults);
    }

    #[test]
    fn settings_given_are_laid_over_the_presets() {
        let over = r#"{ "run": { "reach_past_edge": 0.05 } }"#;
        let (_, settings) = resolve("push-mog-time-riders", Some(over), "over.json").unwrap();
        assert_eq!(settings.run.reach_past_edge, 0.05);
        // What the preset sets in the same table stays.
        assert!(settings.run.fuse_looks && settings.riders.enabled);
        let wrong = resolve(
            "push-mog-time",
            Some(r#"{ "run": { "fuse": true } }"#),
            "w.json",
        );
        let message = wrong.unwrap_err().to_string();
        assert!(
            message.contains("w.json") && message.contains("fuse"),
            "{message}"
        );
        let unknown = resolve("push-mog-fast", None, "-").unwrap_err().to_string();
        assert!(unknown.contains("push-mog-time-riders"), "{unknown}");
    }
}
