//! Options given as objects (Python's keywords), decided in plain Rust: the Python binding reads
//! each keyword's value into an [`Object`] (a tree of what the value is: `None`, a bool, a
//! number, a string, a path, a dict, a list, a numpy array's shape and items), stopping where
//! [`Reading`] says, and [`run_config`] makes the configuration of it. Nothing here knows
//! PyO3: the fuzz target `python_conversion` (`faze4::fuzzing`) builds such trees from bytes
//! and runs the same code.
//!
//! What is decided here: the type each option's kind takes (another type is a
//! [`Refusal::Type`], Python's `TypeError`), a motors dict's conversion to the motors file's
//! schema, and the caps: at most [`MAX_NESTING`] levels (a dict holding itself crashed the
//! interpreter, issue 49) and [`MAX_OBJECT_VALUES`] values read for one keyword.

use std::borrow::Cow;
use std::path::PathBuf;

use super::fields::{Kind, Value, any_field};
use super::{Command, MotorEntry, Motors, RunConfig};
use crate::choice::Choice;
use crate::error::{Error, Words};

/// Deepest nesting read from one keyword's value (a dict, a list, …): a motors dict holding
/// itself, or 20,000 nested ones, crashed the interpreter (the conversion recursed). The
/// motors file's schema nests 3 deep (`{"joint": [{"kind": ...}]}`).
pub const MAX_NESTING: usize = 32;

/// Most values (each dict, list, key's value, number, string alike) read from one keyword's
/// value: about as many as a motors file at its cap ([`crate::input::MAX_MOTORS_BYTES`], 1 MiB)
/// could hold. A per-joint option or a motors dict needs a few dozen.
pub const MAX_OBJECT_VALUES: usize = 1 << 20;

/// What a Python value is, as the conversion reads it.
#[derive(Clone, Debug, PartialEq)]
pub enum Object {
    /// `None`.
    None,
    /// A `bool` or a numpy `bool_`.
    Bool(bool),
    /// A whole number that fits an `i128` (Python `int`, numpy integers).
    Int(i128),
    /// Any other real number (`float`, numpy floats, an `int` beyond `i128`, a 0-d array).
    Float(f64),
    /// A `str`.
    Str(String),
    /// An `os.PathLike` that is not a `str` (`pathlib.Path`).
    Path(PathBuf),
    /// A `dict`: each key as `str()` writes it, with its value.
    Dict(Vec<(String, Object)>),
    /// A `list` or a `tuple`.
    List(Vec<Object>),
    /// A numpy array of at least one dimension: its shape and its items along the first axis.
    Array {
        /// The array's shape.
        shape: Vec<usize>,
        /// Its items (numbers, or arrays of one dimension fewer).
        items: Vec<Object>,
    },
    /// Another iterable (a generator, a `range`), read only where the keyword's kind takes
    /// one ([`Reading::iterates`]): its items.
    Iterable(Vec<Object>),
    /// Anything else: its type's name.
    Other(String),
    /// Not read: [`Reading::admit`] refused it.
    Cut(Limit),
}

/// Why a value was not read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Limit {
    /// Deeper than [`MAX_NESTING`].
    Depth,
    /// Past [`MAX_OBJECT_VALUES`].
    Count,
}

/// The caps of one keyword's reading: its reader asks [`Reading::admit`] before each value.
#[derive(Debug)]
pub struct Reading {
    values: usize,
    iterates: bool,
}

impl Reading {
    /// A reading of a value for an option of `kind`.
    pub fn new(kind: Kind) -> Self {
        Reading {
            values: 0,
            iterates: matches!(
                kind,
                Kind::Texts | Kind::Paths | Kind::PerJoint | Kind::Numbers | Kind::Center
            ),
        }
    }

    /// Whether a value `depth` levels down (0: the keyword's own) may be read; `Err`: read
    /// [`Object::Cut`] instead.
    pub fn admit(&mut self, depth: usize) -> Result<(), Limit> {
        if depth > MAX_NESTING {
            return Err(Limit::Depth);
        }
        self.values += 1;
        match self.values > MAX_OBJECT_VALUES {
            true => Err(Limit::Count),
            false => Ok(()),
        }
    }

    /// Whether an iterable that is not a list, tuple, array or dict is read, `depth` levels
    /// down: only the keyword's own value, and only for a kind that takes a sequence (a
    /// generator given for `dt` is a type error, not iterated).
    pub fn iterates(&self, depth: usize) -> bool {
        self.iterates && depth == 0
    }
}

