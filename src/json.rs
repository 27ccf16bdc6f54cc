//! Reading and writing JSON documents (scenes, object sets, settings) with errors that say where.
//!
//! Parse errors give the line, the column and the path of the offending field
//! (`objects[3].vertices[1]`), found with `serde_path_to_error`; a scene that parses is then validated
//! by [`Scene::new`], whose errors name the object and the field.
//!
//! Documents are written by [`to_json`]: indented objects, with arrays of numbers (coordinates, vertex
//! lists) kept on one line so a scene stays readable.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;

use crate::error::{Error, Result};
use crate::scene::{Scene, SceneSpec};

/// Parses `text`, a JSON object, as a `T`; `source_name` (a path or `<stdin>`) goes into error
/// messages. A leading UTF-8 byte-order mark is skipped.
///
/// # Errors
/// [`Error::Json`] with line, column and field path.
pub fn from_json<T: DeserializeOwned>(text: &str, source_name: &str) -> Result<T> {
    // Editors on some systems start UTF-8 files with a byte-order mark; it carries nothing.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // Every document pushmog reads is an object; serde would also take a struct from an array of
    // its fields in order, so `[]` would silently mean "all defaults".
    if let Some(first) = text.trim_start().chars().next()
        && first != '{'
    {
        let before = &text[..text.len() - text.trim_start().len()];
        return Err(Error::Json {
            source_name: source_name.to_string(),
            line: before.matches('\n').count() + 1,
            column: before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1,
            path: String::new(),
            message: format!("expected a JSON object `{{…}}`, found `{first}`"),
        });
    }
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let to_error = |path: String, inner: serde_json::Error| Error::Json {
        source_name: source_name.to_string(),
        line: inner.line(),
        column: inner.column(),
        path,
        message: strip_position(&inner.to_string()),
    };
    let value: T = serde_path_to_error::deserialize(&mut deserializer)
        .map_err(|e| to_error(known_path(&e.path().to_string()), e.into_inner()))?;
    deserializer.end().map_err(|e| to_error(String::new(), e))?;
    Ok(value)
}

/// The path without the `?` segments serde_path_to_error writes where the parser lost track of the
/// field (after a syntax error).
fn known_path(path: &str) -> String {
    path.split('.')
        .filter(|segment| *segment != "?")
        .collect::<Vec<_>>()
        .join(".")
}

/// serde_json appends " at line L column C" to its messages; the error type reports those itself.
fn strip_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(cut) => message[..cut].to_string(),
        None => message.to_string(),
    }
}

/// Parses and validates a scene.
///
/// # Errors
/// [`Error::Json`] for malformed JSON or a field of the wrong type; the validation errors of
/// [`Scene::new`] otherwise.
pub fn scene_from_json(text: &str, source_name: &str) -> Result<Scene> {
    let spec: SceneSpec = from_json(text, source_name)?;
    Scene::new(spec)
}

/// Reads a whole file as text.
///
/// # Errors
/// [`Error::Io`] naming the path.
pub fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    text_from_bytes(bytes, &path.display().to_string())
}

/// Decodes UTF-8 text; `source_name` says where it came from in error messages.
///
/// # Errors
/// [`Error::InvalidField`] giving the line, column and byte offset of the first byte that is not
/// UTF-8.
pub fn text_from_bytes(bytes: Vec<u8>, source_name: &str) -> Result<String> {
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let before = &e.as_bytes()[..offset];
        let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
        // Columns count characters, as editors do; the prefix is valid UTF-8.
        let column = String::from_utf8_lossy(&before[line_start..])
            .chars()
            .count()
            + 1;
        Error::field(
            source_name,
            "encoding",
            format!(
                "not UTF-8 text: byte 0x{:02x} at line {line}, column {column} (byte offset \
                 {offset})",
                e.as_bytes()[offset]
            ),
        )
    })
}

/// Reads, parses and validates a scene file.
///
/// # Errors
/// As [`read_text`] and [`scene_from_json`].
pub fn read_scene(path: &Path) -> Result<Scene> {
    scene_from_json(&read_text(path)?, &path.display().to_string())
}

