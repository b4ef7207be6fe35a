//! A time-stamped joint trajectory, as ROS 2's `trajectory_msgs/msg/JointTrajectory` holds one:
//! joint names and points at uneven times. The file formats that carry one (YAML, JSON, MCAP,
//! CSV; [`super::files`]) read into it and write from it; `retime` produces one; [`super::Spline`]
//! plays one as ros2_control's `joint_trajectory_controller` does (docs/trajectories.md).

use std::path::Path;

use ndarray::ArrayView2;

use crate::choice::Choice;
use crate::error::{Error, Result, quoted, shortest};
use crate::input::{MAX_MOVING_JOINTS, MAX_TRAJECTORY_POINTS};

/// A time-stamped joint trajectory: the joints it names, and its points in time order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimedTrajectory {
    /// The joints each point gives values for, in the points' order (URDF joint names; `qK`
    /// names the model's K-th degree of freedom, 1-based, where the model has no joint of that
    /// name: see [`TimedTrajectory::in_joint_order`]).
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

/// How a trajectory's points are joined, by what they give, as `joint_trajectory_controller`
/// decides (docs/trajectories.md): positions only → linear; positions and velocities → cubic
/// Hermite; positions, velocities and accelerations → quintic Hermite.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Straight segments; the velocity steps at every point, the acceleration is 0.
    Linear,
    /// Cubic polynomials matching position and velocity at both ends.
    Cubic,
    /// Quintic polynomials matching position, velocity and acceleration at both ends.
    Quintic,
}

crate::choice::choice_words!(Interpolation { Linear => "linear", Cubic => "cubic", Quintic => "quintic" });

/// A model joint a trajectory does not name (see [`TimedTrajectory::in_joint_order`]): it holds
/// `position` with zero velocity and acceleration.
#[derive(Clone, Debug, PartialEq)]
pub struct HeldJoint {
    /// The joint's name.
    pub name: String,
    /// The position it holds (rad or m).
    pub position: f64,
}

/// Nanoseconds per second: ROS times (`builtin_interfaces/Duration`, `Time`) are whole
/// nanoseconds.
const NANOS: i64 = 1_000_000_000;

/// A time in s from ROS's whole nanoseconds, as rclcpp's `Duration::seconds()` gives it
/// (`ns / 1e9`, correctly rounded).
pub fn seconds_from_nanoseconds(ns: i64) -> f64 {
    ns as f64 / NANOS as f64
}

/// The whole nanoseconds nearest to `t` s (ROS's resolution). For every `ns` below 2^50
/// (13 days), `nanoseconds(seconds_from_nanoseconds(ns)) == ns`: a time read from a ROS file
/// is written back unchanged.
pub fn nanoseconds(t: f64) -> i64 {
    (t * NANOS as f64).round() as i64
}

/// A ROS `(sec, nanosec)` pair in whole nanoseconds.
pub fn ros_nanoseconds(sec: i64, nanosec: i64) -> i64 {
    sec.saturating_mul(NANOS).saturating_add(nanosec)
}

/// Whole nanoseconds as ROS's `(sec, nanosec)`, `0 ≤ nanosec < 1e9`.
pub fn ros_sec_nanosec(ns: i64) -> (i64, u32) {
    (ns.div_euclid(NANOS), ns.rem_euclid(NANOS) as u32)
}

