//! The motors behind the joints (`motors`, `supply_voltage`, `gear_ratio`, `rotor_inertia`),
//! resolved once into one value per joint: its gear ratio and rotor inertia, put on the model's
//! joint, and its motor, whose envelope clips the joint's torque ([`fit`]). docs/motors.md.

use std::path::{Path, PathBuf};

use crate::control::catalog::{sts3215, xm540_w270};
use crate::control::{self, JointMotor, Motor};
use crate::error::{Error, Result, escape_controls, quoted};
use crate::faze4::motors::{faze4, faze4_bom};
use crate::model::{Joint, Model};
use crate::sim::check::override_per_joint;

pub use super::motors_file::MotorEntry;

/// The presets `motors` knows, by name (in the order of [`PRESET_SETS`]).
pub const PRESETS: [&str; 4] = ["faze4", "faze4-bom", "sts3215", "xm540-w270"];

/// A preset of `motors`: its name, its motors and where their figures come from. `faze4 list
/// motors` prints each of [`PRESET_SETS`] from here: a preset added to the list appears there.
#[derive(Clone, Copy, Debug)]
pub struct Preset {
    /// Its name, as `motors` takes it (one of [`PRESETS`]).
    pub name: &'static str,
    /// The motors at a supply (V; `None`: the preset's own): one per joint of a 6-joint arm,
    /// or, for a preset of one motor on every joint, that one motor.
    pub motors: fn(Option<f64>) -> Vec<Option<JointMotor>>,
    /// Whether its one motor goes on every joint of any arm (else its motors are for a 6-joint
    /// arm, in joint order).
    pub every_joint: bool,
    /// Where each of its figures is published (docs/motors.md has the addresses).
    pub sources: &'static str,
}

/// Every preset, in the order of [`PRESETS`].
pub const PRESET_SETS: [Preset; 4] = [
    Preset {
        name: "faze4",
        motors: faze4,
        every_joint: false,
        sources: "motor 17HS16-2004S1: 0.45 N·m holding, 2.0 A (StepperOnline's listing), 1.1 Ω, 2.6 mH, 50 pole \
                  pairs (Source Robotics' STEPFOC table), rotor 54 g·cm² (StepperOnline's datasheet); ratios: the \
                  Faze4's B_Design_decisions.rst; microsteps: its 2020 firmware; reducer efficiency not \
                  published, taken as 1 (docs/motors.md, \"The presets and their figures\")",
    },
    Preset {
        name: "faze4-bom",
        motors: faze4_bom,
        every_joint: false,
        sources: "motors: the Faze4's BOM_7_11_2023.xlsx on the joints of its firmware's step angles; currents \
                  and supplies: its electronics guide; each motor's figures (StepperOnline's listings and \
                  datasheets, Source Robotics' STEPFOC table, the stepper-simulator database; J1's and J2's \
                  rotors and J2's inductance are same-frame proxies): docs/motors.md, \"faze4-bom: the Faze4 as \
                  built\"",
    },
    Preset {
        name: "sts3215",
        motors: |supply| vec![Some(sts3215(supply))],
        every_joint: true,
        sources: "19.5 kg·cm stall, 0.192 s/60° no-load at 7.4 V, 1:345 gear train (DFRobot SER0069 listing); \
                  rotor inertia and continuous torque not published",
    },
    Preset {
        name: "xm540-w270",
        motors: |supply| vec![Some(xm540_w270(supply))],
        every_joint: true,
        sources: "10.6 N·m stall, 30 rev/min no-load at 12 V, 272.5:1 (ROBOTIS e-Manual)",
    },
];

/// Where a run's motors come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Motors {
    /// A preset of [`PRESETS`], by name.
    Preset(String),
    /// A motors file (TOML, docs/motors.md).
    File(PathBuf),
    /// The entries of a motors file, given as values (Python's dict of the file's schema).
    Entries(Vec<MotorEntry>),
}

impl Motors {
    /// A preset's name or a `.toml` file's path, as the command line and Python write it.
    pub fn named(text: &str) -> Result<Motors> {
        if PRESETS.contains(&text) {
            Ok(Motors::Preset(text.to_string()))
        } else if text.ends_with(".toml") {
            Ok(Motors::File(PathBuf::from(text)))
        } else {
            Err(Error::option(
                "motors",
                format!(
                    "{} is not a preset ({}) nor a .toml file",
                    quoted(text),
                    PRESETS.join(", ")
                ),
            ))
        }
    }
}

