//! A time-stamped trajectory as a run's command: its joints matched to the model's by name,
//! checked against the limits, played once as `joint_trajectory_controller` plays it
//! ([`Spline`]; docs/trajectories.md).

use std::path::Path;

use super::Warning;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::traj::{HeldJoint, Spline, TimedTrajectory, Trajectory};

/// What a run of a time-stamped trajectory commands: the spline over the model's joints, the
/// time it takes, and the model's joints it does not name.
#[derive(Clone, Debug)]
pub struct TimedCommand {
    /// [`Trajectory::Spline`], one column per degree of freedom in the model's order.
    pub trajectory: Trajectory,
    /// The last point's time from the first (s): the run's default duration.
    pub duration: f64,
    /// The model's joints the trajectory does not name: each holds its start position (0,
    /// clamped into its limits) with zero velocity.
    pub held: Vec<HeldJoint>,
}

impl TimedCommand {
    /// The command of `trajectory` (checked: [`TimedTrajectory::check`]) on `model`: its joint
    /// names matched to the model's in any order ([`TimedTrajectory::in_joint_order`]; a name
    /// the model lacks is an error listing its joints), every point within the joint limits.
    /// `source` names the trajectory in errors and in the warning.
    pub fn new(model: &Model, trajectory: &TimedTrajectory, source: &Path) -> Result<TimedCommand> {
        trajectory.check(source)?;
        let names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
        let hold: Vec<f64> = model.joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)).collect();
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
        Ok(TimedCommand {
            duration: ordered.duration(),
            trajectory: Trajectory::Spline(Spline::new(&ordered)),
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
