//! A recorded `sensor_msgs/msg/JointState` stream as a trajectory: the conversion every
//! container calls (an MCAP topic, a rosbag2 folder, a ROS 1 bag, a YAML or JSON echo), given
//! the messages of one topic with the times their container logged them.
//!
//! Every message is a point: its header stamp the time (from the first stamp), its positions,
//! and its velocities when every message has them.

use std::path::Path;

use super::invalid;
use super::ros::JointStateMsg;
use crate::error::Result;
use crate::traj::timed::seconds_from_nanoseconds;
use crate::traj::{TimedTrajectory, TrajectoryPoint};

/// One JointState message of a topic, and when its container logged it (ns since the epoch,
/// `None` for a container that keeps no log time, such as a `ros2 topic echo`).
#[derive(Clone, Debug, PartialEq)]
pub struct StampedState {
    /// The container's log (receive) time, ns.
    pub log_time: Option<u64>,
    /// The message.
    pub message: JointStateMsg,
}

/// A recorded stream as a trajectory, with what the conversion noticed.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    /// The recorded motion (unchecked).
    pub trajectory: TimedTrajectory,
}

/// The JointState messages `states` of `topic` (in the order the container logged them) as a
/// trajectory: the first message's joints, each later message's values put in that order; its
/// velocities when every message has them. `path` names the file in errors.
pub fn recorded_motion(states: Vec<StampedState>, topic: &str, path: &Path) -> Result<Recording> {
    let Some(first) = states.first() else {
        return Err(invalid(path, format!("topic {topic} has no messages")));
    };
    let start = first.message.header.stamp.nanoseconds();
    let names = first.message.name.clone();
    let with_velocity = states.iter().all(|s| !s.message.velocity.is_empty());
    let mut points = Vec::with_capacity(states.len());
    for (k, s) in states.iter().enumerate() {
        let s = &s.message;
        let bad = |what: String| invalid(path, format!("topic {topic}, message {}: {what}", k + 1));
        if s.position.len() != s.name.len() {
            return Err(bad(format!(
                "{} positions for {} joint names",
                s.position.len(),
                s.name.len()
            )));
        }
        if with_velocity && s.velocity.len() != s.name.len() {
            return Err(bad(format!(
                "{} velocities for {} joint names",
                s.velocity.len(),
                s.name.len()
            )));
        }
        let order = (names.iter())
            .map(|n| s.name.iter().position(|m| m == n))
            .collect::<Option<Vec<_>>>()
            .filter(|_| s.name.len() == names.len())
            .ok_or_else(|| {
                bad(format!(
                    "names the joints {:?}; the first message names {names:?}",
                    s.name
                ))
            })?;
        points.push(TrajectoryPoint {
            // from the first stamp in whole nanoseconds: an absolute stamp in s would round to 0.2 µs
            time_from_start: seconds_from_nanoseconds(s.header.stamp.nanoseconds() - start),
            positions: order.iter().map(|&i| s.position[i]).collect(),
            velocities: match with_velocity {
                true => order.iter().map(|&i| s.velocity[i]).collect(),
                false => Vec::new(),
            },
            accelerations: Vec::new(),
        });
    }
    Ok(Recording {
        trajectory: TimedTrajectory {
            joint_names: names,
            points,
        },
    })
}
