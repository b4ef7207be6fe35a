//! The motors file (`motors = "FILE.toml"`, docs/motors.md): `[[joint]]` entries read with the
//! `toml` crate. The file format stays at this edge: it reads into the [`MotorEntry`] list
//! that a Python dict of the same schema also gives (`super::motors` pairs them with joints).
//! The fields every entry has are here; each kind's own are its file's (`control/kinds/`).

use std::path::Path;

use serde::Deserialize;

use crate::error::{Error, Result};
use crate::input::{MAX_MOTORS_BYTES, into_text, read_capped};

/// One joint's motor as a motors file gives it (a `[[joint]]` entry; docs/motors.md).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
pub struct MotorEntry {
    /// The URDF joint it drives (none: entries pair with joints in order).
    pub name: Option<String>,
    /// A label for people (default: the kind).
    pub label: Option<String>,
    /// Motor turns per joint turn (> 0; none keeps the model's).
    pub gear_ratio: Option<f64>,
    /// The reducer's efficiency η (default 1).
    pub efficiency: Option<f64>,
    /// Rotor inertia at the motor shaft (kg·m², ≥ 0; none keeps the model's).
    pub rotor_inertia: Option<f64>,
    /// The continuous torque rating (N·m), for the heating check.
    pub continuous_torque: Option<f64>,
    /// `kind` and that kind's own fields, as given: the kind reads them with its own serde
    /// struct ([`crate::control::KINDS`]), so a new kind's fields are declared in its file.
    #[serde(flatten)]
    pub figures: serde_json::Map<String, serde_json::Value>,
}

/// The fields of [`MotorEntry`] every kind has (the others are `kind` and its kind's).
pub const COMMON_FIELDS: [&str; 6] = [
    "name",
    "label",
    "gear_ratio",
    "efficiency",
    "rotor_inertia",
    "continuous_torque",
];

/// A motors file: `[[joint]]` entries.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    joint: Vec<MotorEntry>,
}

/// The `[[joint]]` entries of the motors file at `path`, read whole: at most
/// [`MAX_MOTORS_BYTES`] (a stream too).
pub fn read(path: &Path) -> Result<Vec<MotorEntry>> {
    let text = read_capped(path, MAX_MOTORS_BYTES, "a motors file").and_then(|b| into_text(path, b));
    let text = text.map_err(|e| match e {
        Error::Io { source, .. } => at(path, source.to_string()),
        Error::InvalidData { message, .. } => at(path, message),
        other => at(path, other.to_string()),
    })?;
    parse_text(&text, path)
}

/// [`read`] on the file's text; `path` names it in the errors.
pub fn parse_text(text: &str, path: &Path) -> Result<Vec<MotorEntry>> {
    let file: File = toml::from_str(text).map_err(|e| at(path, crate::error::file_words(e.message())))?;
    for (k, entry) in file.joint.iter().enumerate() {
        if let Some(field) = entry.figures.iter().find(|(_, v)| holds_null(v)).map(|(f, _)| f) {
            let name = entry
                .name
                .as_deref()
                .map_or("by order".to_string(), crate::error::escape_controls);
            return Err(at(
                path,
                format!(
                    "J{} ({name}): {field} must be finite (nan and inf are not figures)",
                    k + 1
                ),
            ));
        }
    }
    Ok(file.joint)
}

/// Whether `value` holds a JSON null: in a TOML file's figures, a `nan` or `inf` (JSON has
/// neither, so the kind's figures, read as JSON values, hold them as null).
fn holds_null(value: &serde_json::Value) -> bool {
    match value {
        serde_json::Value::Null => true,
        serde_json::Value::Array(items) => items.iter().any(holds_null),
        serde_json::Value::Object(map) => map.values().any(holds_null),
        _ => false,
    }
}

/// An error of the motors file at `path`, naming the field.
fn at(path: &Path, message: String) -> Error {
    Error::option("motors", format!("{}: {message}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`COMMON_FIELDS`] are [`MotorEntry`]'s own fields: each is read into its field, none is
    /// left among the kind's figures.
    #[test]
    fn the_common_fields_are_the_entrys() {
        let text = "[[joint]]\nname = \"a\"\nlabel = \"b\"\ngear_ratio = 2.0\nefficiency = 0.5\nrotor_inertia = 1e-6\ncontinuous_torque = 0.1\nkind = \"dc\"\n";
        let entries = parse_text(text, Path::new("m.toml")).unwrap();
        assert_eq!(entries[0].figures.keys().collect::<Vec<_>>(), ["kind"]);
        let given = COMMON_FIELDS
            .iter()
            .filter(|f| text.contains(&format!("{f} = ")))
            .count();
        assert_eq!(given, COMMON_FIELDS.len());
    }

    /// A kind's figure of `nan` or `inf` is refused, naming it (JSON, which holds the kind's
    /// figures, has no such number: read as absent, `peak_torque = nan` took the stall torque).
    #[test]
    fn non_finite_figures_are_refused() {
        for (field, value) in [
            ("peak_torque", "nan"),
            ("stall_torque", "inf"),
            ("curve", "[[0.0, -inf]]"),
        ] {
            let text = format!("[[joint]]\nkind = \"dc\"\n{field} = {value}\n");
            let e = parse_text(&text, Path::new("m.toml")).unwrap_err().to_string();
            assert!(e.contains(&format!("J1 (by order): {field} must be finite")), "{e}");
        }
    }
}
