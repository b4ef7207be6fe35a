//! The open-loop stepper drive (`--drive stepper`; docs/motors.md, "The open-loop stepper
//! drive"): no controller, the driver sets the phase currents for the commanded microstep and
//! the rotor follows through the torque–angle curve.
//!
//! A hybrid stepper with N_r rotor teeth, its rotor at θ (rad at the shaft) and the driver's
//! current vector at the microstep θ_cmd, gives
//!
//! ```text
//!   T(θ) = −T_max(|ω|) · sin(N_r (θ − θ_cmd)) − T_d · sin(4 N_r θ)
//! ```
//!
//! T_max(ω) the pull-out envelope at the rotor's speed ω (its standstill value the holding
//! torque at the drive's current), T_d the detent torque (one period per full step). The
//! rotor's stable points are N_r (θ − θ_cmd) = 2πc; a rotor pushed past the curve's peak
//! (one full step of lag) and on past N_r δ = ±π falls to the next stable point, c one
//! electrical cycle (4 full steps) further: it has slipped, and stays there.

use super::motor::{Electrics, Envelope, Motor, StepperLosses, Stepping};

/// Microsteps per full step where neither the motor's build nor `--microsteps` says.
pub const DEFAULT_MICROSTEPS: u32 = 16;

/// Full steps per electrical cycle of a two-phase hybrid stepper.
pub const STEPS_PER_CYCLE: u32 = 4;

/// The torque–angle curve (N·m): `−t_max · sin(rotor_teeth · lag)`, `lag` = θ − θ_cmd (rad
/// at the shaft). Restoring for |N_r·lag| < π, largest at one full step of lag.
#[inline]
pub fn torque_angle(t_max: f64, rotor_teeth: f64, lag: f64) -> f64 {
    -t_max * (rotor_teeth * lag).sin()
}

/// The detent torque's fundamental (N·m) at rotor angle `theta` (rad): `−t_d · sin(4 N_r θ)`,
/// stable at the full steps.
#[inline]
pub fn detent(t_d: f64, rotor_teeth: f64, theta: f64) -> f64 {
    -t_d * (4.0 * rotor_teeth * theta).sin()
}

/// One joint's stepper driven open loop: its rotor, its driver's microstep and what damps it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OpenLoopStepper {
    /// Rotor teeth N_r.
    pub rotor_teeth: f64,
    /// Detent torque T_d (N·m at the shaft).
    pub detent_torque: f64,
    /// Microsteps per full step m.
    pub microsteps: u32,
    /// The microstep μ = 2π / (4·N_r·m) (rad at the shaft).
    pub microstep: f64,
    /// What damps the rotor: its driver's current loop, its own losses, its reducer's friction.
    pub losses: StepperLosses,
    /// Its viscous damping and the figures of its ringing, at the run's start pose.
    pub damping: StepperDamping,
}

/// An open-loop stepper's viscous damping at the motor shaft, each part, and what it makes of
/// the rotor's ringing about its microstep at the run's start pose (docs/motors.md, "The
/// stepper's damping").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepperDamping {
    /// The driver's current loop on the winding, b_e (N·m·s/rad at the shaft;
    /// [`super::StepperWinding::electrical_damping`] at the ringing frequency).
    pub electrical: f64,
    /// The rotor's own, b_r (N·m·s/rad).
    pub rotor: f64,
    /// The reducer's viscous friction, b_g (N·m·s/rad).
    pub reducer: f64,
    /// The joint's own damping (the model's, N·m·s/rad at the joint), before these were added.
    pub joint: f64,
    /// The ringing's natural frequency ω_n = √(k / I) (rad/s), k = r²·η·N_r·T_max(0) the
    /// torque–angle curve's stiffness at the joint, I the joint's inertia at the start pose (the
    /// joint and its rotor ring together, at one frequency).
    pub natural_frequency: f64,
    /// Critical damping at the joint, 2√(k I) (N·m·s/rad).
    pub critical: f64,
    /// The damping ratio ζ = (joint + r²(b_e + b_r + b_g)) / (2√(k I)).
    pub ratio: f64,
}

