//! Every option of a [`RunConfig`], declared once ([`FIELDS`]): its name, the kind of value it
//! takes, its default, its help, the commands that take it, and how it is set and checked.
//! Every front end reads this table: the command line builds its arguments from it (the flag
//! is the name with dashes, `--payload-kg`) and sets the configuration through
//! [`RunConfig::set`]; the Python binding takes its keywords, their defaults and docstrings from
//! it; a sweep varies its numeric fields ([`Field::set_number`]). The help names other options as
//! the library's messages do (`` `motors` ``), which each front end writes in its own words
//! ([`crate::error::in_words`]).
//!
//! Nothing here knows a front end: no flag, no parser, no default output file (the command
//! line's `faze4_trail.csv` is the binary's own).

use std::path::PathBuf;

use super::{Center, Command, DriveMode, Motion, Motors, RunConfig};
use crate::choice::Choice;
use crate::control::FeedForward;
use crate::error::{Error, Result, Words, in_words, shortest};
use crate::geometry::{ClearanceGeometry, PairFilter};
use crate::traj::Interpolation;
use crate::traj::files::Rename;
use crate::traj::files::lerobot::Units;
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
    /// One of a few words (a [`Choice`]'s).
    Choice(&'static [&'static str]),
    /// A file or directory.
    Path,
    /// Several files or directories.
    Paths,
    /// Several words or texts (a repeated option: `rename`, `xacro_arg`).
    Texts,
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
    /// Not given: the field's default (`Field::default`).
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
    /// Several texts.
    Texts(Vec<String>),
    /// One value per joint (`None`: keep the joint's own).
    PerJoint(Vec<Option<f64>>),
    /// Motors given as values.
    Motors(Motors),
}

/// A field's default, as the front ends show it and as [`Value::Default`] sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    /// None to show: off, empty, not written, or worked out by the run (the help says how).
    None,
    /// A number.
    Number(f64),
    /// A whole number.
    Count(u64),
    /// A word of the field's [`Kind::Choice`].
    Word(&'static str),
    /// A number shown as the default that the field leaves unset, the run working it out the
    /// same (a command's `duration`: [`Motion::default_duration`]).
    Computed(f64),
}

impl DefaultValue {
    /// The default as text (`8`, `0.0002`, `mesh`), `None` where there is none to show.
    pub fn shown(self) -> Option<String> {
        match self {
            DefaultValue::None => None,
            DefaultValue::Number(x) | DefaultValue::Computed(x) => Some(x.to_string()),
            DefaultValue::Count(n) => Some(n.to_string()),
            DefaultValue::Word(w) => Some(w.to_string()),
        }
    }

    /// The value [`Value::Default`] sets.
    fn value(self) -> Value {
        match self {
            DefaultValue::None | DefaultValue::Computed(_) => Value::Default,
            DefaultValue::Number(x) => Value::Number(x),
            DefaultValue::Count(n) => Value::Count(n),
            DefaultValue::Word(w) => Value::Text(w.to_string()),
        }
    }
}

/// Which commands have a field: a set of [`Command`]s.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Commands(u8);

impl Commands {
    /// `wave`.
    pub const WAVE: Commands = Commands::of(Command::Wave);
    /// `replay`.
    pub const REPLAY: Commands = Commands::of(Command::Replay);
    /// `shape`.
    pub const SHAPE: Commands = Commands::of(Command::Shape);
    /// `retime`.
    pub const RETIME: Commands = Commands::of(Command::Retime);
    /// The commands that read a trajectory file (`replay`, `retime`).
    pub const TRAJECTORY: Commands = Commands::REPLAY.and(Commands::RETIME);
    /// Every command: the options every command shares.
    pub const ALL: Commands = Commands::WAVE.and(Commands::SHAPE).and(Commands::TRAJECTORY);

    /// `command` alone.
    pub const fn of(command: Command) -> Commands {
        Commands(1 << command as u8)
    }

    /// The commands of both.
    pub const fn and(self, other: Commands) -> Commands {
        Commands(self.0 | other.0)
    }

    /// Whether `command` is one of them.
    pub fn has(self, command: Command) -> bool {
        self.0 & Commands::of(command).0 != 0
    }
}

/// A reference to a numeric field, for a sweep (`None`: the command has no such field).
type NumberSlot = fn(&mut RunConfig) -> Option<&mut f64>;

/// One option of a run, declared once: what every front end knows of it.
#[derive(Clone, Copy)]
pub struct Field {
    /// Its name (`payload_kg`): the field, Python's keyword, and with dashes the command line's
    /// flag.
    pub name: &'static str,
    /// Its old names, still read (`urdf` for `robot`): a flag's visible aliases, Python's
    /// keywords beside the name.
    pub aliases: &'static [&'static str],
    /// What it takes.
    pub kind: Kind,
    /// Which commands have it.
    pub commands: Commands,
    /// What it does, for people: one paragraph ending in a full stop, other options named as
    /// `` `field` `` ([`Field::help_in`] writes them in a front end's words).
    pub help: &'static str,
    /// How its value is written in usage lines (`E1,E2,…`; `None`: its name in capitals).
    pub value_name: Option<&'static str>,
    /// Its default.
    pub default: DefaultValue,
    /// Whether its command cannot run without it.
    pub required: bool,
    /// A one-letter name (`q` for `quiet`).
    pub short: Option<char>,
    /// The largest whole number it takes (a port's 65535).
    pub most: Option<u64>,
    /// The options it cannot be given with.
    pub conflicts: &'static [&'static str],
    /// The options it needs.
    pub requires: &'static [&'static str],
    /// What a sweep does with it (`None` for a field that is not a number, which no sweep
    /// varies; every numeric field says, a test checks).
    pub swept: Option<Swept>,
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

/// What a sweep (`--vary`, `--find`) does with a numeric field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Swept {
    /// Varied, and its values leave a run's commanded path q_cmd(t) and the times of its
    /// clearance's samples as they are (the arm's dynamics, the motors, the verdict's
    /// thresholds): the runs share the path's clearance (docs/clearance.md "Sweeps").
    KeepsPath,
    /// Varied, and its values move the command or the samples' times: each run has its own
    /// clearance.
    MovesPath,
    /// Not varied: how a run is shown (`port`), another command's (retime's `grid`), or read
    /// once for every run (a dataset's `episode`).
    Never,
}

