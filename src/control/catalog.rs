//! Published figures of the motors the presets use, each with its source (docs/motors.md has
//! the table and the addresses). A figure no source gives is left out, and the doc says so.

use super::motor::{Electrics, Envelope, JointMotor, Motor, StepperLosses, StepperWinding, Stepping};
use super::servo::{Protection, ServoSpec};

/// Points of a preset's pull-out curve (evenly spaced speeds).
pub const CURVE_POINTS: usize = 256;
/// A preset's pull-out curve ends where the model's torque has fallen to this share of its
/// standstill value; past it the envelope is zero.
pub const CURVE_TAIL: f64 = 0.05;

/// StepperOnline 17HS16-2004S1 (NEMA17, 1.8°): 0.45 N·m holding torque, 2.0 A
/// (StepperOnline's listing), 1.1 Ω and 2.6 mH per phase, 50 pole pairs (Source Robotics'
/// STEPFOC "tested motors" table).
pub const NEMA17_17HS16_2004S1: StepperWinding = StepperWinding {
    holding_torque: 0.45,
    rated_current: 2.0,
    resistance: 1.1,
    inductance: 2.6e-3,
    rotor_teeth: 50.0,
};
/// Its rotor inertia, 54 g·cm² (kg·m²; StepperOnline's datasheet).
pub const NEMA17_17HS16_2004S1_ROTOR: f64 = 54e-7;

/// StepperOnline 23HM22-2804S (NEMA23, 0.9°): 1.26 N·m, 2.8 A (StepperOnline's listing, linked
/// from the Faze4 BOM), 1.16 Ω and 4.2 mH per phase, 100 pole pairs (Source Robotics' STEPFOC
/// table).
pub const NEMA23_23HM22_2804S: StepperWinding = StepperWinding {
    holding_torque: 1.26,
    rated_current: 2.8,
    resistance: 1.16,
    inductance: 4.2e-3,
    rotor_teeth: 100.0,
};
/// Its rotor inertia, 300 g·cm² (kg·m²; StepperOnline's datasheet).
pub const NEMA23_23HM22_2804S_ROTOR: f64 = 300e-7;

/// StepperOnline 23HS22-1504S (NEMA23, 1.8°): 1.16 N·m, 1.5 A, 5.4 V (StepperOnline's listing,
/// linked from the Faze4 BOM; R = 5.4 V / 1.5 A = 3.6 Ω), 13 mH per phase (StepperOnline's
/// datasheet as quoted by a public design note), 50 rotor teeth (a 1.8° hybrid).
pub const NEMA23_23HS22_1504S: StepperWinding = StepperWinding {
    holding_torque: 1.16,
    rated_current: 1.5,
    resistance: 3.6,
    inductance: 13e-3,
    rotor_teeth: 50.0,
};

/// Its rotor inertia, 300 g·cm² (kg·m²): StepperOnline publishes none for this motor where it
/// could be opened; the same maker's 56 mm NEMA23 of the stepper-simulator database,
/// 3-23HE22-2804S, has 300 g·cm² (as have LDO's 56 mm 57STH56-2804A): a same-frame proxy.
pub const NEMA23_23HS22_1504S_ROTOR: f64 = 300e-7;

/// StepperOnline 23HS33-4008D (NEMA23, 1.8°, 8 wires, dual shaft): 2.83 N·m at 4.0 A and
/// 2.26 V (its listing's title and the Faze4 BOM), so R = 2.26 V / 4.0 A = 0.565 Ω; 50 rotor
/// teeth (a 1.8° hybrid). Its inductance, 2.8 mH, is a proxy: none was found for this motor;
/// the stepper-simulator database's one NEMA23 of its length and winding, Sanyo Denki's
/// SM2564C40B41 (85.8 mm, 4 A, 0.59 Ω), has 2.8 mH.
pub const NEMA23_23HS33_4008D: StepperWinding = StepperWinding {
    holding_torque: 2.83,
    rated_current: 4.0,
    resistance: 2.26 / 4.0,
    inductance: 2.8e-3,
    rotor_teeth: 50.0,
};
/// Its rotor inertia, 600 g·cm² (kg·m²): the same proxy's (SM2564C40B41), none being found for
/// the 23HS33-4008D itself.
pub const NEMA23_23HS33_4008D_ROTOR: f64 = 600e-7;

/// StepperOnline 14HS13-0804S (NEMA14, 1.8°, the motor of the 14HS13-0804S-PG19): 0.18 N·m,
/// 0.8 A, 6.8 Ω, 10 mH, rotor 14 g·cm² (StepperOnline's figures as tabulated by the public
/// stepper-simulator database), 50 rotor teeth.
pub const NEMA14_14HS13_0804S: StepperWinding = StepperWinding {
    holding_torque: 0.18,
    rated_current: 0.8,
    resistance: 6.8,
    inductance: 10e-3,
    rotor_teeth: 50.0,
};
/// Its rotor inertia, 14 g·cm² (kg·m²; the PG19 gearbox's own inertia is not published).
pub const NEMA14_14HS13_0804S_ROTOR: f64 = 14e-7;

