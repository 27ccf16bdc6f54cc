//! Named presets in a configuration's policy entries (`name = "push-mog-time-riders"`,
//! [`crate::policy::preset`]). They are resolved when the configuration is read, after any
//! `settings_file` (`settings_file.rs`): the entry's `name` becomes the preset's policy, its
//! `settings` are the preset's with the entry's own (its file's, then its table's) laid over them
//! key by key, and its `label` is the preset's name unless it gives one. So a log made with a
//! preset name has the header, and the `config_hash`, of the same configuration written out in
//! full, and each resumes the other.

use super::settings_file::{policy_entries, policy_entries_mut};
use crate::error::{Error, Result};
use crate::policy::preset::Preset;

/// Whether any policy entry of the parsed document names a preset.
pub(super) fn any(document: &toml::Table) -> bool {
    policy_entries(document).any(|entry| preset_of(entry).is_some())
}

fn preset_of(entry: &toml::Table) -> Option<&'static Preset> {
    entry
        .get("name")
        .and_then(toml::Value::as_str)
        .and_then(Preset::named)
}

/// Replaces each preset name of `document`'s policy entries by its policy and settings (module
/// docs); `name` names the configuration in errors.
///
/// # Errors
/// [`Error::InvalidField`] naming the entry when its `settings` are not a table or do not fit.
pub(super) fn resolve(document: &mut toml::Table, name: &str) -> Result<()> {
    for (index, entry) in policy_entries_mut(document) {
        let Some(preset) = preset_of(entry) else {
            continue;
        };
        let component = format!("{name}, policy {}", index + 1);
        let refuse = |why: String| Error::field(&component, "settings", why);
        let mut settings = preset.settings_json()?;
        if let Some(own) = entry.remove("settings") {
            let own = serde_json::to_value(own).map_err(|e| refuse(e.to_string()))?;
            let serde_json::Value::Object(own) = own else {
                return Err(refuse("must be a table of policy settings".to_string()));
            };
            crate::json::lay_over(&mut settings, &own);
        }
        let settings = toml::Value::try_from(&settings).map_err(|e| refuse(e.to_string()))?;
        entry.insert("settings".to_string(), settings);
        entry.insert("name".to_string(), preset.kind.name().into());
        if !entry.contains_key("label") {
            entry.insert("label".to_string(), preset.name.into());
        }
    }
    Ok(())
}
