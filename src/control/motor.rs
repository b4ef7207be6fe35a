//! Motors that lose torque with speed: the torque–speed envelope of a DC motor or servo and the
//! pull-out curve of a stepper, at the motor shaft, and the stepper model that derives a
//! pull-out curve from a datasheet (docs/motors.md).
//!
//! A joint driven through a reducer of ratio r (motor turns per joint turn) and efficiency η
//! turns its motor at ω_m = r·q̇ and gets `τ_joint = r·η·τ_m`. At ω_m the motor gives its
//! [`Envelope`], each kind's in its own file (`kinds/`).

pub use super::kinds::{Envelope, StepperLosses, Stepping};

/// One joint's motor: its envelope at the shaft, the reducer's efficiency and the continuous
/// rating; for a stepper, what an open-loop drive needs of it; and where known, the electrics
/// behind the envelope (the sizing report's supply current). The ratio and the rotor inertia
/// are the joint's ([`crate::model::Joint`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Motor {
    /// What it is, for tables ("17HS16-2004S1, 2.0 A, 24 V").
    pub label: String,
    /// The envelope at the motor shaft.
    pub envelope: Envelope,
    /// η in (0, 1]: joint torque = ratio × η × motor torque.
    pub efficiency: f64,
    /// RMS torque it can give without overheating (N·m at the shaft), if known.
    pub continuous_torque: Option<f64>,
    /// A stepper's rotor and driver setting (`--drive stepper` needs them); `None` for a DC
    /// motor, or a stepper given by its curve alone.
    pub stepping: Option<Stepping>,
    /// The drive's supply and the winding behind the envelope, where known.
    pub electrics: Option<Electrics>,
    /// A smart servo's own position loop and protection registers (`--drive servo` needs
    /// them; the `sts3215` and `xm540-w270` presets have them); `None` for a bare motor.
    pub servo: Option<super::ServoSpec>,
}

/// The electrics behind a motor's envelope: enough to turn a shaft torque and speed into the
/// power drawn from the supply (docs/motors.md, "Sizing").
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Electrics {
    /// A DC motor (or servo) driven by an ideal PWM bridge from `supply` volts: its torque
    /// constant K = V/ω₀ and resistance R = K·V/τ_s follow from its envelope.
    Dc {
        /// Supply voltage V (V).
        supply: f64,
    },
    /// A stepper's winding, its chopper holding a phase current amplitude of `current` A, from
    /// `supply` volts.
    Stepper {
        /// The winding.
        winding: StepperWinding,
        /// Phase current amplitude I (A).
        current: f64,
        /// Supply voltage V (V).
        supply: f64,
    },
}

impl Electrics {
    /// The supply voltage (V).
    pub fn supply(&self) -> f64 {
        match *self {
            Electrics::Dc { supply } | Electrics::Stepper { supply, .. } => supply,
        }
    }

    /// The power drawn from the supply (W; negative: returned to it) when `envelope`'s motor
    /// gives `torque` (N·m) at `omega` (rad/s):
    ///
    /// ```text
    ///   dc:      P = τ ω + R (τ/K)²,  K = V/ω₀,  R = K V/τ_s      (the copper loss of i = τ/K)
    ///   stepper: P = τ ω + R I²                                  (two phases at amplitude I:
    ///                                                              2 R (I/√2)², whatever τ)
    /// ```
    ///
    /// No driver, iron or friction loss; a stepper above its corner speed carries less than
    /// I, so its estimate is high there.
    pub fn supply_power(&self, envelope: &Envelope, torque: f64, omega: f64) -> f64 {
        let mechanical = torque * omega;
        match (*self, envelope) {
            (
                Electrics::Dc { supply },
                Envelope::Dc {
                    stall_torque,
                    no_load_speed,
                    ..
                },
            ) => {
                let k = supply / no_load_speed;
                let r = k * supply / stall_torque;
                let i = torque / k;
                mechanical + r * i * i
            }
            (Electrics::Stepper { winding, current, .. }, _) => mechanical + winding.resistance * current * current,
            // a DC supply given to another kind's envelope: the mechanical power alone
            (Electrics::Dc { .. }, _) => mechanical,
        }
    }
}

