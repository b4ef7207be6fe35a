//! A recorded `sensor_msgs/msg/JointState` stream as a trajectory: the conversion every
//! container calls (an MCAP topic, a rosbag2 folder, a ROS 1 bag, a YAML or JSON echo), given
//! the messages of one topic with the times their container logged them (docs/trajectories.md,
//! "Recorded JointState streams").
//!
//! * Each message is a state at its header stamp (from the first; the log times when every
//!   stamp is the same); its joints the model lacks are left out ([`Note::IgnoredJoints`]).
//! * Messages naming different joints (an arm and its gripper published apart) are merged by
//!   time ([`Note::Merged`]): a point at every stamp, each joint between its own messages joined
//!   as the points will be played (linear, or cubic through its velocities), held before its
//!   first and after its last. Two messages giving one joint different positions at one stamp
//!   are refused (two publishers of the same joints).
//! * The recorded velocities are used when every message gives them and they agree with the
//!   positions (integrated over each interval by the trapezoid rule, they miss at most
//!   [`VELOCITY_AGREEMENT`] of the positions' motion): joint_trajectory_controller's rule then
//!   plays the points cubic ([`Note::VelocitiesChoseCubic`]). Zeros (a driver that does not
//!   measure them), partial or disagreeing velocities (measured noise) are left out
//!   ([`Note::VelocitiesIgnored`]): cubic through them would stop and go at every message.

use std::collections::BTreeMap;
use std::path::Path;

use super::reading::Unused;
use super::{Note, Selection, invalid};
use crate::error::{Result, quoted, shortest};
use crate::traj::timed::seconds_from_nanoseconds;
use crate::traj::{Interpolation, Spline, TimedTrajectory, TrajectoryPoint};

use super::ros::JointStateMsg;

/// The largest share of the positions' motion the recorded velocities may miss, integrated
/// over each interval, for them to be used: Σ|½(vᵢ + vᵢ₊₁)·Δt − Δq| ≤ 0.25 · Σ|Δq| over every
/// joint and interval. A smooth motion's true velocities miss by the trapezoid rule's error
/// (O(Δt³) per interval, far below); zeros miss all of it; velocity noise of a quarter of the
/// speed misses about that much.
pub const VELOCITY_AGREEMENT: f64 = 0.25;

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
    /// The recorded motion (unchecked; its joints as the file names them).
    pub trajectory: TimedTrajectory,
    /// What the user should know about how it was read.
    pub notes: Vec<Note>,
}

/// One joint's recorded state: time (ns), position, velocity when the message gives one.
#[derive(Clone, Copy, Debug)]
struct Sample {
    t: i64,
    q: f64,
    v: Option<f64>,
}

/// The JointState messages `states` of `topic` (`None`: the file's; in the order the container
/// logged them) as a trajectory: the joints `selection` keeps ([`Selection::keeps`]), merged
/// by time, their velocities where they are used (see the module's documentation; under a
/// given `selection.interpolation` linear they are left out, and they choose nothing). `path`
/// names the file in errors.
pub fn recorded_motion(
    states: Vec<StampedState>,
    topic: Option<&str>,
    selection: &Selection,
    path: &Path,
) -> Result<Recording> {
    let stream = match topic {
        Some(topic) => format!("topic {topic}'s JointState messages"),
        None => "its JointState messages".to_string(),
    };
    let at = |k: usize| match topic {
        Some(topic) => format!("topic {topic}, message {}", k + 1),
        None => format!("JointState message {}", k + 1),
    };
    if states.is_empty() {
        return Err(invalid(
            path,
            format!("{} has no messages", topic.unwrap_or("the file")),
        ));
    }
    for (k, s) in states.iter().enumerate() {
        check_lengths(&s.message, &at(k), path)?;
    }
    let mut notes = Vec::new();
    let times = times(&states, &stream, &at, path, &mut notes)?;
    let Joints {
        names,
        series,
        ignored,
        groups,
    } = joint_series(&states, &times, selection);
    if names.is_empty() && ignored.is_empty() {
        return Err(invalid(path, format!("{stream} name no joint")));
    }
    if names.is_empty() {
        let named: Vec<String> = ignored.iter().map(|n| quoted(n)).collect();
        return Err(invalid(
            path,
            format!(
                "{stream} name none of the model's joints (they name {}; `rename` maps a prefix to the model's)",
                named.join(", ")
            ),
        ));
    }
    if !ignored.is_empty() {
        notes.push(Note::IgnoredJoints {
            stream: stream.clone(),
            joints: ignored,
        });
    }
    if groups.len() > 1 {
        notes.push(Note::Merged {
            stream: stream.clone(),
            groups,
        });
    }
    let series = (names.iter().zip(series))
        .map(|(name, s)| distinct(s, name, &stream, path))
        .collect::<Result<Vec<_>>>()?;
    let velocities = use_velocities(&names, &series, selection.interpolation, &stream, &mut notes);
    let grid: Vec<i64> = {
        let mut all: Vec<i64> = series.iter().flatten().map(|s| s.t).collect();
        all.sort_unstable();
        all.dedup();
        all
    };
    let columns: Vec<Vec<(f64, f64)>> = (series.iter()).map(|s| resampled(s, &grid, velocities)).collect();
    let points = (grid.iter().enumerate())
        .map(|(k, &t)| TrajectoryPoint {
            // from the first stamp in whole nanoseconds: an absolute stamp in s would round to 0.2 µs
            time_from_start: seconds_from_nanoseconds(t - grid[0]),
            positions: columns.iter().map(|c| c[k].0).collect(),
            velocities: match velocities {
                true => columns.iter().map(|c| c[k].1).collect(),
                false => Vec::new(),
            },
            accelerations: Vec::new(),
        })
        .collect();
    Ok(Recording {
        trajectory: TimedTrajectory {
            joint_names: names,
            points,
        },
        notes,
    })
}

