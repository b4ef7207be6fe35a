//! `--motors PRESET|FILE.toml` → a motor per joint ([`JointMotor`]): the presets by name, or a
//! TOML file read with the `toml` crate (the file format stays at this edge; the library takes
//! the parsed motors). docs/motors.md describes the file.

use std::path::Path;

use serde::Deserialize;

use super::args::RunArgs;
use crate::control::catalog::{sts3215, xm540_w270};
use crate::control::{Envelope, JointMotor, Motor};
use crate::error::{Error, Result, one_line};
use crate::faze4::motors::{faze4, faze4_bom};
use crate::input::{MAX_MOTORS_BYTES, into_text, read_capped};
use crate::model::Model;

/// The presets `--motors` knows, by name.
pub const PRESETS: [&str; 4] = ["faze4", "faze4-bom", "sts3215", "xm540-w270"];

/// The motors `run` asks for on `model` (`None`: no `--motors`).
pub fn motors(run: &RunArgs, model: &Model) -> Result<Option<Vec<Option<JointMotor>>>> {
    let Some(name) = run.motors.as_deref() else {
        if run.supply_voltage.is_some() {
            return Err(Error::argument("--supply-voltage", "is for --motors' presets"));
        }
        return Ok(None);
    };
    if let Some(v) = run.supply_voltage
        && !(v.is_finite() && v > 0.0)
    {
        return Err(Error::argument("--supply-voltage", format!("{v} must be > 0")));
    }
    let n = model.dof();
    let six = |set: Vec<Option<JointMotor>>| {
        if n == set.len() {
            Ok(set)
        } else {
            Err(Error::argument(
                "--motors",
                format!("{name}'s motors are for a 6-joint arm; {} has {n} joints", model.source),
            ))
        }
    };
    let every = |m: JointMotor| vec![Some(m); n];
    let set = match name {
        "faze4" => six(faze4(run.supply_voltage))?,
        "faze4-bom" => six(faze4_bom(run.supply_voltage))?,
        "sts3215" => every(sts3215(run.supply_voltage)),
        "xm540-w270" => every(xm540_w270(run.supply_voltage)),
        file if file.ends_with(".toml") => {
            if run.supply_voltage.is_some() {
                return Err(Error::argument(
                    "--supply-voltage",
                    "is for --motors' presets: a file gives its motors' figures",
                ));
            }
            read(Path::new(file), model)?
        }
        other => {
            return Err(Error::argument(
                "--motors",
                format!("'{other}' is not a preset ({}) nor a .toml file", PRESETS.join(", ")),
            ));
        }
    };
    Ok(Some(set))
}

/// A motors file: `[[joint]]` entries.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    joint: Vec<Entry>,
}

/// One `[[joint]]` of a motors file (docs/motors.md).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    name: Option<String>,
    label: Option<String>,
    gear_ratio: Option<f64>,
    efficiency: Option<f64>,
    rotor_inertia: Option<f64>,
    kind: String,
    stall_torque: Option<f64>,
    no_load_speed: Option<f64>,
    peak_torque: Option<f64>,
    /// Points `[speed, torque]`, read as lists so that a point of another length is refused
    /// (an array `[f64; 2]` took the first two values of `[0.0, 0.3, 7]` and dropped the third).
    curve: Option<Vec<Vec<f64>>>,
    continuous_torque: Option<f64>,
}

/// The motors of the file at `path` for `model`: one entry per moving joint in joint order, or
/// entries naming URDF joints (the joints not named have no motor).
/// The file is read whole, at most [`MAX_MOTORS_BYTES`] (a stream too).
pub fn read(path: &Path, model: &Model) -> Result<Vec<Option<JointMotor>>> {
    let text = read_capped(path, MAX_MOTORS_BYTES, "a motors file").and_then(|b| into_text(path, b));
    let text = text.map_err(|e| match e {
        Error::Io { source, .. } => Error::argument("--motors", format!("{}: {source}", path.display())),
        other => Error::argument("--motors", other.to_string()),
    })?;
    parse_text(&text, path, model)
}