impl Motor {
    /// The joint torque range [lo, hi] (N·m) at joint speed `qd` through a reducer of ratio
    /// `ratio`: `r·η·bounds(r·q̇)`.
    #[inline]
    pub fn joint_bounds(&self, ratio: f64, qd: f64) -> (f64, f64) {
        let (lo, hi) = self.envelope.bounds(ratio * qd);
        let k = ratio * self.efficiency;
        (k * lo, k * hi)
    }

    /// The most joint torque it gives at any speed (N·m): `r·η·max_torque`.
    pub fn joint_limit(&self, ratio: f64) -> f64 {
        ratio * self.efficiency * self.envelope.max_torque()
    }

    /// Whether its figures make an envelope: efficiency in (0, 1], a DC motor's stall torque,
    /// no-load speed and peak > 0, a stepper's curve non-empty, from ω = 0, its speeds
    /// ascending and its torques ≥ 0, a continuous torque > 0. The error says which figure.
    pub fn check(&self) -> Result<(), String> {
        let positive = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(format!("{name} {x} must be > 0"))
            }
        };
        if !(self.efficiency > 0.0 && self.efficiency <= 1.0) {
            return Err(format!("efficiency {} must be in (0, 1]", self.efficiency));
        }
        if let Some(c) = self.continuous_torque {
            positive("continuous_torque", c)?;
        }
        if let Some(s) = &self.stepping {
            s.losses.check()?;
        }
        if let Some(s) = &self.servo {
            s.check()?;
        }
        self.envelope.check()
    }
}

/// A joint's motor as a file or a preset gives it: the motor, and the reducer's ratio and the
/// rotor's inertia where given (`None` keeps the model's, e.g. its URDF transmission's).
#[derive(Clone, Debug, PartialEq)]
pub struct JointMotor {
    /// Motor turns per joint turn (> 0).
    pub gear_ratio: Option<f64>,
    /// Rotor inertia at the motor shaft (kg·m², ≥ 0), reflected as ratio² × I.
    pub rotor_inertia: Option<f64>,
    /// The motor.
    pub motor: Motor,
}

/// A hybrid stepper's winding and its drive, the datasheet figures the pull-out model needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepperWinding {
    /// Holding torque T_h with both phases at the rated current (N·m).
    pub holding_torque: f64,
    /// Rated phase current I_r (A).
    pub rated_current: f64,
    /// Phase resistance R (Ω).
    pub resistance: f64,
    /// Phase inductance L (H).
    pub inductance: f64,
    /// Rotor teeth N_r (50 for a 1.8° motor, 100 for 0.9°).
    pub rotor_teeth: f64,
}

impl StepperWinding {
    /// Torque constant K = T_h / (√2 I_r) (N·m/A, and V·s/rad of the back-EMF): the holding
    /// torque is two phases at I_r, √2 times one.
    pub fn torque_constant(&self) -> f64 {
        self.holding_torque / (std::f64::consts::SQRT_2 * self.rated_current)
    }

    /// The copper loss at the rating (W): both phases at the rated current, as the holding
    /// torque is measured, 2·R·I_r². A chopper holding an amplitude I dissipates R·I² at any
    /// torque (docs/motors.md, "Sizing").
    pub fn rated_loss(&self) -> f64 {
        2.0 * self.resistance * self.rated_current * self.rated_current
    }

    /// The largest phase current amplitude whose torque its datasheet supports (A): √2·I_r, the
    /// current vector of both phases at the rated current, as the holding torque is measured
    /// (K·√2·I_r = T_h). A drive set above it is taken at it for the torque (the iron saturates
    /// beyond what any datasheet figure shows); its copper loss is still the drive's.
    pub fn torque_current_limit(&self) -> f64 {
        std::f64::consts::SQRT_2 * self.rated_current
    }

