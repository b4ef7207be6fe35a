//! `.json`: a `trajectory_msgs/msg/JointTrajectory` with the fields of the YAML form (one
//! message, or an array of messages), read and written with serde_json (floats to the last bit).

use std::path::Path;

use serde::Deserialize;

use super::ros::{JointTrajectoryMsg, LooseJointTrajectory};
use super::{invalid, pick};
use crate::error::Result;
use crate::traj::TimedTrajectory;

/// One message, or several.
#[derive(Deserialize)]
#[serde(untagged)]
enum Messages {
    One(LooseJointTrajectory),
    Many(Vec<LooseJointTrajectory>),
}

/// The `message`-th (from 1; `None`: the first) JointTrajectory of a JSON text, unchecked.
pub fn parse(text: &str, message: Option<usize>, path: &Path) -> Result<TimedTrajectory> {
    let parsed: Messages = serde_json::from_str(text).map_err(|e| {
        invalid(
            path,
            format!("not a trajectory_msgs/msg/JointTrajectory (or an array of them) as JSON: {e}"),
        )
    })?;
    let mut messages = match parsed {
        Messages::One(m) => vec![m],
        Messages::Many(m) => m,
    };
    let k = pick(messages.len(), message, "JointTrajectory messages", path)?;
    Ok(messages.swap_remove(k).into_trajectory())
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
        let t = parse(one, None, Path::new("t.json")).unwrap();
        assert_eq!(t.points[0].time_from_start, 5e-9);
        assert_eq!(t.points[1].positions, [2.0]);
        let many = format!("[{one}, {}]", one.replace("[2]", "[7]"));
        let t = parse(&many, Some(2), Path::new("t.json")).unwrap();
        assert_eq!(t.points[1].positions, [7.0]);
        let e = parse("{\"points\": 1}", None, Path::new("t.json"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.json: not a trajectory_msgs/msg/JointTrajectory"),
            "{e}"
        );
    }
}