/// One keyword as given: its name, its value's type's name (for a type error), its value.
#[derive(Clone, Debug, PartialEq)]
pub struct Keyword {
    /// The keyword (an option's name, or an old name).
    pub name: String,
    /// The Python type's name of its value (`float`, `list`, `Path`).
    pub type_name: String,
    /// Its value.
    pub value: Object,
}

/// Why a keyword was refused.
#[derive(Debug)]
pub enum Refusal {
    /// A value of a type the option does not take: Python's `TypeError`, with this line.
    Type(String),
    /// A value the option refuses (`faze4.Error`).
    Value(Error),
}

impl From<Error> for Refusal {
    fn from(e: Error) -> Self {
        Refusal::Value(e)
    }
}

/// The configuration of `command` (`wave`, `replay`, `shape`, `retime`) with `keywords`, each
/// set by name in order ([`RunConfig::set`]); its messages name options as keywords.
pub fn run_config(command: &str, keywords: &[Keyword]) -> Result<RunConfig, Refusal> {
    let Some(command) = Command::from_word(command) else {
        return Err(Refusal::Value(Error::option(
            "command",
            format!("'{command}' is not one of {}", Command::WORDS.join(", ")),
        )));
    };
    let mut config = RunConfig::new(command.motion());
    config.outputs.words = Words::Keywords;
    for keyword in keywords {
        let value = match any_field(&keyword.name) {
            Some(f) => value(keyword, f.kind)?,
            None => Value::Default,
        };
        config.set(&keyword.name, value)?;
    }
    Ok(config)
}

/// The keyword's value as a value of `kind`: `None` is the default; a value of another type is
/// a [`Refusal::Type`].
pub fn value(keyword: &Keyword, kind: Kind) -> Result<Value, Refusal> {
    let name = keyword.name.as_str();
    if let Some(limit) = cut(&keyword.value) {
        return Err(Refusal::Value(too_much(name, limit)));
    }
    let bad = || {
        Refusal::Type(format!(
            "{name}: takes {}, not {}",
            super::fields::kind_name(kind),
            keyword.type_name
        ))
    };
    let object = &keyword.value;
    Ok(match (kind, object) {
        (_, Object::None) => Value::Default,
        (Kind::Flag, Object::Bool(on)) => Value::Flag(*on),
        (Kind::Number, Object::Int(n)) => Value::Number(*n as f64),
        (Kind::Number, Object::Float(x)) => Value::Number(*x),
        (Kind::Count, Object::Int(n)) => Value::Count(
            u64::try_from(*n)
                .map_err(|_| Refusal::Value(Error::option(name, format!("{n} must be a whole number ≥ 0"))))?,
        ),
        (Kind::Text | Kind::Choice(_) | Kind::Texts, Object::Str(t)) => Value::Text(t.clone()),
        (Kind::Texts, _) => Value::Texts(
            (items(object).ok_or_else(bad)?.iter())
                .map(|item| match item {
                    Object::Str(t) => Ok(t.clone()),
                    _ => Err(bad()),
                })
                .collect::<Result<_, _>>()?,
        ),
        (Kind::Path | Kind::Motors, Object::Str(t)) => Value::Text(t.clone()),
        (Kind::Path | Kind::Paths | Kind::Motors, Object::Path(p)) => Value::Path(p.clone()),
        (Kind::Paths, Object::Str(t)) => Value::Path(t.into()),
        (Kind::Paths, _) => Value::Paths(
            (items(object).ok_or_else(bad)?.iter())
                .map(|item| match item {
                    Object::Str(t) => Ok(PathBuf::from(t)),
                    Object::Path(p) => Ok(p.clone()),
                    _ => Err(bad()),
                })
                .collect::<Result<_, _>>()?,
        ),
        (Kind::PerJoint | Kind::Numbers | Kind::Center, Object::Str(t)) => Value::Text(t.clone()),
        (Kind::PerJoint | Kind::Numbers | Kind::Center, _) => Value::PerJoint(per_joint(name, object, bad)?),
        (Kind::Motors, Object::Dict(_)) => Value::Motors(Motors::Entries(motor_entries(object)?)),
        _ => return Err(bad()),
    })
}

/// The first limit a reading met in `object`, if any.
fn cut(object: &Object) -> Option<Limit> {
    match object {
        Object::Cut(limit) => Some(*limit),
        Object::Dict(entries) => entries.iter().find_map(|(_, v)| cut(v)),
        Object::List(items) | Object::Array { items, .. } | Object::Iterable(items) => items.iter().find_map(cut),
        _ => None,
    }
}

/// The error of a value cut by `limit` for keyword `name`.
fn too_much(name: &str, limit: Limit) -> Error {
    match limit {
        Limit::Depth => nested_too_deep(name),
        Limit::Count => Error::option(name, format!("holds more than {MAX_OBJECT_VALUES} values")),
    }
}

