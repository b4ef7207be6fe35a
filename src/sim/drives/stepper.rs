//! The open-loop stepper drive of a scenario (`drive` stepper; docs/motors.md, "The open-loop
//! stepper drive" and "The stepper's damping"): which joints it drives and at what microsteps,
//! what damps each rotor (its driver's current loop on the winding, the rotor's own losses, the
//! reducer's friction), put on the model's joint damping once, and the warning when Δt resolves
//! a rotor's ringing coarsely; its actuation in the step, its settled start, its slips and
//! its summary fields.

use super::{JointDrive, with_friction};
use crate::algo::{Data, State, crba, gravity};
use crate::control::{DEFAULT_MICROSTEPS, Motor, OpenLoopStepper, Slips, StepperDamping, StepperLosses};
use crate::error::{Error, Result};
use crate::model::{Joint, Model};
use crate::sim::check::{count, override_per_joint, positive};
use crate::sim::{MotorSummary, Ringing, STEPPER_STEPS_PER_RADIAN, Scenario, Step, Warning};

/// What the drive does, for people (`faze4 list drives`).
pub const ABOUT: &str = "open loop for the joints with a stepper: the driver's microstep through the stepper's \
                         torque–angle curve, its rotor damped by the driver's current loop, its own losses and its \
                         reducer's friction; slips and all (the other joints stay on the PD)";

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
    let (rotor, friction) = given_losses(options, n)?;
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

/// `options`' per-joint values checked (one per joint where given, the bandwidth > 0, the
/// losses finite and ≥ 0): each joint's rotor damping and reducer friction, NaN where not
/// given.
fn given_losses(options: &StepperOptions, n: usize) -> Result<(Vec<f64>, Vec<f64>)> {
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
    Ok((rotor, friction))
}

/// `given` unless it is the NaN that marks "not given".
fn given_or(given: f64, own: f64) -> f64 {
    if given.is_nan() { own } else { given }
}

/// Each open-loop stepper's damping at the start pose `q_start` of `model` (the simulated
/// model: payload and rotors on it): its figures into the drive ([`StepperDamping::of`], the
/// joint's inertia M_ii(q_start)), and r²(b_e + b_r + b_g) added to the joint's damping, where
/// the discrete step takes it implicitly.
pub fn damp(model: &mut Model, motors: &[Option<Motor>], drives: &mut [JointDrive], q_start: &[f64]) {
    let m = crba(model, &mut Data::new(model), q_start).clone();
    for (i, (drive, motor)) in drives.iter_mut().zip(motors).enumerate() {
        let (JointDrive::Stepper(drive), Some(motor)) = (drive, motor.as_ref()) else {
            continue;
        };
        let joint = &mut model.joints[i];
        let ratio = joint.gear_ratio;
        drive.damping = StepperDamping::of(motor, &drive.losses, drive.rotor_teeth, ratio, m[(i, i)], joint.damping);
        joint.damping += drive.damping.added(ratio);
    }
}

/// The shortest window (s) over which a timing may move the torque it asks of `drive`'s joint
/// so that the rotor's ringing fits in `margin` of the pull-out torque (docs/retime.md, "The
/// drive's own limits"): a change of the load spread over a ramp of w seconds leaves an undamped
/// rotor ringing about its lag with |sin(ω_n w/2)| / (ω_n w/2) ≤ 2/(ω_n w) of the change; a
/// change from one side of the (1 − margin) share the timing uses to the other (accelerating,
/// then braking), 2(1 − margin), fits in the margin where 2/(ω_n w)·2(1 − margin) ≤ margin,
/// w ≥ 4(1 − margin)/(margin·ω_n). +∞ at margin 0 (no room for any ringing); 0 before the
/// drive's damping figures are known. The damping is left out (the rotors' ratios are
/// 0.002–0.05: a ringing decays over tens of periods).
pub fn least_window(drive: &OpenLoopStepper, margin: f64) -> f64 {
    let omega = drive.damping.natural_frequency;
    match omega > 0.0 {
        true => 4.0 * (1.0 - margin) / (margin * omega),
        false => 0.0,
    }
}

