//! The motors file (`motors = "FILE.toml"`, docs/motors.md): `[[joint]]` entries read with the
//! `toml` crate. The file format stays at this edge: it reads into the [`MotorEntry`] list
//! that a Python dict of the same schema also gives (`super::motors` pairs them with joints).

use std::path::Path;

use serde::Deserialize;

use crate::error::{Error, Result, one_line};

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
    /// A stepper's pull-out curve: (speed rad/s, torque N·m) points.
    pub curve: Option<Vec<[f64; 2]>>,
    /// A stepper's full step (degrees, in (0, 90]), for the open-loop drive.
    pub step_angle: Option<f64>,
    /// A stepper's unpowered detent torque (N·m, ≥ 0; default 0).
    pub detent_torque: Option<f64>,
    /// A stepper driver's microsteps per full step (≥ 1; default the drive's).
    pub microsteps: Option<u32>,
    /// The continuous torque rating (N·m), for the heating check.
    pub continuous_torque: Option<f64>,
}

/// A motors file: `[[joint]]` entries.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    joint: Vec<MotorEntry>,
}

/// The `[[joint]]` entries of the motors file at `path`.
pub fn read(path: &Path) -> Result<Vec<MotorEntry>> {
    let at = |message: String| Error::option("motors", format!("{}: {message}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| at(e.to_string()))?;
    let file: File = toml::from_str(&text).map_err(|e| at(one_line(e.message())))?;
    Ok(file.joint)
}
