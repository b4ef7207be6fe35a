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

/// A `JointTrajectory` as YAML or JSON may write it: as `ros2 topic echo` or `rostopic echo`
/// (ROS 1) prints it, or as `ros2 topic pub` and `ros2 action send_goal` take it: every field
/// optional with ROS's default (a missing `time_from_start` is 0), `header` and `effort`
/// ignored, `time_from_start` a [`LooseTime`].
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
    /// Time since the start (0 when not given, as the ROS tools fill a missing field).
    #[serde(default)]
    pub time_from_start: LooseTime,
}

/// A `sensor_msgs/JointState` as YAML or JSON may write it (ROS 2 or ROS 1): `header.stamp` a
/// [`LooseTime`] (`seq` and `frame_id` ignored), `effort` ignored.
#[derive(Debug, Deserialize)]
pub struct LooseJointState {
    /// The header (its stamp the state's time; 0 when missing).
    #[serde(default)]
    pub header: LooseHeader,
    /// The joints.
    #[serde(default)]
    pub name: Vec<String>,
    /// Positions.
    #[serde(default)]
    pub position: Vec<f64>,
    /// Velocities, or empty.
    #[serde(default)]
    pub velocity: Vec<f64>,
}

/// A header's stamp, ROS 2 (`sec`, `nanosec`) or ROS 1 (`seq`, `secs`, `nsecs`).
#[derive(Debug, Default, Deserialize)]
pub struct LooseHeader {
    /// The stamp.
    #[serde(default)]
    pub stamp: LooseTime,
}

/// A time or duration as people write it: `{sec, nanosec}` (ROS 2's `builtin_interfaces`),
/// `{secs, nsecs}` (ROS 1's `rostopic echo`), either part optional (0), or a number of
/// seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LooseTime {
    /// Whole nanoseconds (from `{sec, nanosec}` or `{secs, nsecs}`).
    Nanoseconds(i64),
    /// Seconds.
    Seconds(f64),
}

impl Default for LooseTime {
    fn default() -> Self {
        LooseTime::Nanoseconds(0)
    }
}

impl LooseTime {
    /// In seconds (whole nanoseconds as rclcpp's `Duration::seconds()` gives them).
    pub fn seconds(self) -> f64 {
        match self {
            LooseTime::Nanoseconds(ns) => seconds_from_nanoseconds(ns),
            LooseTime::Seconds(t) => t,
        }
    }

    /// In whole nanoseconds (seconds rounded to the nearest).
    pub fn nanoseconds(self) -> i64 {
        match self {
            LooseTime::Nanoseconds(ns) => ns,
            LooseTime::Seconds(t) => nanoseconds(t),
        }
    }
}

impl<'de> Deserialize<'de> for LooseTime {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(TimeVisitor)
    }
}

/// Reads a [`LooseTime`] from a number or a map, naming the layouts it takes when it is neither.
struct TimeVisitor;

impl<'de> serde::de::Visitor<'de> for TimeVisitor {
    type Value = LooseTime;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a time: {sec, nanosec} (ROS 2), {secs, nsecs} (ROS 1) or a number of seconds")
    }

    fn visit_f64<E: serde::de::Error>(self, t: f64) -> Result<LooseTime, E> {
        Ok(LooseTime::Seconds(t))
    }

    fn visit_i64<E: serde::de::Error>(self, t: i64) -> Result<LooseTime, E> {
        Ok(LooseTime::Seconds(t as f64))
    }

    fn visit_u64<E: serde::de::Error>(self, t: u64) -> Result<LooseTime, E> {
        Ok(LooseTime::Seconds(t as f64))
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<LooseTime, A::Error> {
        use serde::de::Error;
        // each part with the name it was given by
        let mut seconds: Option<(String, i64)> = None;
        let mut nanos: Option<(String, i64)> = None;
        while let Some(key) = map.next_key::<String>()? {
            let slot = match key.as_str() {
                "sec" | "secs" => &mut seconds,
                "nanosec" | "nsecs" => &mut nanos,
                _ => {
                    return Err(A::Error::custom(format!(
                        "a time has no field {}: it is {{sec, nanosec}} (ROS 2) or {{secs, nsecs}} (ROS 1)",
                        crate::error::quoted(&key)
                    )));
                }
            };
            if let Some((first, _)) = slot {
                return Err(A::Error::custom(format!("a time gives both {first} and {key}")));
            }
            *slot = Some((key, map.next_value::<i64>()?));
        }
        if let (Some((s, _)), Some((n, _))) = (&seconds, &nanos)
            && (s == "sec") != (n == "nanosec")
        {
            return Err(A::Error::custom(format!(
                "a time mixes ROS 2's and ROS 1's fields ({s}, {n})"
            )));
        }
        let (sec, nanosec) = (seconds.map_or(0, |s| s.1), nanos.map_or(0, |n| n.1));
        Ok(LooseTime::Nanoseconds(ros_nanoseconds(sec, nanosec)))
    }
}

impl LooseJointTrajectory {
    /// The trajectory it holds (unchecked).
    pub fn into_trajectory(self) -> TimedTrajectory {
        TimedTrajectory {
            joint_names: self.joint_names,
            points: (self.points.into_iter())
                .map(|p| TrajectoryPoint {
                    time_from_start: p.time_from_start.seconds(),
                    positions: p.positions,
                    velocities: p.velocities,
                    accelerations: p.accelerations,
                })
                .collect(),
        }
    }
}

impl LooseJointState {
    /// The message it holds, its stamp in ROS 2's `{sec, nanosec}`; `None` when the stamp is
    /// beyond the ±68 years a ROS 2 time holds.
    pub fn into_message(self) -> Option<JointStateMsg> {
        let (sec, nanosec) = ros_sec_nanosec(self.header.stamp.nanoseconds());
        Some(JointStateMsg {
            header: Header {
                stamp: RosTime {
                    sec: i32::try_from(sec).ok()?,
                    nanosec,
                },
                frame_id: String::new(),
            },
            name: self.name,
            position: self.position,
            velocity: self.velocity,
            effort: Vec::new(),
        })
    }
}
