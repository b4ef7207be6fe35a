//! The options of a [`RunConfig`] by name: what kind of value each takes, which commands have
//! it, and how it is set. A front end that has names and values (Python's keywords) sets a
//! configuration through [`RunConfig::set`]; a sweep varies its numeric fields through
//! [`Field::set_number`]. The names are the fields' own (`payload_kg`): the command line's
//! flags are the same words with dashes (`--payload-kg`).

use std::path::PathBuf;

use super::{Center, DriveMode, Motion, Motors, RunConfig};
use crate::control::FeedForward;
use crate::error::{Error, Result, shortest};
use crate::geometry::{ClearanceGeometry, PairFilter};
use crate::traj::shape::Shape;

/// The kind of value a field takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A flag: on or off.
    Flag,
    /// A real number.
    Number,
    /// A whole number ≥ 0.
    Count,
    /// A word or text.
    Text,
    /// One of a few words.
    Choice(&'static [&'static str]),
    /// A file or directory.
    Path,
    /// Several files or directories.
    Paths,
    /// One value per joint (`None`: keep the joint's own).
    PerJoint,
    /// One number per joint, all given.
    Numbers,
    /// A wave's centre: `mid` or one value per joint.
    Center,
    /// Motors: a preset, a file, or the file's entries.
    Motors,
}

/// A value for a field, of its [`Kind`].
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// Not given: the field's default.
    Default,
    /// A flag.
    Flag(bool),
    /// A number.
    Number(f64),
    /// A whole number.
    Count(u64),
    /// A word or text (also a [`Kind::Choice`]'s word, a path's text, `mid`).
    Text(String),
    /// A path.
    Path(PathBuf),
    /// Several paths.
    Paths(Vec<PathBuf>),
    /// One value per joint (`None`: keep the joint's own).
    PerJoint(Vec<Option<f64>>),
    /// Motors given as values.
    Motors(Motors),
}

/// Which commands have a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Commands {
    /// Every command of the configuration (`wave`, `replay`, `shape`, `retime`).
    All,
    /// The commands that run a motion for a time (`wave`, `replay`, `shape`; `retime` finds
    /// its own).
    Runs,
    /// `wave` only.
    Wave,
    /// The commands that read a trajectory file (`replay`, `retime`).
    Trajectory,
    /// `shape` only.
    Shape,
    /// `retime` only.
    Retime,
}

impl Commands {
    /// Whether `motion`'s command has the field.
    pub fn has(self, motion: &Motion) -> bool {
        matches!(
            (self, motion),
            (Commands::All, _)
                | (Commands::Runs, Motion::Wave(_) | Motion::Replay(_) | Motion::Shape(_))
                | (Commands::Wave, Motion::Wave(_))
                | (Commands::Trajectory, Motion::Replay(_) | Motion::Retime(_))
                | (Commands::Shape, Motion::Shape(_))
                | (Commands::Retime, Motion::Retime(_))
        )
    }
}

/// A reference to a numeric field, for a sweep (`None`: the command has no such field).
type NumberSlot = fn(&mut RunConfig) -> Option<&mut f64>;

/// One option of a run.
#[derive(Clone, Copy)]
pub struct Field {
    /// Its name (`payload_kg`).
    pub name: &'static str,
    /// What it takes.
    pub kind: Kind,
    /// Which commands have it.
    pub commands: Commands,
    set: fn(&mut RunConfig, Value) -> Result<()>,
    number: Option<NumberSlot>,
}

impl std::fmt::Debug for Field {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Field")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .finish()
    }
}

impl Field {
    /// Whether a sweep can vary it: a number, or a whole number (`shape_points`).
    pub fn is_numeric(&self) -> bool {
        self.number.is_some() || self.kind == Kind::Count
    }

