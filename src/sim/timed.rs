//! A time-stamped trajectory as a run's command: its joints matched to the model's by name,
//! checked against the limits, played once from the state the arm is in as
//! `joint_trajectory_controller` plays a message it receives ([`Spline`], [`Playback`];
//! docs/trajectories.md).

use std::path::Path;

use super::Warning;
use crate::error::{Error, Result, quoted, shortest};
use crate::model::Model;
use crate::traj::{HeldJoint, Interpolation, Playback, Spline, TimedTrajectory, Trajectory, TrajectoryPoint};

/// How a message is played: where the arm starts and how the points are joined (`start`,
/// `interpolation`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Play {
    /// The arm's start, one value per degree of freedom (rad or m), at rest; `None`: the first
    /// point's positions.
    pub start: Option<Vec<f64>>,
    /// The interpolation; `None`: by what the points give, as the controller decides.
    pub interpolation: Option<Interpolation>,
}

/// What a run of a time-stamped trajectory commands: the spline over the model's joints, the
/// time it takes, and the model's joints it does not name.
#[derive(Clone, Debug)]
pub struct TimedCommand {
    /// [`Trajectory::Spline`], one column per degree of freedom in the model's order.
    pub trajectory: Trajectory,
    /// The last point's time (s): the run's default duration, the approach to the first point
    /// included.
    pub duration: f64,
    /// The model's joints the trajectory does not name: each holds its start position (the
    /// start given, else 0 clamped into its limits) with zero velocity.
    pub held: Vec<HeldJoint>,
}

impl TimedCommand {
    /// The command of `trajectory` (checked: [`TimedTrajectory::check`]) on `model`, played as
    /// `play` says: its joint names matched to the model's in any order
    /// ([`TimedTrajectory::in_joint_order`]; a name the model lacks is an error listing its
    /// joints), every point and the start within the joint limits, the points joined by the
    /// interpolation given ([`TimedTrajectory::with_interpolation`]) or by what they give; a
    /// first point at t > 0 is reached from the start over that time (an approach segment from
    /// the start at rest, as the controller interpolates from the state before the
    /// trajectory). `source` names the trajectory in errors and in the warning.
    pub fn new(model: &Model, trajectory: &TimedTrajectory, source: &Path, play: &Play) -> Result<TimedCommand> {
        trajectory.check(source)?;
        if let Some(start) = &play.start {
            check_start(model, start)?;
        }
        let names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
        let hold: Vec<f64> = match &play.start {
            Some(start) => start.clone(),
            None => model.joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)).collect(),
        };
        let (ordered, held) = trajectory.in_joint_order(&names, &hold, source)?;
        for (k, point) in ordered.points.iter().enumerate() {
            for (i, (joint, &q)) in model.joints.iter().zip(&point.positions).enumerate() {
                if !joint.within_limits(q) {
                    return Err(Error::InvalidData {
                        path: source.to_path_buf(),
                        message: format!(
                            "point {k}: joint J{} ({}) is commanded to {} {}, beyond its limits [{}, {}]{}",
                            i + 1,
                            joint.name,
                            shortest(q),
                            joint.kind.unit(),
                            shortest(joint.lower),
                            shortest(joint.upper),
                            model.mimic_note(i)
                        ),
                    });
                }
            }
        }
        let ordered = match play.interpolation {
            Some(rule) => ordered.with_interpolation(rule, source)?,
            None => ordered,
        };
        let first = &ordered.points[0];
        let playback = Playback {
            interpolation: ordered.interpolation(),
            interpolation_forced: play.interpolation.is_some(),
            start: play.start.clone().unwrap_or_else(|| first.positions.clone()),
            start_given: play.start.is_some(),
            approach_s: first.time_from_start,
            points: ordered.points.len(),
        };
        let played = with_approach(ordered, &playback.start);
        let spline = Spline::played(&played, playback);
        Ok(TimedCommand {
            duration: spline.duration(),
            trajectory: Trajectory::Spline(spline),
            held,
        })
    }

    /// The warning that names the held joints, if any.
    pub fn warning(&self, source: &Path) -> Option<Warning> {
        (!self.held.is_empty()).then(|| Warning::HeldJoints {
            source: source.display().to_string(),
            joints: self.held.clone(),
        })
    }
}

/// `trajectory` with, before a first point at t > 0, the state before it: `start` at t = 0, at
/// rest (zero velocities and accelerations where the points give them, as
/// `set_point_before_trajectory_msg` fills them).
fn with_approach(mut trajectory: TimedTrajectory, start: &[f64]) -> TimedTrajectory {
    let first = &trajectory.points[0];
    if first.time_from_start > 0.0 {
        let zeros = |given: &Vec<f64>| vec![0.0; given.len()];
        let before = TrajectoryPoint {
            time_from_start: 0.0,
            positions: start.to_vec(),
            velocities: zeros(&first.velocities),
            accelerations: zeros(&first.accelerations),
        };
        trajectory.points.insert(0, before);
    }
    trajectory
}