impl StepperDamping {
    /// The damping of `motor`'s stepper with `rotor_teeth` behind a reducer of `ratio`, on a
    /// joint of inertia `inertia` (kg·m², the rotor's reflected share included) and damping
    /// `joint` (N·m·s/rad), with its drive's `losses`: the electrical part at the ringing
    /// frequency, where the motor's winding is known.
    pub fn of(motor: &Motor, losses: &StepperLosses, rotor_teeth: f64, ratio: f64, inertia: f64, joint: f64) -> Self {
        let stiffness = ratio * ratio * motor.efficiency * rotor_teeth * motor.envelope.max_torque();
        let natural_frequency = (stiffness / inertia).sqrt();
        let electrical = match (motor.electrics, losses.driver_bandwidth) {
            (Some(Electrics::Stepper { winding, .. }), Some(f_c)) => winding.electrical_damping(f_c, natural_frequency),
            _ => 0.0,
        };
        let critical = 2.0 * (stiffness * inertia).sqrt();
        let shaft = electrical + losses.rotor_damping + losses.reducer_damping;
        StepperDamping {
            electrical,
            rotor: losses.rotor_damping,
            reducer: losses.reducer_damping,
            joint,
            natural_frequency,
            critical,
            ratio: (joint + ratio * ratio * shaft) / critical,
        }
    }

    /// What the drive adds to the joint's damping (N·m·s/rad at the joint): r²(b_e + b_r + b_g).
    pub fn added(&self, ratio: f64) -> f64 {
        ratio * ratio * (self.electrical + self.rotor + self.reducer)
    }

    /// The natural frequency in Hz, ω_n / 2π.
    pub fn ring_hz(&self) -> f64 {
        self.natural_frequency / std::f64::consts::TAU
    }
}

impl OpenLoopStepper {
    /// The drive of a stepper `stepping` set to `microsteps` per full step (≥ 1), with
    /// `stepping`'s losses, its damping figures not yet known ([`StepperDamping::default`]).
    pub fn new(stepping: &Stepping, microsteps: u32) -> OpenLoopStepper {
        let full_step = std::f64::consts::TAU / (f64::from(STEPS_PER_CYCLE) * stepping.rotor_teeth);
        OpenLoopStepper {
            rotor_teeth: stepping.rotor_teeth,
            detent_torque: stepping.detent_torque,
            microsteps,
            microstep: full_step / f64::from(microsteps),
            losses: stepping.losses,
            damping: StepperDamping::default(),
        }
    }

    /// A full step (rad at the shaft), 2π / (4·N_r).
    pub fn full_step(&self) -> f64 {
        self.microstep * f64::from(self.microsteps)
    }

    /// The angle the driver holds (rad at the shaft) for a commanded shaft angle `angle`: the
    /// nearest microstep, μ·round(angle/μ).
    #[inline]
    pub fn commanded(&self, angle: f64) -> f64 {
        (angle / self.microstep).round() * self.microstep
    }

    /// The motor torque (N·m at the shaft) with its rotor at `theta` turning at `omega` (rad,
    /// rad/s) and the driver at `theta_cmd`: the torque–angle curve, its amplitude the
    /// envelope at |ω|, plus the detent torque.
    #[inline]
    pub fn torque(&self, envelope: &Envelope, theta: f64, omega: f64, theta_cmd: f64) -> f64 {
        let t_max = envelope.bounds(omega).1;
        torque_angle(t_max, self.rotor_teeth, theta - theta_cmd) + detent(self.detent_torque, self.rotor_teeth, theta)
    }

    /// The electrical cycles c between the rotor's nearest stable point and the driver's at a
    /// lag θ − θ_cmd (rad): round(N_r·lag / 2π). Each change of c is a slip of 4 full steps.
    #[inline]
    pub fn cycles(&self, lag: f64) -> i64 {
        (self.rotor_teeth * lag / std::f64::consts::TAU).round() as i64
    }

    /// Whether a lag (rad) is past the torque–angle curve's peak, |N_r·lag − 2πc| > π/2: the
    /// load there is more than the curve gives.
    #[inline]
    pub fn past_peak(&self, lag: f64) -> bool {
        let e = self.rotor_teeth * lag;
        let c = (e / std::f64::consts::TAU).round();
        (e - std::f64::consts::TAU * c).abs() > std::f64::consts::FRAC_PI_2
    }
}