/// The motor per joint of `motors` on `model` (`None` for a joint it leaves out): a preset
/// (at `supply` volts where given), or a file's or the given entries, paired with the joints
/// by name where they name them, else in order. `None` for no motors.
pub fn resolve(motors: Option<&Motors>, supply: Option<f64>, model: &Model) -> Result<Option<Vec<Option<JointMotor>>>> {
    let Some(motors) = motors else {
        if supply.is_some() {
            return Err(Error::option("supply_voltage", "is for `motors`' presets"));
        }
        return Ok(None);
    };
    if let Some(v) = supply
        && !(v.is_finite() && v > 0.0)
    {
        return Err(Error::option(
            "supply_voltage",
            format!("{} must be > 0", crate::error::shortest(v)),
        ));
    }
    let n = model.dof();
    let set = match motors {
        Motors::Preset(name) => {
            let six = |set: Vec<Option<JointMotor>>| {
                if n == set.len() {
                    Ok(set)
                } else {
                    Err(Error::option(
                        "motors",
                        format!("{name}'s motors are for a 6-joint arm; {} has {n} joints", model.source),
                    ))
                }
            };
            match PRESET_SETS.iter().find(|p| p.name == name) {
                Some(p) if p.every_joint => vec![(p.motors)(supply).swap_remove(0); n],
                Some(p) => six((p.motors)(supply))?,
                None => return Err(Motors::named(name).err().unwrap_or_else(|| unknown(name))),
            }
        }
        Motors::File(path) => {
            no_supply(supply)?;
            let entries = super::motors_file::read(path)?;
            pair(entries, model).map_err(|e| at(path, e))?
        }
        Motors::Entries(entries) => {
            no_supply(supply)?;
            pair(entries.clone(), model).map_err(|e| Error::option("motors", e))?
        }
    };
    Ok(Some(set))
}

/// The motors of a motors file's `text` on the joints of `model` (what [`resolve`] does with a
/// file once it is read); `path` names the file in the errors.
pub fn file_motors(text: &str, path: &Path, model: &Model) -> Result<Vec<Option<JointMotor>>> {
    let entries = super::motors_file::parse_text(text, path)?;
    pair(entries, model).map_err(|e| at(path, e))
}

fn unknown(name: &str) -> Error {
    Error::option(
        "motors",
        format!("{} is not a preset ({})", quoted(name), PRESETS.join(", ")),
    )
}

fn no_supply(supply: Option<f64>) -> Result<()> {
    match supply {
        Some(_) => Err(Error::option(
            "supply_voltage",
            "is for `motors`' presets: a file gives its motors' figures",
        )),
        None => Ok(()),
    }
}

fn at(path: &Path, message: String) -> Error {
    Error::option("motors", format!("{}: {message}", path.display()))
}

/// The entries on the joints of `model`: by name when every entry names one (a joint not named
/// has no motor), in order when none does (then one per joint).
fn pair(entries: Vec<MotorEntry>, model: &Model) -> std::result::Result<Vec<Option<JointMotor>>, String> {
    check_fields(&entries)?;
    let n = model.dof();
    let named = entries.iter().filter(|e| e.name.is_some()).count();
    let mut out: Vec<Option<JointMotor>> = vec![None; n];
    if named == 0 {
        if entries.len() != n {
            return Err(format!(
                "{} [[joint]] entries without names; {} has {n} moving joints (give one per joint, or name them)",
                entries.len(),
                model.source
            ));
        }
        for (i, e) in entries.into_iter().enumerate() {
            out[i] = Some(entry(e, i)?);
        }
    } else if named == entries.len() {
        for (k, e) in entries.into_iter().enumerate() {
            let name = e.name.clone().unwrap_or_default();
            let i = (model.joints.iter()).position(|j| j.name == name).ok_or_else(|| {
                let names: Vec<String> = model.joints.iter().map(|j| escape_controls(&j.name)).collect();
                format!(
                    "joint {} names {}, not a moving joint of {} ({})",
                    k + 1,
                    quoted(&name),
                    escape_controls(&model.source),
                    names.join(", ")
                )
            })?;
            if out[i].is_some() {
                return Err(format!("{} has two [[joint]] entries", quoted(&name)));
            }
            out[i] = Some(entry(e, i)?);
        }
    } else {
        return Err("name every [[joint]] or none".into());
    }
    Ok(out)
}