/// One kilogram-force centimetre in N·m.
const KGF_CM: f64 = 9.80665e-2;

/// The current-loop bandwidth taken for a TB6600-class chopper driver (Hz): a stated
/// assumption (docs/motors.md, "The stepper's damping"). The TB6600HG is a PWM constant-current
/// chopper (Toshiba's datasheet) whose loop settles within a few chopping periods; no bandwidth
/// is published. [`CHOPPER_BANDWIDTH_RANGE_HZ`] is the range the verdict's robustness is
/// stated over.
pub const CHOPPER_BANDWIDTH_HZ: f64 = 5_000.0;
/// The range of [`CHOPPER_BANDWIDTH_HZ`] (Hz): a slower loop damps more, a faster one less.
pub const CHOPPER_BANDWIDTH_RANGE_HZ: (f64, f64) = (2_000.0, 20_000.0);

/// The presets' steppers' losses: the driver's current loop at [`CHOPPER_BANDWIDTH_HZ`]; the
/// rotor's iron and bearing losses and the reducers' friction are published for none of them:
/// 0, the model's least damping (a motors file or `rotor_damping`, `reducer_friction` give
/// them).
pub const PRESET_LOSSES: StepperLosses = StepperLosses {
    driver_bandwidth: Some(CHOPPER_BANDWIDTH_HZ),
    rotor_damping: 0.0,
    reducer_damping: 0.0,
    reducer_friction: 0.0,
};

/// A stepper driven at a phase current amplitude of `current` (A) from `supply` (V): its
/// pull-out curve from the model at that current, or at the most its datasheet supports
/// ([`StepperWinding::torque_current_limit`]) when the drive is set above it; its rotor (no
/// detent torque: none of the presets' motors publishes one), its driver's `microsteps` where
/// the build gives them, its winding at the drive's current, its losses [`PRESET_LOSSES`].
pub fn stepper(label: String, winding: &StepperWinding, current: f64, supply: f64, microsteps: Option<u32>) -> Motor {
    let torque_current = current.min(winding.torque_current_limit());
    Motor {
        label,
        envelope: Envelope::Stepper {
            curve: winding.pull_out_curve(torque_current, supply, CURVE_POINTS, CURVE_TAIL),
        },
        efficiency: 1.0,
        continuous_torque: None,
        stepping: Some(Stepping {
            rotor_teeth: winding.rotor_teeth,
            detent_torque: 0.0,
            microsteps,
            losses: PRESET_LOSSES,
        }),
        electrics: Some(Electrics::Stepper {
            winding: *winding,
            current,
            supply,
        }),
        servo: None,
    }
}

/// A servo given at its output (stall torque N·m and no-load speed rad/s at `datasheet_volts`)
/// through a reducer of `ratio`, at `supply` volts: a DC motor's stall torque and no-load speed
/// are both proportional to its voltage (τ_s = K V/R, ω₀ = V/K). Efficiency 1: the output
/// figures already include the gears. `spec`: its own loop and protection at that supply.
fn servo(
    label: &str,
    ratio: f64,
    stall: f64,
    no_load: f64,
    datasheet_volts: f64,
    supply: f64,
    spec: ServoSpec,
) -> JointMotor {
    let scale = supply / datasheet_volts;
    JointMotor {
        gear_ratio: Some(ratio),
        rotor_inertia: None,
        motor: Motor {
            label: format!("{label}, {supply} V"),
            envelope: Envelope::Dc {
                stall_torque: stall * scale / ratio,
                no_load_speed: no_load * scale * ratio,
                peak_torque: stall * scale / ratio,
            },
            efficiency: 1.0,
            continuous_torque: None,
            stepping: None,
            electrics: Some(Electrics::Dc { supply }),
            servo: Some(spec),
        },
    }
}

/// Feetech STS3215, the SO-100's servo (7.4 V version): 19.5 kg·cm stall torque and 0.192 s/60°
/// no-load at 7.4 V, a 1:345 gear train (DFRobot SER0069 listing). Rotor inertia and continuous
/// torque: not published. `supply` (V) scales both figures; `None`: 7.4 V.
pub fn sts3215(supply: Option<f64>) -> JointMotor {
    let v = supply.unwrap_or(7.4);
    let no_load = (std::f64::consts::PI / 3.0) / 0.192;
    servo(
        "Feetech STS3215",
        345.0,
        19.5 * KGF_CM,
        no_load,
        7.4,
        v,
        sts3215_servo(supply),
    )
}

/// ROBOTIS Dynamixel XM540-W270: 10.6 N·m stall torque and 30 rev/min no-load at 12 V, 272.5:1
/// (ROBOTIS e-Manual). `supply` (V) scales both; `None`: 12 V.
pub fn xm540_w270(supply: Option<f64>) -> JointMotor {
    let v = supply.unwrap_or(12.0);
    let no_load = 30.0 * 2.0 * std::f64::consts::PI / 60.0;
    servo(
        "Dynamixel XM540-W270",
        272.5,
        10.6,
        no_load,
        12.0,
        v,
        xm540_w270_servo(supply),
    )
}