/// What a stepper's slips came to over a run (`--drive stepper`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Slips {
    /// The electrical cycles c the rotor's stable point is off the driver's now (negative:
    /// behind, at lower angles).
    pub cycles: i64,
    /// When c first changed (s).
    pub first: Option<f64>,
    /// Steps with the lag past the curve's peak.
    pub past_peak: u64,
    /// The largest lag of the rotor from its nearest stable point, |N_r·lag − 2πc| (electrical
    /// rad; π/2 is one full step, the curve's peak; π its unstable top).
    pub max_lag: f64,
}

impl Slips {
    /// Folds in the lag (rad at the shaft) of `drive`'s rotor at time `t` (s).
    #[inline]
    pub fn add(&mut self, drive: &OpenLoopStepper, lag: f64, t: f64) {
        let c = drive.cycles(lag);
        if c != self.cycles {
            self.cycles = c;
            self.first.get_or_insert(t);
        }
        self.past_peak += u64::from(drive.past_peak(lag));
        let e = drive.rotor_teeth * lag;
        let from_stable = (e - std::f64::consts::TAU * (e / std::f64::consts::TAU).round()).abs();
        self.max_lag = self.max_lag.max(from_stable);
    }

    /// The largest lag in full steps (one full step is the torque–angle curve's peak, two its
    /// unstable top, where the rotor slips).
    pub fn max_lag_steps(&self) -> f64 {
        self.max_lag / std::f64::consts::FRAC_PI_2
    }

    /// Full steps the rotor is off its command (a multiple of 4).
    pub fn steps_lost(&self) -> u64 {
        self.cycles.unsigned_abs() * u64::from(STEPS_PER_CYCLE)
    }