impl TimedTrajectory {
    /// A trajectory from arrays (the Python binding's `t`, `q`, `v`, `a`): `times` (s, N
    /// entries), `positions` N×J, optional `velocities` and `accelerations` N×J, `joint_names`
    /// J names (`None`: `q1…qJ`, the model's joints in order). Checked as
    /// [`TimedTrajectory::check`] checks a file, `source` naming it in the messages.
    pub fn from_arrays(
        joint_names: Option<Vec<String>>,
        times: &[f64],
        positions: ArrayView2<f64>,
        velocities: Option<ArrayView2<f64>>,
        accelerations: Option<ArrayView2<f64>>,
        source: &Path,
    ) -> Result<TimedTrajectory> {
        let bad = |message: String| Error::InvalidData {
            path: source.to_path_buf(),
            message,
        };
        let (rows, columns) = positions.dim();
        // as a trajectory file's points and joints are counted, before anything is copied
        if rows > MAX_TRAJECTORY_POINTS {
            return Err(bad(format!(
                "{rows} rows: more than the {MAX_TRAJECTORY_POINTS} points a trajectory may have (docs/development.md, Caps)"
            )));
        }
        if columns > MAX_MOVING_JOINTS {
            return Err(bad(format!(
                "{columns} columns; a model has at most {MAX_MOVING_JOINTS} moving joints (docs/development.md, Caps)"
            )));
        }
        if times.len() != rows {
            return Err(bad(format!(
                "{} times for {rows} rows of positions: one time per row",
                times.len()
            )));
        }
        for (what, array) in [("velocities", velocities), ("accelerations", accelerations)] {
            if let Some(a) = array
                && a.dim() != (rows, columns)
            {
                return Err(bad(format!(
                    "{what} are {}×{}, positions {rows}×{columns}: they must have the same shape",
                    a.nrows(),
                    a.ncols()
                )));
            }
        }
        let row = |a: Option<ArrayView2<f64>>, k: usize| a.map_or(Vec::new(), |a| a.row(k).to_vec());
        let trajectory = TimedTrajectory {
            joint_names: joint_names.unwrap_or_else(|| (1..=columns).map(|i| format!("q{i}")).collect()),
            points: (0..rows)
                .map(|k| TrajectoryPoint {
                    time_from_start: times[k],
                    positions: positions.row(k).to_vec(),
                    velocities: row(velocities, k),
                    accelerations: row(accelerations, k),
                })
                .collect(),
        };
        trajectory.check(source)?;
        Ok(trajectory)
    }

    /// Checks that the trajectory can be played: at least one joint, each named once; at least
    /// one point (one point is a goal: the arm is brought to it, as joint_trajectory_controller
    /// does); finite times, the first not before the start (0), strictly increasing; every
    /// point with one position per joint,
    /// and velocities and accelerations given at every point or at none (one per joint where
    /// given; accelerations only with velocities); every value finite. The first fault is the
    /// error, `source` naming the file.
    pub fn check(&self, source: &Path) -> Result<()> {
        let bad = |message: String| Error::InvalidData {
            path: source.to_path_buf(),
            message,
        };
        let n = self.joint_names.len();
        if n == 0 {
            return Err(bad("names no joint".into()));
        }
        if n > MAX_MOVING_JOINTS {
            return Err(bad(format!(
                "names {n} joints; a model has at most {MAX_MOVING_JOINTS} moving joints (docs/development.md, Caps)"
            )));
        }
        for (i, name) in self.joint_names.iter().enumerate() {
            if self.joint_names[..i].contains(name) {
                return Err(bad(format!("names joint {} twice", quoted(name))));
            }
        }
        let Some(first) = self.points.first() else {
            return Err(bad("has no points".into()));
        };
        if first.time_from_start < 0.0 {
            return Err(bad(format!(
                "point 0: time_from_start {} s is before the trajectory's start (0): joint_trajectory_controller would begin in its middle",
                shortest(first.time_from_start)
            )));
        }
        let given = |v: &Vec<f64>| !v.is_empty();
        if given(&first.accelerations) && !given(&first.velocities) {
            return Err(bad(
                "gives accelerations without velocities (joint_trajectory_controller then commands nothing sensible): give velocities too, or neither".into(),
            ));
        }
        for (k, p) in self.points.iter().enumerate() {
            if !p.time_from_start.is_finite() {
                return Err(bad(format!("point {k}: time_from_start is {}", p.time_from_start)));
            }
            if k > 0 && p.time_from_start <= self.points[k - 1].time_from_start {
                return Err(bad(format!(
                    "point {k}: time_from_start {} s is not after point {}'s {} s: times must increase",
                    shortest(p.time_from_start),
                    k - 1,
                    shortest(self.points[k - 1].time_from_start)
                )));
            }
            for (what, values, wanted) in [
                ("positions", &p.positions, true),
                ("velocities", &p.velocities, given(&first.velocities)),
                ("accelerations", &p.accelerations, given(&first.accelerations)),
            ] {
                match (wanted, values.len()) {
                    (false, 0) => {}
                    (false, _) => {
                        return Err(bad(format!(
                            "point {k} gives {what}, point 0 does not: give them at every point or at none"
                        )));
                    }
                    (true, len) if len != n => {
                        return Err(bad(format!("point {k} has {len} {what}; joint_names names {n} joints")));
                    }
                    (true, _) => {}
                }
                if let Some(i) = values.iter().position(|x| !x.is_finite()) {
                    return Err(bad(format!(
                        "point {k}: {what} of joint {} is {}: every value must be finite",
                        quoted(&self.joint_names[i]),
                        values[i]
                    )));
                }
            }
        }
        Ok(())
    }

