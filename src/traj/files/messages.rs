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
use super::{Read, Selection, invalid, pick};
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
    /// A JointTrajectory.
    Trajectory(&'a D),
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
                Found::Trajectory(t) => trajectories.push((label, t)),
                Found::State(s) => states.push((label, s)),
            }
        }
    }
    if !states.is_empty() {
        if let Some((label, _)) = trajectories.first() {
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
    let (label, t) = trajectories[k];
    let trajectory: LooseJointTrajectory = decode(t, label, "trajectory_msgs/msg/JointTrajectory", path)?;
    Ok(trajectory.into_trajectory().into())
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
        return Ok(vec![Found::Trajectory(document)]);
    }
    if has("name") && has("position") {
        return Ok(vec![Found::State(document)]);
    }
    if let Some(robot) = document.field("joint_trajectory") {
        // a RobotTrajectory: its joint part (a multi-DOF part alone is not played)
        let empty = |t: &D| t.field("points").and_then(|p| p.items()).is_none_or(|p| p.is_empty());
        if empty(robot) && document.field("multi_dof_joint_trajectory").is_some_and(|m| !empty(m)) {
            return Err("a moveit_msgs/RobotTrajectory with only a multi_dof_joint_trajectory (poses of frames, not joint positions)".into());
        }
        return find(robot).map_err(|what| format!("a RobotTrajectory whose joint_trajectory is {what}"));
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