    /// The offset the slips leave at the shaft (rad; negative: behind), 2π·c / N_r.
    pub fn offset(&self, drive: &OpenLoopStepper) -> f64 {
        std::f64::consts::TAU * self.cycles as f64 / drive.rotor_teeth
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::catalog::{NEMA17_17HS16_2004S1, NEMA17_17HS16_2004S1_ROTOR};

    /// The 17HS16-2004S1 at 2.0 A from 24 V, 16 microsteps, no detent.
    fn nema17() -> (OpenLoopStepper, Envelope) {
        let w = NEMA17_17HS16_2004S1;
        let stepping = Stepping {
            rotor_teeth: w.rotor_teeth,
            detent_torque: 0.0,
            microsteps: None,
            losses: StepperLosses::default(),
        };
        let envelope = Envelope::Stepper {
            curve: w.pull_out_curve(2.0, 24.0, 256, 0.05),
        };
        (OpenLoopStepper::new(&stepping, DEFAULT_MICROSTEPS), envelope)
    }

    /// The static torque–angle curve (Oriental Motor's angle–torque characteristic): zero at
    /// the command, restoring, largest (the holding torque at the drive's current, K·I) one full
    /// step (1.8°) off, zero again two full steps off (the unstable point), pushing on past it
    /// towards the next stable point one electrical cycle (4 full steps, 7.2°) away.
    #[test]
    fn the_torque_angle_curve_peaks_one_full_step_off_and_turns_two_off() {
        let (d, e) = nema17();
        let t0 = NEMA17_17HS16_2004S1.torque_constant() * 2.0;
        let full = d.full_step();
        assert!((full - 1.8f64.to_radians()).abs() < 1e-15, "{full}");
        let at = |lag: f64| d.torque(&e, lag, 0.0, 0.0);
        assert_eq!(at(0.0), 0.0);
        assert!((at(-full) - t0).abs() < 1e-12 * t0, "{} vs {t0}", at(-full));
        assert!((at(full) + t0).abs() < 1e-12 * t0);
        // its peak: no lag gives more
        for k in 0..=400 {
            let lag = -4.0 * full * k as f64 / 400.0;
            assert!(at(lag) <= t0 * (1.0 + 1e-12), "{lag}: {}", at(lag));
            // restoring within two full steps, pushing away past them
            let inside = lag.abs() < 2.0 * full - 1e-12;
            let beyond = lag.abs() > 2.0 * full + 1e-12 && lag.abs() < 4.0 * full - 1e-12;
            if inside && lag != 0.0 {
                assert!(at(lag) > 0.0, "{lag}");
            }
            if beyond {
                assert!(at(lag) < 0.0, "{lag}");
            }
        }
        assert!(at(-2.0 * full).abs() < 1e-12 * t0);
        // the next stable point is one electrical cycle, 4 full steps, away
        assert_eq!(d.cycles(-4.0 * full), -1);
        assert_eq!(d.cycles(-1.99 * full), 0);
        assert_eq!(d.cycles(-2.01 * full), -1);
        assert!(d.past_peak(-1.01 * full) && !d.past_peak(-0.99 * full));
        // a load T_L held at standstill lags by asin(T_L/T_max)/N_r
        let load = 0.5 * t0;
        let lag = -(load / t0).asin() / d.rotor_teeth;
        assert!((at(lag) - load).abs() < 1e-12);
    }

    /// The driver holds the nearest microstep.
    #[test]
    fn the_command_is_the_nearest_microstep() {
        let (d, _) = nema17();
        let mu = d.microstep;
        assert!((mu - 1.8f64.to_radians() / 16.0).abs() < 1e-18);
        assert_eq!(d.commanded(0.49 * mu), 0.0);
        assert_eq!(d.commanded(0.51 * mu), mu);
        assert_eq!(d.commanded(-7.6 * mu), -8.0 * mu);
    }

    /// The detent torque is stable at the full steps and has one period per full step.
    #[test]
    fn the_detent_torque_has_a_period_of_one_full_step() {
        let (d, _) = nema17();
        let full = d.full_step();
        for k in -3..=3 {
            let theta = k as f64 * full;
            assert!(detent(0.02, d.rotor_teeth, theta).abs() < 1e-15);
            assert!(detent(0.02, d.rotor_teeth, theta + 0.1 * full) < 0.0);
            assert!(detent(0.02, d.rotor_teeth, theta - 0.1 * full) > 0.0);
        }
    }

    /// A rotor of inertia `inertia` (kg·m²) driven open loop against a constant `load`
    /// (N·m, against the motion) while the driver follows `command(t)` (rad), for `duration`
    /// s at steps of `dt` s (semi-implicit Euler): the time of its first slip, if any.
    fn first_slip(
        d: &OpenLoopStepper,
        e: &Envelope,
        inertia: f64,
        load: f64,
        command: impl Fn(f64) -> f64,
        (duration, dt): (f64, f64),
    ) -> Option<f64> {
        let (mut theta, mut omega) = (command(0.0), 0.0);
        let mut slips = Slips::default();
        for k in 0..(duration / dt) as usize {
            let t = k as f64 * dt;
            let cmd = d.commanded(command(t));
            slips.add(d, theta - cmd, t);
            if slips.first.is_some() {
                return slips.first;
            }
            let torque = d.torque(e, theta, omega, cmd) - load * omega.signum();
            omega += dt * torque / inertia;
            theta += dt * omega;
        }
        None
    }

    /// Pull-out: brought gently up to a speed and held there against a load T_L, the motor
    /// keeps step where its curve gives more than T_L and slips where it gives less; so the
    /// highest speed it holds against T_L is where the curve crosses T_L (here within 5 %),
    /// with a load inertia equal to the rotor's.
    #[test]
    fn the_pull_out_speed_under_a_load_is_where_the_curve_crosses_it() {
        let (d, e) = nema17();
        let inertia = 2.0 * NEMA17_17HS16_2004S1_ROTOR;
        let curve = |w: f64| e.bounds(w).1;
        for share in [0.8, 0.5, 0.25] {
            let load = share * curve(0.0);
            // where the curve crosses the load (it falls monotonically)
            let (mut lo, mut hi) = (0.0, 2000.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if curve(mid) > load { lo = mid } else { hi = mid }
            }
            let crossing = lo;
            // a ramp to the speed slow enough that accelerating takes 1 % of the load, held 0.3 s
            let ramp = 100.0 * inertia * crossing / load;
            let holds = |w: f64| {
                let a = w / ramp;
                let command = |t: f64| match t < ramp {
                    true => 0.5 * a * t * t,
                    false => 0.5 * a * ramp * ramp + w * (t - ramp),
                };
                first_slip(&d, &e, inertia, load, command, (ramp + 0.3, 1e-5)).is_none()
            };
            assert!(
                holds(0.95 * crossing),
                "T_L {load:.3}: slips at 0.95 × {crossing:.1} rad/s"
            );
            assert!(
                !holds(1.05 * crossing),
                "T_L {load:.3}: holds at 1.05 × {crossing:.1} rad/s"
            );
        }
    }

    /// A rotor at rest one microstep off its command rings down about it at ω_n = √(N_r T_max
    /// / J) with the amplitude falling as e^(−ζ ω_n t), ζ = b / (2√(k J)): the damping figures
    /// of [`StepperDamping::of`] are those of the rotor's own motion (integrated at 1 µs).
    #[test]
    fn a_damped_rotor_rings_down_at_its_damping_ratio() {
        let (d, e) = nema17();
        let w = NEMA17_17HS16_2004S1;
        let motor = crate::control::catalog::stepper(String::new(), &w, 2.0, 24.0, Some(16));
        let losses = StepperLosses {
            driver_bandwidth: Some(5000.0),
            rotor_damping: 2e-4,
            reducer_damping: 1e-4,
            reducer_friction: 0.0,
        };
        let inertia = NEMA17_17HS16_2004S1_ROTOR;
        let damping = StepperDamping::of(&motor, &losses, d.rotor_teeth, 1.0, inertia, 0.0);
        let b = damping.electrical + 3e-4;
        assert!((damping.ratio * damping.critical - b).abs() < 1e-15);
        // integrate, record the peaks of the lag
        let dt = 1e-6;
        let (mut theta, mut omega) = (-d.microstep, 0.0);
        let mut peaks = Vec::new();
        let mut last = theta;
        let mut rising = true;
        for k in 0..200_000 {
            let torque = d.torque(&e, theta, omega, 0.0) - b * omega;
            omega += dt * torque / inertia;
            theta += dt * omega;
            if rising && theta < last && k > 0 {
                peaks.push((k as f64 * dt, last));
            }
            rising = theta >= last;
            last = theta;
        }
        let (t0, a0) = peaks[1];
        let (t1, a1) = peaks[6];
        let zeta_omega = (a0 / a1).ln() / (t1 - t0);
        let period = (t1 - t0) / 5.0;
        let omega_d = std::f64::consts::TAU / period;
        let omega_n = damping.natural_frequency;
        assert!((omega_d - omega_n).abs() < 0.01 * omega_n, "{omega_d} vs {omega_n}");
        let zeta = zeta_omega / omega_n;
        assert!(
            (zeta - damping.ratio).abs() < 0.03 * damping.ratio,
            "{zeta} vs {}",
            damping.ratio
        );
    }

    /// Pull-in (start–stop): the highest speed the motor can be started at from rest without
    /// slipping falls with the load inertia as Oriental Motor's f = f_s / √(1 + J_L/J_0)
    /// (here within 5 %), f_s the rate of the bare rotor.
    #[test]
    fn the_pull_in_rate_falls_with_the_load_inertia() {
        let (d, e) = nema17();
        let rotor = NEMA17_17HS16_2004S1_ROTOR;
        let pull_in = |inertia: f64| {
            let (mut lo, mut hi) = (1.0, 2000.0);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                if first_slip(&d, &e, inertia, 0.0, |t| mid * t, (0.1, 2e-6)).is_none() {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            lo
        };
        let bare = pull_in(rotor);
        let mut last = bare;
        for ratio in [1.0, 3.0, 10.0] {
            let f = pull_in(rotor * (1.0 + ratio));
            let oriental = bare / (1.0 + ratio).sqrt();
            assert!(f < last, "J_L/J_0 = {ratio}: {f} not below {last}");
            assert!(
                (f - oriental).abs() < 0.05 * oriental,
                "J_L/J_0 = {ratio}: {f:.1} vs {oriental:.1} rad/s"
            );
            last = f;
        }
        // and f_s itself: the undamped rotor catches a field turning at ω_s while
        // ½ J ω_s² < 2 T_max / N_r (it swings over the curve's unstable top past that)
        let t0 = NEMA17_17HS16_2004S1.torque_constant() * 2.0;
        let energy = 2.0 * (t0 / (d.rotor_teeth * rotor)).sqrt();
        assert!((bare - energy).abs() < 0.05 * energy, "{bare} vs {energy}");
    }
}
