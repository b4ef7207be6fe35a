//! The Faze4's motors (`--motors faze4`, `--motors faze4-bom`; docs/motors.md).
//!
//! `faze4` is the original's assumption made physical: a StepperOnline 17HS16-2004S1 behind
//! every reducer, driven at its rated 2.0 A, its pull-out curve from the stepper model at the
//! supply voltage. At standstill it gives K·I = 0.45/√2 = 0.318 N·m, which the original rounded
//! to 0.315 N·m (its seed limits [7.9, 8.5, 4.7, 3.7, 3.5, 6.0] N·m are 0.315 N·m × the ratios).
//!
//! `faze4-bom` is the motors the Faze4 is built with (its repository's `BOM_7_11_2023.xlsx`),
//! on the joints its firmware says (`step_angle = {1.8, 1.8, 0.9, 1.8, 1.8, 1.8}`: the BOM's one
//! 0.9° motor, the 23HM22-2804S, drives J3), at the currents and voltages of its electronics
//! guide (`FAZE4 Robotic arm electronics setup.pdf`): J1 23HS22-1504S at 2.7 A, J2 23HS33-4008D
//! at 2.7 A and 36 V, J3 23HM22-2804S at 2.2 A, J4 and J5 17HS16-2004S1 at 1.2 A, J6
//! 14HS13-0804S-PG19 at 0.7 A, 24 V but J2. Both presets' drivers are at the 2020 firmware's
//! microsteps, [`MICROSTEPS`].

use crate::control::catalog::{
    NEMA14_14HS13_0804S, NEMA14_14HS13_0804S_ROTOR, NEMA17_17HS16_2004S1, NEMA17_17HS16_2004S1_ROTOR,
    NEMA23_23HM22_2804S, NEMA23_23HM22_2804S_ROTOR, NEMA23_23HS22_1504S, NEMA23_23HS22_1504S_ROTOR,
    NEMA23_23HS33_4008D, NEMA23_23HS33_4008D_ROTOR, stepper,
};
use crate::control::{JointMotor, StepperWinding};

/// Reducer ratio of each joint, J1..J6 (motor turns per joint turn): the Faze4's published
/// ratios (its docs' `B_Design_decisions.rst`; J4's 11.846 is 11 × 28/26, which the 2020
/// firmware rounds to 11.847).
pub const GEAR_RATIO: [f64; 6] = [25.0, 27.0, 15.0, 11.846, 11.0, 19.19];

/// Microsteps per full step of each joint's driver, J1..J6: the 2020 firmware's
/// (`Robot_Arduino_trajectory.ino`: `microstep[] = {0.125, 0.125, 0.25, 0.5, 0.5, 0.5}`).
pub const MICROSTEPS: [u32; 6] = [8, 8, 4, 2, 2, 2];

/// Rotor inertia of the 17HS16-2004S1 (kg·m² at the motor shaft): its datasheet lists 54 g·cm².
pub const ROTOR_INERTIA: f64 = NEMA17_17HS16_2004S1_ROTOR;

/// The supply of the Faze4's drivers (V), its electronics guide's (J2's is [`J2_SUPPLY_VOLTS`]).
pub const SUPPLY_VOLTS: f64 = 24.0;

/// J2's driver supply in the electronics guide (V).
pub const J2_SUPPLY_VOLTS: f64 = 36.0;

/// `--motors faze4`: a 17HS16-2004S1 at its rated 2.0 A on every joint, at `supply` volts
/// (`None`: 24 V), with the published ratios, the motor's rotor and the firmware's microsteps.
pub fn faze4(supply: Option<f64>) -> Vec<Option<JointMotor>> {
    let v = supply.unwrap_or(SUPPLY_VOLTS);
    (GEAR_RATIO.iter().zip(MICROSTEPS))
        .map(|(&ratio, microsteps)| {
            Some(JointMotor {
                gear_ratio: Some(ratio),
                rotor_inertia: Some(ROTOR_INERTIA),
                motor: stepper(
                    format!("17HS16-2004S1, 2.0 A, {v} V"),
                    &NEMA17_17HS16_2004S1,
                    2.0,
                    v,
                    Some(microsteps),
                ),
            })
        })
        .collect()
}

/// One joint of `faze4-bom`: its motor `name` and `winding` at `amps` (A, the guide's peak
/// current) from `volts`, the joint's ratio and microsteps, the rotor where published.
fn built(joint: usize, name: &str, winding: &StepperWinding, amps: f64, volts: f64, rotor: Option<f64>) -> JointMotor {
    JointMotor {
        gear_ratio: Some(GEAR_RATIO[joint]),
        rotor_inertia: rotor,
        motor: stepper(
            format!("{name}, {amps} A, {volts} V"),
            winding,
            amps,
            volts,
            Some(MICROSTEPS[joint]),
        ),
    }
}