/// A message's positions and velocities (when given) are one per name, and no name is given
/// twice.
fn check_lengths(s: &JointStateMsg, at: &str, path: &Path) -> Result<()> {
    let bad = |what: String| invalid(path, format!("{at}: {what}"));
    if s.position.len() != s.name.len() {
        return Err(bad(format!(
            "{} positions for {} joint names",
            s.position.len(),
            s.name.len()
        )));
    }
    if !s.velocity.is_empty() && s.velocity.len() != s.name.len() {
        return Err(bad(format!(
            "{} velocities for {} joint names",
            s.velocity.len(),
            s.name.len()
        )));
    }
    if let Some(name) = s
        .name
        .iter()
        .enumerate()
        .find_map(|(i, n)| s.name[..i].contains(n).then_some(n))
    {
        return Err(bad(format!("names joint {} twice", quoted(name))));
    }
    Ok(())
}

/// Each message's time (ns): its header stamp, or, when every message has the same stamp,
/// the container's log time (a [`Note::LogTimes`]); an error when neither tells the messages
/// apart, or when some messages are stamped 0 among stamped ones.
fn times(
    states: &[StampedState],
    stream: &str,
    at: &dyn Fn(usize) -> String,
    path: &Path,
    notes: &mut Vec<Note>,
) -> Result<Vec<i64>> {
    let stamps: Vec<i64> = states.iter().map(|s| s.message.header.stamp.nanoseconds()).collect();
    if states.len() > 1 && stamps.iter().all(|&s| s == stamps[0]) {
        let logged: Option<Vec<i64>> = (states.iter())
            .map(|s| s.log_time.and_then(|t| i64::try_from(t).ok()))
            .collect();
        return match logged {
            Some(logged) => {
                notes.push(Note::LogTimes {
                    stream: stream.to_string(),
                });
                Ok(logged)
            }
            None => Err(invalid(
                path,
                format!(
                    "{stream} all have the header stamp {} s and the file keeps no other time: they make no motion",
                    shortest(seconds_from_nanoseconds(stamps[0]))
                ),
            )),
        };
    }
    if stamps.contains(&0)
        && let Some(k) = stamps.iter().position(|&s| s != 0)
    {
        let zero = stamps.iter().position(|&s| s == 0).unwrap_or(0);
        return Err(invalid(
            path,
            format!(
                "{}: header stamp 0 where {} is stamped {} s: the messages' times disagree",
                at(zero),
                at(k),
                shortest(seconds_from_nanoseconds(stamps[k]))
            ),
        ));
    }
    Ok(stamps)
}

/// A stream's joints, as [`joint_series`] sorts them out.
struct Joints {
    /// The joints kept, in the order the messages first name them.
    names: Vec<String>,
    /// Each kept joint's samples, in the messages' order.
    series: Vec<Vec<Sample>>,
    /// The joints left out, in the order the messages first name them.
    ignored: Vec<String>,
    /// The kept joints of each distinct set the messages name (a publisher's).
    groups: Vec<Vec<String>>,
}

/// The joints of `states` (at `times`) that `selection` keeps, and the others.
fn joint_series(states: &[StampedState], times: &[i64], selection: &Selection) -> Joints {
    let (mut names, mut series, mut ignored) = (Vec::<String>::new(), Vec::<Vec<Sample>>::new(), Vec::new());
    let mut groups: BTreeMap<Vec<String>, Vec<String>> = BTreeMap::new();
    for (s, &t) in states.iter().zip(times) {
        let s = &s.message;
        let mut group = Vec::new();
        for (i, name) in s.name.iter().enumerate() {
            if !selection.keeps(name) {
                if !ignored.contains(name) {
                    ignored.push(name.clone());
                }
                continue;
            }
            let j = match names.iter().position(|n| n == name) {
                Some(j) => j,
                None => {
                    names.push(name.clone());
                    series.push(Vec::new());
                    names.len() - 1
                }
            };
            series[j].push(Sample {
                t,
                q: s.position[i],
                v: s.velocity.get(i).copied(),
            });
            group.push(name.clone());
        }
        if !group.is_empty() {
            let mut key = group.clone();
            key.sort();
            groups.entry(key).or_insert(group);
        }
    }
    Joints {
        names,
        series,
        ignored,
        groups: groups.into_values().collect(),
    }
}

