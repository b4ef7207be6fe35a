//! The motors file (`motors = "FILE.toml"`, docs/motors.md): `[[joint]]` entries read with the
//! `toml` crate. The file format stays at this edge: it reads into the [`MotorEntry`] list
//! that a Python dict of the same schema also gives (`super::motors` pairs them with joints).

use std::path::Path;

use serde::Deserialize;

use crate::error::{Error, Result};
use crate::input::{MAX_MOTORS_BYTES, into_text, read_capped};

/// One joint's motor as a motors file gives it (a `[[joint]]` entry; docs/motors.md).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
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
    /// `dc` or `stepper`.
    pub kind: String,
    /// A DC motor's stall torque (N·m).
    pub stall_torque: Option<f64>,
    /// A DC motor's no-load speed (rad/s).
    pub no_load_speed: Option<f64>,
    /// A DC motor's peak torque (N·m; default the stall torque).
    pub peak_torque: Option<f64>,
    /// A stepper's pull-out curve: points `[speed rad/s, torque N·m]`, read as lists so that a
    /// point of another length is refused (an array `[f64; 2]` took the first two values of
    /// `[0.0, 0.3, 7]` and dropped the third).
    pub curve: Option<Vec<Vec<f64>>>,
    /// A stepper's full step (degrees, in (0, 90]), for the open-loop drive.
    pub step_angle: Option<f64>,
    /// A stepper's unpowered detent torque (N·m, ≥ 0; default 0).
    pub detent_torque: Option<f64>,
    /// A stepper driver's microsteps per full step (≥ 1; default the drive's).
    pub microsteps: Option<u32>,
    /// A stepper driver's current-loop bandwidth (Hz, > 0; default none: no electrical damping,
    /// which needs the winding a file does not give).
    pub driver_bandwidth: Option<f64>,
    /// A stepper rotor's viscous damping, iron losses and bearings (N·m·s/rad at the shaft,
    /// ≥ 0; default 0).
    pub rotor_damping: Option<f64>,
    /// The reducer's viscous friction (N·m·s/rad at the motor shaft, ≥ 0; default 0), for the
    /// open-loop stepper drive.
    pub reducer_damping: Option<f64>,
    /// The reducer's Coulomb friction (N·m at the motor shaft, ≥ 0; default 0), for the
    /// open-loop stepper drive.
    pub reducer_friction: Option<f64>,
    /// The continuous torque rating (N·m), for the heating check.
    pub continuous_torque: Option<f64>,
}

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
    Ok(file.joint)
}

/// An error of the motors file at `path`, naming the field.
fn at(path: &Path, message: String) -> Error {
    Error::option("motors", format!("{}: {message}", path.display()))
}