    /// The electrical damping (N·m·s/rad at the shaft) of this winding behind a driver whose
    /// current loop has a bandwidth of `bandwidth` Hz, for a rotor oscillating at `omega` rad/s
    /// about a microstep: the loop, `L di/dt = (R + L ω_c)(i_ref − i) − e`, leaves the back-EMF
    /// e = K ω a current −e / Z(jω), Z = R + L ω_c + j ω L, whose torque brakes the rotor:
    ///
    /// ```text
    ///   b_e = K² · Re(1 / Z(jω)) = K² (R + L ω_c) / ((R + L ω_c)² + (ω L)²),   ω_c = 2π f_c
    /// ```
    ///
    /// (docs/motors.md, "The stepper's damping"; the two phases' braking currents add to a
    /// torque independent of the rotor's angle).
    pub fn electrical_damping(&self, bandwidth: f64, omega: f64) -> f64 {
        let k = self.torque_constant();
        let r = self.resistance + self.inductance * std::f64::consts::TAU * bandwidth;
        let x = omega * self.inductance;
        k * k * r / (r * r + x * x)
    }

    /// The pull-out torque (N·m) at shaft speed `omega` (rad/s, ≥ 0) driven with a phase current
    /// amplitude of at most `current` (A) from a supply of `supply` (V): the largest
    /// `K·i_q` over the load angle with `|i| ≤ current` and `|Z i + j K ω| ≤ V`, where
    /// `Z = R + j N_r ω L` (docs/motors.md).
    pub fn pull_out_torque(&self, omega: f64, current: f64, supply: f64) -> f64 {
        let k = self.torque_constant();
        let (r, x) = (self.resistance, self.rotor_teeth * omega * self.inductance);
        let z2 = r * r + x * x;
        // i = (v − jKω)/Z over |v| ≤ V: a disc of radius ρ = V/|Z| about c = −jKω/Z
        let e = k * omega;
        let (cx, cy) = (-e * x / z2, -e * r / z2);
        let rho = supply / z2.sqrt();
        // the current limit alone: i = j·I
        let within = |px: f64, py: f64| (px - cx).powi(2) + (py - cy).powi(2) <= rho * rho * (1.0 + 1e-12);
        if within(0.0, current) {
            return k * current;
        }
        // the voltage limit alone: the disc's top, if inside the current circle
        let (tx, ty) = (cx, cy + rho);
        if tx * tx + ty * ty <= current * current {
            return (k * ty).max(0.0);
        }
        // both: the higher crossing of the circle |i| = I with the disc's edge
        let d = (cx * cx + cy * cy).sqrt();
        if d > current + rho || d < (current - rho).abs() || d == 0.0 {
            return 0.0;
        }
        let a = (current * current - rho * rho + d * d) / (2.0 * d);
        let h = (current * current - a * a).max(0.0).sqrt();
        let my = a * cy / d;
        let y1 = my + h * cx / d;
        let y2 = my - h * cx / d;
        (k * y1.max(y2)).max(0.0)
    }

