//! A time-stamped joint trajectory, as ROS 2's `trajectory_msgs/msg/JointTrajectory` holds one:
//! joint names and points at uneven times. The file formats that carry one (YAML, JSON, MCAP,
//! CSV) read into it and write from it; `retime` produces one.

/// A time-stamped joint trajectory: the joints it names, and its points in time order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimedTrajectory {
    /// The joints each point gives values for, in the points' order (URDF joint names).
    pub joint_names: Vec<String>,
    /// The points, `time_from_start` increasing.
    pub points: Vec<TrajectoryPoint>,
}

/// One point of a [`TimedTrajectory`]: positions, and optionally velocities and accelerations,
/// one entry per joint of `joint_names` (an empty vector: not given).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrajectoryPoint {
    /// Time since the trajectory's start (s).
    pub time_from_start: f64,
    /// Joint positions (rad or m).
    pub positions: Vec<f64>,
    /// Joint velocities (rad/s or m/s); empty when not given.
    pub velocities: Vec<f64>,
    /// Joint accelerations (rad/s² or m/s²); empty when not given.
    pub accelerations: Vec<f64>,
}
