//! What a YAML or JSON document holds, by its fields, whichever format it came in
//! ([`Document`]): a `trajectory_msgs/JointTrajectory`, or one inside the messages that carry
//! one — a `control_msgs/FollowJointTrajectory` goal (`trajectory:`), a MoveIt
//! `RobotTrajectory` (`joint_trajectory:`), `DisplayTrajectory` (`trajectory: [...]`, each a
//! trajectory of the file), `MotionPlanResponse` or `MoveGroup` result (`planned_trajectory:`)
//! — or a `sensor_msgs/JointState` (a recorded stream, all the file's documents together).
//! ROS 2 and ROS 1 layouts alike ([`super::ros::LooseTime`]). Anything else is named for what it
//! is: a ROS parameter file, a `MultiDOFJointTrajectory`, a message of another type.

use std::path::Path;

use serde::de::DeserializeOwned;

use super::joint_states::{StampedState, recorded_motion};
use super::ros::{LooseJointState, LooseJointTrajectory};
use super::{Note, Read, Selection, invalid, pick};
use crate::error::{Error, Result, quoted};

/// A parsed YAML or JSON value: a format's own tree, seen through what reading a message needs.
pub(super) trait Document: Sized {
    /// A mapping's keys (those that are strings); `None` when it is not a mapping.
    fn keys(&self) -> Option<Vec<String>>;
    /// A mapping's field.
    fn field(&self, key: &str) -> Option<&Self>;
    /// A sequence's items; `None` when it is not a sequence.
    fn items(&self) -> Option<&[Self]>;
    /// The value as `T`, or the deserializer's error.
    fn decode<T: DeserializeOwned>(&self) -> std::result::Result<T, String>;
}

/// What faze4 reads from YAML and JSON, for the messages that name what a file is instead.
const READS: &str = "faze4 reads a trajectory_msgs/JointTrajectory, a FollowJointTrajectory goal (`trajectory:`), a MoveIt RobotTrajectory (`joint_trajectory:`) or DisplayTrajectory, or sensor_msgs/JointState messages";

/// A message found in a document.
enum Found<'a, D> {
    /// A JointTrajectory, and the `multi_dof_joint_trajectory` with points beside it (a
    /// MoveIt `RobotTrajectory`'s), which is not played.
    Trajectory(&'a D, Option<&'a D>),
    /// A JointState.
    State(&'a D),
}