    /// Sets it to the number `x` in `config` (a sweep's value): an error for a field that is not
    /// numeric, that `config`'s command does not have, or a whole-number field given a
    /// fraction.
    pub fn set_number(&self, config: &mut RunConfig, x: f64) -> Result<()> {
        if !self.commands.has(&config.motion) {
            return Err(Error::option(
                self.name,
                format!("is not an option of {}", config.motion.name()),
            ));
        }
        match (self.number, self.kind) {
            (Some(slot), _) => {
                let slot = slot(config).ok_or_else(|| Error::option(self.name, "is not a number"))?;
                *slot = x;
                Ok(())
            }
            (None, Kind::Count) => {
                if !(x >= 0.0 && x.fract() == 0.0 && x <= u32::MAX as f64) {
                    return Err(Error::option(
                        self.name,
                        format!("takes whole numbers ≥ 0, not {}", shortest(x)),
                    ));
                }
                (self.set)(config, Value::Count(x as u64))
            }
            _ => Err(Error::option(self.name, "is not a number")),
        }
    }
}

/// The field called `name`.
pub fn field(name: &str) -> Option<&'static Field> {
    FIELDS.iter().find(|f| f.name == name)
}

impl RunConfig {
    /// Sets the field `name` to `value` (of the field's kind; [`Value::Default`] restores its
    /// default). An error names the field: unknown, not an option of this command, or a value
    /// of another kind.
    pub fn set(&mut self, name: &str, value: Value) -> Result<()> {
        let field = field(name).ok_or_else(|| {
            Error::option(
                name,
                format!(
                    "is not an option of {} (its options: {})",
                    self.motion.name(),
                    names(&self.motion).join(", ")
                ),
            )
        })?;
        if !field.commands.has(&self.motion) {
            return Err(Error::option(
                name,
                format!("is not an option of {}", self.motion.name()),
            ));
        }
        (field.set)(self, value)
    }
}

/// The names of the fields `motion`'s command has, in table order.
pub fn names(motion: &Motion) -> Vec<&'static str> {
    FIELDS
        .iter()
        .filter(|f| f.commands.has(motion))
        .map(|f| f.name)
        .collect()
}

/// An error for a value of another kind.
fn wrong(name: &str, kind: Kind, value: &Value) -> Error {
    let given = match value {
        Value::Default => "nothing".to_string(),
        Value::Flag(on) => on.to_string(),
        Value::Number(x) => shortest(*x),
        Value::Count(n) => n.to_string(),
        Value::Text(t) => format!("'{t}'"),
        Value::Path(p) => format!("'{}'", p.display()),
        Value::Paths(_) => "several paths".to_string(),
        Value::PerJoint(v) => format!("{} values", v.len()),
        Value::Motors(_) => "motors".to_string(),
    };
    Error::option(name, format!("{given} is not {}", kind_name(kind)))
}

/// A kind for people.
pub fn kind_name(kind: Kind) -> String {
    match kind {
        Kind::Flag => "on or off".into(),
        Kind::Number => "a number".into(),
        Kind::Count => "a whole number".into(),
        Kind::Text => "a text".into(),
        Kind::Choice(words) => format!("one of {}", words.join(", ")),
        Kind::Path => "a path".into(),
        Kind::Paths => "paths".into(),
        Kind::PerJoint => "one value per joint".into(),
        Kind::Numbers => "one number per joint".into(),
        Kind::Center => "'mid' or one value per joint".into(),
        Kind::Motors => "a preset, a .toml file or the file's entries".into(),
    }
}

/// Parses one value per joint as the command line writes it: comma-separated numbers, `auto`
/// keeping a joint's own. An empty item is refused (`1,,3` is a typo, not `auto`).
pub fn parse_per_joint(text: &str) -> std::result::Result<Vec<Option<f64>>, String> {
    text.split(',')
        .enumerate()
        .map(|(i, item)| match item.trim() {
            "auto" => Ok(None),
            "" => Err(format!("J{} is empty: give a number or 'auto'", i + 1)),
            text => text
                .parse::<f64>()
                .map(Some)
                .map_err(|_| format!("J{} '{text}' is not a number", i + 1)),
        })
        .collect()
}

/// Every joint's value, `auto` refused (it keeps a gain's tuned value; a limit has none).
pub fn all_given(name: &str, values: &[Option<f64>]) -> Result<Vec<f64>> {
    values
        .iter()
        .enumerate()
        .map(|(i, v)| v.ok_or_else(|| Error::option(name, format!("J{} has no value ('auto' is for gains)", i + 1))))
        .collect()
}