/// The error of a value nested deeper than [`MAX_NESTING`].
fn nested_too_deep(name: &str) -> Error {
    let schema = match name {
        "motors" => "; a motors dict is {\"joint\": [{...}, ...]}",
        _ => "",
    };
    Error::option(
        name,
        format!("nested more than {MAX_NESTING} deep (a dict or list holding itself?){schema}"),
    )
}

/// The items of a sequence, borrowed (a dict's: its keys, as Python iterates it); `None` for a
/// value that is not one.
fn items(object: &Object) -> Option<Cow<'_, [Object]>> {
    match object {
        Object::List(items) | Object::Array { items, .. } | Object::Iterable(items) => Some(Cow::Borrowed(items)),
        Object::Dict(entries) => Some(Cow::Owned(
            entries.iter().map(|(k, _)| Object::Str(k.clone())).collect(),
        )),
        _ => None,
    }
}

/// One value per joint from a sequence or a 1-D array of numbers (None: keep a joint's own).
fn per_joint(name: &str, object: &Object, bad: impl Fn() -> Refusal) -> Result<Vec<Option<f64>>, Refusal> {
    if let Object::Array { shape, .. } = object
        && shape.len() != 1
    {
        return Err(Refusal::Value(Error::option(
            name,
            format!("shape {shape:?}; expected one value per joint"),
        )));
    }
    (items(object).ok_or_else(&bad)?.iter())
        .map(|item| match item {
            Object::None => Ok(None),
            Object::Int(n) => Ok(Some(*n as f64)),
            Object::Float(x) => Ok(Some(*x)),
            _ => Err(bad()),
        })
        .collect()
}

/// A motors dict (`{"joint": [{...}, ...]}`, the motors file's schema) as its entries.
fn motor_entries(object: &Object) -> Result<Vec<MotorEntry>, Refusal> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Table {
        joint: Vec<MotorEntry>,
    }
    let json = to_json(object, 0)?;
    serde_json::from_value::<Table>(json)
        .map(|t| t.joint)
        .map_err(|e| Refusal::Value(Error::option("motors", crate::error::file_words(&e.to_string()))))
}

/// A motors dict's value, `depth` deep in the dict, as JSON; deeper than [`MAX_NESTING`] is an
/// error.
fn to_json(object: &Object, depth: usize) -> Result<serde_json::Value, Refusal> {
    use serde_json::Value as J;
    if depth > MAX_NESTING {
        return Err(Refusal::Value(nested_too_deep("motors")));
    }
    Ok(match object {
        Object::None => J::Null,
        Object::Bool(on) => J::Bool(*on),
        Object::Str(s) => J::String(s.clone()),
        Object::Dict(entries) => {
            let mut map = serde_json::Map::new();
            for (k, v) in entries {
                map.insert(k.clone(), to_json(v, depth + 1)?);
            }
            J::Object(map)
        }
        Object::List(items) | Object::Array { items, .. } => J::Array(
            (items.iter())
                .map(|i| to_json(i, depth + 1))
                .collect::<Result<_, _>>()?,
        ),
        Object::Int(n) => match i64::try_from(*n) {
            Ok(i) => J::from(i),
            Err(_) => number(*n as f64)?,
        },
        Object::Float(x) => number(*x)?,
        Object::Cut(limit) => return Err(Refusal::Value(too_much("motors", *limit))),
        Object::Path(_) | Object::Iterable(_) | Object::Other(_) => {
            return Err(Refusal::Type(format!(
                "motors: a value of type {} is not a string, number, boolean, list or dict",
                type_name(object)
            )));
        }
    })
}

/// A finite number as JSON.
fn number(x: f64) -> Result<serde_json::Value, Refusal> {
    serde_json::Number::from_f64(x)
        .map(serde_json::Value::Number)
        .ok_or_else(|| Refusal::Value(Error::option("motors", format!("{x} is not a finite number"))))
}

