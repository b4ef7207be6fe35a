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
//!   are refused (two publishers of the same joints), and so are a joint's messages going back
//!   in time (a bag played in a loop).
//! * The recorded velocities are used when every message gives them and they agree with the
//!   positions (each between the slopes of the positions on either side of it, to within
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

/// The largest share of the positions' motion by which the recorded velocities may fall
/// outside the positions' slopes for them to be used: Σᵢ dist(vᵢ, [sᵢ₋, sᵢ₊])·Δtᵢ ≤ 0.25 ·
/// Σ|Δq| over every joint (sᵢ₋, sᵢ₊ the secant slopes before and after sample i, Δtᵢ half the
/// time they span). A smooth motion's true velocities lie between them (outside by O(Δt²)
/// where the acceleration turns: far below); zeros fall outside by about all of the motion,
/// and velocity noise of a quarter of the speed by about a quarter. A choice of faze4's
/// (docs/trajectories.md), not a figure from ros2_control.
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
    backwards(&states, &times, selection, &at, path)?;
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
                    "{stream} all have the header stamp {} s{}",
                    shortest(seconds_from_nanoseconds(stamps[0])),
                    match differing(states) {
                        Some((name, a, b)) => format!(
                            " and give joint {} different positions ({} and {}): two publishers of the same joints, or a publisher that does not stamp its messages (the file keeps no other time)",
                            quoted(name),
                            shortest(a),
                            shortest(b)
                        ),
                        None => " and the file keeps no other time: they make no motion".to_string(),
                    }
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

