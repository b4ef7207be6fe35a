//! `.json`: the messages of the YAML form as JSON (one message, or an array of them), read and
//! written with serde_json (floats to the last bit); what a message holds is read by
//! `messages.rs`.

use std::path::Path;

use serde::de::DeserializeOwned;
use serde_json::Value;

use super::bounded::{self, Budget, Tree};
use super::messages::{self, Document};
use super::ros::JointTrajectoryMsg;
use super::{Read, Selection, invalid};
use crate::error::{Result, file_words, quoted};
use crate::traj::TimedTrajectory;

/// The trajectory `selection` picks from a JSON text (one message, or an array of messages),
/// unchecked. Its values are counted as they are built ([`bounded::tree`]).
pub fn parse(text: &str, selection: &Selection, path: &Path) -> Result<Read> {
    let (mut parser, budget) = (serde_json::Deserializer::from_str(text), Budget::default());
    let value: Value = bounded::tree(&mut parser, &budget)
        .and_then(|value| parser.end().map(|()| value))
        .map_err(|e| match budget.refusal() {
            Some(refusal) => invalid(path, refusal),
            None => invalid(path, format!("not JSON: {}", file_words(&e.to_string()))),
        })?;
    let documents: Vec<(String, Value)> = match value {
        Value::Array(items) => (items.into_iter().enumerate())
            .map(|(i, item)| (format!("message {}", i + 1), item))
            .collect(),
        value => vec![("the message".to_string(), value)],
    };
    messages::read(&documents, selection, path)
}

impl Document for Value {
    fn keys(&self) -> Option<Vec<String>> {
        Some(self.as_object()?.keys().cloned().collect())
    }

    fn field(&self, key: &str) -> Option<&Value> {
        self.as_object()?.get(key)
    }

    fn items(&self) -> Option<&[Value]> {
        self.as_array().map(Vec::as_slice)
    }

    fn decode<T: DeserializeOwned>(&self) -> std::result::Result<T, String> {
        T::deserialize(self).map_err(|e| file_words(&e.to_string()))
    }
}

impl Tree for Value {
    fn null() -> Self {
        Value::Null
    }

    fn bool(b: bool) -> Self {
        Value::Bool(b)
    }

    fn int(i: i64) -> Self {
        Value::from(i)
    }

    fn uint(u: u64) -> Self {
        Value::from(u)
    }

    fn float(x: f64) -> Self {
        Value::from(x)
    }

    fn string(s: String) -> Self {
        Value::String(s)
    }

    fn seq(items: Vec<Self>) -> Self {
        Value::Array(items)
    }

    fn map(entries: Vec<(Self, Self)>) -> std::result::Result<Self, String> {
        let mut map = serde_json::Map::new();
        for (key, value) in entries {
            let Value::String(key) = key else {
                return Err("a key that is not a string".into());
            };
            if map.contains_key(&key) {
                return Err(format!("the key {} is given twice", quoted(&key)));
            }
            map.insert(key, value);
        }
        Ok(Value::Object(map))
    }

    fn tagged(_: String, _: Self) -> Option<Self> {
        None
    }
}

/// `trajectory` as one JointTrajectory message (header stamp 0, empty efforts, times in whole
/// nanoseconds), pretty-printed.
pub fn to_string(trajectory: &TimedTrajectory, path: &Path) -> Result<String> {
    let msg = JointTrajectoryMsg::of(trajectory)
        .ok_or_else(|| invalid(path, "a time is beyond the ±68 years a ROS Duration holds"))?;
    let mut text = serde_json::to_string_pretty(&msg).map_err(|e| invalid(path, e.to_string()))?;
    text.push('\n');
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_message_or_an_array() {
        let one = r#"{"joint_names": ["a"], "points": [
            {"positions": [1], "time_from_start": {"sec": 0, "nanosec": 5}},
            {"positions": [2], "time_from_start": 0.5}]}"#;
        let at = |message: Option<usize>| Selection {
            message,
            ..Default::default()
        };
        let t = parse(one, &at(None), Path::new("t.json")).unwrap().trajectory;
        assert_eq!(t.points[0].time_from_start, 5e-9);
        assert_eq!(t.points[1].positions, [2.0]);
        let many = format!("[{one}, {}]", one.replace("[2]", "[7]"));
        let t = parse(&many, &at(Some(2)), Path::new("t.json")).unwrap().trajectory;
        assert_eq!(t.points[1].positions, [7.0]);
        let e = parse("{\"points\": 1}", &at(None), Path::new("t.json"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.json: the message is not a trajectory_msgs/msg/JointTrajectory"),
            "{e}"
        );
    }
}
