//! The stepper kind: an open-loop stepper's pull-out curve, `|τ_m| ≤ curve(|ω_m|)` (linear
//! between the points, zero past the last; above it the stepper loses steps), and its
//! `[[joint]]` fields: the curve and, for the open-loop drive, its rotor, driver and losses
//! (docs/motors.md).

use serde::Deserialize;

use super::{Envelope, Kind, KindMotor, fields_of, read_as};

/// What an open-loop drive needs of a stepper beyond its pull-out curve (docs/motors.md,
/// "The open-loop stepper drive").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stepping {
    /// Rotor teeth N_r: 50 for a 1.8° motor, 100 for 0.9° (a full step is 2π/(4·N_r) rad).
    pub rotor_teeth: f64,
    /// Detent torque T_d (N·m at the shaft, ≥ 0; 0 where none is published): the unpowered
    /// rotor's cogging, one period per full step.
    pub detent_torque: f64,
    /// Microsteps per full step the driver is set to, where the build says (`None`: the
    /// default of [`crate::control::DEFAULT_MICROSTEPS`] unless `--microsteps` gives one).
    pub microsteps: Option<u32>,
    /// What damps its rotor besides the joint's own damping (docs/motors.md, "The stepper's
    /// damping").
    pub losses: StepperLosses,
}

/// What damps an open-loop stepper's rotor, at the motor shaft (docs/motors.md, "The stepper's
/// damping"): the driver's current loop (with the winding behind [`crate::control::Electrics::Stepper`], the
/// electrical damping), the rotor's own viscous losses and the reducer's friction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepperLosses {
    /// The driver's current-loop bandwidth f_c (Hz, > 0): the phase current follows its
    /// reference as a first-order loop of this bandwidth, so the back-EMF leaves a current that
    /// brakes the rotor. `None`: no electrical damping (an ideal current source, or a winding
    /// not known).
    pub driver_bandwidth: Option<f64>,
    /// The rotor's viscous damping b_r (N·m·s/rad at the shaft, ≥ 0): iron losses and
    /// bearings.
    pub rotor_damping: f64,
    /// The reducer's viscous friction b_g (N·m·s/rad at the shaft, ≥ 0).
    pub reducer_damping: f64,
    /// The reducer's Coulomb friction T_c (N·m at the shaft, ≥ 0).
    pub reducer_friction: f64,
}

impl StepperLosses {
    /// Whether each figure is finite and ≥ 0 (the bandwidth > 0); the error names the field.
    pub fn check(&self) -> Result<(), String> {
        if let Some(f) = self.driver_bandwidth
            && !(f.is_finite() && f > 0.0)
        {
            return Err(format!("driver_bandwidth {f} must be > 0"));
        }
        for (name, x) in [
            ("rotor_damping", self.rotor_damping),
            ("reducer_damping", self.reducer_damping),
            ("reducer_friction", self.reducer_friction),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!("{name} {x} must be ≥ 0"));
            }
        }
        Ok(())
    }
}

impl Stepping {
    /// A 1.8° or 0.9° step angle (degrees) as rotor teeth, N_r = 90° / step angle.
    pub fn rotor_teeth_of(step_angle_deg: f64) -> f64 {
        90.0 / step_angle_deg
    }
}

/// The smallest full step a file's stepper may have (degrees): 900 rotor teeth, where the
/// finest hybrid steppers have 100 (0.9°) to 250 (0.36°).
pub const MIN_STEP_ANGLE_DEG: f64 = 0.1;

/// The kind's registration ([`super::KINDS`]).
pub(super) const KIND: Kind = Kind {
    name: "stepper",
    fields: fields_of::<File>,
    read,
    types: |value| read_as::<File>(value).map(drop),
    has_no,
};

/// What the motor plot says of a stepper's missing continuous line.
pub(super) const NO_CONTINUOUS: &str =
    "no continuous line: a constant-current driver heats a stepper alike at any torque";

/// A `kind = "stepper"` entry's own fields.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    /// The pull-out curve: points `[speed rad/s, torque N·m]`, read as lists so that a point
    /// of another length is refused (an array `[f64; 2]` took the first two values of
    /// `[0.0, 0.3, 7]` and dropped the third).
    curve: Option<Vec<Vec<f64>>>,
    /// The full step (degrees, in [[`MIN_STEP_ANGLE_DEG`], 90]), for the open-loop drive.
    step_angle: Option<f64>,
    /// The unpowered detent torque (N·m, ≥ 0; default 0).
    detent_torque: Option<f64>,
    /// The driver's microsteps per full step (≥ 1; default the drive's).
    microsteps: Option<u32>,
    /// The driver's current-loop bandwidth (Hz, > 0; default none: no electrical damping,
    /// which needs the winding a file does not give).
    driver_bandwidth: Option<f64>,
    /// The rotor's viscous damping, iron losses and bearings (N·m·s/rad at the shaft, ≥ 0;
    /// default 0).
    rotor_damping: Option<f64>,
    /// The reducer's viscous friction (N·m·s/rad at the motor shaft, ≥ 0; default 0).
    reducer_damping: Option<f64>,
    /// The reducer's Coulomb friction (N·m at the motor shaft, ≥ 0; default 0).
    reducer_friction: Option<f64>,
}