/// Refuses a kept joint whose messages, in the order the stream gives them, go back in time:
/// one publisher's clock does not (a bag played in a loop, a simulation restarted), and sorting
/// them by stamp would interleave two motions unsaid. Publishers of different joints may
/// interleave as they like.
fn backwards(
    states: &[StampedState],
    times: &[i64],
    selection: &Selection,
    at: &dyn Fn(usize) -> String,
    path: &Path,
) -> Result<()> {
    let mut last: BTreeMap<&str, (i64, usize)> = BTreeMap::new();
    for (k, (s, &t)) in states.iter().zip(times).enumerate() {
        for name in s.message.name.iter().filter(|n| selection.keeps(n)) {
            if let Some(&(before, j)) = last.get(name.as_str())
                && t < before
            {
                return Err(invalid(
                    path,
                    format!(
                        "{}: joint {} at {} s, before the {} s of {}: its messages go back in time (a bag played in a loop, a simulation restarted?)",
                        at(k),
                        quoted(name),
                        shortest(seconds_from_nanoseconds(t)),
                        shortest(seconds_from_nanoseconds(before)),
                        at(j)
                    ),
                ));
            }
            last.insert(name, (t, k));
        }
    }
    Ok(())
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

/// A joint that two of `states` give different positions, with the two.
fn differing(states: &[StampedState]) -> Option<(&str, f64, f64)> {
    let mut first: BTreeMap<&str, f64> = BTreeMap::new();
    for s in states {
        for (name, &q) in s.message.name.iter().zip(&s.message.position) {
            match first.get(name.as_str()) {
                Some(&p) if p != q => return Some((name, p, q)),
                Some(_) => {}
                None => {
                    first.insert(name, q);
                }
            }
        }
    }
    None
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
    // Σ dist(vᵢ, the slopes on either side)·Δtᵢ against Σ|Δq|, and the joint missing most
    let (mut miss, mut motion, mut worst) = (0.0, 0.0, (0.0, 0));
    for (j, s) in series.iter().enumerate() {
        let joint_miss = outside_slopes(s);
        motion += s.windows(2).map(|p| (p[1].q - p[0].q).abs()).sum::<f64>();
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

/// How far a joint's recorded velocities fall outside the slopes of its positions, in
/// position: Σᵢ dist(vᵢ, [min(sᵢ₋, sᵢ₊), max(sᵢ₋, sᵢ₊)])·Δtᵢ, sᵢ₋ and sᵢ₊ the secant slopes
/// of the intervals before and after sample i (one at either end), Δtᵢ half the time they
/// span. A smooth motion's velocity lies between the slopes on either side of it (to O(Δt²)
/// where its acceleration turns); zeros, and noise even alternating in sign, do not.
fn outside_slopes(series: &[Sample]) -> f64 {
    let slopes: Vec<(f64, f64)> = (series.windows(2))
        .map(|p| {
            let dt = seconds_from_nanoseconds(p[1].t - p[0].t);
            ((p[1].q - p[0].q) / dt, dt)
        })
        .collect();
    (series.iter().enumerate())
        .map(|(i, s)| {
            let before = i.checked_sub(1).and_then(|i| slopes.get(i));
            let after = slopes.get(i);
            let (lo, hi, span) = match (before, after) {
                (Some(&(a, ta)), Some(&(b, tb))) => (a.min(b), a.max(b), 0.5 * (ta + tb)),
                (Some(&(a, ta)), None) | (None, Some(&(a, ta))) => (a, a, 0.5 * ta),
                (None, None) => return 0.0,
            };
            let v = s.v.unwrap_or(0.0);
            (lo - v).max(v - hi).max(0.0) * span
        })
        .sum()
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::files::ros::{Header, RosTime};

    /// A message at `ms` milliseconds (from an epoch stamp), logged then too.
    fn at(ms: i64, names: &[&str], q: &[f64], v: &[f64]) -> StampedState {
        let ns = 1_700_000_000_000_000_000 + ms * 1_000_000;
        StampedState {
            log_time: Some(ns as u64),
            message: JointStateMsg {
                header: Header {
                    stamp: RosTime {
                        sec: (ns / 1_000_000_000) as i32,
                        nanosec: (ns % 1_000_000_000) as u32,
                    },
                    frame_id: String::new(),
                },
                name: names.iter().map(|s| s.to_string()).collect(),
                position: q.to_vec(),
                velocity: v.to_vec(),
                effort: Vec::new(),
            },
        }
    }

    fn read(states: Vec<StampedState>, selection: &Selection) -> Result<Recording> {
        recorded_motion(states, Some("/joint_states"), selection, Path::new("b.mcap"))
    }

    fn model(joints: &[&str]) -> Selection {
        Selection {
            joints: Some(joints.iter().map(|s| s.to_string()).collect()),
            ..Default::default()
        }
    }

    /// An arm and its gripper published apart, and a camera the model lacks: one point at every
    /// stamp, each joint joined between its own messages, held outside them.
    #[test]
    fn publishers_are_merged_by_time_and_other_joints_left_out() {
        let states = vec![
            at(0, &["a", "b"], &[0.0, 1.0], &[]),
            at(5, &["g"], &[0.5], &[]),
            at(7, &["pan"], &[0.1], &[]),
            at(10, &["b", "a"], &[2.0, 1.0], &[]),
            at(15, &["g"], &[0.25], &[]),
            at(20, &["a", "b"], &[0.0, 3.0], &[]),
        ];
        let r = read(states, &model(&["a", "b", "g"])).unwrap();
        let t = &r.trajectory;
        assert_eq!(t.joint_names, ["a", "b", "g"]);
        let times: Vec<f64> = t.points.iter().map(|p| p.time_from_start).collect();
        assert_eq!(times, [0.0, 0.005, 0.01, 0.015, 0.02]);
        let q = |k: usize| t.points[k].positions.clone();
        assert_eq!(q(0), [0.0, 1.0, 0.5], "the gripper held at its first state before it");
        assert_eq!(q(1), [0.5, 1.5, 0.5], "the arm between its own messages");
        assert_eq!(q(4), [0.0, 3.0, 0.25], "the gripper held after its last");
        assert!(t.points.iter().all(|p| p.velocities.is_empty()));
        assert_eq!(
            r.notes,
            vec![
                Note::IgnoredJoints {
                    stream: "topic /joint_states's JointState messages".into(),
                    joints: vec!["pan".into()],
                },
                Note::Merged {
                    stream: "topic /joint_states's JointState messages".into(),
                    groups: vec![vec!["a".into(), "b".into()], vec!["g".into()]],
                },
            ]
        );
        // renamed, the camera's joint is the model's
        let mut renamed = model(&["a", "b", "g", "cam_pan"]);
        renamed.rename = crate::traj::files::Rename::parse_list("pan=cam_pan").unwrap();
        let states = vec![
            at(0, &["a", "pan"], &[0.0, 0.1], &[]),
            at(10, &["a", "pan"], &[1.0, 0.2], &[]),
        ];
        assert_eq!(read(states, &renamed).unwrap().trajectory.joint_names, ["a", "pan"]);
        // none of the model's
        let e = read(vec![at(0, &["x", "y"], &[0.0, 0.0], &[])], &model(&["a"])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "b.mcap: topic /joint_states's JointState messages name none of the model's joints (they name 'x', 'y'; `rename` maps a prefix to the model's)"
        );
    }

    /// Recorded velocities: used when they agree with the positions (said), left out when they
    /// are zeros, partial or noise (said why), not judged under a given linear.
    #[test]
    fn recorded_velocities_are_used_only_when_they_agree() {
        // q = t² on a 10 ms grid: v = 2t is the true velocity
        let smooth = |v: &dyn Fn(f64) -> f64| -> Vec<StampedState> {
            (0..20)
                .map(|k| {
                    let t = k as f64 * 0.01;
                    at(k * 10, &["a"], &[t * t], &[v(t)])
                })
                .collect()
        };
        let all = Selection::default();
        let r = read(smooth(&|t| 2.0 * t), &all).unwrap();
        assert!(!r.trajectory.points[3].velocities.is_empty());
        assert!(
            matches!(r.notes[..], [Note::VelocitiesChoseCubic { .. }]),
            "{:?}",
            r.notes
        );
        let r = read(smooth(&|_| 0.0), &all).unwrap();
        assert!(r.trajectory.points[3].velocities.is_empty());
        assert!(
            matches!(r.notes[..], [Note::VelocitiesIgnored { why: Unused::Zero, .. }]),
            "{:?}",
            r.notes
        );
        // noise of the speed's size: alternating ±0.4 around the true velocity
        let r = read(
            smooth(&|t| 2.0 * t + if (t * 100.0).round() as i64 % 2 == 0 { 0.4 } else { -0.4 }),
            &all,
        )
        .unwrap();
        assert!(r.trajectory.points[3].velocities.is_empty());
        let Note::VelocitiesIgnored {
            why: Unused::Disagree { joint, share },
            ..
        } = &r.notes[0]
        else {
            panic!("{:?}", r.notes)
        };
        assert_eq!(joint, "a");
        assert!(*share > VELOCITY_AGREEMENT, "{share}");
        let forced = Selection {
            interpolation: Some(Interpolation::Linear),
            ..Default::default()
        };
        let r = read(smooth(&|t| 2.0 * t), &forced).unwrap();
        assert!(r.notes.is_empty() && r.trajectory.points[3].velocities.is_empty());
        let cubic = Selection {
            interpolation: Some(Interpolation::Cubic),
            ..Default::default()
        };
        assert!(
            read(smooth(&|t| 2.0 * t), &cubic).unwrap().notes.is_empty(),
            "a given rule: nothing chose it"
        );
        let mut partial = smooth(&|t| 2.0 * t);
        partial[4].message.velocity.clear();
        let r = read(partial, &all).unwrap();
        assert!(matches!(&r.notes[0], Note::VelocitiesIgnored { why: Unused::Partial { joint }, .. } if joint == "a"));
        let said = r.notes[0].to_string();
        assert!(said.starts_with("topic /joint_states's JointState messages give velocities that some messages leave out ('a' has none in some): left out"), "{said}");
    }

    /// Times: the stamps, else the log times (said), else refused; two publishers of one joint
    /// are refused, a repeated message is kept once.
    #[test]
    fn times_and_publishers_of_one_joint() {
        let mut same = vec![at(0, &["a"], &[0.0], &[]), at(10, &["a"], &[1.0], &[])];
        same[1].message.header = same[0].message.header.clone();
        let r = read(same.clone(), &Selection::default()).unwrap();
        assert_eq!(r.trajectory.points[1].time_from_start, 0.01);
        assert!(matches!(r.notes[..], [Note::LogTimes { .. }]));
        for s in &mut same {
            s.log_time = None;
        }
        let e = read(same, &Selection::default()).unwrap_err().to_string();
        assert!(
            e.contains("all have the header stamp 1700000000 s and give joint 'a' different positions (0 and 1): two publishers of the same joints, or a publisher that does not stamp its messages"),
            "{e}"
        );
        let mut zero = vec![at(0, &["a"], &[0.0], &[]), at(10, &["a"], &[1.0], &[])];
        zero[1].message.header.stamp = RosTime::default();
        let e = read(zero, &Selection::default()).unwrap_err().to_string();
        assert!(
            e.contains(
                "topic /joint_states, message 2: header stamp 0 where topic /joint_states, message 1 is stamped"
            ),
            "{e}"
        );
        // two publishers of the same joints (a joint_state_publisher beside the broadcaster)
        let two = vec![
            at(0, &["a"], &[0.5], &[]),
            at(0, &["a"], &[0.0], &[]),
            at(10, &["a"], &[1.0], &[]),
        ];
        let e = read(two, &Selection::default()).unwrap_err().to_string();
        assert!(
            e.contains("give joint 'a' two positions at one time (0.5 and 0 at stamp 1700000000 s): two publishers give the same joint"),
            "{e}"
        );
        let repeated = vec![
            at(0, &["a"], &[0.5], &[]),
            at(0, &["a"], &[0.5], &[]),
            at(10, &["a"], &[1.0], &[]),
        ];
        assert_eq!(
            read(repeated, &Selection::default()).unwrap().trajectory.points.len(),
            2
        );
        let e = read(vec![at(0, &["a", "b"], &[0.5], &[])], &Selection::default()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "b.mcap: topic /joint_states, message 1: 1 positions for 2 joint names"
        );
        let e = read(vec![at(0, &["a", "a"], &[0.5, 0.5], &[])], &Selection::default()).unwrap_err();
        assert!(e.to_string().ends_with("message 1: names joint 'a' twice"), "{e}");
    }
}
