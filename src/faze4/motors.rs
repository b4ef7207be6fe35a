//! The Faze4's motors (`--motors faze4`, `--motors faze4-bom`; docs/motors.md).
//!
//! `faze4` is the original's assumption made physical: a StepperOnline 17HS16-2004S1 behind
//! every reducer, driven at its rated 2.0 A, its pull-out curve from the stepper model at the
//! supply voltage. At standstill it gives K·I = 0.45/√2 = 0.318 N·m, which the original rounded
//! to 0.315 N·m (its seed limits [7.9, 8.5, 4.7, 3.7, 3.5, 6.0] N·m are 0.315 N·m × the ratios).
//!
//! `faze4-bom` is the motors the Faze4 is built with (its repository's `BOM_7_11_2023.xlsx`),
//! at the currents and voltages of its electronics guide (`FAZE4 Robotic arm electronics
//! setup.pdf`): J1 23HM22-2804S at 2.7 A, J2 23HS33-4008D at 2.7 A and 36 V, J3 23HS22-1504S
//! at 2.2 A, J4 and J5 17HS16-2004S1 at 1.2 A, J6 14HS13-0804S-PG19 at 0.7 A, 24 V but J2. No
//! winding figures of the 23HS33-4008D were found: J2 keeps the constant limit.

use crate::control::catalog::{
    NEMA14_14HS13_0804S, NEMA14_14HS13_0804S_ROTOR, NEMA17_17HS16_2004S1, NEMA17_17HS16_2004S1_ROTOR,
    NEMA23_23HM22_2804S, NEMA23_23HS22_1504S, stepper,
};
use crate::control::{JointMotor, StepperWinding};

/// Reducer ratio of each joint, J1..J6 (motor turns per joint turn): the Faze4's published
/// ratios.
pub const GEAR_RATIO: [f64; 6] = [25.0, 27.0, 15.0, 11.846, 11.0, 19.19];

/// Rotor inertia of the 17HS16-2004S1 (kg·m² at the motor shaft): its datasheet lists 54 g·cm².
pub const ROTOR_INERTIA: f64 = NEMA17_17HS16_2004S1_ROTOR;

/// The supply of the Faze4's drivers (V), its electronics guide's (J2's is 36 V).
pub const SUPPLY_VOLTS: f64 = 24.0;

/// `--motors faze4`: a 17HS16-2004S1 at its rated 2.0 A on every joint, at `supply` volts
/// (`None`: 24 V), with the published ratios and the motor's rotor.
pub fn faze4(supply: Option<f64>) -> Vec<Option<JointMotor>> {
    let v = supply.unwrap_or(SUPPLY_VOLTS);
    (GEAR_RATIO.iter())
        .map(|&ratio| {
            Some(JointMotor {
                gear_ratio: Some(ratio),
                rotor_inertia: Some(ROTOR_INERTIA),
                motor: stepper(format!("17HS16-2004S1, 2.0 A, {v} V"), &NEMA17_17HS16_2004S1, 2.0, v),
            })
        })
        .collect()
}

/// `--motors faze4-bom`: the built arm's motors at the electronics guide's driver currents, at
/// `supply` volts for every stepper (`None`: the guide's 24 V). J2 (a 23HS33-4008D, no winding
/// figures found) has no motor model: it keeps the constant limit. Rotors not found (J1, J3)
/// are left at the model's.
pub fn faze4_bom(supply: Option<f64>) -> Vec<Option<JointMotor>> {
    let v = supply.unwrap_or(SUPPLY_VOLTS);
    let joint = |name: &str, winding: &StepperWinding, amps: f64, ratio: f64, rotor: Option<f64>| {
        Some(JointMotor {
            gear_ratio: Some(ratio),
            rotor_inertia: rotor,
            motor: stepper(format!("{name}, {amps} A, {v} V"), winding, amps, v),
        })
    };
    vec![
        joint("23HM22-2804S", &NEMA23_23HM22_2804S, 2.7, GEAR_RATIO[0], None),
        None,
        joint("23HS22-1504S", &NEMA23_23HS22_1504S, 2.2, GEAR_RATIO[2], None),
        joint(
            "17HS16-2004S1",
            &NEMA17_17HS16_2004S1,
            1.2,
            GEAR_RATIO[3],
            Some(NEMA17_17HS16_2004S1_ROTOR),
        ),
        joint(
            "17HS16-2004S1",
            &NEMA17_17HS16_2004S1,
            1.2,
            GEAR_RATIO[4],
            Some(NEMA17_17HS16_2004S1_ROTOR),
        ),
        joint(
            "14HS13-0804S-PG19",
            &NEMA14_14HS13_0804S,
            0.7,
            GEAR_RATIO[5],
            Some(NEMA14_14HS13_0804S_ROTOR),
        ),
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

    /// The built arm's NEMA23s give far more than the original's uniform limit at J1 and J3,
    /// its NEMA14 through the PG19 less at J6.
    #[test]
    fn the_bill_of_materials_against_the_uniform_assumption() {
        let bom = faze4_bom(None);
        let limit = |j: usize| {
            let m = bom[j].as_ref().unwrap();
            m.motor.joint_limit(m.gear_ratio.unwrap())
        };
        assert!(limit(0) > 2.0 * FAZE4_EFFORT[0], "J1 {}", limit(0));
        assert!(limit(2) > 2.0 * FAZE4_EFFORT[2], "J3 {}", limit(2));
        assert!(limit(5) < FAZE4_EFFORT[5], "J6 {}", limit(5));
        assert!(bom[1].is_none());
    }
}
