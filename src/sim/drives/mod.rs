//! The drives, each in its own file: what turns a joint's command into its torque. The PD
//! (`pd.rs`) clips the controller's torque to the limits and each motor's envelope; the
//! open-loop stepper (`stepper.rs`) gives what its torque–angle curve gives at the rotor's lag
//! behind the driver's microstep; the smart servo (`servo.rs`) what its own position loop gives
//! on the goal it was sent, within its torque limit and its protection. A drive's options, its
//! state per joint (made once by [`Drive::joints`], set at the start pose by [`prepare`]), its
//! actuation in the step ([`JointDrive::actuate`], nothing allocated; a state that changes over
//! a run in [`Step`], as the servos' [`Servos`]), what a run records of it ([`DriveRecord`]),
//! its summary fields ([`DriveRecord::summarize`]) and its warnings are its file's.
//!
//! This file is the one registration point: a drive is a [`DriveMode`] word, a [`Drive`] and a
//! [`JointDrive`] variant, one arm in each of their methods and of [`DriveRecord`]'s
//! (ARCHITECTURE.md, "How to add a drive").

mod pd;
mod servo;
mod stepper;

pub(super) use pd::actuate_without_motors;
pub use servo::{DEFAULT_GOAL_RATE, Holding, ServoDrive, ServoOptions, Servos};
pub use stepper::StepperOptions;

use super::{MotorSummary, Scenario, Step, Warning};
use crate::algo::{Data, State};
use crate::choice::Choice;
use crate::control::{Motor, OpenLoopStepper};
use crate::error::Result;
use crate::model::{Joint, Model};

/// How the joints are driven (`drive`), with the drive's options.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Drive {
    /// The PD controller's torque, clipped to each motor's envelope (the original's).
    #[default]
    Pd,
    /// The joints with a stepper driven open loop: the command is the microstep the driver
    /// holds, the torque the stepper's torque–angle curve, its rotor damped by its driver's
    /// current loop, its own losses and its reducer's friction (docs/motors.md); the other
    /// joints stay on the PD.
    Stepper(StepperOptions),
    /// The joints with a smart servo driven by the servo's own position loop on the goal it
    /// is sent, within its torque limit, protecting itself (docs/motors.md, "Smart servos");
    /// the other joints stay on the PD.
    Servo(ServoOptions),
}

/// How the joints with a motor are driven (`drive`; the summary's `drive` of each motor).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DriveMode {
    /// The controller's torque clipped to each motor's envelope (the original's).
    #[default]
    Pd,
    /// Open loop: the driver's microstep through the stepper's torque–angle curve.
    Stepper,
    /// A smart servo's own position loop on the goal it is sent.
    Servo,
}

crate::choice::choice_words!(DriveMode { Pd => "pd", Stepper => "stepper", Servo => "servo" });

impl DriveMode {
    /// What the drive does, in a sentence for people (`faze4 list drives`).
    pub fn about(self) -> &'static str {
        match self {
            DriveMode::Pd => pd::ABOUT,
            DriveMode::Stepper => stepper::ABOUT,
            DriveMode::Servo => servo::ABOUT,
        }
    }
}

impl Drive {
    /// The drive of each of the `n` joints (`motors`: one entry per joint, as the builder has
    /// them, checked), or the error naming the option at fault.
    pub(super) fn joints(&self, motors: Option<&[Option<Motor>]>, n: usize) -> Result<Vec<JointDrive>> {
        match self {
            Drive::Pd => Ok(vec![JointDrive::Pd; n]),
            Drive::Stepper(options) => Ok((stepper::drives(options, motors, n)?.into_iter())
                .map(|d| d.map_or(JointDrive::Pd, JointDrive::Stepper))
                .collect()),
            Drive::Servo(options) => Ok((servo::drives(options, motors)?.into_iter())
                .map(|d| d.map_or(JointDrive::Pd, JointDrive::Servo))
                .collect()),
        }
    }
}

/// What drives one joint of a scenario, with the drive's own state (immutable once the
/// scenario is built).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointDrive {
    /// The PD controller, through the joint's motor's envelope if it has one.
    Pd,
    /// The joint's stepper, open loop (its motor is a stepper).
    Stepper(OpenLoopStepper),
    /// The joint's smart servo (its motor has servo registers).
    Servo(ServoDrive),
}

