//! The ROS 2 messages the trajectory files carry, field for field (`trajectory_msgs/msg/
//! JointTrajectory`, `sensor_msgs/msg/JointState`), and their conversion to and from a
//! [`TimedTrajectory`]. Times are ROS's whole nanoseconds (`sec`, `nanosec`); see
//! [`crate::traj::timed::nanoseconds`]. The messages' lists are read under caps
//! ([`super::bounded`]).

use serde::{Deserialize, Serialize};

use crate::traj::timed::{nanoseconds, ros_nanoseconds, ros_sec_nanosec, seconds_from_nanoseconds};
use crate::traj::{TimedTrajectory, TrajectoryPoint};

/// `builtin_interfaces/msg/Time` and `Duration`: seconds and nanoseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RosTime {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, 0 ≤ nanosec < 1e9.
    pub nanosec: u32,
}

impl RosTime {
    /// The time in whole nanoseconds.
    pub fn nanoseconds(self) -> i64 {
        ros_nanoseconds(self.sec as i64, self.nanosec as i64)
    }
}

/// `std_msgs/msg/Header`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// When the data were taken, or for a trajectory when it starts (0: on receipt).
    pub stamp: RosTime,
    /// The coordinate frame (unused by joint trajectories).
    pub frame_id: String,
}

/// `trajectory_msgs/msg/JointTrajectory`, its fields in the message's order (the CDR layout).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectoryMsg {
    /// The header (its stamp 0: start on receipt).
    pub header: Header,
    /// The joints, in the points' order.
    #[serde(deserialize_with = "super::bounded::names")]
    pub joint_names: Vec<String>,
    /// The points.
    #[serde(deserialize_with = "super::bounded::points")]
    pub points: Vec<JointTrajectoryPointMsg>,
}

/// `trajectory_msgs/msg/JointTrajectoryPoint`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectoryPointMsg {
    /// Positions (rad or m).
    #[serde(deserialize_with = "super::bounded::values")]
    pub positions: Vec<f64>,
    /// Velocities, or empty.
    #[serde(deserialize_with = "super::bounded::values")]
    pub velocities: Vec<f64>,
    /// Accelerations, or empty.
    #[serde(deserialize_with = "super::bounded::values")]
    pub accelerations: Vec<f64>,
    /// Efforts, or empty (read and ignored: faze4's controller makes its own torque).
    #[serde(deserialize_with = "super::bounded::values")]
    pub effort: Vec<f64>,
    /// Time since the trajectory's start.
    pub time_from_start: RosTime,
}

/// `sensor_msgs/msg/JointState`: a recorded state.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointStateMsg {
    /// Its stamp is the time of the state.
    pub header: Header,
    /// The joints.
    #[serde(deserialize_with = "super::bounded::names")]
    pub name: Vec<String>,
    /// Positions (rad or m).
    #[serde(deserialize_with = "super::bounded::values")]
    pub position: Vec<f64>,
    /// Velocities, or empty.
    #[serde(deserialize_with = "super::bounded::values")]
    pub velocity: Vec<f64>,
    /// Efforts, or empty (ignored).
    #[serde(deserialize_with = "super::bounded::values")]
    pub effort: Vec<f64>,
}

/// The ros2msg definition of `trajectory_msgs/msg/JointTrajectory` with its dependencies, as an
/// MCAP schema of encoding `ros2msg` holds it (the dependencies after lines of 80 `=`, each
/// headed `MSG: package/Type`), comments left out.
pub const JOINT_TRAJECTORY_DEFINITION: &str = "\
std_msgs/Header header
string[] joint_names
JointTrajectoryPoint[] points
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: trajectory_msgs/JointTrajectoryPoint
float64[] positions
float64[] velocities
float64[] accelerations
float64[] effort
builtin_interfaces/Duration time_from_start
================================================================================
MSG: builtin_interfaces/Duration
int32 sec
uint32 nanosec
";

/// The type name of a JointTrajectory (an MCAP schema's name).
pub const JOINT_TRAJECTORY: &str = "trajectory_msgs/msg/JointTrajectory";
/// The type name of a JointState.
pub const JOINT_STATE: &str = "sensor_msgs/msg/JointState";

impl JointTrajectoryMsg {
    /// The message of `trajectory` (header stamp 0, no efforts), its times rounded to whole
    /// nanoseconds; `None` when a time is beyond the ±68 years a ROS time holds.
    pub fn of(trajectory: &TimedTrajectory) -> Option<JointTrajectoryMsg> {
        let points = (trajectory.points.iter())
            .map(|p| {
                let (sec, nanosec) = ros_sec_nanosec(nanoseconds(p.time_from_start));
                Some(JointTrajectoryPointMsg {
                    positions: p.positions.clone(),
                    velocities: p.velocities.clone(),
                    accelerations: p.accelerations.clone(),
                    effort: Vec::new(),
                    time_from_start: RosTime {
                        sec: i32::try_from(sec).ok()?,
                        nanosec,
                    },
                })
            })
            .collect::<Option<_>>()?;
        Some(JointTrajectoryMsg {
            header: Header::default(),
            joint_names: trajectory.joint_names.clone(),
            points,
        })
    }

    /// The trajectory the message holds (unchecked).
    pub fn into_trajectory(self) -> TimedTrajectory {
        TimedTrajectory {
            joint_names: self.joint_names,
            points: (self.points.into_iter())
                .map(|p| TrajectoryPoint {
                    time_from_start: seconds_from_nanoseconds(p.time_from_start.nanoseconds()),
                    positions: p.positions,
                    velocities: p.velocities,
                    accelerations: p.accelerations,
                })
                .collect(),
        }
    }
}

/// A `JointTrajectory` as YAML or JSON may write it: `header` and `effort` optional and
/// ignored, `time_from_start` either `{sec, nanosec}` or a number of seconds.
#[derive(Debug, Deserialize)]
pub struct LooseJointTrajectory {
    /// The joints.
    #[serde(default)]
    pub joint_names: Vec<String>,
    /// The points.
    #[serde(default)]
    pub points: Vec<LoosePoint>,
}

/// A point of a [`LooseJointTrajectory`].
#[derive(Debug, Deserialize)]
pub struct LoosePoint {
    /// Positions.
    #[serde(default)]
    pub positions: Vec<f64>,
    /// Velocities, or empty.
    #[serde(default)]
    pub velocities: Vec<f64>,
    /// Accelerations, or empty.
    #[serde(default)]
    pub accelerations: Vec<f64>,
    /// Time since the start.
    pub time_from_start: LooseTime,
}

/// `{sec, nanosec}` (ROS) or seconds.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(untagged)]
pub enum LooseTime {
    /// ROS's `builtin_interfaces/Duration`.
    Ros {
        /// Whole seconds.
        sec: i64,
        /// Nanoseconds.
        #[serde(default)]
        nanosec: i64,
    },
    /// Seconds.
    Seconds(f64),
}

impl LooseJointTrajectory {
    /// The trajectory it holds (unchecked).
    pub fn into_trajectory(self) -> TimedTrajectory {
        TimedTrajectory {
            joint_names: self.joint_names,
            points: (self.points.into_iter())
                .map(|p| TrajectoryPoint {
                    time_from_start: match p.time_from_start {
                        LooseTime::Ros { sec, nanosec } => seconds_from_nanoseconds(ros_nanoseconds(sec, nanosec)),
                        LooseTime::Seconds(t) => t,
                    },
                    positions: p.positions,
                    velocities: p.velocities,
                    accelerations: p.accelerations,
                })
                .collect(),
        }
    }
}