/// [`read`] on the file's text; `path` names it in the errors.
pub fn parse_text(text: &str, path: &Path, model: &Model) -> Result<Vec<Option<JointMotor>>> {
    let at = |message: String| Error::argument("--motors", format!("{}: {message}", path.display()));
    let file: File = toml::from_str(text).map_err(|e| at(one_line(e.message())))?;
    parse(file, model).map_err(at)
}

fn parse(file: File, model: &Model) -> std::result::Result<Vec<Option<JointMotor>>, String> {
    let n = model.dof();
    let named = file.joint.iter().filter(|e| e.name.is_some()).count();
    let mut out: Vec<Option<JointMotor>> = vec![None; n];
    if named == 0 {
        if file.joint.len() != n {
            return Err(format!(
                "{} [[joint]] entries without names; {} has {n} moving joints (give one per joint, or name them)",
                file.joint.len(),
                model.source
            ));
        }
        for (i, e) in file.joint.into_iter().enumerate() {
            out[i] = Some(entry(e, i)?);
        }
    } else if named == file.joint.len() {
        for (k, e) in file.joint.into_iter().enumerate() {
            let name = e.name.clone().unwrap_or_default();
            let i = (model.joints.iter()).position(|j| j.name == name).ok_or_else(|| {
                let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
                format!(
                    "joint {} names '{name}', not a moving joint of {} ({})",
                    k + 1,
                    model.source,
                    names.join(", ")
                )
            })?;
            if out[i].is_some() {
                return Err(format!("'{name}' has two [[joint]] entries"));
            }
            out[i] = Some(entry(e, i)?);
        }
    } else {
        return Err("name every [[joint]] or none".into());
    }
    Ok(out)
}

/// One entry as joint i's motor.
fn entry(e: Entry, i: usize) -> std::result::Result<JointMotor, String> {
    let what = |m: &str| format!("J{} ({}): {m}", i + 1, e.name.as_deref().unwrap_or("by order"));
    let need = |field: Option<f64>, name: &str| field.ok_or_else(|| what(&format!("kind \"{}\" needs {name}", e.kind)));
    let envelope = match e.kind.as_str() {
        "dc" => {
            if e.curve.is_some() {
                return Err(what("a dc motor has no curve (that is a stepper's)"));
            }
            let stall_torque = need(e.stall_torque, "stall_torque")?;
            Envelope::Dc {
                stall_torque,
                no_load_speed: need(e.no_load_speed, "no_load_speed")?,
                peak_torque: e.peak_torque.unwrap_or(stall_torque),
            }
        }
        "stepper" => {
            if e.stall_torque.is_some() || e.no_load_speed.is_some() || e.peak_torque.is_some() {
                return Err(what(
                    "a stepper has a curve, not stall_torque, no_load_speed or peak_torque",
                ));
            }
            let curve = e.curve.as_ref().ok_or_else(|| what("kind \"stepper\" needs curve"))?;
            let points = curve.iter().enumerate().map(|(k, p)| match p[..] {
                [speed, torque] => Ok([speed, torque]),
                _ => Err(what(&format!(
                    "curve point {} has {} values ({p:?}); a point is [speed rad/s, torque N·m]",
                    k + 1,
                    p.len()
                ))),
            });
            Envelope::Stepper {
                curve: points.collect::<std::result::Result<_, _>>()?,
            }
        }
        other => return Err(what(&format!("kind \"{other}\" is not \"dc\" or \"stepper\""))),
    };
    let motor = Motor {
        label: e.label.clone().unwrap_or_else(|| e.kind.clone()),
        envelope,
        efficiency: e.efficiency.unwrap_or(1.0),
        continuous_torque: e.continuous_torque,
    };
    motor.check().map_err(|m| what(&m))?;
    for (name, x) in [("gear_ratio", e.gear_ratio), ("rotor_inertia", e.rotor_inertia)] {
        if let Some(x) = x
            && !(x.is_finite() && (x > 0.0 || (name == "rotor_inertia" && x == 0.0)))
        {
            return Err(what(&format!("{name} {x} must be > 0")));
        }
    }
    Ok(JointMotor {
        gear_ratio: e.gear_ratio,
        rotor_inertia: e.rotor_inertia,
        motor,
    })
}
