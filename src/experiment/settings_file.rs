//! Policy settings kept in a file of their own and named by a configuration's policy entry
//! (`settings_file = "push-mog-time.json"`), so that several experiments share one copy of them.
//!
//! The file is JSON, the format of `pushmog run --settings`, and its path is relative to the
//! configuration's folder. It is resolved when the configuration is read: the file's settings are
//! the base and the entry's own `settings` are laid over them key by key (tables merged, anything
//! else replaced), as a sweep variant's are. The entry then holds the merged settings and no file
//! name, so its log header and its `config_hash` are those of the same configuration with the
//! settings written out inline: a log made either way resumes from the other.

use std::path::Path;

use crate::error::{Error, Result};
use crate::policy::PolicySettings;

/// The key of a policy entry that names a settings file.
pub(super) const KEY: &str = "settings_file";

/// Whether any policy entry of the parsed document names a settings file.
pub(super) fn any(document: &toml::Table) -> bool {
    policy_entries(document).any(|entry| entry.contains_key(KEY))
}

/// The policy entries of a parsed configuration that are tables.
pub(super) fn policy_entries(document: &toml::Table) -> impl Iterator<Item = &toml::Table> {
    document
        .get("policies")
        .and_then(toml::Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(toml::Value::as_table)
}

/// The policy entries of a parsed configuration that are tables, each with its position.
pub(super) fn policy_entries_mut(
    document: &mut toml::Table,
) -> impl Iterator<Item = (usize, &mut toml::Table)> {
    document
        .get_mut("policies")
        .and_then(toml::Value::as_array_mut)
        .into_iter()
        .flatten()
        .enumerate()
        .filter_map(|(index, entry)| entry.as_table_mut().map(|entry| (index, entry)))
}

/// Refuses a configuration whose policies (their `settings_file`s, in order) still name a settings
/// file: one built without reading it through [`resolve`] (`ExperimentConfig::read` or
/// `from_toml`), whose `settings` would lack the file's.
///
/// # Errors
/// [`Error::InvalidField`] naming the first such policy.
pub(super) fn refuse_unread<'a>(
    files: impl IntoIterator<Item = Option<&'a str>>,
    component: &str,
) -> Result<()> {
    match files.into_iter().position(|file| file.is_some()) {
        None => Ok(()),
        Some(index) => Err(Error::field(
            component,
            "policies.settings_file",
            format!(
                "policy {} names a settings file that was not read: configurations are read \
                 with `ExperimentConfig::read` or `from_toml`, which merge it into `settings`",
                index + 1
            ),
        )),
    }
}

/// Replaces every `settings_file` of `document`'s policies by the file's settings with the entry's
/// own laid over them; `base` is the configuration's folder, `name` names it in errors.
///
/// # Errors
/// [`Error::InvalidField`] naming the entry when its file cannot be read, its `settings_file` is
/// not a string or its `settings` not a table, and naming the file when it is not JSON policy
/// settings.
pub(super) fn resolve(document: &mut toml::Table, base: &Path, name: &str) -> Result<()> {
    for (index, entry) in policy_entries_mut(document) {
        let Some(file) = entry.remove(KEY) else {
            continue;
        };
        let component = format!("{name}, policy {}", index + 1);
        let file = file.as_str().ok_or_else(|| {
            Error::field(
                &component,
                KEY,
                "must be the path of a JSON file of policy settings, relative to the configuration",
            )
        })?;
        let path = base.join(file);
        let source = path.display().to_string();
        let text = crate::json::read_text(&path).map_err(|e| {
            Error::field(
                &component,
                KEY,
                format!("{e} (paths are relative to the configuration)"),
            )
        })?;
        // Read as settings first, so that a wrong key is refused naming the file it is in.
        crate::json::from_json::<PolicySettings>(&text, &source)?;
        let mut settings: serde_json::Value = crate::json::from_json(&text, &source)?;
        if let Some(own) = entry.remove("settings") {
            let refuse = |why: String| Error::field(&component, "settings", why);
            let own = serde_json::to_value(own).map_err(|e| refuse(e.to_string()))?;
            let serde_json::Value::Object(own) = own else {
                return Err(refuse("must be a table of policy settings".to_string()));
            };
            crate::json::lay_over(&mut settings, &own);
        }
        let settings = toml::Value::try_from(&settings)
            .map_err(|e| Error::field(&source, "settings", e.to_string()))?;
        entry.insert("settings".to_string(), settings);
    }
    Ok(())
}