/// `over` laid onto `base`: tables merged key by key, anything else replaced.
pub fn lay_over(base: &mut serde_json::Value, over: &serde_json::Map<String, serde_json::Value>) {
    let serde_json::Value::Object(base) = base else {
        *base = serde_json::Value::Object(over.clone());
        return;
    };
    for (key, value) in over {
        match (base.get_mut(key), value) {
            (Some(slot @ serde_json::Value::Object(_)), serde_json::Value::Object(inner)) => {
                lay_over(slot, inner);
            }
            _ => {
                base.insert(key.clone(), value.clone());
            }
        }
    }
}

/// Writes `text` to `path`, creating parent folders.
///
/// # Errors
/// [`Error::Io`] naming the path.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    if let Some(parent) = path.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent).map_err(io)?;
    }
    std::fs::write(path, text).map_err(io)
}

/// Serialises `value` as indented JSON with numeric arrays on one line, ending in a newline.
///
/// Numbers are written in the shortest form that reads back to the same `f64`, so a document
/// round-trips exactly.
pub fn to_json<T: Serialize>(value: &T) -> String {
    // Serialising the crate's own types to a Value cannot fail: every map key is a string and every
    // float is finite in a validated value. A non-finite float becomes `null`.
    let value = serde_json::to_value(value).unwrap_or(Value::Null);
    let mut out = String::new();
    write_value(&mut out, &value, 0);
    out.push('\n');
    out
}

/// As [`to_json`], for a document with one long list: `head` is the document with the list at `key`
/// left empty, and `items` are its elements, each serialised and written in turn, so that the list
/// is never held whole as a JSON tree. The text is the one [`to_json`] writes for the whole
/// document, provided each item serialises to a JSON object (a list of objects is written one item
/// per line).
pub fn to_json_listing<T: Serialize, I: Serialize>(
    head: &T,
    key: &str,
    items: impl ExactSizeIterator<Item = I>,
) -> String {
    let value = serde_json::to_value(head).unwrap_or(Value::Null);
    let Value::Object(map) = &value else {
        return to_json(head);
    };
    let pad = |n: usize| "  ".repeat(n);
    let count = items.len();
    let mut items = Some(items);
    let mut out = String::from("{\n");
    for (k, (name, item)) in map.iter().enumerate() {
        let _ = write!(out, "{}{}: ", pad(1), Value::String(name.clone()));
        if let Some(items) = items.take_if(|_| name == key && count > 0) {
            out.push_str("[\n");
            for (n, element) in items.enumerate() {
                let element = serde_json::to_value(element).unwrap_or(Value::Null);
                out.push_str(&pad(2));
                write_value(&mut out, &element, 2);
                out.push_str(if n + 1 < count { ",\n" } else { "\n" });
            }
            let _ = write!(out, "{}]", pad(1));
        } else {
            write_value(&mut out, item, 1);
        }
        out.push_str(if k + 1 < map.len() { ",\n" } else { "\n" });
    }
    out.push_str("}\n");
    out
}

/// Whether a value is written on one line: arrays of scalars or of scalar arrays, and small objects of
/// scalars (a pose, a gripper).
fn is_flat(value: &Value) -> bool {
    let scalar = |v: &Value| !v.is_array() && !v.is_object();
    match value {
        Value::Object(map) => map.len() <= 4 && map.values().all(scalar),
        Value::Array(items) => items.iter().all(|item| match item {
            Value::Array(inner) => inner.iter().all(scalar),
            Value::Object(_) => false,
            _ => true,
        }),
        _ => true,
    }
}

fn write_value(out: &mut String, value: &Value, indent: usize) {
    let pad = |n: usize| "  ".repeat(n);
    match value {
        Value::Object(map) if map.is_empty() => out.push_str("{}"),
        Value::Object(map) if is_flat(value) => {
            out.push('{');
            for (k, (key, item)) in map.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                let _ = write!(out, "{}: {item}", Value::String(key.clone()));
            }
            out.push('}');
        }
        Value::Object(map) => {
            out.push_str("{\n");
            for (k, (key, item)) in map.iter().enumerate() {
                let _ = write!(out, "{}{}: ", pad(indent + 1), Value::String(key.clone()));
                write_value(out, item, indent + 1);
                out.push_str(if k + 1 < map.len() { ",\n" } else { "\n" });
            }
            let _ = write!(out, "{}}}", pad(indent));
        }
        Value::Array(items) if items.is_empty() => out.push_str("[]"),
        Value::Array(items) if is_flat(value) => {
            out.push('[');
            for (k, item) in items.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                write_value(out, item, indent);
            }
            out.push(']');
        }
        Value::Array(items) => {
            out.push_str("[\n");
            for (k, item) in items.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                write_value(out, item, indent + 1);
                out.push_str(if k + 1 < items.len() { ",\n" } else { "\n" });
            }
            let _ = write!(out, "{}]", pad(indent));
        }
        scalar => {
            let _ = write!(out, "{scalar}");
        }
    }
}

