//! `.yaml`/`.yml`: messages as `ros2 topic echo` (or ROS 1's `rostopic echo`) prints them
//! (PyYAML's block style, each message followed by a line `---`), or as `ros2 topic pub` and
//! `ros2 action send_goal` take them (flow style), read with serde_norway: a JointTrajectory,
//! a message carrying one, or JointState messages (`messages.rs`). Times are
//! `{sec, nanosec}`, `{secs, nsecs}` or seconds; `header` and `effort` are ignored. The text's
//! nesting is measured by yaml-rust2's scanner before serde_norway parses it ([`nesting`]), and
//! its values are counted as they are built ([`bounded::tree`]).

use std::fmt::Write;
use std::path::Path;

use serde::de::DeserializeOwned;
use serde_norway::value::{Tag, TaggedValue};
use serde_norway::{Mapping, Number, Value};
use yaml_rust2::scanner::{Scanner, TokenType};

use super::bounded::{self, Budget, Tree};
use super::messages::{self, Document};
use super::ros::JointTrajectoryMsg;
use super::{Read, Selection, invalid};
use crate::error::{Result, file_words, quoted};
use crate::input::{MAX_TEXT_VALUES, MAX_YAML_NESTING};
use crate::traj::TimedTrajectory;

/// The trajectory `selection` picks from a YAML text (documents separated by `---`; empty
/// documents are skipped; a document that is a list holds one message per item), unchecked.
/// A text nested more than [`MAX_YAML_NESTING`] deep is refused before it is parsed.
pub fn parse(text: &str, selection: &Selection, path: &Path) -> Result<Read> {
    nesting(text, path)?;
    let budget = Budget::default();
    let mut documents = Vec::new();
    for (d, document) in serde_norway::Deserializer::from_str(text).enumerate() {
        let value = bounded::tree::<_, Value>(document, &budget).map_err(|e| match budget.refusal() {
            Some(refusal) => invalid(path, format!("document {}: {refusal}", d + 1)),
            None => invalid(
                path,
                format!("document {} is not YAML: {}", d + 1, file_words(&e.to_string())),
            ),
        })?;
        match value {
            Value::Sequence(items) => documents.extend(
                (items.into_iter().enumerate()).map(|(i, item)| (format!("document {}, item {}", d + 1, i + 1), item)),
            ),
            Value::Null => {}
            value => documents.push((format!("document {}", d + 1), value)),
        }
    }
    messages::read(&documents, selection, path)
}

/// Refuses `text` nested more than [`MAX_YAML_NESTING`] collections deep (flow and block),
/// holding more than [`MAX_TEXT_VALUES`] values (scalars, aliases and collections), or that
/// yaml-rust2's scanner cannot read, naming the line. Linear in the text: the scanner stops at
/// the first collection past the limit (libyaml's time grows as the square of the depth,
/// serde_norway's limit of 128 comes after it), and at the value past the cap (serde_norway
/// lists every event of a document, about 180 bytes each, before it builds a value).
pub fn nesting(text: &str, path: &Path) -> Result<()> {
    let mut scanner = Scanner::new(text.chars());
    let (mut depth, mut values) = (0usize, 0usize);
    loop {
        let token = scanner.next_token().map_err(|e| {
            let at = format!("line {}, column {}", e.marker().line(), e.marker().col() + 1);
            match e.info() {
                // the scanner's own limit, 255 flow collections: met first where it looks ahead
                RECURSION => invalid(path, too_deep(&at)),
                info => invalid(path, format!("not YAML: {at}: {info}")),
            }
        })?;
        let Some(token) = token else { return Ok(()) };
        match token.1 {
            TokenType::BlockSequenceStart
            | TokenType::BlockMappingStart
            | TokenType::FlowSequenceStart
            | TokenType::FlowMappingStart => {
                depth += 1;
                values += 1;
            }
            TokenType::Scalar(..) | TokenType::Alias(_) => values += 1,
            TokenType::BlockEnd | TokenType::FlowSequenceEnd | TokenType::FlowMappingEnd => {
                depth = depth.saturating_sub(1)
            }
            TokenType::StreamEnd => return Ok(()),
            _ => {}
        }
        if values > MAX_TEXT_VALUES {
            return Err(invalid(
                path,
                format!(
                    "line {}: more than {MAX_TEXT_VALUES} values (docs/development.md, Caps)",
                    token.0.line()
                ),
            ));
        }
        if depth > MAX_YAML_NESTING {
            let at = format!("line {}, column {}", token.0.line(), token.0.col() + 1);
            return Err(invalid(path, too_deep(&at)));
        }
    }
}

