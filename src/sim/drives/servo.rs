//! The smart-servo drive of a scenario (`drive` servo; docs/motors.md, "Smart servos"): which
//! joints drive themselves by their servo's own position loop ([`crate::control::ServoSpec`]),
//! the goal each is sent and when (the trajectory's own sample times, else `servo_rate`), the
//! speed drag put on the model's joint damping once, its actuation in the step, its trips and
//! its summary fields, and the warning that its protection registers are assumed.

use super::{JointDrive, with_friction};
use crate::control::{Motor, Protection, ServoSpec, ServoState, Trip};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::sim::check::positive;
use crate::sim::{MotorSummary, Scenario, ServoSummary, Step, Warning};

/// What the drive does, for people (`faze4 list drives`).
pub const ABOUT: &str = "the joints with a smart servo (the sts3215 and xm540-w270 presets) by the servo's own \
                         position loop on its register gains, sent its goal at the trajectory's sample times, within \
                         its torque limit, tripping its overload protection (assumed defaults); the other joints stay \
                         on the PD";

/// How often a servo is sent its goal when the command has no sample times of its own (a
/// wave) and `servo_rate` is not given (Hz): LeRobot's recording and datasets' default frame
/// rate (`src/lerobot/scripts/lerobot_record.py`: `DatasetRecordConfig.fps: int = 30`, its
/// `record_loop` sending one action a frame).
pub const DEFAULT_GOAL_RATE: f64 = 30.0;

/// What the summary says of every servo's protection registers: assumed, not published.
pub const ASSUMED: &str = "the protection registers are assumed defaults, not published figures \
                           (docs/motors.md, \"Smart servos\")";

/// What `drive` servo is given beyond the motors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ServoOptions {
    /// How often each servo is sent its goal, the command at that time held until the next
    /// (Hz, > 0; `servo_rate`). `None`: at the trajectory's own sample times, else
    /// [`DEFAULT_GOAL_RATE`].
    pub rate: Option<f64>,
}

/// One joint's smart servo: its registers and motor at the supply, and its goal rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServoDrive {
    /// Its loop, torque limit, motor and protection.
    pub spec: ServoSpec,
    /// Its goal rate (Hz; `None`: the trajectory's sample times, else [`DEFAULT_GOAL_RATE`]).
    pub rate: Option<f64>,
}

/// What a servo's own loop makes of a load it holds at rest (retime's limits at the path's
/// ends; docs/retime.md, "The drive's own limits").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Holding {
    /// The error its loop holds a load at, per N·m of it (rad/(N·m) at the output): the duty
    /// τ/τ_s needs τ/(τ_s·k·P) counts of error, 2π/counts_per_rev rad each; 0 with an I
    /// register (its integral takes the error out).
    pub sag_per_torque: f64,
    /// The most torque it holds at rest for longer than [`Holding::time`] without its
    /// protection acting (N·m at the output; +∞ where the torque limit keeps the duty below
    /// it): Feetech's overload duty, Dynamixel's PWM limit, times the stall torque.
    pub sustained: f64,
    /// How long above [`Holding::sustained`] trips the protection (s).
    pub time: f64,
    /// The protection in words, for a message (`Feetech's overload protection (80 % of its
    /// stall for 2 s)`).
    pub protection: &'static str,
}

/// `drive`'s [`Holding`].
pub fn holding(drive: &ServoDrive) -> Holding {
    let spec = &drive.spec;
    let sag_per_torque = match spec.i > 0.0 {
        true => 0.0,
        false => std::f64::consts::TAU / (spec.counts_per_rev * spec.duty_per_count * spec.p * spec.stall_torque),
    };
    let (duty, time, protection) = match spec.protection {
        Protection::Feetech { overload, time, .. } => (
            (overload < spec.torque_limit).then_some(overload),
            time,
            "Feetech's overload protection",
        ),
        Protection::Dynamixel { time } => (Some(spec.torque_limit), time, "Dynamixel's overload shutdown"),
    };
    Holding {
        sag_per_torque,
        sustained: duty.map_or(f64::INFINITY, |u| u * spec.stall_torque),
        time,
        protection,
    }
}