impl JointDrive {
    /// Its word in the summary's `drive` ([`DriveMode`]'s).
    pub fn word(&self) -> &'static str {
        match self {
            JointDrive::Pd => DriveMode::Pd.word(),
            JointDrive::Stepper(_) => DriveMode::Stepper.word(),
            JointDrive::Servo(_) => DriveMode::Servo.word(),
        }
    }

    /// Whether the drive gives the joint's torque itself rather than the controller's: no
    /// limit clips it (`effort` idle), no saturation is counted, and its τ_raw is the motor's
    /// own torque at the joint (τ adds the drive's friction).
    pub fn open_loop(&self) -> bool {
        !matches!(self, JointDrive::Pd)
    }

    /// The open-loop stepper, if the joint has one (its slip margins, its tests).
    pub fn stepper(&self) -> Option<&OpenLoopStepper> {
        match self {
            JointDrive::Stepper(d) => Some(d),
            JointDrive::Pd | JointDrive::Servo(_) => None,
        }
    }

    /// The smart servo, if the joint has one.
    pub fn servo(&self) -> Option<&ServoDrive> {
        match self {
            JointDrive::Servo(d) => Some(d),
            JointDrive::Pd | JointDrive::Stepper(_) => None,
        }
    }

    /// The shortest window (s) over which a timing that keeps `1 − margin` of the joint's
    /// torque may change it, for the drive to follow (retime's limits beyond the envelope): an
    /// open-loop stepper's ringing (docs/retime.md, "The drive's own limits"); 0 for the drives that close
    /// their own loop.
    pub fn least_window(&self, margin: f64) -> f64 {
        match self {
            JointDrive::Stepper(d) => stepper::least_window(d, margin),
            JointDrive::Pd | JointDrive::Servo(_) => 0.0,
        }
    }

    /// What the drive's own loop makes of a load held at rest (a smart servo's sag and
    /// protection), if it closes one; `None` for the PD and the open-loop stepper.
    pub fn holding(&self) -> Option<Holding> {
        self.servo().map(servo::holding)
    }

    /// (τ_raw, q, v, q_cmd) of joint `i` at time `t` (s), driving motor `motor` ⇒ its τ (held
    /// over the step), its τ_raw where the drive gives it, and `bounds[i]` (docs/model.md,
    /// docs/motors.md).
    #[inline]
    pub fn actuate(&self, sc: &Scenario, s: &mut Step, i: usize, motor: Option<&Motor>, t: f64) {
        match (self, motor) {
            (JointDrive::Stepper(drive), Some(m)) => stepper::actuate(drive, m, sc, s, i),
            (JointDrive::Servo(drive), Some(m)) => servo::actuate(drive, m, sc, s, i, t),
            _ => pd::actuate(motor, sc, s, i),
        }
    }

    /// A fresh record of what a run makes of this drive with its motor.
    pub(in crate::sim) fn record(&self) -> DriveRecord {
        match self {
            JointDrive::Pd => DriveRecord::Pd(pd::Record::default()),
            JointDrive::Stepper(_) => DriveRecord::Stepper(Default::default()),
            JointDrive::Servo(_) => DriveRecord::Servo(servo::Record::default()),
        }
    }
}

/// Sets each joint's drive at the start pose `q_start` of `model` (the simulated model:
/// payload and rotors on it), and what the model takes of it (the open-loop steppers' damping,
/// the servos' speed drag on the joints' damping); the warnings of a drive that `effort`
/// (`effort_given`) does not act on, and of the servos' assumed protection.
pub(super) fn prepare(
    model: &mut Model,
    motors: Option<&[Option<Motor>]>,
    drives: &mut [JointDrive],
    q_start: &[f64],
    effort_given: bool,
) -> Vec<Warning> {
    let Some(motors) = motors else { return Vec::new() };
    let mut warnings = Vec::new();
    if drives.iter().any(|d| matches!(d, JointDrive::Stepper(_))) {
        stepper::damp(model, motors, drives, q_start);
        if effort_given {
            warnings.push(Warning::IdleEffort {
                joints: idle_effort(drives),
                drive: DriveMode::Stepper,
            });
        }
    }
    if drives.iter().any(|d| d.servo().is_some()) {
        servo::damp(model, drives);
        if effort_given {
            warnings.push(Warning::IdleEffort {
                joints: idle_effort(drives),
                drive: DriveMode::Servo,
            });
        }
        warnings.extend(servo::assumed(drives));
    }
    warnings
}