/// The fastest-ringing open-loop stepper's [`Warning::CoarseStepperStep`], if its natural
/// frequency ω_n (its [`StepperDamping::natural_frequency`]) times Δt is above
/// [`STEPPER_STEPS_PER_RADIAN`].
pub fn coarse_step(model: &Model, drives: &[JointDrive], dt: f64) -> Option<Warning> {
    let (i, omega) = (drives.iter().enumerate())
        .filter_map(|(i, d)| Some((i, d.stepper()?.damping.natural_frequency)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    (omega * dt > STEPPER_STEPS_PER_RADIAN).then(|| Warning::CoarseStepperStep {
        joint: format!("J{} ({})", i + 1, crate::error::quoted(&model.joints[i].name)),
        omega,
        dt,
    })
}

/// Joint `i`'s τ under its open-loop stepper `drive` (motor `m`): what its torque–angle curve
/// gives at the rotor's lag behind the driver's microstep, r·η·T(r·q, r·q̇, θ_cmd), which is
/// also its τ_raw (an open-loop stepper asks for nothing else), with its reducer's and the
/// joint's Coulomb friction (the viscous losses are in the joint's damping); `bounds[i]` the
/// envelope's at the joint's speed.
#[inline]
pub fn actuate(drive: &OpenLoopStepper, m: &Motor, sc: &Scenario, s: &mut Step, i: usize) {
    let ratio = sc.model.joints[i].gear_ratio;
    let k = ratio * m.efficiency;
    let theta_cmd = drive.commanded(ratio * s.q_cmd[i]);
    let omega = ratio * s.state.v[i];
    let tau_m = drive.torque(&m.envelope, ratio * s.state.q[i], omega, theta_cmd);
    let (lo, hi) = m.envelope.bounds(omega);
    s.bounds[i] = (k * lo, k * hi);
    s.tau_raw[i] = k * tau_m;
    let most = ratio * drive.losses.reducer_friction + sc.model.joints[i].friction;
    s.state.tau[i] = with_friction(s, i, s.tau_raw[i], most);
}

/// Each stepper's joint at its static lag behind the driver's first microstep: where its
/// torque–angle curve holds the joint's gravity load g_i(q), N_r·δ = −asin(g_i / (r·η·T_max))
/// (clamped to the curve's peak), q_i = (θ_cmd + δ)/r; as an arm that has been switched on and
/// has settled. One pass: the lags are under a full step at the motor, so they barely move g.
pub fn settle(sc: &Scenario, motors: &[Option<Motor>], data: &mut Data, state: &mut State) {
    let g = gravity(&sc.model, data, &state.q).clone();
    for (i, (drive, motor)) in sc.drives.iter().zip(motors).enumerate() {
        let (JointDrive::Stepper(drive), Some(m)) = (drive, motor) else {
            continue;
        };
        let ratio = sc.model.joints[i].gear_ratio;
        let t_max = m.envelope.bounds(ratio * state.v[i]).1;
        let share = (g[i] / (ratio * m.efficiency * t_max)).clamp(-1.0, 1.0);
        let lag = -share.asin() / drive.rotor_teeth;
        state.q[i] = (drive.commanded(ratio * state.q[i]) + lag) / ratio;
    }
}

/// Folds step `p`'s lag of joint `i`'s rotor behind `drive`'s microstep at time `t` (s) into
/// its `slips`.
#[inline]
pub fn record(slips: &mut Slips, drive: &OpenLoopStepper, sc: &Scenario, p: &Step, i: usize, t: f64) {
    let ratio = sc.model.joints[i].gear_ratio;
    let lag = ratio * p.state.q[i] - drive.commanded(ratio * p.q_cmd[i]);
    slips.add(drive, lag, t);
}

/// Its motor summary's fields over `steps` steps (`joint` the stepper's joint): the share of
/// the steps past the curve's peak, the first slip, the steps and position lost, the ringing.
pub fn summarize(slips: &Slips, drive: &OpenLoopStepper, joint: &Joint, steps: f64, summary: &mut MotorSummary) {
    summary.envelope_pct = 100.0 * slips.past_peak as f64 / steps;
    summary.loses_steps_at = Some(slips.first);
    summary.steps_lost = Some(slips.steps_lost());
    summary.position_lost = Some(slips.offset(drive) / joint.gear_ratio);
    summary.ringing = Some(Ringing {
        natural_hz: drive.damping.ring_hz(),
        damping_ratio: drive.damping.ratio,
        electrical_damping: drive.damping.electrical,
        rotor_damping: drive.damping.rotor,
        reducer_damping: drive.damping.reducer,
        reducer_friction: drive.losses.reducer_friction,
        max_lag_steps: slips.max_lag_steps(),
        slips_below: None,
    });
}