/// The servo of each joint whose motor has servo registers (`None`: the PD drives it), or the
/// error naming the option at fault: no `motors`, none of them a servo, a rate not > 0.
pub fn drives(options: &ServoOptions, motors: Option<&[Option<Motor>]>) -> Result<Vec<Option<ServoDrive>>> {
    let Some(motors) = motors else {
        return Err(Error::option(
            "drive",
            "servo drives the smart servos of `motors`: give `motors` (sts3215, xm540-w270)",
        ));
    };
    if let Some(rate) = options.rate {
        positive("servo_rate", rate)?;
    }
    let drives: Vec<Option<ServoDrive>> = (motors.iter())
        .map(|m| {
            let spec = m.as_ref()?.servo?;
            Some(ServoDrive {
                spec,
                rate: options.rate,
            })
        })
        .collect();
    if drives.iter().all(Option::is_none) {
        return Err(Error::option(
            "drive",
            "servo: none of the joints' motors is a smart servo (the presets sts3215 and xm540-w270 are; a motors \
             file's entries are bare motors)",
        ));
    }
    Ok(drives)
}

/// What a run's servos hold: each joint's servo state (its goal, loop and protection; n, the
/// PD's joints' unused), the frame last sent and the command at its time (n each, workspaces).
#[derive(Clone, Debug)]
pub struct Servos {
    /// Each joint's servo state.
    pub states: Vec<ServoState>,
    /// Their goal rate (Hz; `None`: the trajectory's sample times, else
    /// [`DEFAULT_GOAL_RATE`]), one option for every servo.
    rate: Option<f64>,
    /// The frame whose goal the servos hold.
    frame: Option<u64>,
    /// The command at that frame's time: positions (n, rad or m) and velocities (n).
    q: Vec<f64>,
    v: Vec<f64>,
}

impl Servos {
    /// The servos' workspace of a scenario with any servo, allocated once.
    pub fn new(sc: &Scenario) -> Option<Servos> {
        let n = sc.model.dof();
        let rate = sc.drives.iter().find_map(|d| Some(d.servo()?.rate))?;
        Some(Servos {
            states: vec![ServoState::default(); n],
            rate,
            frame: None,
            q: vec![0.0; n],
            v: vec![0.0; n],
        })
    }
}

/// The frame a servo's goal comes from at time `t` (s), and its time: every 1/`rate` s where
/// a rate is given, else the trajectory's own samples, else [`DEFAULT_GOAL_RATE`]'s.
fn frame(sc: &Scenario, rate: Option<f64>, t: f64) -> (u64, f64) {
    let every = |rate: f64| {
        let k = (t * rate + 1e-9).floor().max(0.0);
        (k as u64, k / rate)
    };
    match rate {
        Some(rate) => every(rate),
        None => sc.trajectory.frame(t).unwrap_or_else(|| every(DEFAULT_GOAL_RATE)),
    }
}

/// Sends each servo the goal of the frame at time `t` (s) when that frame is new: the command
/// at the frame's time, held until the next.
#[inline]
pub fn send(sc: &Scenario, servos: &mut Servos, t: f64) {
    let (k, at) = frame(sc, servos.rate, t);
    if servos.frame == Some(k) {
        return;
    }
    servos.frame = Some(k);
    sc.trajectory.eval(at, &mut servos.q, &mut servos.v);
    for (i, drive) in sc.drives.iter().enumerate() {
        if drive.servo().is_some() {
            servos.states[i].send(k, servos.q[i]);
        }
    }
}

/// Each servo's speed drag c = τ_s/ω₀ added to its joint's damping, where the discrete step
/// takes it implicitly (docs/motors.md, "Smart servos").
pub fn damp(model: &mut Model, drives: &[JointDrive]) {
    for (joint, drive) in model.joints.iter_mut().zip(drives) {
        if let Some(d) = drive.servo() {
            joint.damping += d.spec.drag();
        }
    }
}

/// The warning that the servos' protection registers are assumed (their joints, and the
/// figures taken: each preset's, by joint, where an arm mixes them).
pub fn assumed(drives: &[JointDrive]) -> Option<Warning> {
    let servos: Vec<(usize, &ServoDrive)> = (drives.iter().enumerate())
        .filter_map(|(i, d)| Some((i, d.servo()?)))
        .collect();
    servos.first()?;
    let joints: Vec<String> = servos.iter().map(|(i, _)| format!("J{}", i + 1)).collect();
    // each servo's own registers: an arm mixing presets is told each preset's figures, by joint
    let mut groups: Vec<(String, Vec<&str>)> = Vec::new();
    for ((_, servo), joint) in servos.iter().zip(&joints) {
        let figures = protection_figures(&servo.spec.protection);
        match groups.iter_mut().find(|(f, _)| *f == figures) {
            Some((_, js)) => js.push(joint),
            None => groups.push((figures, vec![joint])),
        }
    }
    let figures = match groups.as_slice() {
        [(figures, _)] => figures.clone(),
        _ => (groups.iter())
            .map(|(figures, js)| format!("{}: {figures}", js.join(", ")))
            .collect::<Vec<_>>()
            .join("; "),
    };
    Some(Warning::AssumedProtection {
        joints: joints.join(", "),
        figures,
    })
}