impl Field {
    /// A field with no help, no default and no relations yet (the builders below add them).
    const fn new(
        name: &'static str,
        kind: Kind,
        commands: Commands,
        set: fn(&mut RunConfig, Value) -> Result<()>,
        number: Option<NumberSlot>,
    ) -> Field {
        Field {
            name,
            aliases: &[],
            kind,
            commands,
            help: "",
            value_name: None,
            default: DefaultValue::None,
            required: false,
            short: None,
            most: None,
            conflicts: &[],
            requires: &[],
            swept: None,
            set,
            number,
        }
    }

    const fn help(mut self, help: &'static str) -> Field {
        self.help = help;
        self
    }

    const fn old_names(mut self, names: &'static [&'static str]) -> Field {
        self.aliases = names;
        self
    }

    const fn value_name(mut self, name: &'static str) -> Field {
        self.value_name = Some(name);
        self
    }

    const fn default(mut self, default: DefaultValue) -> Field {
        self.default = default;
        self
    }

    const fn required(mut self) -> Field {
        self.required = true;
        self
    }

    const fn short(mut self, letter: char) -> Field {
        self.short = Some(letter);
        self
    }

    const fn most(mut self, most: u64) -> Field {
        self.most = Some(most);
        self
    }

    const fn conflicts(mut self, names: &'static [&'static str]) -> Field {
        self.conflicts = names;
        self
    }

    const fn requires(mut self, names: &'static [&'static str]) -> Field {
        self.requires = names;
        self
    }

    const fn swept(mut self, swept: Swept) -> Field {
        self.swept = Some(swept);
        self
    }

    /// Whether it is called `name`: its name or one of its [`Field::aliases`].
    pub fn is_called(&self, name: &str) -> bool {
        self.name == name || self.aliases.contains(&name)
    }

    /// Its help with the options it names in `words` (`--motors` or `motors`).
    pub fn help_in(&self, words: Words) -> String {
        in_words(self.help, words)
    }

    /// Whether a sweep can vary it: a number, or a whole number (`shape_points`).
    pub fn is_numeric(&self) -> bool {
        self.number.is_some() || self.kind == Kind::Count
    }

    /// Sets it to the number `x` in `config` (a sweep's value): an error for a field that is not
    /// numeric, that `config`'s command does not have, or a whole-number field given a
    /// fraction.
    pub fn set_number(&self, config: &mut RunConfig, x: f64) -> Result<()> {
        if !self.commands.has(config.motion.command()) {
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

/// The fields `command` has, in the order of `faze4 COMMAND --help`.
pub fn of(command: Command) -> impl Iterator<Item = &'static Field> {
    FIELDS.iter().filter(move |f| f.commands.has(command))
}

/// The fields every command shares (the arm, the controller, the verdict, the outputs).
pub fn shared() -> impl Iterator<Item = &'static Field> {
    FIELDS.iter().filter(|f| f.commands == Commands::ALL)
}

/// The field `command` calls `name` (its name or an old name, [`Field::aliases`]).
pub fn field(name: &str, command: Command) -> Option<&'static Field> {
    of(command).find(|f| f.is_called(name))
}

/// A field called `name` (or of that old name) of any command (the first declared).
pub fn any_field(name: &str) -> Option<&'static Field> {
    FIELDS.iter().find(|f| f.is_called(name))
}

impl RunConfig {
    /// Sets the field `name` to `value` (of the field's kind; [`Value::Default`] sets its
    /// `Field::default`). An error names the field: unknown, not an option of this command,
    /// or a value of another kind.
    pub fn set(&mut self, name: &str, value: Value) -> Result<()> {
        let command = self.motion.command();
        let Some(field) = field(name, command) else {
            let options = match any_field(name) {
                Some(_) => String::new(),
                None => format!(" (its options: {})", names(&self.motion).join(", ")),
            };
            return Err(Error::option(
                name,
                format!("is not an option of {}{options}", command.name()),
            ));
        };
        let value = match value {
            Value::Default => field.default.value(),
            given => given,
        };
        (field.set)(self, value)
    }
}

/// The names of the fields `motion`'s command has, in table order.
pub fn names(motion: &Motion) -> Vec<&'static str> {
    of(motion.command()).map(|f| f.name).collect()
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
        Value::Texts(_) => "several texts".to_string(),
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
        Kind::Texts => "texts".into(),
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

