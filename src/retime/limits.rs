//! The limits a timing must keep, taken from the scenario that checks it (one source: the
//! closed loop judges against the same model, motors, torque limits and speed limits).
//!
//! Per joint: the speed limit, the lowest of the scenario's (`--max-speed`, else the URDF's
//! `velocity`; see [`crate::sim::ScenarioBuilder::max_speed`]) and the motor's top speed over
//! its ratio; the torque range at a speed ([`JointTorque`]): the motor's envelope within the
//! constant limit E, shrunk by the margin, less the joint's damping. Per run: the shortest
//! smoothing window the drives need (an open-loop stepper's ringing; docs/retime.md, "The
//! drive's own limits").

use super::RetimeOptions;
use super::ends::Ends;
use super::envelope::JointTorque;
use super::grid::PathGrid;
use crate::error::{Error, Result};
use crate::id::JointId;
use crate::model::JointKind;
use crate::sim::Scenario;
use crate::sim::check::override_per_joint;

/// Where a joint's speed limit comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpeedSource {
    /// The scenario's speed limit (`--max-speed` or the URDF's `velocity`).
    Given,
    /// The motor's top speed (a DC motor's no-load speed, a stepper's last curve point) over
    /// its ratio.
    Motor,
}

/// Every joint's limits.
#[derive(Clone, Debug)]
pub(crate) struct Limits {
    /// The torque range at a speed, per joint.
    pub torque: Vec<JointTorque>,
    /// The speed limit per joint (rad/s or m/s; +∞ for none).
    pub speed: Vec<f64>,
    /// The acceleration limit per joint (rad/s² or m/s²; +∞ for none).
    pub acceleration: Vec<f64>,
    /// The jerk limit per joint (rad/s³ or m/s³; +∞ for none).
    pub jerk: Vec<f64>,
    /// Where each speed limit comes from.
    pub speed_source: Vec<SpeedSource>,
    /// The unit of each joint's torque: `N·m` (revolute) or `N` (prismatic).
    pub torque_unit: Vec<&'static str>,
    /// The shortest smoothing window the drives need (s; 0 for none): the torque a timing asks
    /// changes over at least this, so that each open-loop stepper's ringing fits in the margin.
    pub window: f64,
}

impl Limits {
    /// The limits of `scenario`'s model and motors, keeping `1 − margin` of each torque limit,
    /// and the acceleration and jerk limits of `options` (an error naming the option where
    /// one does not fit the joints or is not > 0).
    pub fn of(scenario: &Scenario, options: &RetimeOptions) -> Result<Limits> {
        let margin = options.margin;
        let model = &scenario.model;
        let effort = &scenario.controller.gains.effort;
        let torque: Vec<JointTorque> = (0..model.dof())
            .map(|j| {
                let joint = &model.joints[j];
                let motor = (scenario.motors.as_ref())
                    .and_then(|m| m[j].clone())
                    .map(|m| (m, joint.gear_ratio));
                JointTorque::new(effort[j], motor, joint.damping, margin)
            })
            .collect();
        let (speed, speed_source) = (torque.iter().zip(&scenario.speed_limit))
            .map(|(t, &given)| {
                let top = t.top_speed();
                match top < given {
                    true => (top, SpeedSource::Motor),
                    false => (given, SpeedSource::Given),
                }
            })
            .unzip();
        let torque_unit = (model.joints.iter())
            .map(|j| match j.kind {
                JointKind::Prismatic => "N",
                _ => "N·m",
            })
            .collect();
        let n = model.dof();
        let (mut acceleration, mut jerk) = (vec![f64::INFINITY; n], vec![f64::INFINITY; n]);
        let positive = |v: f64| v > 0.0;
        override_per_joint(
            "max_accel",
            &mut acceleration,
            &options.max_acceleration,
            positive,
            "> 0",
        )?;
        override_per_joint("max_jerk", &mut jerk, &options.max_jerk, positive, "> 0")?;
        let window = least_window(scenario, margin)?;
        Ok(Limits {
            torque,
            speed,
            acceleration,
            jerk,
            speed_source,
            torque_unit,
            window,
        })
    }
}

/// Each smart servo of `scenario` holding the arm at rest at both ends of the path (`grid`'s
/// first and last points, where the arm stands before and after any timing; an end the timing
/// passes moving, `ends`, is not stood at): its loop's sag
/// under the load within the verdict's `max_error`, and the load within what its protection
/// holds for longer than its time (the arm stays there); else the error saying which, at that
/// end (docs/retime.md, "The drive's own limits"). No timing changes either.
pub(crate) fn held_at_ends(scenario: &Scenario, grid: &PathGrid, ends: Ends) -> Result<()> {
    let (dof, last) = (grid.dof, grid.points() - 1);
    let max_error = scenario.thresholds.max_error;
    let rests = [(0, ends.start), (last, ends.end)];
    for i in rests.iter().filter(|(_, speed)| *speed == 0.0).map(|&(i, _)| i) {
        for (j, drive) in scenario.drives.iter().enumerate() {
            let Some(hold) = drive.holding() else { continue };
            let load = grid.c[i * dof + j].abs();
            let sag = hold.sag_per_torque * load;
            let end = match i {
                0 => "start",
                _ => "end",
            };
            let message = if load > hold.sustained {
                format!(
                    "J{}'s servo holds {load:.4} N·m to keep the arm at the path's {end}, above the {:.4} N·m its {} allows for {} s (assumed registers: docs/motors.md, \"Smart servos\"): it trips while the arm stands there, whatever the timing",
                    j + 1,
                    hold.sustained,
                    hold.protection,
                    hold.time
                )
            } else if sag > max_error {
                format!(
                    "J{}'s servo sags {sag:.4} rad under the {load:.4} N·m that keeps the arm at the path's {end} (its own loop's error at rest: a P register without I, at the catalog's duty per count), beyond `max_error` {max_error} rad, whatever the timing",
                    j + 1
                )
            } else {
                continue;
            };
            return Err(Error::NothingFollows {
                s: grid.s[i],
                length: grid.s[last],
                point: 0,
                joint: Some(JointId(j)),
                message,
            });
        }
    }
    Ok(())
}

/// The shortest smoothing window `scenario`'s drives need at `margin` (s; 0 when none does), or
/// the error naming `margin` where no window is enough (an open-loop stepper at margin 0).
fn least_window(scenario: &Scenario, margin: f64) -> Result<f64> {
    let mut least = 0.0;
    for (j, drive) in scenario.drives.iter().enumerate() {
        let w = drive.least_window(margin);
        if w.is_infinite() {
            let ring = drive.stepper().map_or(0.0, |d| d.damping.ring_hz());
            return Err(Error::option(
                "margin",
                format!(
                    "0 leaves J{}'s open-loop stepper no torque for its ringing (at {ring:.0} Hz): a timing at its pull-out torque slips at the first change of load; give a margin > 0 (0.1 keeps a 0.1 share for it)",
                    j + 1
                ),
            ));
        }
        least = f64::max(least, w);
    }
    Ok(least)
}
