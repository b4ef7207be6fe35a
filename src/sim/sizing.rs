//! The sizing report of each motored joint (`--sizing`, the summary's `motors[].sizing`),
//! accumulated over the steps: what a motor sizing note asks for (docs/motors.md, "Sizing"),
//! at the motor shaft.

use serde::Serialize;

use crate::control::{Electrics, Motor};

/// A joint's motor as a sizing engineer reads it, over a run; torques, speeds, powers and
/// inertias at the motor shaft.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Sizing {
    /// max over the steps of |τ_m|, the torque the motor gave (N·m).
    pub peak_torque: f64,
    /// max over the steps of τ_m·ω_m, the mechanical power while motoring (W).
    pub peak_power_w: f64,
    /// ∫ max(0, −τ_m·ω_m) dt: the mechanical energy the load returned through the shaft while
    /// the motor braked it (J). What reaches the supply is this less the winding's and the
    /// driver's losses (see `supply_current_a`).
    pub braking_energy_j: f64,
    /// max over the steps of the load inertia reflected to the shaft over the rotor's,
    /// (M_ii(q)/r² − J_rotor) / J_rotor (the rest of the arm held still); `null` when the rotor
    /// inertia is not known (0). Sizing notes keep it at 10 or below for a stepper.
    pub inertia_ratio: Option<f64>,
    /// The current drawn from the supply, estimated from the motor's electrics (A); `null`
    /// where the motor has none (a motors file gives an envelope only).
    pub supply_current_a: Option<SupplyCurrent>,
    /// A stepper's heating under its constant-current driver: the winding's loss at the
    /// drive's current against its loss at the rating; `null` for other motors.
    pub winding_loss_w: Option<WindingLoss>,
}

/// The supply current estimate over a run (A).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SupplyCurrent {
    /// max over the steps of P_supply / V.
    pub peak: f64,
    /// The mean of P_supply / V over the steps (negative: the motor returned more than it
    /// drew).
    pub mean: f64,
}

/// A stepper's winding loss (W): a chopper holds the current amplitude I in both phases at
/// any torque, so its copper loss R·I² does not follow the torque (no RMS-torque check
/// applies); the datasheet's rating is both phases at the rated current, 2·R·I_r².
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct WindingLoss {
    /// R·I² at the drive's current.
    pub at_drive: f64,
    /// 2·R·I_r² at the rating.
    pub at_rating: f64,
    /// The drive's phase current amplitude I (A).
    pub current: f64,
    /// The motor's rated phase current I_r (A).
    pub rated_current: f64,
    /// Whether the drive is set above √2·I_r, both phases at the rating, the most current whose
    /// torque the datasheet supports: the torque is then taken at the holding torque
    /// ([`crate::control::StepperWinding::torque_current_limit`]), the loss at the drive's
    /// current.
    pub above_rating: bool,
}

/// The sums and extremes behind one joint's [`Sizing`].
#[derive(Clone, Copy, Debug, Default)]
pub struct SizingSums {
    peak_torque: f64,
    peak_power: f64,
    braking_energy: f64,
    peak_load_inertia: f64,
    peak_supply_current: f64,
    supply_energy: f64,
}

impl SizingSums {
    /// Folds in a step of `dt` s at which `motor` gave `torque` (N·m) at `omega` (rad/s) and
    /// the joint's mass-matrix diagonal, reflected to the shaft through a ratio r, was
    /// `inertia` = M_ii/r² (kg·m²).
    #[inline]
    pub fn add(&mut self, motor: &Motor, torque: f64, omega: f64, inertia: f64, dt: f64) {
        let power = torque * omega;
        self.peak_torque = self.peak_torque.max(torque.abs());
        self.peak_power = self.peak_power.max(power);
        self.braking_energy += (-power).max(0.0) * dt;
        self.peak_load_inertia = self.peak_load_inertia.max(inertia);
        if let Some(e) = &motor.electrics {
            let drawn = e.supply_power(&motor.envelope, torque, omega);
            self.peak_supply_current = self.peak_supply_current.max(drawn / e.supply());
            self.supply_energy += drawn * dt;
        }
    }

