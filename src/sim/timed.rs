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
                            "point {k}: joint J{} ({}) is commanded to {q} {}, beyond its limits [{}, {}]{}",
                            i + 1,
                            joint.name,
                            joint.kind.unit(),
                            joint.lower,
                            joint.upper,
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