    /// How the points are joined, by what the first point gives (after [`Self::check`], every
    /// point gives the same).
    pub fn interpolation(&self) -> Interpolation {
        match self.points.first() {
            Some(p) if !p.accelerations.is_empty() => Interpolation::Quintic,
            Some(p) if !p.velocities.is_empty() => Interpolation::Cubic,
            _ => Interpolation::Linear,
        }
    }

    /// The same points joined by `rule` instead of by what they give (`--interpolation`):
    /// linear leaves out velocities and accelerations; cubic leaves out accelerations and,
    /// where the points give no velocities, takes those of joint_trajectory_controller's
    /// `positions_upsampling` ([`fill_cubic_spline_velocities`]: the global cubic spline
    /// through the positions, at rest at both ends; one point gets velocity 0); quintic needs
    /// the accelerations the points give (an error names what they give instead). `self` must
    /// be checked; `source` names it in the error.
    pub fn with_interpolation(&self, rule: Interpolation, source: &Path) -> Result<TimedTrajectory> {
        let given = self.interpolation();
        let mut out = self.clone();
        match rule {
            Interpolation::Linear => {
                for p in &mut out.points {
                    p.velocities.clear();
                    p.accelerations.clear();
                }
            }
            Interpolation::Cubic => {
                for p in &mut out.points {
                    p.accelerations.clear();
                }
                if given == Interpolation::Linear {
                    fill_cubic_spline_velocities(&mut out);
                }
            }
            Interpolation::Quintic if given != Interpolation::Quintic => {
                return Err(Error::InvalidData {
                    path: source.to_path_buf(),
                    message: format!(
                        "`interpolation` quintic needs accelerations at every point; its points give {} (joint_trajectory_controller plays them {})",
                        match given {
                            Interpolation::Linear => "positions only",
                            _ => "positions and velocities",
                        },
                        given.word()
                    ),
                });
            }
            Interpolation::Quintic => {}
        }
        Ok(out)
    }

    /// The time the points span, last time minus first (s): the run's default duration.
    pub fn duration(&self) -> f64 {
        match (self.points.first(), self.points.last()) {
            (Some(a), Some(b)) => b.time_from_start - a.time_from_start,
            _ => 0.0,
        }
    }

    /// Every time rounded to the whole nanoseconds ROS files hold
    /// ([`seconds_from_nanoseconds`]`(`[`nanoseconds`]`(t))`), so that writing it to YAML,
    /// JSON or MCAP and reading it back gives it unchanged, bit for bit.
    pub fn round_times_to_nanoseconds(&mut self) {
        for p in &mut self.points {
            p.time_from_start = seconds_from_nanoseconds(nanoseconds(p.time_from_start));
        }
    }

    /// The trajectory over the model's degrees of freedom `joints` (their names, in the model's
    /// order): each joint the trajectory names gets its values, whatever their order in the
    /// file; a joint it does not name holds `hold[i]` (zero velocity and acceleration) and is
    /// returned among the held joints. A name the model does not have is an error that lists
    /// the model's joints, except `qK` (K = 1…n) where the model has no joint of that name: the
    /// K-th degree of freedom. Two names for one joint are an error. `self` must be checked
    /// ([`Self::check`]).
    pub fn in_joint_order(
        &self,
        joints: &[String],
        hold: &[f64],
        source: &Path,
    ) -> Result<(TimedTrajectory, Vec<HeldJoint>)> {
        let bad = |message: String| Error::InvalidData {
            path: source.to_path_buf(),
            message,
        };
        let n = joints.len();
        let mut column: Vec<Option<usize>> = vec![None; n];
        for (c, name) in self.joint_names.iter().enumerate() {
            let by_position = || {
                (name.strip_prefix('q'))
                    .filter(|k| k.bytes().all(|b| b.is_ascii_digit()) && !k.starts_with('0'))
                    .and_then(|k| k.parse::<usize>().ok())
                    .filter(|&k| (1..=n).contains(&k))
                    .map(|k| k - 1)
            };
            let Some(i) = joints.iter().position(|j| j == name).or_else(by_position) else {
                return Err(bad(format!(
                    "names joint {}, which the model does not have (its joints: {}; `rename` FROM=TO maps a prefix of the file's names to the model's)",
                    quoted(name),
                    joints.iter().map(|j| quoted(j)).collect::<Vec<_>>().join(", ")
                )));
            };
            if let Some(other) = column[i] {
                return Err(bad(format!(
                    "names joint {} twice: as {} and as {}",
                    quoted(&joints[i]),
                    quoted(&self.joint_names[other]),
                    quoted(name)
                )));
            }
            column[i] = Some(c);
        }
        // a held joint's entry: its position, zero velocity and acceleration
        let reorder = |values: &[f64], held: &dyn Fn(usize) -> f64| -> Vec<f64> {
            match values.is_empty() {
                true => Vec::new(),
                false => (column.iter().enumerate())
                    .map(|(i, c)| c.map_or_else(|| held(i), |c| values[c]))
                    .collect(),
            }
        };
        let ordered = TimedTrajectory {
            joint_names: joints.to_vec(),
            points: (self.points.iter())
                .map(|p| TrajectoryPoint {
                    time_from_start: p.time_from_start,
                    positions: reorder(&p.positions, &|i| hold[i]),
                    velocities: reorder(&p.velocities, &|_| 0.0),
                    accelerations: reorder(&p.accelerations, &|_| 0.0),
                })
                .collect(),
        };
        let held = (column.iter().enumerate())
            .filter(|(_, c)| c.is_none())
            .map(|(i, _)| HeldJoint {
                name: joints[i].clone(),
                position: hold[i],
            })
            .collect();
        Ok((ordered, held))
    }
}

