//! `.json`: the messages of the YAML form as JSON (one message, or an array of them), read and
//! written with serde_json (floats to the last bit); what a message holds is read by
//! `messages.rs`.

use std::path::Path;

use serde::de::DeserializeOwned;
use serde_json::Value;

use super::messages::{self, Document};
use super::ros::JointTrajectoryMsg;
use super::{Read, Selection, invalid};
use crate::error::Result;
use crate::traj::TimedTrajectory;

/// The trajectory `selection` picks from a JSON text (one message, or an array of messages),
/// unchecked.
pub fn parse(text: &str, selection: &Selection, path: &Path) -> Result<Read> {
    let value: Value = serde_json::from_str(text).map_err(|e| invalid(path, format!("not JSON: {e}")))?;
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
        serde_json::from_value(self.clone()).map_err(|e| e.to_string())
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