/// The trajectory `selection` picks from `documents` (each with the label its errors name it
/// by, `document 2`), unchecked: the `message`-th trajectory of the file (`None`: the first),
/// or, when the documents are JointState messages, the recorded stream they make
/// ([`recorded_motion`]).
pub(super) fn read<D: Document>(documents: &[(String, D)], selection: &Selection, path: &Path) -> Result<Read> {
    let (mut trajectories, mut states) = (Vec::new(), Vec::new());
    for (label, document) in documents {
        for found in find(document).map_err(|what| invalid(path, format!("{label} is {what}; {READS}")))? {
            match found {
                Found::Trajectory(t, multi) => trajectories.push((label, t, multi)),
                Found::State(s) => states.push((label, s)),
            }
        }
    }
    if !states.is_empty() {
        if let Some((label, _, _)) = trajectories.first() {
            return Err(invalid(
                path,
                format!("holds JointState messages and a trajectory ({label}): one file, one of them"),
            ));
        }
        if selection.message.is_some() {
            return Err(Error::option(
                "message",
                format!(
                    "{} holds JointState messages: together they are one recorded motion",
                    path.display()
                ),
            ));
        }
        let states = (states.iter())
            .map(|(label, s)| {
                known_fields(*s, JOINT_STATE, label, path)?;
                let state: LooseJointState = decode(*s, label, "sensor_msgs/msg/JointState", path)?;
                let message = state.into_message().ok_or_else(|| {
                    invalid(
                        path,
                        format!("{label}: its stamp is beyond the ±68 years a ROS time holds"),
                    )
                })?;
                Ok(StampedState {
                    log_time: None,
                    message,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let recording = recorded_motion(states, None, selection, path)?;
        return Ok(Read {
            trajectory: recording.trajectory,
            notes: recording.notes,
        });
    }
    let k = pick(trajectories.len(), selection.message, "JointTrajectory messages", path)?;
    let (label, t, multi) = trajectories[k];
    known_fields(t, JOINT_TRAJECTORY, label, path)?;
    for (i, point) in t
        .field("points")
        .and_then(|p| p.items())
        .unwrap_or_default()
        .iter()
        .enumerate()
    {
        // points counted from 0, as every other message about a trajectory's points counts them
        known_fields(point, POINT, &format!("{label}, point {i}"), path)?;
    }
    let trajectory: LooseJointTrajectory = decode(t, label, "trajectory_msgs/msg/JointTrajectory", path)?;
    let notes = match multi {
        Some(multi) => vec![Note::MultiDofLeftOut {
            label: label.clone(),
            joints: (multi.field("joint_names").and_then(|n| n.items()).unwrap_or_default())
                .iter()
                .map(|n| n.decode::<String>().unwrap_or_else(|_| "?".into()))
                .collect(),
            points: points(multi).len(),
        }],
        None => Vec::new(),
    };
    Ok(Read {
        trajectory: trajectory.into_trajectory(),
        notes,
    })
}

/// A message type's name and its fields (ROS 2's and ROS 1's).
type Fields = (&'static str, &'static [&'static str]);

/// trajectory_msgs/JointTrajectory.
const JOINT_TRAJECTORY: Fields = (
    "trajectory_msgs/msg/JointTrajectory",
    &["header", "joint_names", "points"],
);
/// trajectory_msgs/JointTrajectoryPoint.
const POINT: Fields = (
    "trajectory_msgs/msg/JointTrajectoryPoint",
    &["positions", "velocities", "accelerations", "effort", "time_from_start"],
);
/// sensor_msgs/JointState.
const JOINT_STATE: Fields = (
    "sensor_msgs/msg/JointState",
    &["header", "name", "position", "velocity", "effort"],
);

/// Refuses a field of `document` its message type does not have, naming it as the file spells
/// it and the field it likely meant: a misspelled `velocites` would otherwise be dropped, and
/// the points played linear instead of cubic, unsaid (issue 49). ROS's own `ros2 topic pub`
/// refuses such a field too.
fn known_fields<D: Document>(document: &D, (kind, fields): Fields, label: &str, path: &Path) -> Result<()> {
    let Some(unknown) = (document.keys().unwrap_or_default().into_iter()).find(|k| !fields.contains(&k.as_str()))
    else {
        return Ok(());
    };
    // the closest field by Jaro-Winkler similarity, if close (clap's threshold is 0.7)
    let likely = (fields.iter())
        .map(|f| (strsim::jaro_winkler(&unknown, f), f))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .filter(|(similarity, _)| *similarity > 0.8)
        .map_or(String::new(), |(_, f)| format!(": did you mean {}?", quoted(f)));
    Err(invalid(
        path,
        format!(
            "{label} has a field {} a {kind} does not have{likely} (its fields: {})",
            quoted(&unknown),
            fields.join(", ")
        ),
    ))
}

/// `value` as a `T`, the error naming the document and the type.
fn decode<T: DeserializeOwned, D: Document>(value: &D, label: &str, kind: &str, path: &Path) -> Result<T> {
    value
        .decode()
        .map_err(|e| invalid(path, format!("{label} is not a {kind}: {e}")))
}

/// The JointTrajectory and JointState messages `document` holds, or what it is instead (an
/// error completing "document K is …").
fn find<D: Document>(document: &D) -> std::result::Result<Vec<Found<'_, D>>, String> {
    let Some(keys) = document.keys() else {
        return Err(match document.items() {
            Some(_) => "a list, not a message".into(),
            None => "not a message (a single value)".into(),
        });
    };
    let has = |key: &str| keys.iter().any(|k| k == key);
    if has("joint_names") || has("points") {
        if let Some(point) = document.field("points").and_then(|p| p.items()).and_then(|p| p.first())
            && point.field("transforms").is_some()
        {
            return Err("a trajectory_msgs/MultiDOFJointTrajectory (poses of frames, not joint positions)".into());
        }
        return Ok(vec![Found::Trajectory(document, None)]);
    }
    if has("name") && has("position") {
        return Ok(vec![Found::State(document)]);
    }
    if let Some(robot) = document.field("joint_trajectory") {
        // a RobotTrajectory: its joint part (a multi-DOF part alone is not played)
        let multi = document
            .field("multi_dof_joint_trajectory")
            .filter(|m| !points(*m).is_empty());
        if points(robot).is_empty() && multi.is_some() {
            return Err("a moveit_msgs/RobotTrajectory with only a multi_dof_joint_trajectory (poses of frames, not joint positions)".into());
        }
        let found = find(robot).map_err(|what| format!("a RobotTrajectory whose joint_trajectory is {what}"))?;
        return Ok((found.into_iter())
            .map(|f| match f {
                Found::Trajectory(t, None) => Found::Trajectory(t, multi),
                other => other,
            })
            .collect());
    }
    for key in ["trajectory", "planned_trajectory"] {
        let Some(inner) = document.field(key) else { continue };
        return match inner.items() {
            // a DisplayTrajectory: each RobotTrajectory a trajectory of the file
            Some(items) => {
                let mut found = Vec::new();
                for (i, item) in items.iter().enumerate() {
                    found.extend(
                        find(item)
                            .map_err(|what| format!("a DisplayTrajectory whose trajectory {} is {what}", i + 1))?,
                    );
                }
                Ok(found)
            }
            // a FollowJointTrajectory goal, a MotionPlanResponse, a MoveGroup result
            None => find(inner).map_err(|what| format!("a message whose `{key}` is {what}")),
        };
    }
    Err(what_else(document, &keys))
}

/// Messages people save that hold no joint trajectory, by fields only they have.
const OTHERS: &[(&[&str], &str)] = &[
    (
        &["layout", "data"],
        "a std_msgs/Float64MultiArray (a forward_command_controller's command: positions without times)",
    ),
    (&["transforms"], "a tf2_msgs/TFMessage (poses of frames)"),
    (&["pose"], "a geometry_msgs/PoseStamped (a pose, not joint positions)"),
    (
        &["position", "orientation"],
        "a geometry_msgs/Pose (a pose, not joint positions)",
    ),
    (&["linear", "angular"], "a geometry_msgs/Twist"),
    (&["twist"], "a geometry_msgs/TwistStamped"),
    (
        &["reference", "feedback", "error"],
        "a control_msgs/JointTrajectoryControllerState (the controller's state at one instant)",
    ),
    (
        &["desired", "actual", "error"],
        "a control_msgs/JointTrajectoryControllerState (the controller's state at one instant)",
    ),
];

/// A trajectory's points (none when it has no list of them).
fn points<D: Document>(trajectory: &D) -> &[D] {
    trajectory.field("points").and_then(|p| p.items()).unwrap_or_default()
}

/// What a mapping with `keys` that holds no trajectory is.
fn what_else<D: Document>(document: &D, keys: &[String]) -> String {
    // a ROS 2 parameter file: `node: {ros__parameters: {...}}`, or `/**:` for every node
    let nodes: Vec<&String> = (keys.iter())
        .filter(|k| *k == "/**" || document.field(k).and_then(|v| v.field("ros__parameters")).is_some())
        .collect();
    if !nodes.is_empty() {
        return format!(
            "a ROS 2 parameter file (the parameters of {}), not a message",
            nodes.iter().map(|n| quoted(n)).collect::<Vec<_>>().join(", ")
        );
    }
    if let Some((_, what)) = OTHERS
        .iter()
        .find(|(fields, _)| fields.iter().all(|f| keys.iter().any(|k| k == f)))
    {
        return what.to_string();
    }
    format!(
        "a message faze4 does not know (its fields: {})",
        keys.iter().map(|k| quoted(k)).collect::<Vec<_>>().join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::TimedTrajectory;
    use crate::traj::files::{json, yaml};

    fn yaml_at(text: &str, message: Option<usize>) -> Result<TimedTrajectory> {
        let selection = Selection {
            message,
            ..Default::default()
        };
        yaml::parse(text, &selection, Path::new("m.yaml")).map(|r| r.trajectory)
    }

    fn yaml(text: &str) -> Result<TimedTrajectory> {
        yaml_at(text, None)
    }

    fn refusal(text: &str) -> String {
        yaml(text).unwrap_err().to_string()
    }

    /// `ros2 action send_goal`'s argument as READMEs give it: one point, no header, a
    /// `time_from_start` without `nanosec`, a trailing comma.
    #[test]
    fn a_follow_joint_trajectory_goal_with_one_point() {
        let goal = "{
  trajectory: {
    joint_names: ['shoulder_pan_joint', 'elbow_joint'],
    points: [
      { positions: [0.0, 0.2], time_from_start: { sec: 2 } },
    ]
  }
}";
        let t = yaml(goal).unwrap();
        assert_eq!(t.joint_names, ["shoulder_pan_joint", "elbow_joint"]);
        assert_eq!(t.points.len(), 1);
        assert_eq!(t.points[0].time_from_start, 2.0);
        assert_eq!(t.points[0].positions, [0.0, 0.2]);
        // a point without a time is at 0, as ros2 topic pub fills a missing field
        let t = yaml("{joint_names: [a], points: [{positions: [1]}]}").unwrap();
        assert_eq!(t.points[0].time_from_start, 0.0);
    }

    /// ROS 1's `rostopic echo`: `header.seq`, `secs`/`nsecs` padded with spaces.
    #[test]
    fn ros1_layouts() {
        let echo = "header: 
  seq: 3
  stamp: 
    secs: 0
    nsecs:         0
  frame_id: ''
joint_names: [joint1, joint2]
points: 
  - 
    positions: [0.0, 1.57]
    velocities: [0.0, 0.0]
    accelerations: []
    effort: []
    time_from_start: 
      secs: 1
      nsecs:   3327291
---
";
        let t = yaml(echo).unwrap();
        assert_eq!(t.points[0].time_from_start, 1.003327291);
        assert_eq!(t.points[0].velocities, [0.0, 0.0]);
        let e = refusal("{joint_names: [a], points: [{positions: [1], time_from_start: {sec: 1, nsecs: 5}}]}");
        assert!(
            e.contains("a time mixes ROS 2's and ROS 1's fields (sec, nsecs)"),
            "{e}"
        );
        let e = refusal("{joint_names: [a], points: [{positions: [1], time_from_start: {secs: 1, msecs: 5}}]}");
        assert!(e.contains("a time has no field 'msecs'"), "{e}");
        let e = refusal("{joint_names: [a], points: [{positions: [1], time_from_start: soon}]}");
        assert!(
            e.contains("expected a time: {sec, nanosec} (ROS 2), {secs, nsecs} (ROS 1) or a number of seconds"),
            "{e}"
        );
    }

    /// MoveIt's messages: a RobotTrajectory, a DisplayTrajectory of two (`--message` picks), a
    /// plan's result (`trajectory:` holding a RobotTrajectory), a MoveGroup result
    /// (`planned_trajectory:`).
    #[test]
    fn moveit_messages() {
        let jt = |q: f64| format!("{{joint_names: [a], points: [{{positions: [{q}], time_from_start: {{sec: 1}}}}]}}");
        let robot = |q: f64| {
            format!(
                "{{joint_trajectory: {}, multi_dof_joint_trajectory: {{joint_names: [], points: []}}}}",
                jt(q)
            )
        };
        assert_eq!(yaml(&robot(0.5)).unwrap().points[0].positions, [0.5]);
        let display = format!(
            "{{model_id: panda, trajectory: [{}, {}], trajectory_start: {{joint_state: {{name: [a], position: [0]}}}}}}",
            robot(0.5),
            robot(0.7)
        );
        assert_eq!(yaml(&display).unwrap().points[0].positions, [0.5]);
        assert_eq!(yaml_at(&display, Some(2)).unwrap().points[0].positions, [0.7]);
        let e = yaml_at(&display, Some(3)).unwrap_err().to_string();
        assert_eq!(e, "`message`: 3: m.yaml holds 2 JointTrajectory messages");
        let response = format!("{{group_name: arm, trajectory: {}, planning_time: 0.1}}", robot(0.25));
        assert_eq!(yaml(&response).unwrap().points[0].positions, [0.25]);
        let result = format!("{{error_code: {{val: 1}}, planned_trajectory: {}}}", robot(0.125));
        assert_eq!(yaml(&result).unwrap().points[0].positions, [0.125]);
        let multi = "{joint_trajectory: {joint_names: [], points: []}, multi_dof_joint_trajectory: {joint_names: [base], points: [{transforms: [{}]}]}}";
        assert!(
            refusal(multi)
                .contains("document 1 is a moveit_msgs/RobotTrajectory with only a multi_dof_joint_trajectory")
        );
    }

    /// What is not a trajectory is named for what it is, and what faze4 reads is said.
    #[test]
    fn other_files_are_named_for_what_they_are() {
        let params = "publisher_joint_trajectory_controller:
  ros__parameters:
    controller_name: joint_trajectory_controller
    goal_names: [pos1]
    pos1:
      positions: [0.785, -1.57]
";
        assert_eq!(
            refusal(params),
            format!(
                "m.yaml: document 1 is a ROS 2 parameter file (the parameters of 'publisher_joint_trajectory_controller'), not a message; {READS}"
            )
        );
        assert!(refusal("/**:\n  ros__parameters: {a: 1}\n").contains("parameter file (the parameters of '/**')"));
        assert!(refusal("{layout: {dim: []}, data: [1, 2]}").contains("document 1 is a std_msgs/Float64MultiArray"));
        assert!(
            refusal("{joint_names: [base], points: [{transforms: [], time_from_start: 1}]}")
                .contains("a trajectory_msgs/MultiDOFJointTrajectory")
        );
        assert!(
            refusal("{speed: 1, mode: fast}")
                .contains("document 1 is a message faze4 does not know (its fields: 'speed', 'mode')")
        );
        assert!(refusal("- 1\n- 2\n").contains("document 1, item 1 is not a message (a single value)"));
        assert!(refusal("{trajectory: 3}").contains("document 1 is a message whose `trajectory` is not a message"));
        let e = json::parse(
            "[{\"joint_names\": [\"a\"], \"points\": []}, {\"pose\": {}}]",
            &Selection::default(),
            Path::new("m.json"),
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("m.json: message 2 is a geometry_msgs/PoseStamped"), "{e}");
    }

    /// JointState messages of an echo are one recorded motion: no `--message`, no trajectory
    /// beside them.
    #[test]
    fn joint_state_echoes_are_a_recorded_motion() {
        let state = |sec: u32, q: f64| {
            format!(
                "header: {{stamp: {{sec: {sec}, nanosec: 0}}, frame_id: ''}}\nname: [a]\nposition: [{q}]\nvelocity: []\neffort: [.nan]\n---\n"
            )
        };
        let echo = format!("{}{}", state(100, 0.0), state(101, 0.5));
        let t = yaml(&echo).unwrap();
        assert_eq!(t.points[1].time_from_start, 1.0);
        assert_eq!(t.points[1].positions, [0.5]);
        assert!(
            yaml_at(&echo, Some(1))
                .unwrap_err()
                .to_string()
                .starts_with("`message`: m.yaml holds JointState messages")
        );
        let mixed = format!("{echo}joint_names: [a]\npoints: []\n");
        assert!(refusal(&mixed).contains("holds JointState messages and a trajectory (document 3)"));
        // ROS 1's layout and JSON
        let ros1 = "header: {seq: 7, stamp: {secs: 16, nsecs: 168000000}, frame_id: ''}\nname: [a]\nposition: [1.0]\n---\nheader: {seq: 8, stamp: {secs: 16, nsecs: 268000000}, frame_id: ''}\nname: [a]\nposition: [2.0]\n";
        let t = yaml(ros1).unwrap();
        assert_eq!(t.points[1].time_from_start, 0.1);
        let text = "[{\"header\": {\"stamp\": {\"sec\": 1}}, \"name\": [\"a\"], \"position\": [0]}, {\"header\": {\"stamp\": {\"sec\": 2}}, \"name\": [\"a\"], \"position\": [1]}]";
        let t = json::parse(text, &Selection::default(), Path::new("m.json"))
            .unwrap()
            .trajectory;
        assert_eq!(t.points[1].time_from_start, 1.0);
    }
}