/// A joint's samples in time order, one per time: a repeated state is kept once, two
/// different positions at one time are an error (two publishers of the same joint).
fn distinct(mut series: Vec<Sample>, name: &str, stream: &str, path: &Path) -> Result<Vec<Sample>> {
    series.sort_by_key(|s| s.t);
    let mut out: Vec<Sample> = Vec::with_capacity(series.len());
    for s in series {
        match out.last() {
            Some(last) if last.t == s.t && last.q == s.q => {}
            Some(last) if last.t == s.t => {
                return Err(invalid(
                    path,
                    format!(
                        "{stream} give joint {} two positions at one time ({} and {} at stamp {} s): two publishers give the same joint (faze4 merges publishers of different joints)",
                        quoted(name),
                        shortest(last.q),
                        shortest(s.q),
                        shortest(seconds_from_nanoseconds(s.t))
                    ),
                ));
            }
            _ => out.push(s),
        }
    }
    Ok(out)
}

/// Whether the recorded velocities are used, with the note that says so or why not (see the
/// module's documentation).
fn use_velocities(
    names: &[String],
    series: &[Vec<Sample>],
    interpolation: Option<Interpolation>,
    stream: &str,
    notes: &mut Vec<Note>,
) -> bool {
    let given = series.iter().flatten().any(|s| s.v.is_some());
    if !given || interpolation == Some(Interpolation::Linear) {
        return false;
    }
    let ignored = |why: Unused| Note::VelocitiesIgnored {
        stream: stream.to_string(),
        why,
    };
    if let Some(j) = series.iter().position(|s| s.iter().any(|s| s.v.is_none())) {
        notes.push(ignored(Unused::Partial {
            joint: names[j].clone(),
        }));
        return false;
    }
    // Σ|½(vᵢ + vᵢ₊₁)·Δt − Δq| against Σ|Δq|, and the joint missing most
    let (mut miss, mut motion, mut worst) = (0.0, 0.0, (0.0, 0));
    for (j, s) in series.iter().enumerate() {
        let mut joint_miss = 0.0;
        for pair in s.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let dt = seconds_from_nanoseconds(b.t - a.t);
            let dq = b.q - a.q;
            joint_miss += (0.5 * (a.v.unwrap_or(0.0) + b.v.unwrap_or(0.0)) * dt - dq).abs();
            motion += dq.abs();
        }
        miss += joint_miss;
        if joint_miss > worst.0 {
            worst = (joint_miss, j);
        }
    }
    let zeros = series.iter().flatten().all(|s| s.v == Some(0.0));
    if zeros && motion > 0.0 {
        notes.push(ignored(Unused::Zero));
        return false;
    }
    if miss > VELOCITY_AGREEMENT * motion {
        notes.push(ignored(Unused::Disagree {
            joint: names[worst.1].clone(),
            share: miss / motion,
        }));
        return false;
    }
    let points = series.iter().map(Vec::len).max().unwrap_or(0);
    if interpolation.is_none() && points > 1 {
        notes.push(Note::VelocitiesChoseCubic {
            stream: stream.to_string(),
        });
    }
    true
}

/// A joint's samples at the `grid` times (ns), (position, velocity): its own where it has one,
/// else between its samples as its own spline through them (linear, or cubic Hermite with
/// `velocities`) gives it, held at rest before its first and after its last.
fn resampled(series: &[Sample], grid: &[i64], velocities: bool) -> Vec<(f64, f64)> {
    let (first, last) = (series[0], series[series.len() - 1]);
    let own = TimedTrajectory {
        joint_names: vec![String::new()],
        points: (series.iter())
            .map(|s| TrajectoryPoint {
                time_from_start: seconds_from_nanoseconds(s.t - first.t),
                positions: vec![s.q],
                velocities: match velocities {
                    true => vec![s.v.unwrap_or(0.0)],
                    false => Vec::new(),
                },
                accelerations: Vec::new(),
            })
            .collect(),
    };
    let spline = Spline::new(&own);
    let mut k = 0;
    (grid.iter())
        .map(|&t| {
            while k < series.len() && series[k].t < t {
                k += 1;
            }
            match series.get(k) {
                Some(s) if s.t == t => (s.q, if velocities { s.v.unwrap_or(0.0) } else { 0.0 }),
                _ if t < first.t => (first.q, 0.0),
                _ if t > last.t => (last.q, 0.0),
                _ => {
                    let (mut q, mut v) = ([0.0], [0.0]);
                    spline.eval(seconds_from_nanoseconds(t - first.t), &mut q, &mut v);
                    (q[0], v[0])
                }
            }
        })
        .collect()
}