/// A wave's centre as the command line writes it: `mid`, `home`, or one value per joint.
pub fn parse_center(text: &str) -> Result<Center> {
    match text.trim() {
        "mid" => Ok(Center::Mid),
        "home" => Ok(Center::Home),
        list => (list.split(',').enumerate())
            .map(|(i, x)| {
                x.trim().parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                    Error::option(
                        "center",
                        format!(
                            "J{} value '{}' is not a finite number (or use 'mid' or 'home')",
                            i + 1,
                            x.trim()
                        ),
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()
            .map(Center::Given),
    }
}

/// An output path: the word `none` means no file, whichever front end gives it.
fn output_path(path: PathBuf) -> Option<PathBuf> {
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

/// The value a word of `T` names (`None` for [`Value::Default`]).
fn choose<T: Choice>(name: &str, value: &Value) -> Result<Option<T>> {
    match value {
        Value::Default => Ok(None),
        Value::Text(word) => T::from_word(word)
            .map(Some)
            .ok_or_else(|| wrong(name, Kind::Choice(T::WORDS), value)),
        other => Err(wrong(name, Kind::Choice(T::WORDS), other)),
    }
}

/// A path from `value` (`None` for [`Value::Default`]).
fn path(name: &str, value: Value) -> Result<Option<PathBuf>> {
    match value {
        Value::Path(p) => Ok(Some(p)),
        Value::Text(t) => Ok(Some(PathBuf::from(t))),
        Value::Default => Ok(None),
        other => Err(wrong(name, Kind::Path, &other)),
    }
}

/// A whole number from `value` (`None` for [`Value::Default`]).
fn count(name: &str, value: Value) -> Result<Option<usize>> {
    match value {
        Value::Count(n) => usize::try_from(n)
            .map(Some)
            .map_err(|_| Error::option(name, "too large")),
        Value::Default => Ok(None),
        other => Err(wrong(name, Kind::Count, &other)),
    }
}

/// A number of a field that always has one (its default is declared).
macro_rules! number {
    ($name:literal, $commands:expr, $slot:expr) => {
        Field::new(
            $name,
            Kind::Number,
            $commands,
            |c, v| {
                let slot: NumberSlot = $slot;
                let x = match v {
                    Value::Number(x) => x,
                    Value::Count(x) => x as f64,
                    other => return Err(wrong($name, Kind::Number, &other)),
                };
                *slot(c).ok_or_else(|| Error::option($name, "is not an option of this command"))? = x;
                Ok(())
            },
            Some($slot),
        )
    };
}

/// A number that may be left unset.
macro_rules! optional_number {
    ($name:literal, $commands:expr, $slot:expr) => {
        Field::new(
            $name,
            Kind::Number,
            $commands,
            |c, v| {
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
            Some(|c| {
                let slot: fn(&mut RunConfig) -> Option<&mut Option<f64>> = $slot;
                slot(c).map(|x| x.insert(0.0))
            }),
        )
    };
}

/// A flag's value for the field `name`: on or off as given, off by default.
fn flag_value(name: &str, v: Value) -> Result<bool> {
    match v {
        Value::Flag(on) => Ok(on),
        Value::Default => Ok(false),
        other => Err(wrong(name, Kind::Flag, &other)),
    }
}

/// A flag every command has.
macro_rules! flag {
    ($name:literal, $($path:ident).+) => {
        Field::new(
            $name,
            Kind::Flag,
            Commands::ALL,
            |c, v| {
                c.$($path).+ = flag_value($name, v)?;
                Ok(())
            },
            None,
        )
    };
}

/// An output file every command has (`none`: none).
macro_rules! output {
    ($name:literal, $($path:ident).+) => {
        Field::new(
            $name,
            Kind::Path,
            Commands::ALL,
            |c, v| {
                c.$($path).+ = path($name, v)?.and_then(output_path);
                Ok(())
            },
            None,
        )
    };
}

/// One value per joint, every command.
macro_rules! per_joint {
    ($name:literal, $($path:ident).+) => {
        Field::new(
            $name,
            Kind::PerJoint,
            Commands::ALL,
            |c, v| {
                c.$($path).+ = per_joint($name, v)?;
                Ok(())
            },
            None,
        )
    };
}

/// A per-joint option of `retime` alone.
macro_rules! retime_per_joint {
    ($name:literal, $field:ident) => {
        Field::new(
            $name,
            Kind::PerJoint,
            Commands::RETIME,
            |c, v| {
                let values = per_joint($name, v)?;
                if let Some(r) = retime(c) {
                    r.$field = values;
                }
                Ok(())
            },
            None,
        )
    };
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

fn shape(c: &mut RunConfig) -> Option<&mut super::ShapeConfig> {
    match &mut c.motion {
        Motion::Shape(s) => Some(s),
        _ => None,
    }
}

/// `duration` of the commands in `commands`.
const fn duration(commands: Commands) -> Field {
    optional_number!("duration", commands, |c| Some(&mut c.duration)).swept(Swept::MovesPath)
}

/// Every option of a run, by name, in the order of `faze4 COMMAND --help`: each command's own,
/// then those every command shares. `duration` is declared once per command whose default or
/// help differs.
pub const FIELDS: &[Field] = &[
    // wave
    duration(Commands::WAVE)
        .default(DefaultValue::Computed(super::DEFAULT_DURATION))
        .help("Simulated time (s)."),
    number!("freq", Commands::WAVE, |c| wave(c).map(|w| &mut w.freq))
        .swept(Swept::MovesPath)
        .default(DefaultValue::Number(super::DEFAULT_FREQ))
        .help("Angular frequency ω of the wave (rad/s, as the original)."),
    number!("amp_deg", Commands::WAVE, |c| wave(c).map(|w| &mut w.amp_deg))
        .swept(Swept::MovesPath)
        .default(DefaultValue::Number(super::DEFAULT_AMP_DEG))
        .help("Amplitude A of the revolute and continuous joints (degrees)."),
    optional_number!("amp_m", Commands::WAVE, |c| wave(c).map(|w| &mut w.amp_m))
        .swept(Swept::MovesPath)
        .help(
            "Amplitude A of the prismatic joints (m). Default: a quarter of each one's range where it has limits, else \
         0.05 m.",
        ),
    Field::new(
        "center",
        Kind::Center,
        Commands::WAVE,
        |c, v| {
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
        None,
    )
    .value_name("Q1,Q2,…|mid|home")
    .help(
        "The pose to wave about: one value per joint (rad or m), 'mid' (the middle of each limited joint's \
         range, 0 for an unlimited one) or 'home' (an MJCF model's home keyframe). Default: zero.",
    ),
    // replay and retime: the trajectory file
    Field::new(
        "q_traj",
        Kind::Path,
        Commands::TRAJECTORY,
        |c, v| {
            let Some(path) = path("q_traj", v)? else {
                return Err(wrong("q_traj", Kind::Path, &Value::Default));
            };
            if let Some(r) = replay(c) {
                r.q_traj = path;
            }
            Ok(())
        },
        None,
    )
    .required()
    .value_name("F.yaml|F.json|F.mcap|F.csv|F.npy")
    .help(
        "The trajectory: a time-stamped trajectory_msgs/JointTrajectory as .yaml (ros2 topic echo) or .json, a \
         rosbag2 .mcap (a JointTrajectory or JointState topic), a .csv (a time column t, time or time_from_start \
         and one column per joint by name), played once; or an N×dof float64/float32 .npy array of joint \
         positions (rad), N ≥ 2, evenly spaced and repeating (docs/trajectories.md). retime takes its points as \
         the path, times ignored.",
    ),
    number!("traj_period", Commands::TRAJECTORY, |c| replay(c)
        .map(|r| &mut r.traj_period))
    .swept(Swept::MovesPath)
    .default(DefaultValue::Number(super::DEFAULT_TRAJ_PERIOD))
    .help(
        ".npy: the time the N frames span (s); frame k is at k·T/(N−1), then the trajectory repeats (retime: \
             the input's own timing it reports its speed-up against).",
    ),
    Field::new(
        "message",
        Kind::Count,
        Commands::TRAJECTORY,
        |c, v| {
            let message = count("message", v)?;
            if let Some(r) = replay(c) {
                r.message = message;
            }
            Ok(())
        },
        None,
    )
    .swept(Swept::MovesPath)
    .value_name("K")
    .help(
        "Which JointTrajectory message of a .yaml, .json or .mcap file to play, counted from 1 (default: the \
         first).",
    ),
    Field::new(
        "topic",
        Kind::Text,
        Commands::TRAJECTORY,
        |c, v| {
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
        None,
    )
    .value_name("NAME")
    .help("The topic of an .mcap file (default: its one JointTrajectory topic, else its one JointState topic)."),
    Field::new(
        "rename",
        Kind::Texts,
        Commands::TRAJECTORY,
        |c, v| {
            let rules = match v {
                Value::Text(t) => Rename::parse_list(&t)?,
                Value::Texts(rules) => (rules.iter().map(|r| Rename::parse_list(r)))
                    .collect::<Result<Vec<_>>>()?
                    .concat(),
                Value::Default => Vec::new(),
                other => return Err(wrong("rename", Kind::Texts, &other)),
            };
            if let Some(r) = replay(c) {
                r.rename = rules;
            }
            Ok(())
        },
        None,
    )
    .value_name("FROM=TO")
    .help(
        "A joint-name prefix of the file renamed, FROM=TO (fr3_joint=panda_joint); repeatable, the first that fits \
         a name applies.",
    ),
    Field::new(
        "episode",
        Kind::Count,
        Commands::TRAJECTORY,
        |c, v| {
            let episode = count("episode", v)?;
            if let Some(r) = replay(c) {
                r.episode = episode;
            }
            Ok(())
        },
        None,
    )
    .swept(Swept::Never)
    .value_name("N")
    .help("A LeRobot dataset's episode, counted from 0 (default: 0)."),
    Field::new(
        "lerobot_key",
        Kind::Text,
        Commands::TRAJECTORY,
        |c, v| {
            let key = match v {
                Value::Text(t) => Some(t),
                Value::Default => None,
                other => return Err(wrong("lerobot_key", Kind::Text, &other)),
            };
            if let Some(r) = replay(c) {
                r.lerobot_key = key;
            }
            Ok(())
        },
        None,
    )
    .value_name("KEY")
    .help("A LeRobot dataset's column of joint values (default: action; e.g. observation.state)."),
    Field::new(
        "units",
        Kind::Choice(Units::WORDS),
        Commands::TRAJECTORY,
        |c, v| {
            let units = choose("units", &v)?;
            if let Some(r) = replay(c) {
                r.units = units;
            }
            Ok(())
        },
        None,
    )
    .value_name("deg|rad")
    .help(
        "What a LeRobot dataset's joint values are: deg (an arm recorded with use_degrees) or rad (default: \
         normalised −100…100, turned into radians by `calibration`).",
    ),
    Field::new(
        "calibration",
        Kind::Path,
        Commands::TRAJECTORY,
        |c, v| {
            let calibration = path("calibration", v)?;
            if let Some(r) = replay(c) {
                r.calibration = calibration;
            }
            Ok(())
        },
        None,
    )
    .value_name("FILE.json")
    .help(
        "LeRobot's calibration file of the arm that recorded a dataset (JSON, per motor drive_mode, range_min, \
         range_max): turns its normalised values into radians.",
    ),
    duration(Commands::REPLAY)
        .help("Simulated time (s); default: a time-stamped trajectory's last time, 8 s for a .npy."),
    Field::new(
        "start",
        Kind::Numbers,
        Commands::REPLAY,
        |c, v| {
            let start = match v {
                Value::Default => None,
                other => Some(all_given("start", &per_joint("start", other)?)?),
            };
            if let Motion::Replay(r) = &mut c.motion {
                r.start = start;
            }
            Ok(())
        },
        None,
    )
    .value_name("Q1,Q2,…")
    .help(
        "A time-stamped trajectory: where the arm starts, at rest, one value per joint (rad or m; default: the \
         first point's positions). A first point at t > 0 is reached from it over that time, as \
         joint_trajectory_controller plays a message from the arm's state.",
    ),
    Field::new(
        "interpolation",
        Kind::Choice(Interpolation::WORDS),
        Commands::REPLAY,
        |c, v| {
            let rule = choose("interpolation", &v)?;
            if let Motion::Replay(r) = &mut c.motion {
                r.interpolation = rule;
            }
            Ok(())
        },
        None,
    )
    .value_name("linear|cubic|quintic")
    .help(
        "A time-stamped trajectory: how its points are joined (default: as joint_trajectory_controller decides, by \
         what the points give: linear with positions, cubic with velocities, quintic with accelerations). cubic on \
         positions alone takes the velocities of the controller's positions_upsampling spline.",
    ),
    // retime
    Field::new(
        "out",
        Kind::Path,
        Commands::RETIME,
        |c, v| {
            let out = path("out", v)?;
            if let Some(r) = retime(c) {
                r.out = out;
            }
            Ok(())
        },
        None,
    )
    .value_name("F.yaml|F.json|F.mcap|F.csv")
    .help(
        "Where the timing is written, by extension: a JointTrajectory as .yaml or .json, a rosbag2 .mcap, or a \
         .csv (positions, velocities, accelerations, time from start), which `faze4 replay` plays as `q_traj`.",
    ),
    Field::new(
        "grid",
        Kind::Count,
        Commands::RETIME,
        |c, v| {
            if let (Some(n), Some(r)) = (count("grid", v)?, retime(c)) {
                r.grid = n;
            }
            Ok(())
        },
        None,
    )
    .swept(Swept::Never)
    .default(DefaultValue::Count(super::DEFAULT_GRID as u64))
    .value_name("N")
    .help("Grid intervals in s (at most 100,000): the limits are kept at the grid's points."),
    number!("margin", Commands::RETIME, |c| retime(c).map(|r| &mut r.margin))
        .swept(Swept::Never)
        .default(DefaultValue::Number(super::DEFAULT_MARGIN))
        .value_name("SHARE")
        .help(
            "The share of every torque limit (each motor's envelope at its speed, or the constant limit) left for \
             the feedback, in [0, 1).",
        ),
    Field::new(
        "attempts",
        Kind::Count,
        Commands::RETIME,
        |c, v| {
            if let (Some(n), Some(r)) = (count("attempts", v)?, retime(c)) {
                r.attempts = n;
            }
            Ok(())
        },
        None,
    )
    .swept(Swept::Never)
    .default(DefaultValue::Count(super::DEFAULT_ATTEMPTS as u64))
    .value_name("N")
    .help("Most closed-loop checks: the first timing's, then one per slowed timing."),
    Field::new(
        "force",
        Kind::Flag,
        Commands::RETIME,
        |c, v| {
            let on = flag_value("force", v)?;
            if let Some(r) = retime(c) {
                r.force = on;
            }
            Ok(())
        },
        None,
    )
    .help(
        "Write the timing (`out`) even when the checked timing does not follow; without it nothing is written then. \
         The exit status is 3 either way.",
    ),
    Field::new(
        "no_check",
        Kind::Flag,
        Commands::RETIME,
        |c, v| {
            let on = flag_value("no_check", v)?;
            if let Some(r) = retime(c) {
                r.no_check = on;
            }
            Ok(())
        },
        None,
    )
    .conflicts(&["summary", "trail", "html", "plot_motors", "view", "hold", "attempts"])
    .help(
        "No closed-loop check: the timing (kept within every limit as a controller plays it) is written unchecked, \
         faster; whether the loop follows it is not known (`faze4 replay` of `out` tells). Exit status 0 when it \
         keeps every limit as played.",
    ),
    retime_per_joint!("max_accel", max_accel).value_name("A1,A2,…").help(
        "Acceleration limits per joint, rad/s² or m/s² ('auto' or none: no limit), kept along the written trajectory \
         as a controller plays it.",
    ),
    retime_per_joint!("max_jerk", max_jerk).value_name("J1,J2,…").help(
        "Jerk limits per joint, rad/s³ or m/s³ ('auto' or none: no limit), kept along the written trajectory as a \
         controller plays it (the smoothing window widens for them).",
    ),
    retime_per_joint!("start_velocity", start_velocity).value_name("V1,V2,…").help(
        "The joint velocities the timing starts at, rad/s or m/s per joint ('auto' or none: 0; none \
         given: at rest), to chain it after another: along the path's tangent at its start and within its limits; the check's arm arrives moving.",
    ),
    retime_per_joint!("end_velocity", end_velocity).value_name("V1,V2,…").help(
        "The joint velocities the timing ends at, rad/s or m/s per joint ('auto' or none: 0; none given: \
         at rest), to chain another after it: \
         along the path's tangent at its end and within its limits.",
    ),
    // shape
    Field::new(
        "shape",
        Kind::Choice(Shape::WORDS),
        Commands::SHAPE,
        |c, v| {
            let Some(drawn) = choose::<Shape>("shape", &v)? else {
                return Err(wrong("shape", Kind::Choice(Shape::WORDS), &v));
            };
            if let Some(s) = shape(c) {
                s.shape = drawn;
            }
            Ok(())
        },
        None,
    )
    .required()
    .help("The path the tool draws on the board."),
    Field::new(
        "shape_points",
        Kind::Count,
        Commands::SHAPE,
        |c, v| {
            if let (Some(n), Some(s)) = (count("shape_points", v)?, shape(c)) {
                s.shape_points = n;
            }
            Ok(())
        },
        None,
    )
    .swept(Swept::MovesPath)
    .default(DefaultValue::Count(super::DEFAULT_SHAPE_POINTS as u64))
    .value_name("N")
    .help("Samples along the path (IK targets), played one loop every 5 s."),
    duration(Commands::SHAPE)
        .default(DefaultValue::Computed(super::DEFAULT_SHAPE_DURATION))
        .help("Simulated time (s)."),
    Field::new(
        "save_q",
        Kind::Path,
        Commands::SHAPE,
        |c, v| {
            let save_q = path("save_q", v)?.and_then(output_path);
            if let Some(s) = shape(c) {
                s.save_q = save_q;
            }
            Ok(())
        },
        None,
    )
    .value_name("F.npy")
    .help("Write the IK joint samples as an N×dof float64 .npy (numpy loads it; `faze4 replay` plays it)."),
    // every command: the arm
    Field::new(
        "robot",
        Kind::Path,
        Commands::ALL,
        |c, v| {
            c.arm.robot = path("robot", v)?;
            Ok(())
        },
        None,
    )
    .old_names(&["urdf"])
    .value_name("F.urdf|F.xacro|F.xml")
    .help(
        "The arm: a URDF, a xacro file (.urdf.xacro) or a MuJoCo MJCF model, told apart by their root element \
         (default: the bundled Faze4, urdf/faze4_arm.urdf).",
    ),
    Field::new(
        "xacro_arg",
        Kind::Texts,
        Commands::ALL,
        |c, v| {
            c.arm.xacro_arg = match v {
                Value::Texts(t) => t,
                Value::Text(t) => vec![t],
                Value::Default => Vec::new(),
                other => return Err(wrong("xacro_arg", Kind::Texts, &other)),
            };
            Ok(())
        },
        None,
    )
    .value_name("NAME:=VALUE")
    .help("A xacro file's argument, NAME:=VALUE, as xacro takes it (repeatable), e.g. ur_type:=ur5e."),
    Field::new(
        "package_path",
        Kind::Paths,
        Commands::ALL,
        |c, v| {
            c.arm.package_path = match v {
                Value::Paths(p) => p,
                Value::Path(p) => vec![p],
                Value::Text(t) => vec![PathBuf::from(t)],
                Value::Default => Vec::new(),
                other => return Err(wrong("package_path", Kind::Paths, &other)),
            };
            Ok(())
        },
        None,
    )
    .value_name("DIR")
    .help(
        "Where `package://` meshes and xacro's $(find PKG) packages are looked for (repeatable; ROS_PACKAGE_PATH is \
         searched after).",
    ),
    flag!("balance_inertia", arm.balance_inertia).help(
        "A moving body whose inertia no rigid body has (not positive definite, or its principal moments break the \
         triangle inequality) gets its principal moments set to their mean, as MuJoCo's balanceinertia does (a \
         warning per body), instead of the model being refused.",
    ),
    Field::new(
        "tool_link",
        Kind::Text,
        Commands::ALL,
        |c, v| {
            c.arm.tool_link = match v {
                Value::Text(t) => Some(t),
                Value::Default => None,
                other => return Err(wrong("tool_link", Kind::Text, &other)),
            };
            Ok(())
        },
        None,
    )
    .value_name("NAME")
    .help(
        "The link traced as the tool (default: tool_link, else the last link of a chain; on a branched tree the \
         deepest common ancestor of the deepest leaves, e.g. a hand).",
    ),
    Field::new(
        "effort",
        Kind::Numbers,
        Commands::ALL,
        |c, v| {
            c.control.effort = match v {
                Value::Default => None,
                other => Some(all_given("effort", &per_joint("effort", other)?)?),
            };
            Ok(())
        },
        None,
    )
    .value_name("E1,E2,…")
    .help(
        "Torque limits per joint, N·m (default: the Faze4 motors' for the bundled arm, else the URDF's effort \
         values).",
    ),
    per_joint!("kp", control.kp)
        .value_name("KP1,KP2,…")
        .help("Proportional gains per joint ('auto' keeps the tuned value), e.g. auto,auto,auto,auto,auto,30."),
    per_joint!("kd", control.kd)
        .value_name("KD1,KD2,…")
        .help("Derivative gains per joint ('auto' keeps the tuned value)."),
    // the motors
    Field::new(
        "motors",
        Kind::Motors,
        Commands::ALL,
        |c, v| {
            c.arm.motors = match v {
                Value::Default => None,
                Value::Motors(m) => Some(m),
                Value::Text(t) => Some(Motors::named(&t)?),
                Value::Path(p) => Some(Motors::File(p)),
                other => return Err(wrong("motors", Kind::Motors, &other)),
            };
            Ok(())
        },
        None,
    )
    .value_name("PRESET|FILE.toml")
    .help(
        "Motors behind the joints, whose torque–speed envelope clips each joint's torque at its speed: a preset \
         (faze4: 17HS16-2004S1 steppers and the Faze4's reducers; faze4-bom: the motors the Faze4 is built with; \
         sts3215: Feetech STS3215 servos, the SO-100's; xm540-w270: Dynamixel XM540-W270) or a FILE.toml \
         (docs/motors.md).",
    ),
    optional_number!("supply_voltage", Commands::ALL, |c| Some(&mut c.arm.supply_voltage))
        .swept(Swept::KeepsPath)
        .value_name("V")
        .help(
            "Supply voltage of the `motors` presets' drives, V (default: the preset's, 24 V for the Faze4's steppers).",
        ),
    Field::new(
        "drive",
        Kind::Choice(DriveMode::WORDS),
        Commands::ALL,
        |c, v| {
            c.control.drive = choose("drive", &v)?.unwrap_or_default();
            Ok(())
        },
        None,
    )
    .value_name("pd|stepper|servo")
    .help(
        "How the joints with a motor are driven: 'pd', the controller's torque clipped to the envelope (the \
         original's; the default); 'stepper', steppers open loop: the driver's microstep through the torque–angle \
         curve, slips and all; or 'servo', smart servos (the sts3215 and xm540-w270 presets) by their own position \
         loop on the goal they are sent, within their torque limit, tripping their protection (with `motors`; \
         docs/motors.md).",
    ),
    per_joint!("microsteps", control.microsteps)
        .value_name("N|N1,N2,…")
        .help(
            "Microsteps per full step of the steppers' drivers under `drive` stepper: one value for every joint or one \
         per joint ('auto' keeps the motor's: the Faze4 presets' firmware 8,8,4,2,2,2; else 16).",
        ),
    optional_number!("driver_bandwidth", Commands::ALL, |c| Some(
        &mut c.control.driver_bandwidth
    ))
    .swept(Swept::KeepsPath)
    .value_name("HZ")
    .help(
        "Under `drive` stepper, every stepper driver's current-loop bandwidth, Hz (default: the motor's; 5000 for \
             the presets' TB6600-class choppers, a stated assumption; docs/motors.md, \"The stepper's damping\").",
    ),
    per_joint!("rotor_damping", control.rotor_damping)
        .value_name("B|B1,B2,…")
        .help(
            "Under `drive` stepper, each rotor's viscous damping (iron losses, bearings), N·m·s/rad at the motor \
             shaft: one value for every joint or one per joint ('auto' keeps the motor's; the presets' 0: not \
             published).",
        ),
    per_joint!("reducer_friction", control.reducer_friction)
        .value_name("T|T1,T2,…")
        .help(
            "Under `drive` stepper, each reducer's Coulomb friction, N·m at the motor shaft: one value for every joint \
             or one per joint ('auto' keeps the motor's; the presets' 0: not published).",
        ),
    optional_number!("servo_rate", Commands::ALL, |c| Some(&mut c.control.servo_rate))
        .swept(Swept::KeepsPath)
        .value_name("HZ")
        .help(
            "Under `drive` servo, how often each servo is sent its goal, Hz: the command at that time, held until \
             the next (default: at the trajectory's own sample times, as a replay sends them; 30 for a wave, \
             LeRobot's frame rate).",
        ),
    flag!("sizing", outputs.sizing).help(
        "Print the motors' sizing report (with `motors`): per joint at the motor peak and RMS torque, peak speed, \
         inertia ratio, peak power, braking energy, supply current, heating.",
    ),
    per_joint!("rotor_inertia", arm.rotor_inertia)
        .value_name("I1,I2,…")
        .help(
            "Rotor inertia per joint, kg·m² at the motor shaft ('auto' keeps the URDF's or `motors`'); overrides the \
         URDF.",
        ),
    per_joint!("gear_ratio", arm.gear_ratio).value_name("R1,R2,…").help(
        "Gear ratio per joint, motor turns per joint turn ('auto' keeps the URDF's or `motors`'); overrides the \
         URDF.",
    ),
    per_joint!("max_speed", control.max_speed).value_name("W1,W2,…").help(
        "Speed limits per joint, rad/s or m/s ('auto' keeps the URDF's velocity; none for the bundled Faze4): \
         counted, not enforced.",
    ),
    // the controller and the step
    flag!("no_ff", control.no_ff).help("No gravity feed-forward (PD alone holds the arm up)."),
    Field::new(
        "ff",
        Kind::Choice(FeedForward::WORDS),
        Commands::ALL,
        |c, v| {
            c.control.ff = choose("ff", &v)?;
            Ok(())
        },
        None,
    )
    .value_name("gravity|full")
    .conflicts(&["no_ff"])
    .help(
        "What the controller feeds forward: 'gravity', g(q) at the measured q (the default), or 'full', the inverse \
         dynamics of the commanded q, v, a (computed torque; docs/trajectories.md).",
    ),
    flag!("no_gravity", arm.no_gravity).help("No gravity field."),
    number!("payload_kg", Commands::ALL, |c| Some(&mut c.arm.payload_kg))
        .swept(Swept::KeepsPath)
        .default(DefaultValue::Number(0.0))
        .value_name("M")
        .help("A point mass at the tool link (kg)."),
    number!("dt", Commands::ALL, |c| Some(&mut c.control.dt))
        .swept(Swept::MovesPath)
        .default(DefaultValue::Number(super::DEFAULT_DT))
        .help("Control and integration period (s); 2e-4 is 5 kHz."),
    // what a run prints
    flag!("debug", outputs.debug)
        .help("Print τ, error, velocity and g(q) with every progress line and add them to the trail."),
    flag!("quiet", outputs.quiet).short('q').help(
        "Print only the verdict, errors, and the warnings that change the result (a mesh not found, a \
         transmission skipped, an inertia balanced).",
    ),
    optional_number!("print_period", Commands::ALL, |c| Some(&mut c.outputs.print_period))
        .swept(Swept::Never)
        .value_name("S")
        .help(
            "Simulated time between progress lines (s); default 0.5 s, or longer so that a long run prints at most \
             about 40 lines.",
        ),
    // the verdict
    number!("max_saturation_pct", Commands::ALL, |c| Some(
        &mut c.verdict.thresholds.max_saturation_pct
    ))
    .swept(Swept::KeepsPath)
    .default(DefaultValue::Number(crate::sim::Thresholds::DEFAULT.max_saturation_pct))
    .value_name("PCT")
    .help("The verdict \"follows\" allows each joint to saturate at most this share of the steps (%)."),
    number!("max_error", Commands::ALL, |c| Some(
        &mut c.verdict.thresholds.max_error
    ))
    .swept(Swept::KeepsPath)
    .default(DefaultValue::Number(crate::sim::Thresholds::DEFAULT.max_error))
    .value_name("RAD")
    .help("The verdict \"follows\" allows tracking errors up to this (rad, or m for a prismatic joint)."),
    number!("max_deviation_mm", Commands::ALL, |c| Some(
        &mut c.verdict.thresholds.max_deviation_mm
    ))
    .swept(Swept::KeepsPath)
    .default(DefaultValue::Number(crate::sim::Thresholds::DEFAULT.max_deviation_mm))
    .value_name("MM")
    .help("The verdict \"follows\" allows a shape's path deviation up to this (mm)."),
    flag!("strict", verdict.strict).help(
        "Exit with status 3 when the verdict is \"cannot follow\" or \"collides\" (for CI jobs that guard a motion); \
         retime always does.",
    ),
    // the files
    output!("trail", outputs.trail)
        .value_name("F.csv")
        .help("Trail CSV (t, x, y, z, q1…); 'none' writes none."),
    output!("summary", outputs.summary)
        .value_name("F.json")
        .help("Summary JSON (the machine-readable result)."),
    number!("record_period", Commands::ALL, |c| Some(&mut c.record_period))
        .swept(Swept::MovesPath)
        .default(DefaultValue::Number(super::DEFAULT_RECORD_PERIOD))
        .value_name("S")
        .help("Time between trail rows (s)."),
    // self-clearance and self-contact
    Field::new(
        "collision_geometry",
        Kind::Choice(ClearanceGeometry::WORDS),
        Commands::ALL,
        |c, v| {
            c.clearance.collision_geometry = choose("collision_geometry", &v)?.unwrap_or_default();
            Ok(())
        },
        None,
    )
    .default(DefaultValue::Word("mesh"))
    .value_name("KIND")
    .help(
        "How self-clearance reads a collision mesh: 'mesh', its exact triangles, or 'hull', its convex hull (as \
         Drake and most simulators do; signed distances).",
    ),
    Field::new(
        "collision_pairs",
        Kind::Choice(PairFilter::WORDS),
        Commands::ALL,
        |c, v| {
            c.clearance.collision_pairs = choose("collision_pairs", &v)?.unwrap_or_default();
            Ok(())
        },
        None,
    )
    .value_name("all")
    .help(
        "Which pairs of links self-clearance checks: 'all' adds the pairs a joint connects to the default (Drake's: \
         links on different bodies not connected by a joint).",
    ),
    number!("clearance_tolerance", Commands::ALL, |c| Some(
        &mut c.clearance.clearance_tolerance
    ))
    .swept(Swept::MovesPath)
    .default(DefaultValue::Number(super::DEFAULT_CLEARANCE_TOLERANCE_MM))
    .value_name("MM")
    .help(
        "How far (mm) the reported self-clearance may be above the true minimum over the samples: it is the \
             distance of two actual parts, and the true minimum is at most this much below it. 0 is exact. \
             Intersections are decided exactly whatever it is.",
    ),
    flag!("no_collisions", clearance.no_collisions)
        .conflicts(&["collision_geometry", "collision_pairs", "clearance_tolerance"])
        .help("No self-clearance: the collision geometry is skipped altogether (its meshes not read)."),
    flag!("self_collisions", clearance.self_collisions)
        .conflicts(&["no_collisions"])
        .help(
            "Contact forces between the checked pairs of the collision geometry, solved inside the step (Drake's \
             compliant point contact; with `collision_geometry` hull the convex hulls touch, as in Drake; exact \
             meshes that intersect stop the run).",
        ),
    number!("friction", Commands::ALL, |c| Some(&mut c.clearance.friction))
        .swept(Swept::KeepsPath)
        .default(DefaultValue::Number(super::DEFAULT_FRICTION))
        .value_name("MU")
        .requires(&["self_collisions"])
        .help("Coulomb friction of `self_collisions` contacts."),
    // the views
    flag!("view", outputs.view).help("Show the run live in the browser at http://127.0.0.1:PORT, in real time."),
    Field::new(
        "port",
        Kind::Count,
        Commands::ALL,
        |c, v| {
            c.outputs.port = match v {
                Value::Count(p) => {
                    u16::try_from(p).map_err(|_| Error::option("port", format!("{p} is not a port (0 to 65535)")))?
                }
                other => return Err(wrong("port", Kind::Count, &other)),
            };
            Ok(())
        },
        None,
    )
    .swept(Swept::Never)
    .default(DefaultValue::Count(super::DEFAULT_PORT as u64))
    .most(u16::MAX as u64)
    .value_name("P")
    .help("Port of the live view (127.0.0.1 only; 0 picks a free one)."),
    flag!("hold", outputs.hold).help("Keep the live view serving after the run until Ctrl-C (implies `view`)."),
    output!("html", outputs.html)
        .value_name("F.html")
        .help("One self-contained HTML file that plays the run back offline; 'none' writes none."),
    output!("plot", outputs.plot).value_name("F.svg|F.png").help(
        "One figure of joint angles vs command, torques vs limits, tracking error (and path deviation for shapes), \
         as .svg or .png.",
    ),
    output!("plot_motors", outputs.plot_motors)
        .value_name("F.svg|F.png")
        .help(
            "The motors' sizing plot (with `motors`): per joint the operating points (|ω_m|, |τ_m|) over the \
         torque–speed envelope, the continuous torque line and the RMS point, as .svg or .png.",
        ),
];

#[cfg(test)]
mod tests {
    use super::*;

    fn motions() -> Vec<Motion> {
        Command::VALUES.iter().map(|c| c.motion()).collect()
    }

    #[test]
    fn every_field_resets_to_its_default() {
        for motion in motions() {
            let fresh = RunConfig::new(motion.clone());
            for f in of(motion.command()).filter(|f| !f.required) {
                let mut c = fresh.clone();
                c.set(f.name, Value::Default).unwrap();
                assert_eq!(c, fresh, "{}", f.name);
                // a default shown is the one a run uses
                if let Some(text) = f.default.shown() {
                    let value = match f.kind {
                        Kind::Count => Value::Count(text.parse().unwrap()),
                        Kind::Number => Value::Number(text.parse().unwrap()),
                        _ => Value::Text(text),
                    };
                    c.set(f.name, value).unwrap();
                    assert_eq!(c.duration(), fresh.duration(), "{}", f.name);
                    c.duration = fresh.duration;
                    assert_eq!(c, fresh, "{}", f.name);
                }
            }
        }
    }

    #[test]
    fn every_field_is_declared_whole_and_once_per_command() {
        for command in Command::VALUES {
            let names = names(&command.motion());
            let mut unique = names.clone();
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), names.len(), "{}", command.name());
        }
        for f in FIELDS {
            assert!(
                f.help.ends_with('.') && !f.help.contains("--"),
                "{}: {}",
                f.name,
                f.help
            );
            for name in f.conflicts.iter().chain(f.requires) {
                assert!(any_field(name).is_some(), "{}: {name}", f.name);
            }
            if let Kind::Choice(words) = f.kind
                && let Some(word) = f.default.shown()
            {
                assert!(words.contains(&word.as_str()), "{}", f.name);
            }
            // a field the help names is a field
            let mut rest = f.help;
            while let Some((_, after)) = rest.split_once('`') {
                let (quoted, next) = after.split_once('`').unwrap();
                if quoted.chars().all(|c| c.is_ascii_lowercase() || c == '_') {
                    assert!(any_field(quoted).is_some(), "{}: `{quoted}`", f.name);
                }
                rest = next;
            }
        }
    }

    #[test]
    fn fields_are_set_by_name_and_refused_by_kind_and_command() {
        let mut c = RunConfig::new(Motion::Wave(super::super::WaveConfig::default()));
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
        assert_eq!(
            message(c.set("ff", Value::Text("none".into())).unwrap_err()),
            "`ff`: 'none' is not one of gravity, full"
        );
        c.set("trail", Value::Text("none".into())).unwrap();
        assert_eq!(c.outputs.trail, None);
        let points = field("shape_points", Command::Shape).unwrap();
        let mut s = RunConfig::new(Command::Shape.motion());
        points.set_number(&mut s, 60.0).unwrap();
        assert!(points.set_number(&mut s, 60.5).is_err());
        assert!(points.set_number(&mut c, 60.0).is_err());
        s.set("shape", Value::Text("tri".into())).unwrap();
        assert!(matches!(&s.motion, Motion::Shape(s) if s.shape == Shape::Tri && s.shape_points == 60));
        let mut r = RunConfig::new(Command::Retime.motion());
        r.set("grid", Value::Count(50)).unwrap();
        r.set("margin", Value::Number(0.2)).unwrap();
        r.set("traj_period", Value::Number(2.0)).unwrap();
        let Motion::Retime(rc) = &r.motion else { unreachable!() };
        assert_eq!((rc.grid, rc.margin, rc.path.traj_period), (50, 0.2, 2.0));
        assert!(message(r.set("duration", Value::Number(1.0)).unwrap_err()).contains("not an option of retime"));
        assert!(message(c.set("margin", Value::Number(0.2)).unwrap_err()).contains("not an option of wave"));
        // each command's duration is its own declaration
        let mut p = RunConfig::new(Command::Replay.motion());
        p.set("duration", Value::Number(3.0)).unwrap();
        assert_eq!(p.duration(), 3.0);
    }
}
