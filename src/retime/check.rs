//! The closed-loop check: the timing played in faze4's own loop (the 5 kHz PD, the motors'
//! envelopes, the verdict), and where it does not follow, the times it failed at
//! (docs/retime.md, "The closed-loop check").
//!
//! Two functions stand between retime and the rest of faze4 and are the ones to change when
//! those change: [`command`] (how a timing becomes a command the loop plays) and [`scenario`]
//! (how the check's scenario is built).

use std::path::Path;
use std::sync::Arc;

use super::SLOWDOWN;
use crate::control::Motor;
use crate::error::{Error, Result, shortest};
use crate::geometry::CollisionSet;
use crate::model::Model;
use crate::sim::{
    BadSteps, Play, Recorder, Sample, Scenario, ScenarioBuilder, StopFlag, Summary, Tape, TimedCommand, run, step_count,
};
use crate::traj::{TimedTrajectory, Trajectory};

/// The command `faze4 replay` makes of `trajectory` (the file retime writes) on `model`: the
/// points joined as `joint_trajectory_controller` joins them ([`TimedCommand`]), and the run's
/// duration, the last point's time (replay's default). The check plays exactly this, so the
/// file plays back to the check's verdict.
pub fn command(model: &Model, trajectory: &TimedTrajectory) -> Result<(Trajectory, f64)> {
    let timed = TimedCommand::new(model, trajectory, Path::new("retime"), &Play::default())?;
    Ok((timed.trajectory, timed.duration))
}

/// The check's scenario: `base` with `trajectory` for `duration` seconds, sharing an already
/// loaded collision set.
pub(crate) fn scenario(
    base: &ScenarioBuilder,
    trajectory: Trajectory,
    duration: f64,
    collision_set: Option<Arc<CollisionSet>>,
) -> Result<Scenario> {
    // retime has no `duration`: a timing the check cannot play is `dt`'s fault
    let dt = base.time_step();
    if let Err(bad) = step_count(duration, dt) {
        return Err(Error::option(
            "dt",
            format!(
                "{} s: the check plays the timing's {} s in steps of it, {}",
                shortest(dt),
                shortest(duration),
                match bad {
                    BadSteps::TooFew => "less than one step",
                    BadSteps::TooMany => "more than the 10^12 steps a run may take",
                }
            ),
        ));
    }
    let mut builder = base
        .clone()
        .trajectory(trajectory)
        .duration(duration)
        .command("retime check");
    if let Some(set) = collision_set {
        builder = builder.collision_set(set);
    }
    builder.build()
}

/// How often the check looks for a failure (s of simulated time): saturation, step loss,
/// tracking error beyond half the threshold, a speed limit passed.
const LOOK_PERIOD: f64 = 1e-3;

/// A speed found beyond its limit is capped at this share of x below what would have kept it
/// (1 % of speed): room for the next check's own overshoot.
pub(crate) const SPEED_HEADROOM: f64 = 0.98;

/// Where a check failed: the time (s), the share of x = ṡ² that would have kept the limit
/// there (for a speed beyond its limit, [`SPEED_HEADROOM`]·(limit/speed)²; else
/// [`SLOWDOWN`]), and for a speed beyond its limit, the joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Failure {
    pub t: f64,
    pub keep: f64,
    pub too_fast: Option<usize>,
}

/// Runs `scenario` and returns its summary and where it failed to follow: where a torque was
/// clipped at its limit or its motor's envelope, a tracking error passed half its threshold
/// or a speed passed its limit (looked at every [`LOOK_PERIOD`]), and each stepper's first
/// lost step and the divergence, if any. `tape`, if given, records the run.
pub(crate) fn run_check(
    scenario: &Scenario,
    tape: Option<&mut Tape>,
    stop: &StopFlag,
) -> Result<(Summary, Vec<Failure>)> {
    let mut failures = Failures::new(scenario);
    let summary = match tape {
        Some(tape) => run(scenario, &mut [&mut failures, tape], stop)?,
        None => run(scenario, &mut [&mut failures], stop)?,
    };
    let mut found = failures.found;
    let lost = summary
        .motors
        .iter()
        .flatten()
        .flatten()
        .filter_map(|m| m.step_loss.map(|l| l.t));
    let diverged = summary.diverged.as_ref().map(|d| d.t);
    found.extend(lost.chain(diverged).map(|t| Failure {
        t,
        keep: SLOWDOWN,
        too_fast: None,
    }));
    Ok((summary, found))
}

/// The recorder that notes when the run fails to follow.
struct Failures {
    /// Per joint its constant limit E (N·m or N).
    effort: Vec<f64>,
    /// Per joint its motor and ratio, if any.
    motors: Vec<Option<(Motor, f64)>>,
    /// Per joint its speed limit (+∞: none).
    speed_limit: Vec<f64>,
    /// Half the tracking threshold (rad or m).
    error: f64,
    found: Vec<Failure>,
}

impl Failures {
    fn new(sc: &Scenario) -> Self {
        let motors = (0..sc.model.dof())
            .map(|j| {
                (sc.motors.as_ref())
                    .and_then(|m| m[j].clone())
                    .map(|m| (m, sc.model.joints[j].gear_ratio))
            })
            .collect();
        Failures {
            effort: sc.controller.gains.effort.clone(),
            motors,
            speed_limit: sc.speed_limit.clone(),
            error: 0.5 * sc.thresholds.max_error,
            found: Vec::new(),
        }
    }

    /// Where joint j fails at `sample`, if it does: [`SPEED_HEADROOM`]·(limit/speed)² of x for
    /// a speed beyond its limit (with the joint); [`SLOWDOWN`] for a torque at a bound of what
    /// actuation allowed (the loop clips τ to exactly that bound) or an error beyond half the
    /// threshold.
    fn fails(&self, sample: &Sample, j: usize) -> Option<Failure> {
        let e = self.effort[j];
        let (lo, hi) = match &self.motors[j] {
            Some((m, r)) => {
                let (lo, hi) = m.joint_bounds(*r, sample.v[j]);
                (lo.max(-e), hi.min(e))
            }
            None => (-e, e),
        };
        let tau = sample.tau[j];
        let speed = sample.v[j].abs();
        let too_fast = (speed > self.speed_limit[j]).then(|| SPEED_HEADROOM * (self.speed_limit[j] / speed).powi(2));
        let t = sample.t;
        if tau <= lo || tau >= hi || (sample.q_cmd[j] - sample.q[j]).abs() > self.error {
            return Some(Failure {
                t,
                keep: too_fast.map_or(SLOWDOWN, |k| k.min(SLOWDOWN)),
                too_fast: None,
            });
        }
        too_fast.map(|keep| Failure {
            t,
            keep,
            too_fast: Some(j),
        })
    }
}

impl Recorder for Failures {
    fn period(&self) -> f64 {
        LOOK_PERIOD
    }

    fn record(&mut self, sample: &Sample) -> Result<()> {
        for j in 0..sample.q.len() {
            if let Some(failure) = self.fails(sample, j) {
                self.found.push(failure);
            }
        }
        Ok(())
    }
}
