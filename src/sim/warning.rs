//! What a scenario runs with that the user should know about: the builder returns these as
//! values instead of printing them.

use std::fmt;

use crate::control::Stability;
use crate::error::shortest;
use crate::geometry;
use crate::model::LoadWarning;

/// Something a scenario runs with that the user should know about; the builder returns these
/// instead of printing them.
#[derive(Clone, Debug, PartialEq)]
pub enum Warning {
    /// The model gives no torque limit for these joints (by name): their torque is not clipped.
    UnlimitedEffort {
        /// The model's source (file).
        source: String,
        /// The joints without a limit.
        joints: Vec<String>,
    },
    /// The gains make the linearised loop unstable about the start pose (ρ not below 1); the
    /// run goes ahead.
    UnstableGains {
        /// The loop's figures with these gains.
        stability: Stability,
        /// Whether the gains were given (`kp`/`kd`) rather than tuned.
        given: bool,
    },
    /// Part of the collision geometry is left out of the clearance (a mesh not found).
    Clearance(geometry::Warning),
    /// Reading the model skipped or changed something (a transmission, an inertia).
    Model(LoadWarning),
    /// A time-stamped trajectory names none of these joints of the model: each holds a
    /// position (see [`super::TimedCommand`]).
    HeldJoints {
        /// The trajectory's file.
        source: String,
        /// The joints and the positions they hold.
        joints: Vec<crate::traj::HeldJoint>,
    },
    /// Under [`super::Drive::Stepper`] or [`super::Drive::Servo`], `effort` was given: it does
    /// not clip the torque of the joints that drive themselves (an open-loop stepper's is its
    /// torque–angle curve's, a servo's its own loop's within its torque limit), only the PD's
    /// joints'.
    IdleEffort {
        /// Those joints, for people (`J1, J2`).
        joints: String,
        /// The drive.
        drive: super::DriveMode,
    },
    /// Under [`super::Drive::Servo`]: the servos' protection registers are assumed defaults,
    /// not published figures (docs/motors.md, "Smart servos").
    AssumedProtection {
        /// The servos' joints, for people (`J1, J2`).
        joints: String,
        /// The figures taken, for people.
        figures: String,
    },
    /// Reading a trajectory file decided something the user should know (joints left out,
    /// recorded velocities used or not).
    Read {
        /// The trajectory's file.
        source: String,
        /// What was decided.
        note: crate::traj::files::Note,
    },
    /// What reading the trajectory noticed (a LeRobot dataset's gripper column left out).
    Trajectory(String),
    /// Under [`super::Drive::Stepper`], a stepper's rotor rings faster than Δt resolves well:
    /// its natural frequency ω_n = √(r²·η·N_r·T_max / I) (rad/s) times Δt is above
    /// [`STEPPER_STEPS_PER_RADIAN`]; a run near a slip can change with Δt.
    CoarseStepperStep {
        /// The joint whose rotor rings fastest, for people (`J6 ('hvataljka')`).
        joint: String,
        /// Its natural frequency at the start pose (rad/s).
        omega: f64,
        /// The run's Δt (s).
        dt: f64,
    },
}

/// Under [`super::Drive::Stepper`], the largest ω_n·Δt (a stepper's natural frequency times the
/// step) the run takes without a [`Warning::CoarseStepperStep`].
pub const STEPPER_STEPS_PER_RADIAN: f64 = 0.1;

/// A step that resolves a ringing at `omega` (rad/s): the largest of 1, 2, 5 × 10ᵏ s with
/// ω·Δt ≤ [`STEPPER_STEPS_PER_RADIAN`].
fn fine_dt(omega: f64) -> f64 {
    let most = STEPPER_STEPS_PER_RADIAN / omega;
    let decade = 10f64.powf(most.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&d| d <= most)
        .unwrap_or(decade)
}

impl Warning {
    /// Whether the run's result differs from what the input says because of it (a mesh left
    /// out, a transmission skipped, an inertia balanced): such a warning is printed even under
    /// `-q`.
    pub fn changes_result(&self) -> bool {
        match self {
            Warning::Read { note, .. } => note.changes_result(),
            _ => matches!(self, Warning::Clearance(_) | Warning::Model(_)),
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::UnlimitedEffort { source, joints } => write!(
                f,
                "{source} gives no effort limit for {}: their torque is not clipped (set `effort`)",
                joints
                    .iter()
                    .map(|j| crate::error::quoted(j))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Warning::UnstableGains { stability: s, given } => write!(
                f,
                "warning: with the {} gains the linearised loop's spectral radius is {:.3} (not below 1: unstable about the start pose; b_max = {:.3}, b_kd = {:.3}); running anyway",
                if *given { "given `kp`/`kd`" } else { "tuned" },
                s.spectral_radius,
                s.b_max,
                s.b_kd
            ),
            Warning::CoarseStepperStep { joint, omega, dt } => write!(
                f,
                "warning: under `drive` stepper the rotor of {joint} rings at {omega:.0} rad/s ({:.0} Hz): Δt = {dt} s takes {:.0} steps a period, coarse for its microsteps and its ringing; a run near a slip can change with Δt (`dt` {} takes {:.0})",
                omega / std::f64::consts::TAU,
                std::f64::consts::TAU / (omega * dt),
                shortest(fine_dt(*omega)),
                std::f64::consts::TAU / (omega * fine_dt(*omega)),
            ),
            Warning::IdleEffort {
                joints,
                drive: super::DriveMode::Servo,
            } => write!(
                f,
                "warning: `effort` does not act on the servos ({joints}) under `drive` servo: their torque is their own loop's within its torque limit, and no saturation is counted for them"
            ),
            Warning::IdleEffort { joints, .. } => write!(
                f,
                "warning: `effort` does not act on the open-loop steppers ({joints}) under `drive` stepper: their torque is their torque–angle curve's, and no saturation is counted for them"
            ),
            Warning::AssumedProtection { joints, figures } => write!(
                f,
                "warning: the servos' protection registers ({joints}) are assumed defaults, not published figures: {figures}; a trip's time and torque move with them (docs/motors.md, \"Smart servos\")"
            ),
            Warning::Clearance(w) => write!(f, "warning: {w}"),
            Warning::Trajectory(w) => write!(f, "warning: {w}"),
            Warning::Model(w) => write!(f, "warning: {w}"),
            Warning::Read { source, note } => write!(f, "warning: {source}: {note}"),
            Warning::HeldJoints { source, joints } => write!(
                f,
                "warning: {source} gives no values for {}: {} its start position with zero velocity",
                joints
                    .iter()
                    .map(|j| format!("{} ({})", crate::error::quoted(&j.name), shortest(j.position)))
                    .collect::<Vec<_>>()
                    .join(", "),
                if joints.len() == 1 { "it holds" } else { "each holds" }
            ),
        }
    }
}
