//! The DC motor (or servo) kind: a voltage-limited motor's four-quadrant envelope
//! (IsaacLab's `DCMotor`), `τ_m ∈ [τ_s(−1 − ω_m/ω₀), τ_s(1 − ω_m/ω₀)] ∩ [−τ_peak, τ_peak]`,
//! and its `[[joint]]` fields (docs/motors.md).

use serde::Deserialize;

use super::{Envelope, Kind, KindMotor, fields_of, read_as};

/// The kind's registration ([`super::KINDS`]).
pub(super) const KIND: Kind = Kind {
    name: "dc",
    fields: fields_of::<File>,
    read,
    types: |value| read_as::<File>(value).map(drop),
    has_no,
};

/// A `kind = "dc"` entry's own fields.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    /// Stall torque (N·m).
    stall_torque: Option<f64>,
    /// No-load speed (rad/s).
    no_load_speed: Option<f64>,
    /// Peak torque (N·m; default the stall torque).
    peak_torque: Option<f64>,
}

/// The entry's fields as an envelope (no stepping: a DC motor has no open-loop drive).
fn read(value: serde_json::Value) -> Result<KindMotor, String> {
    let file: File = read_as(value)?;
    let need = |field: Option<f64>, name: &str| field.ok_or_else(|| format!("kind \"dc\" needs {name}"));
    let stall_torque = need(file.stall_torque, "stall_torque")?;
    let envelope = Envelope::Dc {
        stall_torque,
        no_load_speed: need(file.no_load_speed, "no_load_speed")?,
        peak_torque: file.peak_torque.unwrap_or(stall_torque),
    };
    Ok((envelope, None))
}

/// The words for another kind's `field` on a DC motor.
fn has_no(field: &str) -> String {
    if field == "curve" {
        "a dc motor has no curve (that is a stepper's)".into()
    } else {
        "a dc motor has no step_angle, detent_torque, microsteps, driver_bandwidth, rotor_damping or reducer_damping/friction (those are a stepper's open-loop drive's)".into()
    }
}

/// The torque range at shaft speed `omega`.
#[inline]
pub(super) fn bounds(stall_torque: f64, no_load_speed: f64, peak_torque: f64, omega: f64) -> (f64, f64) {
    let back = omega / no_load_speed;
    let lo = (stall_torque * (-1.0 - back)).clamp(-peak_torque, peak_torque);
    let hi = (stall_torque * (1.0 - back)).clamp(-peak_torque, peak_torque);
    (lo, hi)
}

/// Where the lines meet ±τ_peak, `ω₀(±1 ∓ τ_peak/τ_s)` (unsorted).
pub(super) fn kinks(stall_torque: f64, no_load_speed: f64, peak_torque: f64) -> Vec<f64> {
    let p = peak_torque / stall_torque;
    [1.0 - p, 1.0 + p, -1.0 - p, -1.0 + p]
        .map(|k| k * no_load_speed)
        .to_vec()
}

/// Stall torque, no-load speed and peak finite and > 0.
pub(super) fn check(stall_torque: f64, no_load_speed: f64, peak_torque: f64) -> Result<(), String> {
    for (name, x) in [
        ("stall_torque", stall_torque),
        ("no_load_speed", no_load_speed),
        ("peak_torque", peak_torque),
    ] {
        if !(x.is_finite() && x > 0.0) {
            return Err(format!("{name} {x} must be > 0"));
        }
    }
    Ok(())
}