/// The entry's fields as a pull-out curve and, where it gives a step angle, the rotor, driver
/// and losses of the open-loop drive.
fn read(value: serde_json::Value) -> Result<KindMotor, String> {
    let file: File = read_as(value)?;
    let curve = file.curve.as_ref().ok_or("kind \"stepper\" needs curve")?;
    let points = curve.iter().enumerate().map(|(k, p)| match p[..] {
        [speed, torque] => Ok([speed, torque]),
        _ => Err(format!(
            "curve point {} has {} values ({p:?}); a point is [speed rad/s, torque N·m]",
            k + 1,
            p.len()
        )),
    });
    let envelope = Envelope::Stepper {
        curve: points.collect::<Result<_, _>>()?,
    };
    let drive_figures = file.detent_torque.is_some()
        || file.microsteps.is_some()
        || [
            file.driver_bandwidth,
            file.rotor_damping,
            file.reducer_damping,
            file.reducer_friction,
        ]
        .iter()
        .any(Option::is_some);
    let stepping = match file.step_angle {
        Some(a) if !(a.is_finite() && (MIN_STEP_ANGLE_DEG..=90.0).contains(&a)) => {
            return Err(format!(
                "step_angle {} must be in [{MIN_STEP_ANGLE_DEG}, 90] degrees (a hybrid stepper has 90°/step angle rotor teeth: 1.8° has 50, 0.9° 100)",
                crate::error::shortest(a)
            ));
        }
        Some(a) => Some(Stepping {
            rotor_teeth: Stepping::rotor_teeth_of(a),
            detent_torque: file.detent_torque.unwrap_or(0.0),
            microsteps: file.microsteps,
            losses: StepperLosses {
                driver_bandwidth: file.driver_bandwidth,
                rotor_damping: file.rotor_damping.unwrap_or(0.0),
                reducer_damping: file.reducer_damping.unwrap_or(0.0),
                reducer_friction: file.reducer_friction.unwrap_or(0.0),
            },
        }),
        None if drive_figures => {
            return Err(
                "detent_torque, microsteps, driver_bandwidth, rotor_damping and reducer_damping/friction need the stepper's step_angle".into(),
            );
        }
        None => None,
    };
    if let Some(t) = file.detent_torque.filter(|t| !(t.is_finite() && *t >= 0.0)) {
        return Err(format!("detent_torque {t} must be ≥ 0"));
    }
    if file.microsteps == Some(0) {
        return Err("microsteps 0 must be ≥ 1".into());
    }
    Ok((envelope, stepping))
}

/// The words for another kind's `field` on a stepper.
fn has_no(_field: &str) -> String {
    "a stepper has a curve, not stall_torque, no_load_speed or peak_torque".into()
}

/// The torque range at shaft speed `omega`: symmetric, the curve at |ω|.
#[inline]
pub(super) fn bounds(curve: &[[f64; 2]], omega: f64) -> (f64, f64) {
    let t = pull_out(curve, omega.abs());
    (-t, t)
}

/// The curve's largest torque.
pub(super) fn max_torque(curve: &[[f64; 2]]) -> f64 {
    curve.iter().map(|p| p[1]).fold(0.0, f64::max)
}

/// The curve's speeds on either side (unsorted).
pub(super) fn kinks(curve: &[[f64; 2]]) -> Vec<f64> {
    curve.iter().flat_map(|p| [p[0], -p[0]]).collect()
}

/// The last point's speed (past it the envelope is zero).
pub(super) fn top_speed(curve: &[[f64; 2]]) -> f64 {
    curve.last().map_or(0.0, |p| p[0])
}

/// The curve's torque at speed `w` ≥ 0: linear between the points, the first point's torque
/// below it, zero past the last.
#[inline]
fn pull_out(curve: &[[f64; 2]], w: f64) -> f64 {
    let Some(last) = curve.last() else { return 0.0 };
    if w > last[0] {
        return 0.0;
    }
    if w <= curve[0][0] {
        return curve[0][1];
    }
    // the segment [k−1, k] holding w: the first point at or past w (speeds ascend)
    let k = curve.partition_point(|p| p[0] < w);
    let ([w0, t0], [w1, t1]) = (curve[k - 1], curve[k]);
    if w == w1 {
        return t1;
    }
    t0 + (t1 - t0) * (w - w0) / (w1 - w0)
}

/// At least two points, the first at ω = 0, each finite with its torque ≥ 0, speeds
/// ascending.
pub(super) fn check(curve: &[[f64; 2]]) -> Result<(), String> {
    let Some(first) = curve.first() else {
        return Err("curve has no points".into());
    };
    // the envelope is zero past the last point: one point gives torque at standstill only
    if curve.len() < 2 {
        return Err(format!(
            "curve has one point ({:?}): it would give no torque at any speed above 0 (the curve is zero past its last point); give at least two",
            first
        ));
    }
    if first[0] != 0.0 {
        return Err(format!(
            "curve starts at {} rad/s; its first point must be at 0",
            first[0]
        ));
    }
    for p in curve {
        if !(p[0].is_finite() && p[1].is_finite() && p[1] >= 0.0) {
            return Err(format!(
                "curve point [{}, {}] must be finite, its torque ≥ 0",
                p[0], p[1]
            ));
        }
    }
    if let Some(w) = curve.windows(2).find(|w| w[1][0] <= w[0][0]) {
        return Err(format!("curve speeds must ascend ({} then {})", w[0][0], w[1][0]));
    }
    Ok(())
}