/// The joints that drive themselves, for people (`J4, J6`), whose torque `effort` does not
/// clip.
fn idle_effort(drives: &[JointDrive]) -> String {
    let joints: Vec<String> = (drives.iter().enumerate())
        .filter(|(_, d)| d.open_loop())
        .map(|(i, _)| format!("J{}", i + 1))
        .collect();
    joints.join(", ")
}

/// Sends each servo of `sc` the goal of the frame at time `t` (s) when that frame is new (the
/// trajectory's sample times, else `servo_rate`'s).
#[inline]
pub(super) fn send_goals(sc: &Scenario, s: &mut Step, t: f64) {
    if let Some(servos) = s.servos.as_mut() {
        servo::send(sc, servos, t);
    }
}

/// What the drives of a scenario of `model` at Δt = `dt` (s) warn of once its gains are
/// tuned: a stepper ringing faster than Δt resolves well.
pub(super) fn timing_warnings(model: &Model, drives: &[JointDrive], dt: f64) -> Option<Warning> {
    stepper::coarse_step(model, drives, dt)
}

/// The start state as each drive holds it (at rest in every other respect): under `drive`
/// stepper each stepper's joint at its static lag behind the first microstep.
pub(super) fn settle(sc: &Scenario, data: &mut Data, state: &mut State) {
    let Some(motors) = &sc.motors else { return };
    if sc.drives.iter().any(|d| matches!(d, JointDrive::Stepper(_))) {
        stepper::settle(sc, motors, data, state);
    }
}

/// What a run records of one joint's drive over the steps, as its drive keeps it.
#[derive(Clone, Copy, Debug)]
pub(in crate::sim) enum DriveRecord {
    /// The PD: the steps beyond the envelope, a stepper's first step loss.
    Pd(pd::Record),
    /// The open-loop stepper: its slips.
    Stepper(crate::control::Slips),
    /// The smart servo: its trip, its duty.
    Servo(servo::Record),
}

impl DriveRecord {
    /// Folds in step `p`'s actuation of joint `i` (motor `m`, driven by `drive`) at time `t`
    /// (s).
    #[inline]
    pub(in crate::sim) fn add(&mut self, drive: &JointDrive, m: &Motor, sc: &Scenario, p: &Step, i: usize, t: f64) {
        match (self, drive) {
            (DriveRecord::Stepper(slips), JointDrive::Stepper(d)) => stepper::record(slips, d, sc, p, i, t),
            (DriveRecord::Servo(record), JointDrive::Servo(d)) => record.add(d, p, i),
            (DriveRecord::Pd(record), _) => record.add(m, sc, p, i, t),
            _ => {}
        }
    }

    /// The drive's fields of joint `joint`'s motor summary (`m` its motor) over `steps` steps:
    /// `drive`, `envelope_pct`, a stepper's `loses_steps_at`, `step_loss`, `steps_lost`,
    /// `position_lost`, `ringing`, a servo's `servo`.
    pub(in crate::sim) fn summarize(
        &self,
        drive: &JointDrive,
        m: &Motor,
        joint: &Joint,
        steps: f64,
        summary: &mut MotorSummary,
    ) {
        summary.drive = drive.word();
        match (self, drive) {
            (DriveRecord::Stepper(slips), JointDrive::Stepper(d)) => {
                stepper::summarize(slips, d, joint, steps, summary)
            }
            (DriveRecord::Servo(record), JointDrive::Servo(d)) => record.summarize(d, steps, summary),
            (DriveRecord::Pd(record), _) => record.summarize(m, steps, summary),
            _ => {}
        }
    }
}