/// The Python type's name of a value the motors conversion does not take.
fn type_name(object: &Object) -> &str {
    match object {
        Object::Other(name) => name,
        Object::Path(_) => "PathLike",
        _ => "iterable",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn given(name: &str, value: Object) -> Keyword {
        Keyword {
            name: name.into(),
            type_name: "x".into(),
            value,
        }
    }

    fn refusal(command: &str, keywords: &[Keyword]) -> String {
        match run_config(command, keywords) {
            Ok(_) => panic!("accepted"),
            Err(Refusal::Type(line)) => format!("TypeError: {line}"),
            Err(Refusal::Value(e)) => crate::error::in_words(&e.to_string(), Words::Keywords),
        }
    }

    /// A list nested `depth` deep around a number.
    fn nested(depth: usize) -> Object {
        (0..depth).fold(Object::Float(1.0), |inner, _| Object::List(vec![inner]))
    }

    #[test]
    fn a_motors_dict_converts_to_the_files_entries() {
        let entry = Object::Dict(vec![
            ("name".into(), Object::Str("joint_1".into())),
            ("kind".into(), Object::Str("dc".into())),
            ("stall_torque".into(), Object::Int(2)),
            ("no_load_speed".into(), Object::Float(30.0)),
            ("gear_ratio".into(), Object::Int(1 << 70)),
        ]);
        let motors = Object::Dict(vec![("joint".into(), Object::List(vec![entry]))]);
        let config = run_config("wave", &[given("motors", motors)]).unwrap();
        let Some(Motors::Entries(entries)) = config.arm.motors else {
            panic!("{:?}", config.arm.motors)
        };
        assert_eq!(entries.len(), 1);
        assert_eq!(entries[0].name.as_deref(), Some("joint_1"));
        assert_eq!(entries[0].figures.get("kind"), Some(&serde_json::json!("dc")));
        assert_eq!(
            entries[0].figures.get("stall_torque").and_then(|v| v.as_f64()),
            Some(2.0)
        );
        assert_eq!(entries[0].gear_ratio, Some((1u128 << 70) as f64));
    }

    #[test]
    fn nesting_past_the_cap_is_refused_as_read_or_as_built() {
        let deep = |object| Object::Dict(vec![("joint".into(), object)]);
        // 32 levels in all: the dict, the list of 30 lists, the number
        let ok = refusal("wave", &[given("motors", deep(nested(30)))]);
        assert!(ok.starts_with("motors: invalid type"), "{ok}");
        for value in [deep(nested(32)), deep(Object::Cut(Limit::Depth))] {
            assert_eq!(
                refusal("wave", &[given("motors", value)]),
                "motors: nested more than 32 deep (a dict or list holding itself?); a motors dict is {\"joint\": [{...}, ...]}"
            );
        }
        let cut = Object::List(vec![Object::Float(1.0), Object::Cut(Limit::Count)]);
        assert_eq!(
            refusal("wave", &[given("kp", cut)]),
            "kp: holds more than 1048576 values"
        );
        let mut reading = Reading::new(Kind::Number);
        assert_eq!(reading.admit(MAX_NESTING), Ok(()));
        assert_eq!(reading.admit(MAX_NESTING + 1), Err(Limit::Depth));
        assert!(!reading.iterates(0), "a number's value is not iterated");
        let mut reading = Reading::new(Kind::PerJoint);
        assert!(reading.iterates(0) && !reading.iterates(1));
        let admitted = (0..MAX_OBJECT_VALUES + 1).filter(|_| reading.admit(1).is_ok()).count();
        assert_eq!(admitted, MAX_OBJECT_VALUES);
    }

    #[test]
    fn each_kind_takes_its_types_and_refuses_others() {
        let config = run_config(
            "wave",
            &[
                given("dt", Object::Int(1)),
                given("dt", Object::Float(0.001)),
                given(
                    "kp",
                    Object::Array {
                        shape: vec![2],
                        items: vec![Object::Float(1.0), Object::None],
                    },
                ),
            ],
        )
        .unwrap();
        assert_eq!(config.control.dt, 0.001);
        assert_eq!(
            refusal("wave", &[given("dt", Object::Bool(true))]),
            "TypeError: dt: takes a number, not x"
        );
        assert_eq!(
            refusal("wave", &[given("kp", Object::List(vec![Object::Str("1".into())]))]),
            "TypeError: kp: takes one value per joint, not x"
        );
        let table = Object::Array {
            shape: vec![1, 2],
            items: vec![],
        };
        assert_eq!(
            refusal("wave", &[given("kp", table)]),
            "kp: shape [1, 2]; expected one value per joint"
        );
        assert!(refusal("wave", &[given("motors", Object::Other("set".into()))]).starts_with("TypeError: motors:"));
        let path = Object::Dict(vec![("joint".into(), Object::Path("a".into()))]);
        assert!(refusal("wave", &[given("motors", path)]).starts_with("TypeError: motors: a value of type PathLike"),);
        assert_eq!(
            refusal("walk", &[]),
            "command: 'walk' is not one of wave, replay, shape, retime"
        );
        assert!(refusal("wave", &[given("colour", Object::None)]).starts_with("colour: is not an option of wave"));
    }
}