/// A wave's centre as the command line writes it: `mid`, or one value per joint.
pub fn parse_center(text: &str) -> Result<Center> {
    match text.trim() {
        "mid" => Ok(Center::Mid),
        list => (list.split(',').enumerate())
            .map(|(i, x)| {
                x.trim().parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                    Error::option(
                        "center",
                        format!("J{} value '{}' is not a finite number (or use 'mid')", i + 1, x.trim()),
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()
            .map(Center::Given),
    }
}

macro_rules! number {
    ($name:literal, $commands:expr, $slot:expr, $default:expr) => {
        Field {
            name: $name,
            kind: Kind::Number,
            commands: $commands,
            set: |c, v| {
                let slot: fn(&mut RunConfig) -> Option<&mut f64> = $slot;
                let default: fn() -> f64 = $default;
                let x = match v {
                    Value::Number(x) => x,
                    Value::Count(x) => x as f64,
                    Value::Default => default(),
                    other => return Err(wrong($name, Kind::Number, &other)),
                };
                *slot(c).ok_or_else(|| Error::option($name, "is not an option of this command"))? = x;
                Ok(())
            },
            number: Some($slot),
        }
    };
}

macro_rules! optional_number {
    ($name:literal, $commands:expr, $slot:expr) => {
        Field {
            name: $name,
            kind: Kind::Number,
            commands: $commands,
            set: |c, v| {
                let slot: fn(&mut RunConfig) -> Option<&mut Option<f64>> = $slot;
                let x = match v {
                    Value::Number(x) => Some(x),
                    Value::Count(x) => Some(x as f64),
                    Value::Default => None,
                    other => return Err(wrong($name, Kind::Number, &other)),
                };
                *slot(c).ok_or_else(|| Error::option($name, "is not an option of this command"))? = x;
                Ok(())
            },
            number: Some(|c| {
                let slot: fn(&mut RunConfig) -> Option<&mut Option<f64>> = $slot;
                slot(c).map(|x| x.insert(0.0))
            }),
        }
    };
}

macro_rules! flag {
    ($name:literal, $($path:ident).+) => {
        Field {
            name: $name,
            kind: Kind::Flag,
            commands: Commands::All,
            set: |c, v| {
                c.$($path).+ = match v {
                    Value::Flag(on) => on,
                    Value::Default => false,
                    other => return Err(wrong($name, Kind::Flag, &other)),
                };
                Ok(())
            },
            number: None,
        }
    };
}

macro_rules! optional_path {
    ($name:literal, $($path:ident).+) => {
        Field {
            name: $name,
            kind: Kind::Path,
            commands: Commands::All,
            set: |c, v| {
                c.$($path).+ = match v {
                    Value::Path(p) => none_is_none(p),
                    Value::Text(t) => none_is_none(PathBuf::from(t)),
                    Value::Default => None,
                    other => return Err(wrong($name, Kind::Path, &other)),
                };
                Ok(())
            },
            number: None,
        }
    };
}

macro_rules! per_joint {
    ($name:literal, $($path:ident).+) => {
        Field {
            name: $name,
            kind: Kind::PerJoint,
            commands: Commands::All,
            set: |c, v| {
                c.$($path).+ = per_joint($name, v)?;
                Ok(())
            },
            number: None,
        }
    };
}

/// A path named `none` means no file, as on the command line.
fn none_is_none(path: PathBuf) -> Option<PathBuf> {
    (path.as_os_str() != "none").then_some(path)
}

/// One value per joint from `value` (a list, or the command line's text).
fn per_joint(name: &str, value: Value) -> Result<Vec<Option<f64>>> {
    match value {
        Value::PerJoint(values) => Ok(values),
        Value::Text(text) => parse_per_joint(&text).map_err(|e| Error::option(name, e)),
        Value::Default => Ok(Vec::new()),
        other => Err(wrong(name, Kind::PerJoint, &other)),
    }
}

fn wave(c: &mut RunConfig) -> Option<&mut super::WaveConfig> {
    match &mut c.motion {
        Motion::Wave(w) => Some(w),
        _ => None,
    }
}

/// The trajectory file's options: a replay's, or the path a retime reads.
fn replay(c: &mut RunConfig) -> Option<&mut super::ReplayConfig> {
    match &mut c.motion {
        Motion::Replay(r) => Some(r),
        Motion::Retime(r) => Some(&mut r.path),
        _ => None,
    }
}

fn retime(c: &mut RunConfig) -> Option<&mut super::RetimeConfig> {
    match &mut c.motion {
        Motion::Retime(r) => Some(r),
        _ => None,
    }
}

/// A whole-number field of `retime` from `v` (`default` for [`Value::Default`]).
fn retime_count(name: &str, v: Value, default: usize) -> Result<usize> {
    match v {
        Value::Count(n) => usize::try_from(n).map_err(|_| Error::option(name, "too large")),
        Value::Default => Ok(default),
        other => Err(wrong(name, Kind::Count, &other)),
    }
}

fn shape(c: &mut RunConfig) -> Option<&mut super::ShapeConfig> {
    match &mut c.motion {
        Motion::Shape(s) => Some(s),
        _ => None,
    }
}

/// Every option of a run, by name, in the order of `faze4 COMMAND --help`: the command's own,
/// then those every run command shares.
pub const FIELDS: &[Field] = &[
    optional_number!("duration", Commands::Runs, |c| Some(&mut c.duration)),
    number!("freq", Commands::Wave, |c| wave(c).map(|w| &mut w.freq), || {
        super::DEFAULT_FREQ
    }),
    number!("amp_deg", Commands::Wave, |c| wave(c).map(|w| &mut w.amp_deg), || {
        super::DEFAULT_AMP_DEG
    }),
    optional_number!("amp_m", Commands::Wave, |c| wave(c).map(|w| &mut w.amp_m)),
    Field {
        name: "center",
        kind: Kind::Center,
        commands: Commands::Wave,
        set: |c, v| {
            let center = match v {
                Value::Default => Center::Zero,
                Value::Text(text) => parse_center(&text)?,
                Value::PerJoint(values) => Center::Given(all_given("center", &values)?),
                other => return Err(wrong("center", Kind::Center, &other)),
            };
            if let Some(w) = wave(c) {
                w.center = center;
            }
            Ok(())
        },
        number: None,
    },
    Field {
        name: "q_traj",
        kind: Kind::Path,
        commands: Commands::Trajectory,
        set: |c, v| {
            let path = match v {
                Value::Path(p) => p,
                Value::Text(t) => PathBuf::from(t),
                other => return Err(wrong("q_traj", Kind::Path, &other)),
            };
            if let Some(r) = replay(c) {
                r.q_traj = path;
            }
            Ok(())
        },
        number: None,
    },
    number!(
        "traj_period",
        Commands::Trajectory,
        |c| replay(c).map(|r| &mut r.traj_period),
        || super::DEFAULT_TRAJ_PERIOD
    ),
    Field {
        name: "message",
        kind: Kind::Count,
        commands: Commands::Trajectory,
        set: |c, v| {
            let message = match v {
                Value::Count(k) => Some(usize::try_from(k).map_err(|_| Error::option("message", "too large"))?),
                Value::Default => None,
                other => return Err(wrong("message", Kind::Count, &other)),
            };
            if let Some(r) = replay(c) {
                r.message = message;
            }
            Ok(())
        },
        number: None,
    },
    Field {
        name: "topic",
        kind: Kind::Text,
        commands: Commands::Trajectory,
        set: |c, v| {
            let topic = match v {
                Value::Text(t) => Some(t),
                Value::Default => None,
                other => return Err(wrong("topic", Kind::Text, &other)),
            };
            if let Some(r) = replay(c) {
                r.topic = topic;
            }
            Ok(())
        },
        number: None,
    },
    Field {
        name: "out",
        kind: Kind::Path,
        commands: Commands::Retime,
        set: |c, v| {
            let path = match v {
                Value::Path(p) => Some(p),
                Value::Text(t) => Some(PathBuf::from(t)),
                Value::Default => None,
                other => return Err(wrong("out", Kind::Path, &other)),
            };
            if let Some(r) = retime(c) {
                r.out = path;
            }
            Ok(())
        },
        number: None,
    },
    Field {
        name: "grid",
        kind: Kind::Count,
        commands: Commands::Retime,
        set: |c, v| {
            let n = retime_count("grid", v, super::DEFAULT_GRID)?;
            if let Some(r) = retime(c) {
                r.grid = n;
            }
            Ok(())
        },
        number: None,
    },
    number!("margin", Commands::Retime, |c| retime(c).map(|r| &mut r.margin), || {
        super::DEFAULT_MARGIN
    }),
    Field {
        name: "attempts",
        kind: Kind::Count,
        commands: Commands::Retime,
        set: |c, v| {
            let n = retime_count("attempts", v, super::DEFAULT_ATTEMPTS)?;
            if let Some(r) = retime(c) {
                r.attempts = n;
            }
            Ok(())
        },
        number: None,
    },
    Field {
        name: "shape",
        kind: Kind::Choice(&["sine", "circle", "tri"]),
        commands: Commands::Shape,
        set: |c, v| {
            let Value::Text(name) = &v else {
                return Err(wrong("shape", Kind::Choice(&["sine", "circle", "tri"]), &v));
            };
            let shape_of = Shape::from_name(name)
                .ok_or_else(|| Error::option("shape", format!("'{name}' is not one of sine, circle, tri")))?;
            if let Some(s) = shape(c) {
                s.shape = shape_of;
            }
            Ok(())
        },
        number: None,
    },
    Field {
        name: "shape_points",
        kind: Kind::Count,
        commands: Commands::Shape,
        set: |c, v| {
            let n = match v {
                Value::Count(n) => n,
                Value::Default => super::DEFAULT_SHAPE_POINTS as u64,
                other => return Err(wrong("shape_points", Kind::Count, &other)),
            };
            if let Some(s) = shape(c) {
                s.shape_points = usize::try_from(n).map_err(|_| Error::option("shape_points", "too large"))?;
            }
            Ok(())
        },
        number: None,
    },
    Field {
        name: "save_q",
        kind: Kind::Path,
        commands: Commands::Shape,
        set: |c, v| {
            let path = match v {
                Value::Path(p) => none_is_none(p),
                Value::Text(t) => none_is_none(PathBuf::from(t)),
                Value::Default => None,
                other => return Err(wrong("save_q", Kind::Path, &other)),
            };
            if let Some(s) = shape(c) {
                s.save_q = path;
            }
            Ok(())
        },
        number: None,
    },
    optional_path!("urdf", arm.urdf),
    Field {
        name: "package_path",
        kind: Kind::Paths,
        commands: Commands::All,
        set: |c, v| {
            c.arm.package_path = match v {
                Value::Paths(p) => p,
                Value::Path(p) => vec![p],
                Value::Text(t) => vec![PathBuf::from(t)],
                Value::Default => Vec::new(),
                other => return Err(wrong("package_path", Kind::Paths, &other)),
            };
            Ok(())
        },
        number: None,
    },
    flag!("balance_inertia", arm.balance_inertia),
    Field {
        name: "tool_link",
        kind: Kind::Text,
        commands: Commands::All,
        set: |c, v| {
            c.arm.tool_link = match v {
                Value::Text(t) => Some(t),
                Value::Default => None,
                other => return Err(wrong("tool_link", Kind::Text, &other)),
            };
            Ok(())
        },
        number: None,
    },
    Field {
        name: "effort",
        kind: Kind::Numbers,
        commands: Commands::All,
        set: |c, v| {
            c.control.effort = match v {
                Value::Default => None,
                other => Some(all_given("effort", &per_joint("effort", other)?)?),
            };
            Ok(())
        },
        number: None,
    },
    per_joint!("kp", control.kp),
    per_joint!("kd", control.kd),
    Field {
        name: "motors",
        kind: Kind::Motors,
        commands: Commands::All,
        set: |c, v| {
            c.arm.motors = match v {
                Value::Default => None,
                Value::Motors(m) => Some(m),
                Value::Text(t) => Some(Motors::named(&t)?),
                Value::Path(p) => Some(Motors::File(p)),
                other => return Err(wrong("motors", Kind::Motors, &other)),
            };
            Ok(())
        },
        number: None,
    },
    optional_number!("supply_voltage", Commands::All, |c| Some(&mut c.arm.supply_voltage)),
    per_joint!("rotor_inertia", arm.rotor_inertia),
    per_joint!("gear_ratio", arm.gear_ratio),
    per_joint!("max_speed", control.max_speed),
    flag!("no_ff", control.no_ff),
    Field {
        name: "ff",
        kind: Kind::Choice(&["gravity", "full"]),
        commands: Commands::All,
        set: |c, v| {
            c.control.ff = match &v {
                Value::Default => None,
                Value::Text(t) if t == "gravity" => Some(FeedForward::Gravity),
                Value::Text(t) if t == "full" => Some(FeedForward::Full),
                _ => return Err(wrong("ff", Kind::Choice(&["gravity", "full"]), &v)),
            };
            Ok(())
        },
        number: None,
    },
    Field {
        name: "drive",
        kind: Kind::Choice(&["pd", "stepper"]),
        commands: Commands::All,
        set: |c, v| {
            c.control.drive = match &v {
                Value::Default => DriveMode::Pd,
                Value::Text(t) if t == "pd" => DriveMode::Pd,
                Value::Text(t) if t == "stepper" => DriveMode::Stepper,
                _ => return Err(wrong("drive", Kind::Choice(&["pd", "stepper"]), &v)),
            };
            Ok(())
        },
        number: None,
    },
    per_joint!("microsteps", control.microsteps),
    optional_number!("driver_bandwidth", Commands::All, |c| Some(
        &mut c.control.driver_bandwidth
    )),
    per_joint!("rotor_damping", control.rotor_damping),
    per_joint!("reducer_friction", control.reducer_friction),
    flag!("sizing", outputs.sizing),
    flag!("no_gravity", arm.no_gravity),
    number!("payload_kg", Commands::All, |c| Some(&mut c.arm.payload_kg), || 0.0),
    number!("dt", Commands::All, |c| Some(&mut c.control.dt), || super::DEFAULT_DT),
    flag!("debug", outputs.debug),
    flag!("quiet", outputs.quiet),
    optional_number!("print_period", Commands::All, |c| Some(&mut c.outputs.print_period)),
    number!(
        "max_saturation_pct",
        Commands::All,
        |c| Some(&mut c.verdict.thresholds.max_saturation_pct),
        || crate::sim::Thresholds::default().max_saturation_pct
    ),
    number!(
        "max_error",
        Commands::All,
        |c| Some(&mut c.verdict.thresholds.max_error),
        || crate::sim::Thresholds::default().max_error
    ),
    number!(
        "max_deviation_mm",
        Commands::All,
        |c| Some(&mut c.verdict.thresholds.max_deviation_mm),
        || crate::sim::Thresholds::default().max_deviation_mm
    ),
    flag!("strict", verdict.strict),
    Field {
        name: "trail",
        kind: Kind::Path,
        commands: Commands::All,
        set: |c, v| {
            c.outputs.trail = match v {
                Value::Path(p) => none_is_none(p),
                Value::Text(t) => none_is_none(PathBuf::from(t)),
                Value::Default => Some(PathBuf::from(super::DEFAULT_TRAIL)),
                other => return Err(wrong("trail", Kind::Path, &other)),
            };
            Ok(())
        },
        number: None,
    },
    optional_path!("summary", outputs.summary),
    number!("record_period", Commands::All, |c| Some(&mut c.record_period), || {
        super::DEFAULT_RECORD_PERIOD
    }),
    Field {
        name: "collision_geometry",
        kind: Kind::Choice(&["mesh", "hull"]),
        commands: Commands::All,
        set: |c, v| {
            c.clearance.collision_geometry = match &v {
                Value::Default => ClearanceGeometry::default(),
                Value::Text(t) if t == "mesh" => ClearanceGeometry::Mesh,
                Value::Text(t) if t == "hull" => ClearanceGeometry::Hull,
                _ => return Err(wrong("collision_geometry", Kind::Choice(&["mesh", "hull"]), &v)),
            };
            Ok(())
        },
        number: None,
    },
    Field {
        name: "collision_pairs",
        kind: Kind::Choice(&["all"]),
        commands: Commands::All,
        set: |c, v| {
            c.clearance.collision_pairs = match &v {
                Value::Default => PairFilter::default(),
                Value::Text(t) if t == "all" => PairFilter::All,
                _ => return Err(wrong("collision_pairs", Kind::Choice(&["all"]), &v)),
            };
            Ok(())
        },
        number: None,
    },
    number!(
        "clearance_tolerance",
        Commands::All,
        |c| Some(&mut c.clearance.clearance_tolerance),
        || super::DEFAULT_CLEARANCE_TOLERANCE_MM
    ),
    flag!("no_collisions", clearance.no_collisions),
    flag!("self_collisions", clearance.self_collisions),
    number!("friction", Commands::All, |c| Some(&mut c.clearance.friction), || {
        super::DEFAULT_FRICTION
    }),
    flag!("view", outputs.view),
    Field {
        name: "port",
        kind: Kind::Count,
        commands: Commands::All,
        set: |c, v| {
            c.outputs.port = match v {
                Value::Count(p) => {
                    u16::try_from(p).map_err(|_| Error::option("port", format!("{p} is not a port (0 to 65535)")))?
                }
                Value::Default => super::DEFAULT_PORT,
                other => return Err(wrong("port", Kind::Count, &other)),
            };
            Ok(())
        },
        number: None,
    },
    flag!("hold", outputs.hold),
    optional_path!("html", outputs.html),
    optional_path!("plot", outputs.plot),
    optional_path!("plot_motors", outputs.plot_motors),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{ReplayConfig, RetimeConfig, ShapeConfig, WaveConfig};

    #[test]
    fn every_field_resets_to_its_default() {
        for motion in [
            Motion::Wave(WaveConfig::default()),
            Motion::Replay(ReplayConfig::new("q.npy")),
            Motion::Shape(ShapeConfig::new(Shape::Circle)),
            Motion::Retime(RetimeConfig::new("q.npy")),
        ] {
            let fresh = RunConfig::new(motion.clone());
            for name in names(&motion) {
                if matches!(name, "q_traj" | "shape") {
                    continue;
                }
                let mut c = fresh.clone();
                c.set(name, Value::Default).unwrap();
                assert_eq!(c, fresh, "{name}");
            }
        }
    }

    #[test]
    fn fields_are_set_by_name_and_refused_by_kind_and_command() {
        let mut c = RunConfig::new(Motion::Wave(WaveConfig::default()));
        c.set("dt", Value::Number(1e-3)).unwrap();
        c.set("kp", Value::Text("auto,2".into())).unwrap();
        c.set("center", Value::Text("mid".into())).unwrap();
        assert_eq!((c.control.dt, c.control.kp.clone()), (1e-3, vec![None, Some(2.0)]));
        let message = |e: Error| e.to_string();
        assert_eq!(
            message(c.set("dt", Value::Text("x".into())).unwrap_err()),
            "`dt`: 'x' is not a number"
        );
        assert!(message(c.set("traj_period", Value::Number(1.0)).unwrap_err()).contains("not an option of wave"));
        assert!(message(c.set("dtt", Value::Number(1.0)).unwrap_err()).starts_with("`dtt`: is not an option"));
        assert!(message(c.set("kp", Value::Text("1,,3".into())).unwrap_err()).contains("J2 is empty"));
        let points = field("shape_points").unwrap();
        let mut s = RunConfig::new(Motion::Shape(ShapeConfig::new(Shape::Sine)));
        points.set_number(&mut s, 60.0).unwrap();
        assert!(points.set_number(&mut s, 60.5).is_err());
        assert!(points.set_number(&mut c, 60.0).is_err());
        let mut r = RunConfig::new(Motion::Retime(RetimeConfig::new("q.npy")));
        r.set("grid", Value::Count(50)).unwrap();
        r.set("margin", Value::Number(0.2)).unwrap();
        r.set("traj_period", Value::Number(2.0)).unwrap();
        let Motion::Retime(rc) = &r.motion else { unreachable!() };
        assert_eq!((rc.grid, rc.margin, rc.path.traj_period), (50, 0.2, 2.0));
        assert!(message(r.set("duration", Value::Number(1.0)).unwrap_err()).contains("not an option of retime"));
        assert!(message(c.set("margin", Value::Number(0.2)).unwrap_err()).contains("not an option of wave"));
    }
}
