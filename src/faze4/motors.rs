//! The Faze4's motors: a NEMA17 stepper behind a reducer at every joint (`--motors faze4`).
//!
//! The seed's torque limits [7.9, 8.5, 4.7, 3.7, 3.5, 6.0] N·m are [`MOTOR_TORQUE`] times
//! [`GEAR_RATIO`], rounded: 70 % of a 0.45 N·m NEMA17's holding torque at the motor. Each rotor,
//! spinning `r` times faster than its joint, adds `r²·I_rotor` to that joint's diagonal of the
//! mass matrix (see [`crate::model::Joint::reflected_inertia`]).

use crate::error::{Error, Result};
use crate::model::Model;

/// Reducer ratio of each joint, J1..J6 (motor turns per joint turn): the Faze4's published
/// ratios.
pub const GEAR_RATIO: [f64; 6] = [25.0, 27.0, 15.0, 11.846, 11.0, 19.19];

/// Torque each motor is driven to (N·m at the motor shaft): 70 % of the 0.45 N·m holding
/// torque of a StepperOnline 17HS16-2004S1 (NEMA17, 40 mm body, 2.0 A).
pub const MOTOR_TORQUE: f64 = 0.315;

/// Rotor inertia of that motor (kg·m² at the motor shaft): its datasheet lists 54 g·cm².
pub const ROTOR_INERTIA: f64 = 54e-7;

/// The motor sets `--motors` knows, by name.
pub const MOTOR_SETS: [&str; 1] = ["faze4"];

/// `model` with the Faze4's motors on its six joints: rotor inertia [`ROTOR_INERTIA`] and
/// ratios [`GEAR_RATIO`]. Fails if the model does not have six joints.
pub fn with_faze4_motors(model: &Model) -> Result<Model> {
    if model.dof() != GEAR_RATIO.len() {
        return Err(Error::argument(
            "--motors",
            format!(
                "faze4's motors are for a 6-joint arm; {} has {} joints",
                model.source,
                model.dof()
            ),
        ));
    }
    let mut model = model.clone();
    for (joint, &ratio) in model.joints.iter_mut().zip(&GEAR_RATIO) {
        joint.rotor_inertia = ROTOR_INERTIA;
        joint.gear_ratio = ratio;
    }
    Ok(model)
}

/// The torque limit each joint gets from its motor (N·m): [`MOTOR_TORQUE`] times the
/// joint's gear ratio, so that changing a ratio changes the limit and the reflected inertia
/// together.
pub fn motor_effort(model: &Model) -> Vec<f64> {
    model.joints.iter().map(|j| MOTOR_TORQUE * j.gear_ratio).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::faze4::EFFORT as FAZE4_EFFORT;

    /// The seed's limits are the motors' torque times the ratios, to their rounding.
    #[test]
    fn the_seed_limits_are_motor_torque_times_ratio() {
        let model = with_faze4_motors(&crate::faze4::model()).unwrap();
        for (e, seed) in motor_effort(&model).iter().zip(FAZE4_EFFORT) {
            assert!((e - seed).abs() <= 0.05, "{e} vs {seed}");
        }
    }

    /// J6's reflected rotor (19.19² · 5.4e-6 ≈ 2.0e-3 kg·m²) dwarfs its link (6.45e-6).
    #[test]
    fn the_rotor_dominates_j6() {
        let arm = crate::faze4::model();
        let mut data = crate::algo::Data::new(&arm);
        let q = [0.0; 6];
        let bare = crate::algo::crba(&arm, &mut data, &q)[(5, 5)];
        let motors = with_faze4_motors(&arm).unwrap();
        let with = crate::algo::crba(&motors, &mut data, &q)[(5, 5)];
        let reflected = GEAR_RATIO[5] * GEAR_RATIO[5] * ROTOR_INERTIA;
        assert!(
            (with - bare - reflected).abs() < 1e-15,
            "{with} − {bare} vs {reflected}"
        );
        assert!(reflected > 200.0 * bare);
    }
}