/// One entry as joint i's motor: its kind ([`crate::control::KINDS`]) reads its own fields.
fn entry(mut e: MotorEntry, i: usize) -> std::result::Result<JointMotor, String> {
    let what = |m: &str| {
        let name = e.name.as_deref().map_or("by order".to_string(), escape_controls);
        format!("J{} ({name}): {m}", i + 1)
    };
    let word = match e.figures.remove("kind") {
        Some(serde_json::Value::String(word)) => word,
        Some(other) => return Err(what(&format!("kind {other} must be a word (\"dc\", \"stepper\")"))),
        None => return Err(what("missing field 'kind'")),
    };
    let kind = control::kind(&word).map_err(|m| what(&m))?;
    let own = (kind.fields)();
    if let Some(field) = e.figures.keys().find(|f| !own.contains(&f.as_str())) {
        return Err(what(&(kind.has_no)(field)));
    }
    let figures = serde_json::Value::Object(std::mem::take(&mut e.figures));
    let (envelope, stepping) = (kind.read)(figures).map_err(|m| what(&m))?;
    let motor = Motor {
        label: e.label.clone().unwrap_or(word),
        envelope,
        efficiency: e.efficiency.unwrap_or(1.0),
        continuous_torque: e.continuous_torque,
        stepping,
        electrics: None,
        servo: None,
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

/// What the file's serde structs said before the entries are paired with joints: a missing or
/// non-word `kind`, a field no kind has, a field of the wrong type; in serde's words.
fn check_fields(entries: &[MotorEntry]) -> std::result::Result<(), String> {
    let words = |e: serde_json::Error| crate::error::file_words(&e.to_string());
    for e in entries {
        let kind = e.figures.get("kind").ok_or("missing field 'kind'")?;
        let kind = serde_json::from_value::<String>(kind.clone()).map_err(words)?;
        if let Some(field) = e.figures.keys().find(|f| !known(f)) {
            return Err(unknown_field(field));
        }
        if let Ok(kind) = control::kind(&kind) {
            let own = (e.figures.iter()).filter(|(f, _)| (kind.fields)().contains(&f.as_str()));
            (kind.types)(serde_json::Value::Object(
                own.map(|(f, v)| (f.clone(), v.clone())).collect(),
            ))?;
        }
    }
    Ok(())
}

/// Whether `field` is `kind` or some kind's field.
fn known(field: &str) -> bool {
    field == "kind" || control::KINDS.iter().any(|k| (k.fields)().contains(&field))
}

/// An unknown field in serde's words.
fn unknown_field(field: &str) -> String {
    let mut names: Vec<String> = super::motors_file::COMMON_FIELDS
        .iter()
        .map(|f| format!("'{f}'"))
        .collect();
    names.push("'kind'".into());
    names.extend(
        control::KINDS
            .iter()
            .flat_map(|k| (k.fields)().iter().map(|f| format!("'{f}'"))),
    );
    format!(
        "unknown field {}, expected one of {}",
        crate::error::quoted(field),
        names.join(", ")
    )
}

/// Puts the motors on `model`, once: each joint's ratio and rotor from its motor where the
/// motor gives them (a joint without a motor, or a figure the motor leaves out, keeps the
/// model's), then the per-joint overrides `gear_ratio` and `rotor_inertia` (> 0; `None` keeps
/// a joint's; empty: none). Returns the motors' envelopes, one per joint (`None` without
/// motors).
pub fn fit(
    model: &mut Model,
    motors: Option<Vec<Option<JointMotor>>>,
    gear_ratio: &[Option<f64>],
    rotor_inertia: &[Option<f64>],
) -> Result<Option<Vec<Option<Motor>>>> {
    let envelopes = motors.map(|motors| {
        (model.joints.iter_mut().zip(motors))
            .map(|(joint, m)| {
                m.map(|m| {
                    joint.gear_ratio = m.gear_ratio.unwrap_or(joint.gear_ratio);
                    joint.rotor_inertia = m.rotor_inertia.unwrap_or(joint.rotor_inertia);
                    m.motor
                })
            })
            .collect()
    });
    set_per_joint("gear_ratio", model, gear_ratio, |j| &mut j.gear_ratio)?;
    set_per_joint("rotor_inertia", model, rotor_inertia, |j| &mut j.rotor_inertia)?;
    Ok(envelopes)
}

/// Sets each joint's value that `values` gives (finite, > 0; `None` keeps the model's).
fn set_per_joint(
    field: &str,
    model: &mut Model,
    values: &[Option<f64>],
    slot: fn(&mut Joint) -> &mut f64,
) -> Result<()> {
    let mut current: Vec<f64> = model.joints.iter_mut().map(|j| *slot(j)).collect();
    override_per_joint(field, &mut current, values, |v| v.is_finite() && v > 0.0, "> 0")?;
    for (joint, x) in model.joints.iter_mut().zip(current) {
        *slot(joint) = x;
    }
    Ok(())
}

#[cfg(test)]
mod preset_tests {
    use super::*;

    /// [`PRESETS`] names [`PRESET_SETS`], in order, and each preset gives six motors or one.
    #[test]
    fn the_preset_names_are_the_sets() {
        let names: Vec<&str> = PRESET_SETS.iter().map(|p| p.name).collect();
        assert_eq!(names, PRESETS);
        for p in PRESET_SETS {
            let count = (p.motors)(None).len();
            assert_eq!(count, if p.every_joint { 1 } else { 6 }, "{}", p.name);
        }
    }
}