/// `--motors faze4-bom`: the built arm's motors on the joints the firmware gives them, at the
/// electronics guide's driver currents and supplies (`supply` volts for every joint instead
/// when given). J1's and J2's NEMA23 rotors are same-frame proxies
/// ([`NEMA23_23HS22_1504S_ROTOR`], [`NEMA23_23HS33_4008D_ROTOR`]); J1's 2.7 A is above its
/// 1.5 A winding's rating, and its torque is taken at the holding torque
/// ([`crate::control::StepperWinding::torque_current_limit`]).
pub fn faze4_bom(supply: Option<f64>) -> Vec<Option<JointMotor>> {
    let v = supply.unwrap_or(SUPPLY_VOLTS);
    let j2 = supply.unwrap_or(J2_SUPPLY_VOLTS);
    vec![
        Some(built(
            0,
            "23HS22-1504S",
            &NEMA23_23HS22_1504S,
            2.7,
            v,
            Some(NEMA23_23HS22_1504S_ROTOR),
        )),
        Some(built(
            1,
            "23HS33-4008D",
            &NEMA23_23HS33_4008D,
            2.7,
            j2,
            Some(NEMA23_23HS33_4008D_ROTOR),
        )),
        Some(built(
            2,
            "23HM22-2804S",
            &NEMA23_23HM22_2804S,
            2.2,
            v,
            Some(NEMA23_23HM22_2804S_ROTOR),
        )),
        Some(built(
            3,
            "17HS16-2004S1",
            &NEMA17_17HS16_2004S1,
            1.2,
            v,
            Some(NEMA17_17HS16_2004S1_ROTOR),
        )),
        Some(built(
            4,
            "17HS16-2004S1",
            &NEMA17_17HS16_2004S1,
            1.2,
            v,
            Some(NEMA17_17HS16_2004S1_ROTOR),
        )),
        Some(built(
            5,
            "14HS13-0804S-PG19",
            &NEMA14_14HS13_0804S,
            0.7,
            v,
            Some(NEMA14_14HS13_0804S_ROTOR),
        )),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::faze4::EFFORT as FAZE4_EFFORT;

    /// The seed's limits are the motors' standstill torque times the ratios, to their rounding
    /// (0.315 N·m against the model's 0.318), within 2 %.
    #[test]
    fn the_seed_limits_are_motor_torque_times_ratio() {
        for (m, seed) in faze4(None).iter().zip(FAZE4_EFFORT) {
            let m = m.as_ref().unwrap();
            let e = m.motor.joint_limit(m.gear_ratio.unwrap());
            assert!((e - seed).abs() <= 0.02 * seed, "{e} vs {seed}");
        }
    }

    /// J6's reflected rotor (19.19² · 5.4e-6 ≈ 2.0e-3 kg·m²) dwarfs its link (6.45e-6).
    #[test]
    fn the_rotor_dominates_j6() {
        let arm = crate::faze4::model();
        let mut data = crate::algo::Data::new(&arm);
        let q = [0.0; 6];
        let bare = crate::algo::crba(&arm, &mut data, &q)[(5, 5)];
        let mut motors = arm.clone();
        motors.joints[5].rotor_inertia = ROTOR_INERTIA;
        motors.joints[5].gear_ratio = GEAR_RATIO[5];
        let with = crate::algo::crba(&motors, &mut data, &q)[(5, 5)];
        let reflected = GEAR_RATIO[5] * GEAR_RATIO[5] * ROTOR_INERTIA;
        assert!(
            (with - bare - reflected).abs() < 1e-15,
            "{with} − {bare} vs {reflected}"
        );
        assert!(reflected > 200.0 * bare);
    }

    /// The built arm's standstill limits at the joint are K·I·r of each motor at the guide's
    /// current, at most its holding torque × r: J1 (23HS22-1504S at 2.7 A, above its
    /// √2 × 1.5 A: its holding torque 1.16 N·m) 29.0 N·m, J2 (23HS33-4008D at 2.7 A) 36.5, J3
    /// (23HM22-2804S at 2.2 A) 10.5, J4 2.26, J5 2.10, J6 (14HS13 through the PG19 at 0.7 A)
    /// 2.14: J1–J3 far above the original's uniform limits, J6 below.
    #[test]
    fn the_bill_of_materials_against_the_uniform_assumption() {
        let bom = faze4_bom(None);
        let limit = |j: usize| {
            let m = bom[j].as_ref().unwrap();
            m.motor.joint_limit(m.gear_ratio.unwrap())
        };
        let k_i_r = |w: &StepperWinding, amps: f64, j: usize| {
            w.torque_constant() * amps.min(w.torque_current_limit()) * GEAR_RATIO[j]
        };
        assert!(2.7 > NEMA23_23HS22_1504S.torque_current_limit());
        assert!((k_i_r(&NEMA23_23HS22_1504S, 2.7, 0) - 1.16 * 25.0).abs() < 1e-12);
        let want = [
            k_i_r(&NEMA23_23HS22_1504S, 2.7, 0),
            k_i_r(&NEMA23_23HS33_4008D, 2.7, 1),
            k_i_r(&NEMA23_23HM22_2804S, 2.2, 2),
            k_i_r(&NEMA17_17HS16_2004S1, 1.2, 3),
            k_i_r(&NEMA17_17HS16_2004S1, 1.2, 4),
            k_i_r(&NEMA14_14HS13_0804S, 0.7, 5),
        ];
        for (j, (w, printed)) in want.iter().zip([29.0, 36.5, 10.5, 2.26, 2.10, 2.14]).enumerate() {
            assert!((limit(j) - w).abs() < 1e-12 * w, "J{}: {} vs {w}", j + 1, limit(j));
            assert!(
                (w - printed).abs() < 0.006 * printed,
                "J{}: {w} vs the doc's {printed}",
                j + 1
            );
        }
        assert!(limit(0) > 3.5 * FAZE4_EFFORT[0] && limit(1) > 4.0 * FAZE4_EFFORT[1]);
        assert!(limit(2) > 2.0 * FAZE4_EFFORT[2]);
        assert!(limit(5) < FAZE4_EFFORT[5], "J6 {}", limit(5));
        // the firmware's 0.9° motor is on J3, the 36 V supply on J2
        let teeth: Vec<f64> = bom
            .iter()
            .map(|m| m.as_ref().unwrap().motor.stepping.unwrap().rotor_teeth)
            .collect();
        assert_eq!(teeth, [50.0, 50.0, 100.0, 50.0, 50.0, 50.0]);
        assert!(bom[1].as_ref().unwrap().motor.label.ends_with("36 V"));
    }
}
