//! The open-loop stepper drive of a scenario (`drive` stepper; docs/motors.md, "The open-loop
//! stepper drive" and "The stepper's damping"): which joints it drives and at what microsteps,
//! what damps each rotor (its driver's current loop on the winding, the rotor's own losses, the
//! reducer's friction), put on the model's joint damping once, and the warning when Δt resolves
//! a rotor's ringing coarsely.

use super::Warning;
use super::check::{count, override_per_joint, positive};
use super::warning::STEPPER_STEPS_PER_RADIAN;
use crate::algo::{Data, crba};
use crate::control::{DEFAULT_MICROSTEPS, Motor, OpenLoopStepper, StepperDamping, StepperLosses};
use crate::error::{Error, Result};
use crate::model::Model;

/// What `drive` stepper is given beyond the motors (each `None`, or an empty list, keeps the
/// motor's own).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepperOptions {
    /// Microsteps per full step per joint (`microsteps`; a joint's `None` keeps the motor's
    /// setting, else [`DEFAULT_MICROSTEPS`]).
    pub microsteps: Vec<Option<u32>>,
    /// Every stepper driver's current-loop bandwidth (Hz, > 0; `driver_bandwidth`).
    pub driver_bandwidth: Option<f64>,
    /// Each rotor's viscous damping (N·m·s/rad at the shaft, ≥ 0; `rotor_damping`).
    pub rotor_damping: Vec<Option<f64>>,
    /// Each reducer's Coulomb friction (N·m at the motor shaft, ≥ 0; `reducer_friction`).
    pub reducer_friction: Vec<Option<f64>>,
}

/// The open-loop drive of each joint whose motor is a stepper (`None`: the PD drives it): its
/// microsteps (`options`' where given, ≥ 1, else the motor's own, else
/// [`DEFAULT_MICROSTEPS`]) and its losses (the motor's, with `options`' over them); its damping
/// figures are [`damp`]'s.
pub fn drives(
    options: &StepperOptions,
    motors: Option<&[Option<Motor>]>,
    n: usize,
) -> Result<Vec<Option<OpenLoopStepper>>> {
    let Some(motors) = motors else {
        return Err(Error::option(
            "drive",
            "stepper drives the steppers of `motors`: give `motors`",
        ));
    };
    for (field, given) in [
        ("microsteps", options.microsteps.len()),
        ("rotor_damping", options.rotor_damping.len()),
        ("reducer_friction", options.reducer_friction.len()),
    ] {
        if given > 0 {
            count(field, given, n)?;
        }
    }
    if let Some(f) = options.driver_bandwidth {
        positive("driver_bandwidth", f)?;
    }
    let mut rotor: Vec<f64> = vec![f64::NAN; n];
    let mut friction: Vec<f64> = vec![f64::NAN; n];
    let non_negative = |v: f64| v.is_finite() && v >= 0.0;
    override_per_joint(
        "rotor_damping",
        &mut rotor,
        &options.rotor_damping,
        non_negative,
        "finite and ≥ 0",
    )?;
    override_per_joint(
        "reducer_friction",
        &mut friction,
        &options.reducer_friction,
        non_negative,
        "finite and ≥ 0",
    )?;
    let mut drives = Vec::with_capacity(n);
    for (i, motor) in motors.iter().enumerate() {
        let Some(m) = motor.as_ref().filter(|m| m.envelope.loses_steps()) else {
            drives.push(None);
            continue;
        };
        let Some(stepping) = &m.stepping else {
            return Err(Error::option(
                "drive",
                format!(
                    "stepper: J{}'s stepper ({}) has no step angle: give its step_angle in the motors file",
                    i + 1,
                    m.label
                ),
            ));
        };
        let given = options.microsteps.get(i).copied().flatten();
        if given == Some(0) {
            return Err(Error::option("microsteps", format!("J{} 0 must be ≥ 1", i + 1)));
        }
        let microsteps = given.or(stepping.microsteps).unwrap_or(DEFAULT_MICROSTEPS);
        let mut stepping = *stepping;
        stepping.losses = StepperLosses {
            driver_bandwidth: options.driver_bandwidth.or(stepping.losses.driver_bandwidth),
            rotor_damping: given_or(rotor[i], stepping.losses.rotor_damping),
            reducer_damping: stepping.losses.reducer_damping,
            reducer_friction: given_or(friction[i], stepping.losses.reducer_friction),
        };
        drives.push(Some(OpenLoopStepper::new(&stepping, microsteps)));
    }
    if drives.iter().all(Option::is_none) {
        return Err(Error::option(
            "drive",
            "stepper: none of the joints' motors is a stepper",
        ));
    }
    Ok(drives)
}

/// `given` unless it is the NaN that marks "not given".
fn given_or(given: f64, own: f64) -> f64 {
    if given.is_nan() { own } else { given }
}

/// Each open-loop stepper's damping at the start pose `q_start` of `model` (the simulated
/// model: payload and rotors on it): its figures into the drive ([`StepperDamping::of`], the
/// joint's inertia M_ii(q_start)), and r²(b_e + b_r + b_g) added to the joint's damping, where
/// the discrete step takes it implicitly.
pub fn damp(model: &mut Model, motors: &[Option<Motor>], drives: &mut [Option<OpenLoopStepper>], q_start: &[f64]) {
    let m = crba(model, &mut Data::new(model), q_start).clone();
    for (i, (drive, motor)) in drives.iter_mut().zip(motors).enumerate() {
        let (Some(drive), Some(motor)) = (drive.as_mut(), motor.as_ref()) else {
            continue;
        };
        let joint = &mut model.joints[i];
        let ratio = joint.gear_ratio;
        drive.damping = StepperDamping::of(motor, &drive.losses, drive.rotor_teeth, ratio, m[(i, i)], joint.damping);
        joint.damping += drive.damping.added(ratio);
    }
}

/// The fastest-ringing open-loop stepper's [`Warning::CoarseStepperStep`], if its natural
/// frequency ω_n (its [`StepperDamping::natural_frequency`]) times Δt is above
/// [`STEPPER_STEPS_PER_RADIAN`].
pub fn coarse_step(model: &Model, drives: &[Option<OpenLoopStepper>], dt: f64) -> Option<Warning> {
    let (i, omega) = (drives.iter().enumerate())
        .filter_map(|(i, d)| Some((i, d.as_ref()?.damping.natural_frequency)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    (omega * dt > STEPPER_STEPS_PER_RADIAN).then(|| Warning::CoarseStepperStep {
        joint: format!("J{} ({})", i + 1, crate::error::quoted(&model.joints[i].name)),
        omega,
        dt,
    })
}