/// The duty one unit of an STS servo's P register gives per encoder count of error (k): Feetech
/// publishes no unit, so this is a **stated assumption** (docs/motors.md, "Smart servos"):
/// 4.2e-4, full duty at 149 counts (13°) of error under LeRobot's P 16, stated over half to
/// twice that. Whether a servo holds a load or trips its protection does not depend on it (the
/// steady duty is the load's share of the stall torque; the tests run both ends); its sag does.
/// The D register is taken at the same scale per count per millisecond.
pub const FEETECH_DUTY_PER_COUNT: f64 = 4.2e-4;

/// How long a Dynamixel's output may stay at its PWM limit before its Overload Error shuts it
/// down (s): ROBOTIS' e-Manual (Shutdown(63), bit 5: "persistent load that exceeds maximum
/// output") gives no duration; 1 s is a **stated assumption**.
pub const DYNAMIXEL_OVERLOAD_S: f64 = 1.0;

/// The STS3215's own loop and protection at `supply` volts (`None`: 7.4 V; stall torque and
/// no-load speed as [`sts3215`]'s): the registers as LeRobot's SO-101 follower writes them
/// (`src/lerobot/robots/so_follower/so_follower.py`, `configure`: P_Coefficient 16,
/// I_Coefficient 0, D_Coefficient 32; the arm's joints keep Max_Torque_Limit 1000 ‰), 4096
/// counts a turn; the protection registers at the defaults this model **assumes** for
/// Feetech's STS memory table (no openable primary source found; docs/motors.md):
/// Overload_Torque 80 %, Protection_Time 2.0 s, Protective_Torque 20 %, Protection_Current
/// 500 × 6.5 mA, Over_Current_Protection_Time 2.0 s. The duty scale is
/// [`FEETECH_DUTY_PER_COUNT`], an assumption.
pub fn sts3215_servo(supply: Option<f64>) -> ServoSpec {
    let v = supply.unwrap_or(7.4);
    ServoSpec {
        counts_per_rev: 4096.0,
        p: 16.0,
        d: 32.0,
        i: 0.0,
        duty_per_count: FEETECH_DUTY_PER_COUNT,
        torque_limit: 1.0,
        stall_torque: 19.5 * KGF_CM * v / 7.4,
        no_load_speed: (std::f64::consts::PI / 3.0) / 0.192 * v / 7.4,
        supply: v,
        protection: Protection::Feetech {
            overload: 0.80,
            time: 2.0,
            protective: 0.20,
            current: 500.0 * 6.5e-3,
            current_time: 2.0,
        },
    }
}

/// The XM540-W270's own loop at `supply` volts (`None`: 12 V; its figures as
/// [`xm540_w270`]'s): ROBOTIS e-Manual, XM540-W270 control table: Position P Gain 800, I 0,
/// D 0, K_PP = P/128, the PID's output a PWM value (one unit 0.113 %, PWM Limit 885 = 100 %),
/// 4096 pulses a turn; its Shutdown register's default sets the Overload Error bit, after
/// [`DYNAMIXEL_OVERLOAD_S`] (an assumption). That K_PP·e is in PWM units per pulse is this
/// model's reading of the e-Manual's block diagram.
pub fn xm540_w270_servo(supply: Option<f64>) -> ServoSpec {
    let v = supply.unwrap_or(12.0);
    ServoSpec {
        counts_per_rev: 4096.0,
        p: 800.0,
        d: 0.0,
        i: 0.0,
        duty_per_count: 0.113e-2 / 128.0,
        torque_limit: 1.0,
        stall_torque: 10.6 * v / 12.0,
        no_load_speed: 30.0 * std::f64::consts::TAU / 60.0 * v / 12.0,
        supply: v,
        protection: Protection::Dynamixel {
            time: DYNAMIXEL_OVERLOAD_S,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The servo presets give their datasheet's output figures at the joint.
    #[test]
    fn servos_give_their_output_figures_at_the_joint() {
        let s = sts3215(None);
        let r = s.gear_ratio.unwrap();
        let (_, hi) = s.motor.joint_bounds(r, 0.0);
        assert!((hi - 19.5 * KGF_CM).abs() < 1e-12, "{hi}");
        // zero torque at the no-load output speed, 60° in 0.192 s
        let (_, hi) = s.motor.joint_bounds(r, (std::f64::consts::PI / 3.0) / 0.192);
        assert!(hi.abs() < 1e-12, "{hi}");
        let x = xm540_w270(Some(6.0));
        let (_, hi) = x.motor.joint_bounds(272.5, 0.0);
        assert!((hi - 5.3).abs() < 1e-12, "{hi}");
    }
}