/// The JSON Schema of the scene format.
pub fn scene_schema() -> Value {
    serde_json::to_value(schemars::schema_for!(SceneSpec)).unwrap_or(Value::Null)
}

/// The JSON Schema of the object-set format.
pub fn object_set_schema() -> Value {
    serde_json::to_value(schemars::schema_for!(crate::scene::ObjectSet)).unwrap_or(Value::Null)
}

/// Reads a fixed-length array of numbers, refusing extra or missing elements whatever the format
/// (TOML readers otherwise drop extras silently). Use as `#[serde(deserialize_with =
/// "crate::json::exact_array")]`.
///
/// # Errors
/// The format's error, naming the expected and given lengths.
pub fn exact_array<'de, D, const N: usize>(
    deserializer: D,
) -> std::result::Result<[f64; N], D::Error>
where
    D: serde::Deserializer<'de>,
{
    let values = <Vec<f64> as serde::Deserialize>::deserialize(deserializer)?;
    let given = values.len();
    values.try_into().map_err(|_| {
        serde::de::Error::invalid_length(given, &format!("exactly {N} numbers").as_str())
    })
}

/// A list that, when given, holds at least one number: an empty list given on purpose is a mistake
/// (leaving the key out is how not to sweep). Use with `#[serde(default)]`.
///
/// # Errors
/// A deserialisation error for an empty list.
pub fn non_empty_list<'de, D>(deserializer: D) -> std::result::Result<Vec<f64>, D::Error>
where
    D: serde::Deserializer<'de>,
{
    let values = <Vec<f64> as serde::Deserialize>::deserialize(deserializer)?;
    if values.is_empty() {
        return Err(serde::de::Error::invalid_length(
            0,
            &"at least one value (leave the key out to keep the executor's own)",
        ));
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 38, defect 7: `[]` is not "all defaults", and a byte-order mark is not an error.
    #[test]
    fn documents_must_be_objects_and_may_start_with_a_byte_order_mark() {
        #[derive(serde::Deserialize, Default, Debug)]
        #[serde(default)]
        struct Settings {
            min_push: f64,
        }
        let error = from_json::<Settings>(" \n []", "s.json")
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("line 2") && error.contains("expected a JSON object"),
            "{error}"
        );
        let read: Settings = from_json("\u{feff}{\"min_push\": 0.004}", "s.json").unwrap();
        assert_eq!(read.min_push, 0.004);
    }

    #[test]
    fn errors_give_line_column_and_path() {
        let text = "{\n  \"workspace\": {\"min\": [0, 0], \"max\": [1, 1]},\n  \"objects\": [\n    {\"id\": 0, \"vertices\": [[0, 0], [1, \"x\"]], \"height\": 0.03, \"pose\": {\"x\": 0, \"y\": 0, \"yaw\": 0}}\n  ]\n}\n";
        let err = scene_from_json(text, "t.json").unwrap_err();
        let message = err.to_string();
        assert!(message.contains("line 4"), "{message}");
        assert!(message.contains("objects[0].vertices[1]"), "{message}");
    }

    #[test]
    fn numeric_arrays_stay_on_one_line() {
        let value = serde_json::json!({"a": [[1.5, 2.0], [3.0, 4.0]], "b": {"c": [1, 2]}});
        let text = to_json(&value);
        assert!(text.contains("\"a\": [[1.5, 2.0], [3.0, 4.0]]"), "{text}");
        assert_eq!(serde_json::from_str::<Value>(&text).unwrap(), value);
    }
}