/// The drive's torque `tau` at joint i (N·m or N, held over the step) with the Coulomb friction
/// of a joint whose friction is `most` (its own, and a stepper's reducer's at the joint) added:
/// the friction is the torque that would stop the joint within the step, −(M_ii·v/Δt + τ − (C v + g)_i), within
/// ±`most`. So a joint at rest stays there while the rest of its torque is within the friction
/// (it sticks), and a moving joint is braked by `most` without being turned back. The joint
/// alone: the other joints' accelerations through M's off-diagonal are left out of the estimate
/// (docs/model.md §2.3, docs/motors.md). `tau` itself, bit for bit, without friction.
#[inline]
fn with_friction(s: &Step, i: usize, tau: f64, most: f64) -> f64 {
    if most == 0.0 {
        return tau;
    }
    let stop = -(s.data.m[(i, i)] * s.state.v[i] / s.state.dt + tau - s.data.bias[i]);
    tau + stop.clamp(-most, most)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{Envelope, Stepping};

    /// The Faze4's J1 stepper, or (`stepper` false) a DC motor (no steps to lose).
    fn motor(stepper: bool) -> Motor {
        let mut m = (crate::faze4::motors::faze4(None).swap_remove(0))
            .expect("J1's motor")
            .motor;
        if !stepper {
            m.envelope = Envelope::Dc {
                stall_torque: 1.0,
                no_load_speed: 10.0,
                peak_torque: 1.0,
            };
            m.stepping = None::<Stepping>;
        }
        m
    }

    /// Each drive's word is its mode's, said once, with a sentence of its own; the PD drives
    /// every joint under `drive` pd and the joints without a stepper under `drive` stepper,
    /// which refuses an arm without motors or without any stepper, naming `drive`.
    #[test]
    fn each_drive_is_registered_once() {
        let words: Vec<&str> = DriveMode::VALUES.iter().map(|d| d.word()).collect();
        assert_eq!(words, ["pd", "stepper", "servo"]);
        let about: Vec<&str> = DriveMode::VALUES.iter().map(|d| d.about()).collect();
        assert!(
            about[0] != about[1] && about[1] != about[2] && about.iter().all(|a| a.len() > 40),
            "{about:?}"
        );

        let pd = Drive::Pd.joints(None, 3).unwrap();
        assert_eq!(pd, [JointDrive::Pd; 3]);
        assert!(
            pd.iter()
                .all(|d| d.word() == "pd" && !d.open_loop() && d.stepper().is_none())
        );

        let stepper = Drive::Stepper(StepperOptions::default());
        let motors = [Some(motor(true)), None, Some(motor(false))];
        let drives = stepper.joints(Some(&motors), 3).unwrap();
        assert!(matches!(drives[0], JointDrive::Stepper(_)) && drives[0].open_loop());
        assert_eq!(drives[0].word(), "stepper");
        assert_eq!(drives[1..], [JointDrive::Pd, JointDrive::Pd]);
        assert!(matches!(drives[0].record(), DriveRecord::Stepper(_)));
        assert!(matches!(drives[2].record(), DriveRecord::Pd(_)));

        for motors in [None, Some(&[None, Some(motor(false))][..])] {
            let e = stepper.joints(motors, 2).unwrap_err().to_string();
            assert!(e.contains("`drive`"), "{e}");
        }
    }

    /// `drive` servo drives the joints whose motor has servo registers (the presets') by their
    /// servo and the rest by the PD, and refuses an arm without motors or without any servo,
    /// naming `drive`, and a goal rate not > 0, naming `servo_rate`.
    #[test]
    fn the_servo_drive_takes_the_joints_with_servo_registers() {
        let servo = Drive::Servo(ServoOptions::default());
        let sts = crate::control::catalog::sts3215(None).motor;
        let motors = [Some(motor(true)), Some(sts.clone()), None, Some(motor(false))];
        let drives = servo.joints(Some(&motors), 4).unwrap();
        assert_eq!(drives[0], JointDrive::Pd);
        assert!(drives[1].servo().is_some() && drives[1].open_loop() && drives[1].stepper().is_none());
        assert_eq!(drives[1].word(), "servo");
        assert_eq!(drives[1].servo().unwrap().spec, sts.servo.unwrap());
        assert_eq!(drives[2..], [JointDrive::Pd, JointDrive::Pd]);
        assert!(matches!(drives[1].record(), DriveRecord::Servo(_)));
        for motors in [None, Some(&[Some(motor(true)), Some(motor(false))][..])] {
            let e = servo.joints(motors, 2).unwrap_err().to_string();
            assert!(e.contains("`drive`"), "{e}");
        }
        for rate in [0.0, -30.0, f64::NAN] {
            let bad = Drive::Servo(ServoOptions { rate: Some(rate) });
            let e = bad.joints(Some(&motors), 4).unwrap_err().to_string();
            assert!(e.contains("`servo_rate`"), "{e}");
        }
    }
}