    /// The sizing of `motor` behind a rotor of `rotor` kg·m² over `duration` s.
    pub fn sizing(&self, motor: &Motor, rotor: f64, duration: f64) -> Sizing {
        Sizing {
            peak_torque: self.peak_torque,
            peak_power_w: self.peak_power,
            braking_energy_j: self.braking_energy,
            inertia_ratio: (rotor > 0.0).then(|| (self.peak_load_inertia - rotor) / rotor),
            supply_current_a: motor.electrics.map(|e| SupplyCurrent {
                peak: self.peak_supply_current,
                mean: self.supply_energy / (e.supply() * duration.max(f64::MIN_POSITIVE)),
            }),
            winding_loss_w: match motor.electrics {
                Some(Electrics::Stepper { winding, current, .. }) => Some(WindingLoss {
                    at_drive: winding.resistance * current * current,
                    at_rating: winding.rated_loss(),
                    current,
                    rated_current: winding.rated_current,
                    above_rating: current > winding.torque_current_limit(),
                }),
                _ => None,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::catalog::{NEMA17_17HS16_2004S1, stepper, xm540_w270};

    /// A motor driving a constant torque over a speed that reverses: the power peaks while
    /// motoring, braking returns τ·ω·t, the current follows P/V.
    #[test]
    fn power_braking_energy_and_supply_current_follow_their_definitions() {
        let m = stepper("17HS16".into(), &NEMA17_17HS16_2004S1, 2.0, 24.0, None);
        let mut s = SizingSums::default();
        let dt = 1e-3;
        // 1 s motoring at 0.2 N·m and 10 rad/s, then 1 s braking (−10 rad/s)
        for k in 0..2000 {
            let omega = if k < 1000 { 10.0 } else { -10.0 };
            s.add(&m, 0.2, omega, 3.0 * 54e-7, dt);
        }
        let z = s.sizing(&m, 54e-7, 2.0);
        assert_eq!(z.peak_torque, 0.2);
        assert!((z.peak_power_w - 2.0).abs() < 1e-12);
        assert!((z.braking_energy_j - 2.0).abs() < 1e-9, "{}", z.braking_energy_j);
        assert!((z.inertia_ratio.unwrap() - 2.0).abs() < 1e-12);
        // the chopper's copper loss R·I² = 1.1 · 4 = 4.4 W on top of ±2 W
        let c = z.supply_current_a.unwrap();
        assert!((c.peak - 6.4 / 24.0).abs() < 1e-12, "{c:?}");
        assert!((c.mean - 4.4 / 24.0).abs() < 1e-9, "{c:?}");
        let w = z.winding_loss_w.unwrap();
        assert!((w.at_drive - 4.4).abs() < 1e-12 && (w.at_rating - 8.8).abs() < 1e-12);
    }

    /// A DC motor draws τω + R(τ/K)²: at stall torque and standstill, V·τ_s/K = V²/R.
    #[test]
    fn a_dc_motor_at_stall_draws_its_stall_current() {
        let m = xm540_w270(None).motor;
        let Some(Electrics::Dc { supply }) = m.electrics else {
            panic!()
        };
        let crate::control::Envelope::Dc {
            stall_torque,
            no_load_speed,
            ..
        } = m.envelope
        else {
            panic!()
        };
        let k = supply / no_load_speed;
        let mut s = SizingSums::default();
        s.add(&m, stall_torque, 0.0, 0.0, 1e-3);
        let z = s.sizing(&m, 0.0, 1e-3);
        assert!(z.inertia_ratio.is_none() && z.winding_loss_w.is_none());
        let stall_current = stall_torque / k;
        assert!((z.supply_current_a.unwrap().peak - stall_current).abs() < 1e-9 * stall_current);
    }
}