/// yaml-rust2's error past 255 nested flow collections.
const RECURSION: &str = "recursion limit exceeded";

/// The refusal of a text nested too deep, `at` where the scanner found it.
fn too_deep(at: &str) -> String {
    format!("{at}: collections nested more than {MAX_YAML_NESTING} deep (docs/development.md, Caps)")
}

impl Tree for Value {
    fn null() -> Self {
        Value::Null
    }

    fn bool(b: bool) -> Self {
        Value::Bool(b)
    }

    fn int(i: i64) -> Self {
        Value::Number(i.into())
    }

    fn uint(u: u64) -> Self {
        Value::Number(u.into())
    }

    fn float(x: f64) -> Self {
        Value::Number(Number::from(x))
    }

    fn string(s: String) -> Self {
        Value::String(s)
    }

    fn seq(items: Vec<Self>) -> Self {
        Value::Sequence(items)
    }

    fn map(entries: Vec<(Self, Self)>) -> std::result::Result<Self, String> {
        let mut mapping = Mapping::with_capacity(entries.len());
        for (key, value) in entries {
            if mapping.contains_key(&key) {
                let key = serde_norway::to_string(&key).unwrap_or_default();
                return Err(format!("the key {} is given twice", quoted(key.trim_end())));
            }
            mapping.insert(key, value);
        }
        Ok(Value::Mapping(mapping))
    }

    fn tagged(tag: String, value: Self) -> Option<Self> {
        Some(Value::Tagged(Box::new(TaggedValue {
            tag: Tag::new(tag),
            value,
        })))
    }
}

impl Document for Value {
    fn keys(&self) -> Option<Vec<String>> {
        let mapping = self.as_mapping()?;
        Some(mapping.keys().filter_map(|k| k.as_str().map(String::from)).collect())
    }

    fn field(&self, key: &str) -> Option<&Value> {
        self.as_mapping()?.get(key)
    }

    fn items(&self) -> Option<&[Value]> {
        self.as_sequence().map(Vec::as_slice)
    }

    fn decode<T: DeserializeOwned>(&self) -> std::result::Result<T, String> {
        T::deserialize(self).map_err(|e| file_words(&e.to_string()))
    }
}

/// `trajectory` as one JointTrajectory message the way `ros2 topic echo` prints it (header
/// stamp 0, empty efforts, times in whole nanoseconds), followed by `---`. Floats are written
/// with the fewest digits that read back to the same `f64`, always with a `.` and a signed
/// exponent (`1.0e-20`), so that PyYAML (YAML 1.1) reads them as floats too.
pub fn to_string(trajectory: &TimedTrajectory, path: &Path) -> Result<String> {
    let msg = JointTrajectoryMsg::of(trajectory)
        .ok_or_else(|| invalid(path, "a time is beyond the ±68 years a ROS Duration holds"))?;
    let mut out = String::new();
    let o = &mut out;
    let _ = write!(
        o,
        "header:\n  stamp:\n    sec: {}\n    nanosec: {}\n  frame_id: ''\n",
        msg.header.stamp.sec, msg.header.stamp.nanosec
    );
    o.push_str("joint_names:");
    list(o, "", msg.joint_names.iter().map(|n| name(n)));
    o.push_str("points:");
    if msg.points.is_empty() {
        o.push_str(" []\n");
    } else {
        o.push('\n');
    }
    for p in &msg.points {
        for (i, (key, values)) in [
            ("positions", &p.positions),
            ("velocities", &p.velocities),
            ("accelerations", &p.accelerations),
            ("effort", &p.effort),
        ]
        .into_iter()
        .enumerate()
        {
            o.push_str(if i == 0 { "- " } else { "  " });
            o.push_str(key);
            o.push(':');
            list(o, "  ", values.iter().map(|&x| float(x)));
        }
        let _ = write!(
            o,
            "  time_from_start:\n    sec: {}\n    nanosec: {}\n",
            p.time_from_start.sec, p.time_from_start.nanosec
        );
    }
    o.push_str("---\n");
    Ok(out)
}

/// A block sequence after its key (`key:` already written): ` []` when empty, else one
/// `indent- item` line per item.
fn list(out: &mut String, indent: &str, items: impl ExactSizeIterator<Item = String>) {
    if items.len() == 0 {
        out.push_str(" []\n");
        return;
    }
    out.push('\n');
    for item in items {
        let _ = writeln!(out, "{indent}- {item}");
    }
}