/// A start (`start`) of one value per degree of freedom, each finite and within its joint's
/// limits; the error names the option and the joint.
fn check_start(model: &Model, start: &[f64]) -> Result<()> {
    if start.len() != model.dof() {
        return Err(Error::option(
            "start",
            format!(
                "gives {} values; {} has {} degrees of freedom ({})",
                start.len(),
                model.name,
                model.dof(),
                model
                    .joints
                    .iter()
                    .map(|j| quoted(&j.name))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    for (i, (joint, &q)) in model.joints.iter().zip(start).enumerate() {
        if !q.is_finite() || !joint.within_limits(q) {
            return Err(Error::option(
                "start",
                format!(
                    "J{} ({}) is {} {}, beyond its limits [{}, {}]",
                    i + 1,
                    quoted(&joint.name),
                    shortest(q),
                    joint.kind.unit(),
                    shortest(joint.lower),
                    shortest(joint.upper)
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::TrajectoryPoint;

    /// The Faze4's six joints, named as the model names them.
    fn faze4() -> Model {
        crate::faze4::model()
    }

    fn goal(model: &Model, times: &[f64], q: f64, velocities: bool) -> TimedTrajectory {
        TimedTrajectory {
            joint_names: model.joints.iter().map(|j| j.name.clone()).collect(),
            points: (times.iter().enumerate())
                .map(|(k, &t)| TrajectoryPoint {
                    time_from_start: t,
                    positions: vec![q * (k + 1) as f64; 6],
                    velocities: if velocities { vec![0.0; 6] } else { Vec::new() },
                    accelerations: Vec::new(),
                })
                .collect(),
        }
    }

    fn at(command: &TimedCommand, t: f64) -> ([f64; 6], [f64; 6]) {
        let (mut q, mut v) = ([0.0; 6], [0.0; 6]);
        command.trajectory.eval(t, &mut q, &mut v);
        (q, v)
    }

    fn start_of(command: &TimedCommand) -> ([f64; 6], [f64; 6]) {
        let (mut q, mut v) = ([0.0; 6], [0.0; 6]);
        command.trajectory.start_state(&mut q, &mut v);
        (q, v)
    }

    /// A first point at 4 s is kept: by default the arm holds the first point's positions until
    /// then; from a start, it goes there over the 4 s (cubic from rest with velocities).
    #[test]
    fn a_first_time_is_the_approach_from_the_start() {
        let model = faze4();
        let source = Path::new("goal.yaml");
        let one = goal(&model, &[4.0], 0.2, true);
        let held = TimedCommand::new(&model, &one, source, &Play::default()).unwrap();
        assert_eq!(held.duration, 4.0);
        assert_eq!(at(&held, 2.0), ([0.2; 6], [0.0; 6]));
        assert_eq!(start_of(&held), ([0.2; 6], [0.0; 6]));
        let play = Play {
            start: Some(vec![0.0; 6]),
            interpolation: None,
        };
        let approach = TimedCommand::new(&model, &one, source, &play).unwrap();
        assert_eq!(start_of(&approach), ([0.0; 6], [0.0; 6]));
        let (q, v) = at(&approach, 2.0);
        assert!((q[0] - 0.1).abs() < 1e-15 && v[0] > 0.0, "halfway, moving: {q:?} {v:?}");
        assert_eq!(at(&approach, 4.0).0, [0.2; 6]);
        let Trajectory::Spline(s) = &approach.trajectory else {
            panic!()
        };
        let p = s.playback().unwrap();
        assert_eq!(
            (p.approach_s, p.points, p.start_given, p.interpolation),
            (4.0, 1, true, Interpolation::Cubic)
        );
        // at t = 0 with a start: the controller commands the point at once, the arm at the start
        let now = goal(&model, &[0.0, 1.0], 0.2, false);
        let step = TimedCommand::new(&model, &now, source, &play).unwrap();
        assert_eq!(start_of(&step), ([0.0; 6], [0.0; 6]));
        assert_eq!(at(&step, 0.0).0, [0.2; 6]);
        // without a start and at t = 0: the first point's own state, as before
        let plain = TimedCommand::new(&model, &now, source, &Play::default()).unwrap();
        assert_eq!(start_of(&plain), at(&plain, 0.0));
        assert_eq!(start_of(&plain).1, [0.2; 6], "the first segment's slope");
    }

    #[test]
    fn a_start_is_checked_against_the_model() {
        let model = faze4();
        let one = goal(&model, &[1.0], 0.2, false);
        let bad = |start: Vec<f64>| {
            let play = Play {
                start: Some(start),
                interpolation: None,
            };
            TimedCommand::new(&model, &one, Path::new("g.yaml"), &play)
                .unwrap_err()
                .to_string()
        };
        assert!(
            bad(vec![0.0; 5]).starts_with("`start`: gives 5 values; faze4_arm has 6 degrees of freedom ("),
            "{}",
            bad(vec![0.0; 5])
        );
        let e = bad(vec![0.0, 9.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(e.starts_with("`start`: J2 ('"), "{e}");
        assert!(e.contains("is 9 rad, beyond its limits"), "{e}");
        assert!(bad(vec![f64::NAN; 6]).contains("J1"));
    }
}