/// Velocities for positions-only points, as joint_trajectory_controller's `positions_upsampling`
/// makes them (`fill_cubic_spline_velocities` in
/// `joint_trajectory_controller/src/trajectory.cpp`, ros2_controllers): per joint, the knot
/// velocities of the global cubic spline through the positions (continuous acceleration at
/// every inner point) at rest at both ends, solved by the Thomas algorithm in the controller's
/// order of operations. One point gets velocity 0.
pub fn fill_cubic_spline_velocities(trajectory: &mut TimedTrajectory) {
    let n = trajectory.points.len();
    let joints = trajectory.joint_names.len();
    for p in &mut trajectory.points {
        p.velocities = vec![0.0; joints];
    }
    if n < 2 {
        return;
    }
    let times: Vec<f64> = trajectory.points.iter().map(|p| p.time_from_start).collect();
    let (mut lower, mut diagonal, mut upper, mut rhs) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut sweep, mut velocities) = (vec![0.0; n], vec![0.0; n]);
    for joint in 0..joints {
        let q = |i: usize| trajectory.points[i].positions[joint];
        // rest at both ends
        (diagonal[0], upper[0], rhs[0]) = (1.0, 0.0, 0.0);
        (lower[n - 1], diagonal[n - 1], rhs[n - 1]) = (0.0, 1.0, 0.0);
        // inner knots: continuous acceleration
        for i in 1..n - 1 {
            let (before, after) = (times[i] - times[i - 1], times[i + 1] - times[i]);
            lower[i] = 1.0 / before;
            diagonal[i] = 2.0 * (1.0 / before + 1.0 / after);
            upper[i] = 1.0 / after;
            rhs[i] = 3.0 * ((q(i + 1) - q(i)) / (after * after) + (q(i) - q(i - 1)) / (before * before));
        }
        sweep[0] = upper[0] / diagonal[0];
        velocities[0] = rhs[0] / diagonal[0];
        for i in 1..n {
            let pivot = diagonal[i] - lower[i] * sweep[i - 1];
            sweep[i] = if i + 1 < n { upper[i] / pivot } else { 0.0 };
            velocities[i] = (rhs[i] - lower[i] * velocities[i - 1]) / pivot;
        }
        for i in (0..n - 1).rev() {
            velocities[i] -= sweep[i] * velocities[i + 1];
        }
        for (p, &v) in trajectory.points.iter_mut().zip(&velocities) {
            p.velocities[joint] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(t: f64, q: &[f64]) -> TrajectoryPoint {
        TrajectoryPoint {
            time_from_start: t,
            positions: q.to_vec(),
            ..Default::default()
        }
    }

    fn two_joints() -> TimedTrajectory {
        TimedTrajectory {
            joint_names: vec!["b".into(), "a".into()],
            points: vec![point(0.5, &[1.0, 2.0]), point(1.0, &[3.0, 4.0])],
        }
    }

    fn message(t: &TimedTrajectory) -> String {
        t.check(Path::new("f.yaml")).unwrap_err().to_string()
    }

    #[test]
    fn check_names_the_first_fault() {
        let mut t = two_joints();
        t.points[1].time_from_start = 0.5;
        assert!(message(&t).contains("point 1: time_from_start 0.5 s is not after point 0's 0.5 s"));
        let mut t = two_joints();
        t.points[1].positions[0] = f64::NAN;
        assert!(message(&t).contains("point 1: positions of joint 'b' is NaN"));
        let mut t = two_joints();
        t.points[1].positions.pop();
        assert!(message(&t).contains("point 1 has 1 positions; joint_names names 2 joints"));
        let mut t = two_joints();
        t.points[1].velocities = vec![0.0, 0.0];
        assert!(message(&t).contains("point 1 gives velocities, point 0 does not"));
        let mut t = two_joints();
        t.joint_names[1] = "b".into();
        assert!(message(&t).contains("names joint 'b' twice"));
        let mut t = two_joints();
        t.points.clear();
        assert!(message(&t).contains("has no points"));
        let mut t = two_joints();
        t.points.pop();
        assert!(t.check(Path::new("f")).is_ok(), "one point is a goal");
        t.points[0].time_from_start = -0.25;
        assert!(message(&t).contains("point 0: time_from_start -0.25 s is before the trajectory's start (0)"));
        assert!(two_joints().check(Path::new("f")).is_ok());
    }

    #[test]
    fn joint_order_by_name_with_held_joints() {
        let joints: Vec<String> = ["a", "b", "c"].map(String::from).to_vec();
        let (t, held) = two_joints()
            .in_joint_order(&joints, &[0.0, 0.0, 0.25], Path::new("f"))
            .unwrap();
        assert_eq!(t.points[1].positions, vec![4.0, 3.0, 0.25]);
        assert!(t.points[1].velocities.is_empty());
        assert_eq!(
            held,
            vec![HeldJoint {
                name: "c".into(),
                position: 0.25
            }]
        );
        let mut cubic = two_joints();
        for p in &mut cubic.points {
            p.velocities = vec![5.0, 6.0];
        }
        let (t, _) = cubic.in_joint_order(&joints, &[9.0; 3], Path::new("f")).unwrap();
        assert_eq!(t.points[0].velocities, vec![6.0, 5.0, 0.0]);
    }

    #[test]
    fn unknown_names_are_refused_and_qk_is_positional() {
        let joints: Vec<String> = ["a", "b"].map(String::from).to_vec();
        let mut t = two_joints();
        t.joint_names = vec!["q2".into(), "x".into()];
        let e = t
            .in_joint_order(&joints, &[0.0; 2], Path::new("f"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "f: names joint 'x', which the model does not have (its joints: 'a', 'b'; `rename` FROM=TO maps a prefix of the file's names to the model's)"
        );
        t.joint_names = vec!["q2".into(), "q1".into()];
        let (o, held) = t.in_joint_order(&joints, &[0.0; 2], Path::new("f")).unwrap();
        assert_eq!(o.points[0].positions, vec![2.0, 1.0]);
        assert!(held.is_empty());
        t.joint_names = vec!["q2".into(), "b".into()];
        let e = t
            .in_joint_order(&joints, &[0.0; 2], Path::new("f"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("names joint 'b' twice: as 'q2' and as 'b'"), "{e}");
        t.joint_names = vec!["q3".into(), "a".into()];
        assert!(t.in_joint_order(&joints, &[0.0; 2], Path::new("f")).is_err());
    }

    #[test]
    fn from_arrays_checks_shapes_and_names_by_position() {
        let q = ndarray::arr2(&[[0.0, 1.0], [0.5, 1.5], [1.0, 2.0]]);
        let v = ndarray::arr2(&[[0.0, 0.0], [1.0, 1.0], [0.0, 0.0]]);
        let source = Path::new("q");
        let t = TimedTrajectory::from_arrays(None, &[0.0, 0.5, 1.0], q.view(), Some(v.view()), None, source).unwrap();
        assert_eq!(t.joint_names, ["q1", "q2"]);
        assert_eq!(t.points[1].velocities, [1.0, 1.0]);
        assert_eq!(t.interpolation(), Interpolation::Cubic);
        let e = TimedTrajectory::from_arrays(None, &[0.0, 0.5], q.view(), None, None, source).unwrap_err();
        assert_eq!(e.to_string(), "q: 2 times for 3 rows of positions: one time per row");
        let a = ndarray::arr2(&[[0.0], [0.0], [0.0]]);
        let e = TimedTrajectory::from_arrays(None, &[0.0, 0.5, 1.0], q.view(), Some(v.view()), Some(a.view()), source)
            .unwrap_err();
        assert!(e.to_string().contains("accelerations are 3×1, positions 3×2"), "{e}");
        let e = TimedTrajectory::from_arrays(None, &[0.0, 1.0, 0.5], q.view(), None, None, source).unwrap_err();
        assert!(
            e.to_string().contains("point 2: time_from_start 0.5 s is not after"),
            "{e}"
        );
        let names = Some(vec!["b".to_string(), "a".to_string()]);
        let t = TimedTrajectory::from_arrays(names, &[0.0, 0.5, 1.0], q.view(), None, None, source).unwrap();
        let joints: Vec<String> = ["a", "b"].map(String::from).to_vec();
        let (ordered, _) = t.in_joint_order(&joints, &[0.0; 2], source).unwrap();
        assert_eq!(ordered.points[2].positions, [2.0, 1.0]);
    }

    /// `positions_upsampling`'s velocities make the cubic spline C²: at every inner point the
    /// acceleration from the left segment equals the one from the right; at rest at both ends.
    #[test]
    fn spline_velocities_are_continuous_in_acceleration() {
        let times = [0.0, 0.3, 0.5, 1.1, 1.4];
        let q = [0.0, 0.4, 0.1, -0.7, 0.2];
        let mut t = TimedTrajectory {
            joint_names: vec!["a".into()],
            points: (times.iter().zip(q)).map(|(&t, q)| point(t, &[q])).collect(),
        };
        fill_cubic_spline_velocities(&mut t);
        let v: Vec<f64> = t.points.iter().map(|p| p.velocities[0]).collect();
        assert_eq!((v[0], v[4]), (0.0, 0.0));
        // a cubic Hermite segment's acceleration at its start and end
        let accelerations = |i: usize| {
            let h = times[i + 1] - times[i];
            let d = (q[i + 1] - q[i]) / h;
            (
                (6.0 * d - 4.0 * v[i] - 2.0 * v[i + 1]) / h,
                (-6.0 * d + 2.0 * v[i] + 4.0 * v[i + 1]) / h,
            )
        };
        for i in 1..4 {
            let (end_before, start_after) = (accelerations(i - 1).1, accelerations(i).0);
            assert!(
                (end_before - start_after).abs() < 1e-12,
                "point {i}: {end_before} {start_after}"
            );
        }
        let mut one = two_joints();
        one.points.pop();
        fill_cubic_spline_velocities(&mut one);
        assert_eq!(one.points[0].velocities, [0.0, 0.0]);
    }

    #[test]
    fn a_given_interpolation_keeps_or_fills_what_it_needs() {
        let source = Path::new("f.yaml");
        let mut quintic = two_joints();
        for p in &mut quintic.points {
            p.velocities = vec![1.0, 2.0];
            p.accelerations = vec![3.0, 4.0];
        }
        let linear = quintic.with_interpolation(Interpolation::Linear, source).unwrap();
        assert_eq!(linear.interpolation(), Interpolation::Linear);
        let cubic = quintic.with_interpolation(Interpolation::Cubic, source).unwrap();
        assert_eq!(
            (cubic.interpolation(), cubic.points[1].velocities.clone()),
            (Interpolation::Cubic, vec![1.0, 2.0])
        );
        let filled = two_joints().with_interpolation(Interpolation::Cubic, source).unwrap();
        assert_eq!(
            filled.points[0].velocities,
            [0.0, 0.0],
            "two points: at rest at both ends"
        );
        assert_eq!(
            quintic.with_interpolation(Interpolation::Quintic, source).unwrap(),
            quintic
        );
        let e = cubic
            .with_interpolation(Interpolation::Quintic, source)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "f.yaml: `interpolation` quintic needs accelerations at every point; its points give positions and velocities (joint_trajectory_controller plays them cubic)"
        );
        let e = two_joints()
            .with_interpolation(Interpolation::Quintic, source)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("its points give positions only (joint_trajectory_controller plays them linear)"),
            "{e}"
        );
    }

    #[test]
    fn nanoseconds_round_trip() {
        for ns in [0i64, 1, 999_999_999, 1_000_000_001, 123_456_789_012, (1 << 50) - 1] {
            assert_eq!(nanoseconds(seconds_from_nanoseconds(ns)), ns);
            let (s, n) = ros_sec_nanosec(ns);
            assert_eq!(ros_nanoseconds(s, n as i64), ns);
        }
        assert_eq!(ros_sec_nanosec(-1), (-1, 999_999_999));
    }
}