    /// The pull-out curve at `current` (A) and `supply` (V) as `points` (≥ 2) evenly spaced
    /// speeds from 0 to the speed where the model's torque has fallen to `tail` of its
    /// standstill value (the curve's last point; past it the envelope is zero).
    pub fn pull_out_curve(&self, current: f64, supply: f64, points: usize, tail: f64) -> Vec<[f64; 2]> {
        let t0 = self.pull_out_torque(0.0, current, supply);
        // the torque falls monotonically: bisect for the tail speed
        let (mut lo, mut hi) = (0.0, 1.0);
        while self.pull_out_torque(hi, current, supply) > tail * t0 && hi < 1e7 {
            hi *= 2.0;
        }
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if self.pull_out_torque(mid, current, supply) > tail * t0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let points = points.max(2);
        (0..points)
            .map(|i| {
                let w = hi * i as f64 / (points - 1) as f64;
                [w, self.pull_out_torque(w, current, supply)]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dc() -> Envelope {
        Envelope::Dc {
            stall_torque: 0.5,
            no_load_speed: 300.0,
            peak_torque: 0.4,
        }
    }

    /// At stall the DC motor gives ±τ_s, capped at the peak.
    #[test]
    fn dc_at_stall_gives_the_stall_torque_capped_at_the_peak() {
        assert_eq!(dc().bounds(0.0), (-0.4, 0.4));
        let uncapped = Envelope::Dc {
            stall_torque: 0.5,
            no_load_speed: 300.0,
            peak_torque: 0.5,
        };
        assert_eq!(uncapped.bounds(0.0), (-0.5, 0.5));
    }

    /// At the no-load speed it can only brake (up to the peak), driving torque is zero.
    #[test]
    fn dc_at_no_load_speed_gives_no_driving_torque() {
        let (lo, hi) = dc().bounds(300.0);
        assert_eq!(hi, 0.0);
        assert_eq!(lo, -0.4);
        let (lo, hi) = dc().bounds(-300.0);
        assert_eq!((lo, hi), (0.0, 0.4));
        // past it the motor must brake
        let (_, hi) = dc().bounds(450.0);
        assert!(hi < 0.0, "{hi}");
    }

    /// Braking (torque against the motion) gets more than the stall torque, up to the peak.
    #[test]
    fn dc_braking_quadrant_reaches_beyond_stall_up_to_the_peak() {
        let e = Envelope::Dc {
            stall_torque: 0.5,
            no_load_speed: 300.0,
            peak_torque: 0.9,
        };
        // at +150 rad/s: [0.5(−1.5), 0.5(0.5)] = [−0.75, 0.25]
        let (lo, hi) = e.bounds(150.0);
        assert!((lo + 0.75).abs() < 1e-15 && (hi - 0.25).abs() < 1e-15, "{lo} {hi}");
        // at +300 rad/s the braking bound −1.0 is capped to −0.9
        assert_eq!(e.bounds(300.0).0, -0.9);
    }

    /// A stepper's curve is linear between its points, symmetric, and zero past the last.
    #[test]
    fn stepper_curve_interpolates_and_is_zero_past_the_last_point() {
        let e = Envelope::Stepper {
            curve: vec![[0.0, 0.32], [60.0, 0.31], [120.0, 0.2], [200.0, 0.08]],
        };
        assert_eq!(e.bounds(0.0), (-0.32, 0.32));
        let (_, hi) = e.bounds(90.0);
        assert!((hi - 0.255).abs() < 1e-15, "{hi}");
        assert_eq!(e.bounds(-90.0), e.bounds(90.0));
        assert_eq!(e.bounds(200.0).1, 0.08);
        assert_eq!(e.bounds(200.000001), (-0.0, 0.0));
        assert_eq!(e.max_torque(), 0.32);
    }

    /// The joint gets r·η times the motor's torque, at r times the joint's speed.
    #[test]
    fn joint_bounds_scale_speed_and_torque_by_the_ratio() {
        let m = Motor {
            label: String::new(),
            envelope: dc(),
            efficiency: 0.8,
            continuous_torque: None,
            stepping: None,
            electrics: None,
            servo: None,
        };
        let (lo, hi) = m.joint_bounds(10.0, 15.0); // ω_m = 150
        assert!((hi - 10.0 * 0.8 * 0.25).abs() < 1e-14, "{hi}");
        assert!((lo + 10.0 * 0.8 * 0.4).abs() < 1e-14, "{lo}");
        assert!((m.joint_limit(10.0) - 3.2).abs() < 1e-15);
    }

    /// Between two kinks (and past the outermost) both bounds are affine in ω: the midpoint's
    /// bounds are the mean of the ends'.
    #[test]
    fn bounds_are_affine_between_kinks() {
        let stepper = Envelope::Stepper {
            curve: vec![[0.0, 0.32], [60.0, 0.31], [120.0, 0.2], [200.0, 0.08]],
        };
        let wide = Envelope::Dc {
            stall_torque: 0.5,
            no_load_speed: 300.0,
            peak_torque: 0.9,
        };
        for e in [dc(), wide, stepper] {
            let mut ends = e.kinks();
            if e.kind() == "dc" {
                // a stepper's envelope jumps to zero past its last point; a DC motor's goes on
                ends.insert(0, ends[0] - 50.0);
                ends.push(ends[ends.len() - 1] + 50.0);
            }
            for w in ends.windows(2) {
                let (a, b, m) = (e.bounds(w[0]), e.bounds(w[1]), e.bounds(0.5 * (w[0] + w[1])));
                assert!((m.0 - 0.5 * (a.0 + b.0)).abs() < 1e-12, "{} lo on {w:?}", e.kind());
                assert!((m.1 - 0.5 * (a.1 + b.1)).abs() < 1e-12, "{} hi on {w:?}", e.kind());
            }
        }
        let kinks = dc().kinks();
        assert_eq!(kinks.len(), 4);
        for (k, want) in kinks.iter().zip([-540.0, -60.0, 60.0, 540.0]) {
            assert!((k - want).abs() < 1e-9, "{kinks:?}");
        }
        assert_eq!(dc().top_speed(), 300.0);
    }

    fn nema17() -> StepperWinding {
        StepperWinding {
            holding_torque: 0.45,
            rated_current: 2.0,
            resistance: 1.1,
            inductance: 2.6e-3,
            rotor_teeth: 50.0,
        }
    }

    /// At standstill the stepper gives K·I; the model's curve then falls, never rising.
    #[test]
    fn stepper_model_gives_k_times_current_at_standstill_and_falls_with_speed() {
        let w = nema17();
        let t0 = w.pull_out_torque(0.0, 2.0, 24.0);
        assert!((t0 - 0.45 / 2f64.sqrt()).abs() < 1e-15, "{t0}");
        let half = w.pull_out_torque(0.0, 1.0, 24.0);
        assert!((half - t0 / 2.0).abs() < 1e-15);
        let mut last = t0;
        for i in 1..400 {
            let t = w.pull_out_torque(i as f64, 2.0, 24.0);
            assert!(t <= last + 1e-12, "rises at {i} rad/s: {t} > {last}");
            last = t;
        }
        assert!(last < 0.5 * t0);
        // a higher supply keeps more torque at speed
        assert!(w.pull_out_torque(200.0, 2.0, 48.0) > w.pull_out_torque(200.0, 2.0, 24.0));
    }

    /// Past the corner speed the voltage limit alone sets the torque, K(V − KωR/|Z|)/|Z|.
    #[test]
    fn stepper_model_at_high_speed_is_the_voltage_limited_pull_out() {
        let w = nema17();
        let (omega, v) = (300.0, 24.0);
        let k = w.torque_constant();
        let z = (1.1f64.powi(2) + (50.0 * omega * 2.6e-3f64).powi(2)).sqrt();
        let want = k * (v - k * omega * 1.1 / z) / z;
        let got = w.pull_out_torque(omega, 2.0, v);
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    }

    /// The electrical damping is K²·Re(1/Z(jω)), Z = R + L·2π·f_c + jωL: the voltage drive's
    /// K²/R with no loop and a still rotor, less the faster the loop, and less at a faster
    /// ringing (the inductance holds the current back).
    #[test]
    fn electrical_damping_is_the_back_emf_current_the_loop_leaves() {
        let w = nema17();
        let k = w.torque_constant();
        // a loop of bandwidth 0 is a voltage drive: K²/R at a still rotor
        assert!((w.electrical_damping(0.0, 0.0) - k * k / 1.1).abs() < 1e-15);
        // the complex admittance, written out
        let (f_c, omega) = (5000.0, 1700.0);
        let (re, im) = (1.1 + 2.6e-3 * std::f64::consts::TAU * f_c, omega * 2.6e-3);
        let want = k * k * re / (re * re + im * im);
        assert!((w.electrical_damping(f_c, omega) - want).abs() < 1e-15 * want);
        // faster loops damp less; at 5 kHz and 1700 rad/s about 3e-4 N·m·s/rad
        assert!(w.electrical_damping(20_000.0, omega) < w.electrical_damping(2_000.0, omega));
        assert!(
            (w.electrical_damping(f_c, omega) - 3.05e-4).abs() < 0.01e-4,
            "{}",
            w.electrical_damping(f_c, omega)
        );
    }

    /// Above √2·I_r (both phases at the rated current) no datasheet figure says what the
    /// torque is: the presets take the torque there.
    #[test]
    fn the_torque_current_is_capped_at_the_holding_condition() {
        let w = nema17();
        assert!((w.torque_constant() * w.torque_current_limit() - 0.45).abs() < 1e-15);
    }

    /// The sampled curve starts at the standstill torque and ends at the tail.
    #[test]
    fn pull_out_curve_runs_from_standstill_to_the_tail() {
        let curve = nema17().pull_out_curve(2.0, 24.0, 40, 0.05);
        assert_eq!(curve.len(), 40);
        assert_eq!(curve[0][0], 0.0);
        let t0 = curve[0][1];
        let last = curve[39];
        assert!((last[1] - 0.05 * t0).abs() < 1e-9 * t0, "{last:?}");
    }
}