/// A servo's assumed protection registers, for people.
fn protection_figures(protection: &Protection) -> String {
    match *protection {
        Protection::Feetech {
            overload,
            time,
            protective,
            ..
        } => format!(
            "Feetech's overload above {:.0} % for {time} s, then held to {:.0} %",
            100.0 * overload,
            100.0 * protective
        ),
        Protection::Dynamixel { time } => format!("Dynamixel's shutdown after {time} s at its limit"),
    }
}

/// Joint `i`'s τ under its servo `drive` (motor `m`) at time `t` (s): its loop's duty on the
/// goal it holds, its protection's answer, τ_s·u' (the drag −c·q̇ is in the joint's damping),
/// with the joint's Coulomb friction; τ_raw the servo's output torque at the step's start,
/// τ_s·u' − c·q̇; `bounds[i]` its envelope's at the joint's speed.
#[inline]
pub fn actuate(drive: &ServoDrive, m: &Motor, sc: &Scenario, s: &mut Step, i: usize, t: f64) {
    let (q, v) = (s.state.q[i], s.state.v[i]);
    let Some(servos) = s.servos.as_mut() else { return };
    let given = drive.spec.step(&mut servos.states[i], q, v, t, sc.dt);
    s.bounds[i] = m.joint_bounds(sc.model.joints[i].gear_ratio, v);
    s.tau_raw[i] = given - drive.spec.drag() * v;
    s.state.tau[i] = with_friction(s, i, given, sc.model.joints[i].friction);
}

/// What a run records of a servo.
#[derive(Clone, Copy, Debug, Default)]
pub struct Record {
    /// Steps with the duty asked at the torque limit.
    at_limit: u64,
    /// The first trip.
    trip: Option<Trip>,
    /// The largest duty asked (share).
    max_duty: f64,
}

impl Record {
    /// Folds in step `p`'s state of joint `i`'s servo `drive`.
    #[inline]
    pub fn add(&mut self, drive: &ServoDrive, p: &Step, i: usize) {
        let Some(state) = p.servos.as_ref().map(|s| &s.states[i]) else {
            return;
        };
        self.at_limit += u64::from(state.asked.abs() >= drive.spec.torque_limit * (1.0 - 1e-12));
        self.trip = state.trip;
        self.max_duty = state.max_duty;
    }

    /// Its motor summary's fields over `steps` steps: the share of the steps at the torque
    /// limit, the servo's trip and duty.
    pub fn summarize(&self, drive: &ServoDrive, steps: f64, summary: &mut MotorSummary) {
        summary.envelope_pct = 100.0 * self.at_limit as f64 / steps;
        summary.servo = Some(ServoSummary {
            trip: self.trip,
            max_duty: self.max_duty,
            protective: match drive.spec.protection {
                Protection::Feetech { protective, .. } => Some(protective),
                Protection::Dynamixel { .. } => None,
            },
            goal_rate: drive.rate,
            note: ASSUMED,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::catalog::{sts3215_servo, xm540_w270_servo};

    fn servo(spec: ServoSpec) -> JointDrive {
        JointDrive::Servo(ServoDrive { spec, rate: None })
    }

    /// The warning gives each joint its own preset's assumed registers, one line for one kind.
    #[test]
    fn an_arm_mixing_presets_is_told_each_presets_assumed_registers() {
        let (feetech, dynamixel) = (sts3215_servo(None), xm540_w270_servo(None));
        let mixed = [servo(feetech), JointDrive::Pd, servo(dynamixel), servo(feetech)];
        let Some(Warning::AssumedProtection { joints, figures }) = assumed(&mixed) else {
            panic!("no warning");
        };
        assert_eq!(joints, "J1, J3, J4");
        assert_eq!(
            figures,
            "J1, J4: Feetech's overload above 80 % for 2 s, then held to 20 %; \
             J3: Dynamixel's shutdown after 1 s at its limit"
        );
        let Some(Warning::AssumedProtection { figures, .. }) = assumed(&mixed[..2]) else {
            panic!("no warning");
        };
        assert_eq!(figures, "Feetech's overload above 80 % for 2 s, then held to 20 %");
        assert!(assumed(&[JointDrive::Pd]).is_none());
    }
}