/// `x` as PyYAML writes a float: the shortest decimal that reads back to `x`, with a `.` in
/// the mantissa and a sign on the exponent.
fn float(x: f64) -> String {
    if !x.is_finite() {
        return match x {
            _ if x.is_nan() => ".nan".into(),
            _ if x > 0.0 => ".inf".into(),
            _ => "-.inf".into(),
        };
    }
    let text = ryu::Buffer::new().format_finite(x).to_string();
    let Some((mantissa, exponent)) = text.split_once('e') else {
        return text;
    };
    let dot = if mantissa.contains('.') { "" } else { ".0" };
    let sign = if exponent.starts_with('-') { "" } else { "+" };
    format!("{mantissa}{dot}e{sign}{exponent}")
}

/// A joint name as a YAML scalar: plain where it reads back as the same string (letters,
/// digits, `_`, `/`, `.`, `-`, not starting with a digit, `.` or `-`, not a YAML 1.1 keyword),
/// else double-quoted with JSON's escapes (valid YAML).
fn name(name: &str) -> String {
    const KEYWORDS: [&str; 11] = ["y", "n", "yes", "no", "true", "false", "on", "off", "null", "~", ""];
    let plain = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_' || c == '/')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || "_/.-".contains(c))
        && !KEYWORDS.contains(&name.to_ascii_lowercase().as_str());
    match plain {
        true => name.to_string(),
        false => serde_json::to_string(name).unwrap_or_default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_as_pyyaml_writes_them() {
        assert_eq!(float(1e-20), "1.0e-20");
        assert_eq!(float(1.5e300), "1.5e+300");
        assert_eq!(float(-0.0), "-0.0");
        assert_eq!(float(0.25), "0.25");
        for x in [1e-310, 123_456_789.123_456_79, -1.0 / 3.0, 2.5e-17, 1e16, 5e-324] {
            assert_eq!(float(x).parse::<f64>().unwrap().to_bits(), x.to_bits());
        }
    }

    #[test]
    fn names_are_quoted_where_yaml_would_read_something_else() {
        assert_eq!(name("shoulder_pan_joint"), "shoulder_pan_joint");
        assert_eq!(name("yes"), "\"yes\"");
        assert_eq!(name("1"), "\"1\"");
        assert_eq!(name("a: b"), "\"a: b\"");
    }

    /// What `ros2 topic echo /joint_trajectory` prints (Humble; two messages, the second one
    /// without velocities), and a message with times in seconds.
    const ECHOED: &str = "header:
  stamp:
    sec: 0
    nanosec: 0
  frame_id: ''
joint_names:
- shoulder_pan_joint
- elbow_joint
points:
- positions:
  - 0.0
  - -1.57
  velocities:
  - 0.0
  - 0.0
  accelerations: []
  effort: []
  time_from_start:
    sec: 0
    nanosec: 0
- positions:
  - 0.5
  - -1.2
  velocities:
  - 0.1
  - 0.2
  accelerations: []
  effort: []
  time_from_start:
    sec: 1
    nanosec: 500000000
---
joint_names: [elbow_joint, shoulder_pan_joint]
points:
- {positions: [1, 2], time_from_start: 0.25}
- {positions: [3, 4], time_from_start: 0.75}
---
";

    #[test]
    fn reads_what_ros2_topic_echo_prints() {
        let path = Path::new("echo.yaml");
        let at = |message: Option<usize>| Selection {
            message,
            ..Default::default()
        };
        let t = parse(ECHOED, &at(None), path).unwrap().trajectory;
        assert_eq!(t.joint_names, ["shoulder_pan_joint", "elbow_joint"]);
        assert_eq!(t.points[1].time_from_start, 1.5);
        assert_eq!(t.points[1].positions, [0.5, -1.2]);
        assert_eq!(t.points[1].velocities, [0.1, 0.2]);
        let second = parse(ECHOED, &at(Some(2)), path).unwrap().trajectory;
        assert_eq!(second.points[1].positions, [3.0, 4.0]);
        assert_eq!(second.points[1].time_from_start, 0.75);
        let e = parse(ECHOED, &at(Some(3)), path).unwrap_err().to_string();
        assert_eq!(e, "`message`: 3: echo.yaml holds 2 JointTrajectory messages");
        let e = parse("joint_names: [a]\npoints: 3\n", &at(None), path)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("echo.yaml: document 1 is not a trajectory_msgs/msg/JointTrajectory"),
            "{e}"
        );
    }
}
