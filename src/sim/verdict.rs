//! The answer to the question a run is for: can the arm follow its command?
//!
//! A run follows when it did not diverge, no joint saturates more than
//! [`Thresholds::max_saturation_pct`] of the steps, every joint's tracking error stays within
//! [`Thresholds::max_error`] (rad, or m for a prismatic joint) and, for shapes, the tool's path
//! deviation stays within [`Thresholds::max_deviation_mm`], and no joint exceeds its speed limit
//! (where it has one). Each figure beyond its threshold is a [`Reason`], naming the joint and the
//! figure.
//!
//! A run whose collision geometry intersects itself at any trail sample *collides*
//! ([`Reason::Collides`], first among the reasons, naming the pairs and when each first
//! intersected): it does not follow either, whatever its other figures; the verdict line reads
//! `verdict: collides — …`, followed by `; cannot follow — …` when other figures are beyond
//! their thresholds too.

use std::fmt;

use serde::{Serialize, Serializer};

use super::check::non_negative;
use super::{DriveMode, MotorSummary, ROBUST_DAMPING_RATIO, Ringing, SlipMargin, StepLoss, Summary};
use crate::choice::Choice;
use crate::control::{Trip, TripKind};
use crate::error::quoted;
use crate::model::JointId;

/// The limits a run must stay within to follow its command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    /// Largest share of steps a joint may saturate (%), 5 by default.
    pub max_saturation_pct: f64,
    /// Largest tracking error |q_cmd − q| of any joint (rad, or m for a prismatic joint), 0.05
    /// by default.
    pub max_error: f64,
    /// Largest distance of the tool from a shape's path (mm), 5 by default.
    pub max_deviation_mm: f64,
}

impl Thresholds {
    /// Checks each limit is finite and ≥ 0, naming its field.
    pub fn check(&self) -> crate::Result<()> {
        non_negative("max_saturation_pct", self.max_saturation_pct)?;
        non_negative("max_error", self.max_error)?;
        non_negative("max_deviation_mm", self.max_deviation_mm)
    }
}

impl Thresholds {
    /// The defaults: 5 % saturation, 0.05 rad (or m), 5 mm.
    pub const DEFAULT: Thresholds = Thresholds {
        max_saturation_pct: 5.0,
        max_error: 0.05,
        max_deviation_mm: 5.0,
    };
}

impl Default for Thresholds {
    fn default() -> Self {
        Thresholds::DEFAULT
    }
}

/// A checked pair of links that intersected during a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Intersection {
    /// The two URDF link names.
    pub links: [String; 2],
    /// Simulated time of the first trail sample at which they intersect (s).
    pub from_t: f64,
}

/// How many intersecting pairs the verdict names (the summary's `"clearance"` has them all).
const INTERSECTIONS_NAMED: usize = 3;

/// Why a run cannot follow its command.
#[derive(Clone, Debug, PartialEq)]
pub enum Reason {
    /// The collision geometry intersects itself: these pairs, in the order they first did.
    Collides {
        /// The intersecting pairs (at least one).
        pairs: Vec<Intersection>,
    },
    /// The loop went unstable at time `t` (s) on joint `joint`.
    Diverged {
        /// Simulated time (s).
        t: f64,
        /// The joint.
        joint: JointId,
    },
    /// A joint's torque reached its limit in more than the allowed share of the steps.
    Saturates {
        /// The joint.
        joint: JointId,
        /// Its share of saturated steps (%).
        pct: f64,
        /// The allowed share (%).
        limit: f64,
    },
    /// A joint's tracking error went beyond the allowed error.
    TrackingError {
        /// The joint.
        joint: JointId,
        /// Its largest |q_cmd − q| (rad or m).
        error: f64,
        /// The allowed error (rad or m).
        limit: f64,
        /// Whether the joint is prismatic (the figures are metres).
        prismatic: bool,
    },
    /// A joint moved faster than its speed limit in some of the steps.
    OverSpeed {
        /// The joint.
        joint: JointId,
        /// Its fastest speed (rad/s or m/s).
        max_speed: f64,
        /// Its speed limit (rad/s or m/s).
        limit: f64,
        /// Its share of steps above the limit (%).
        pct: f64,
    },
    /// A joint asked its motor for more than its envelope gave at its speed in more than the
    /// allowed share of the steps.
    EnvelopeSaturates {
        /// The joint.
        joint: JointId,
        /// Its share of steps beyond the envelope (%).
        pct: f64,
        /// The allowed share (%).
        limit: f64,
    },
    /// A joint's stepper was asked for more than its pull-out torque: it loses steps.
    LosesSteps {
        /// The joint.
        joint: JointId,
        /// Where and by how much.
        loss: StepLoss,
    },
    /// A joint's stepper, driven open loop (`--drive stepper`), slipped: its rotor fell past
    /// the torque–angle curve to another stable point, whole electrical cycles away.
    Slips {
        /// The joint.
        joint: JointId,
        /// The first slip (s).
        t: f64,
        /// Full steps the rotor ends off its command (a multiple of 4).
        steps_lost: u64,
        /// The offset the slips left at the joint, actual − commanded (rad or m).
        position_lost: f64,
        /// Whether the joint is prismatic (the offset is metres).
        prismatic: bool,
        /// How its rotor rang, and whether the slip survives more damping.
        ringing: Option<Ringing>,
    },
    /// A joint's smart servo (`--drive servo`) tripped its protection.
    ServoTrips {
        /// The joint.
        joint: JointId,
        /// When, which protection, at what torque and for how long.
        trip: Trip,
        /// The duty a Feetech servo is held to after its overload protection (share).
        protective: Option<f64>,
    },
    /// A joint's motor ran at an RMS torque above its continuous rating.
    Overheats {
        /// The joint.
        joint: JointId,
        /// Its RMS torque (N·m at the shaft).
        rms: f64,
        /// Its continuous rating (N·m).
        continuous: f64,
    },
    /// The tool left the shape's path by more than allowed.
    PathDeviation {
        /// The largest distance (mm).
        max_mm: f64,
        /// The allowed distance (mm).
        limit: f64,
    },
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Reason::Collides { ref pairs } => {
                let named: Vec<String> = (pairs.iter().take(INTERSECTIONS_NAMED))
                    .map(|p| {
                        format!(
                            "{}–{} intersect from t = {:.2} s",
                            quoted(&p.links[0]),
                            quoted(&p.links[1]),
                            p.from_t
                        )
                    })
                    .collect();
                write!(f, "{}", named.join(", "))?;
                match pairs.len().saturating_sub(INTERSECTIONS_NAMED) {
                    0 => Ok(()),
                    more => write!(f, " (and {more} more pairs)"),
                }
            }
            Reason::Diverged { t, joint } => write!(f, "the loop diverged at t = {t:.4} s on {joint}"),
            Reason::Saturates { joint, pct, limit } => {
                write!(f, "{joint} saturates {} of the steps (limit {limit} %)", percent(pct))
            }
            Reason::TrackingError {
                joint,
                error,
                limit,
                prismatic,
            } => {
                let unit = if prismatic { "m" } else { "rad" };
                // three decimals, unless they would not tell the error from its limit
                let shown = format!("{error:.3}");
                let shown = match shown.parse::<f64>().is_ok_and(|x| x > limit) {
                    true => shown,
                    false => format!("{error:.3e}"),
                };
                write!(f, "{joint} tracking error {shown} {unit} (limit {limit} {unit})")
            }
            Reason::OverSpeed {
                joint,
                max_speed,
                limit,
                pct,
            } => write!(
                f,
                "{joint} exceeds its speed limit {limit} in {} of the steps (up to {max_speed:.3})",
                percent(pct)
            ),
            Reason::EnvelopeSaturates { joint, pct, limit } => write!(
                f,
                "{joint} asks its motor for more than its torque–speed envelope in {} of the steps (limit {limit} %)",
                percent(pct)
            ),
            Reason::LosesSteps { joint, loss } => {
                // four decimals, unless they would show the need as nothing or equal to the
                // curve (a supply of 1e-300 V gives 1e-300 N·m)
                let (needs, gives) = (format!("{:.4}", loss.needs), format!("{:.4}", loss.gives));
                let (needs, gives) = match needs != gives && needs.parse::<f64>().is_ok_and(|x| x > 0.0) {
                    true => (needs, gives),
                    false => (scientific(loss.needs), scientific(loss.gives)),
                };
                write!(
                    f,
                    "{joint}'s stepper loses steps at t = {:.2} s: it needs {needs} N·m at {:.0} rad/s, {} more than its curve gives ({gives})",
                    loss.t,
                    loss.speed,
                    excess(loss.needs, loss.gives),
                )
            }
            Reason::Slips {
                joint,
                t,
                steps_lost,
                position_lost,
                prismatic,
                ringing,
            } => {
                let unit = if prismatic { "m" } else { "rad" };
                write!(f, "{joint}'s stepper slips at t = {t:.3} s")?;
                match steps_lost {
                    0 => write!(f, " and slips back: it ends on its command")?,
                    n => write!(
                        f,
                        ": {n} full steps lost, the joint off by {position_lost:.5} {unit} from then on"
                    )?,
                }
                match ringing.and_then(|r| r.slips_below.map(|m| (r, m))) {
                    Some((r, SlipMargin::Robust)) => write!(
                        f,
                        " (robust: it slips with its damping ratio {} raised to {ROBUST_DAMPING_RATIO})",
                        ratio(r.damping_ratio)
                    ),
                    Some((r, SlipMargin::Below(below))) => write!(
                        f,
                        " (marginal: it rings near its {:.0} Hz resonance, and slips only if its damping ratio is below {}; the model's is {})",
                        r.natural_hz,
                        ratio(below),
                        ratio(r.damping_ratio)
                    ),
                    None => Ok(()),
                }
            }
            Reason::ServoTrips {
                joint,
                trip,
                protective,
            } => {
                match trip.kind {
                    TripKind::Overload => write!(
                        f,
                        "{joint}'s servo trips its overload protection at t = {:.2} s: {:.2} N·m for {:.1} s",
                        trip.t, trip.torque, trip.duration
                    )?,
                    TripKind::OverCurrent => write!(
                        f,
                        "{joint}'s servo trips its over-current protection at t = {:.2} s: {:.2} N·m for {:.1} s, its output off",
                        trip.t, trip.torque, trip.duration
                    )?,
                    TripKind::Shutdown => write!(
                        f,
                        "{joint}'s servo shuts down on overload at t = {:.2} s: {:.2} N·m at its limit for {:.1} s, its torque off until a reboot",
                        trip.t, trip.torque, trip.duration
                    )?,
                }
                if let (TripKind::Overload, Some(p)) = (trip.kind, protective) {
                    write!(f, ", then held to {:.0} % of its stall torque", 100.0 * p)?;
                }
                write!(f, " (its protection registers assumed)")
            }
            Reason::Overheats { joint, rms, continuous } => write!(
                f,
                "{joint}'s motor runs at {rms:.3} N·m RMS, above its continuous {continuous} N·m"
            ),
            Reason::PathDeviation { max_mm, limit } => {
                write!(f, "path deviation {max_mm:.1} mm (limit {limit} mm)")
            }
        }
    }
}

impl Serialize for Reason {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// A damping ratio for people: three decimals (`0.031`), two significant digits below 0.01
/// (`0.0025`).
fn ratio(zeta: f64) -> String {
    match zeta >= 0.01 {
        true => format!("{zeta:.3}"),
        false => format!("{zeta:.2e}"),
    }
}

/// An open-loop stepper that followed but came near a slip: it rang past its torque–angle
/// curve's peak, and slips with less damping (the verdict's `marginal`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearSlip {
    /// The joint.
    pub joint: JointId,
    /// How its rotor rang; its `slips_below` is a ratio.
    pub ringing: Ringing,
}

impl fmt::Display for NearSlip {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.ringing;
        write!(
            f,
            "{}'s stepper rings near its {:.0} Hz resonance, up to {:.2} full steps off its microstep (it slips at 2)",
            self.joint, r.natural_hz, r.max_lag_steps
        )?;
        if let Some(SlipMargin::Below(below)) = r.slips_below {
            write!(
                f,
                ", and slips if its damping ratio is below {}; the model's is {}",
                ratio(below),
                ratio(r.damping_ratio)
            )?;
        }
        Ok(())
    }
}

impl Serialize for NearSlip {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// Four significant digits in scientific notation (`4.237e-7`); a zero is `0`.
fn scientific(x: f64) -> String {
    match x == 0.0 {
        true => "0".into(),
        false => format!("{x:.3e}"),
    }
}

/// How much more `needs` is than `gives`, in percent for people (`0.05 %`, scientific past
/// 10⁶ %), or `all of it` where the curve gives nothing.
fn excess(needs: f64, gives: f64) -> String {
    let pct = 100.0 * (needs - gives) / gives;
    if gives > 0.0 && pct < 1e6 {
        format!("{pct:.2} %")
    } else if gives > 0.0 {
        format!("{pct:.2e} %")
    } else {
        "all of it".into()
    }
}

/// A share in percent for people: `0 %`, `< 0.01 %`, `0.52 %`, `99.0 %`.
pub fn percent(pct: f64) -> String {
    if pct == 0.0 {
        "0 %".into()
    } else if pct < 0.01 {
        "< 0.01 %".into()
    } else if pct < 10.0 {
        format!("{pct:.2} %")
    } else {
        format!("{pct:.1} %")
    }
}

/// Whether the arm follows its command, and if not, why.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Verdict {
    /// True when no reason was found.
    pub follows: bool,
    /// True when the collision geometry intersects itself ([`Reason::Collides`] is among the
    /// reasons).
    pub collides: bool,
    /// Every figure beyond its threshold (empty when the arm follows).
    pub reasons: Vec<Reason>,
    /// The open-loop steppers that did not slip but came near, and would with less damping.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub marginal: Vec<NearSlip>,
}

impl Verdict {
    /// The verdict on `summary` under `thresholds`; `prismatic[i]` says joint i is prismatic.
    pub fn judge(summary: &Summary, thresholds: &Thresholds, prismatic: &[bool]) -> Verdict {
        let mut reasons = Vec::new();
        if let Some(d) = &summary.diverged {
            reasons.push(Reason::Diverged { t: d.t, joint: d.joint });
        }
        for (joint, &pct) in JointId::all(summary.dof).zip(&summary.saturation_pct) {
            if pct > thresholds.max_saturation_pct {
                reasons.push(Reason::Saturates {
                    joint,
                    pct,
                    limit: thresholds.max_saturation_pct,
                });
            }
        }
        for (joint, &error) in JointId::all(summary.dof).zip(&summary.max_tracking_error_rad) {
            if error > thresholds.max_error || error.is_nan() {
                reasons.push(Reason::TrackingError {
                    joint,
                    error,
                    limit: thresholds.max_error,
                    prismatic: prismatic.get(joint.0).copied().unwrap_or(false),
                });
            }
        }
        let over_speed = JointId::all(summary.dof).zip(&summary.velocity_limit_pct);
        for (joint, pct) in over_speed.filter_map(|(j, p)| p.filter(|&p| p > 0.0).map(|p| (j, p))) {
            reasons.push(Reason::OverSpeed {
                joint,
                max_speed: summary.max_speed[joint.0],
                limit: summary.velocity_limit[joint.0],
                pct,
            });
        }
        for (joint, m) in (JointId::all(summary.dof).zip(summary.motors.iter().flatten()))
            .filter_map(|(j, m)| m.as_ref().map(|m| (j, m)))
        {
            motor_reasons(joint, m, thresholds, prismatic, &mut reasons);
        }
        if let Some(d) = &summary.path_deviation_mm
            && (d.max > thresholds.max_deviation_mm || d.max.is_nan())
        {
            reasons.push(Reason::PathDeviation {
                max_mm: d.max,
                limit: thresholds.max_deviation_mm,
            });
        }
        let marginal = near_slips(summary);
        Verdict {
            follows: reasons.is_empty(),
            collides: false,
            reasons,
            marginal,
        }
    }

    /// This verdict with the pairs that intersected (none: unchanged): the run collides, and
    /// so does not follow; [`Reason::Collides`] goes first.
    pub fn with_intersections(mut self, pairs: Vec<Intersection>) -> Verdict {
        if !pairs.is_empty() {
            self.reasons.insert(0, Reason::Collides { pairs });
            self.follows = false;
            self.collides = true;
        }
        self
    }
}

/// The reasons joint `joint`'s motor `m` gives not to follow, appended to `reasons`: a PD's
/// demand beyond the envelope too often, a stepper's step loss or slip, a servo's trip, an RMS
/// torque over the continuous rating.
fn motor_reasons(
    joint: JointId,
    m: &MotorSummary,
    thresholds: &Thresholds,
    prismatic: &[bool],
    reasons: &mut Vec<Reason>,
) {
    // an open-loop stepper asks for nothing: its slips are the reason, not a demand
    if m.drive == DriveMode::Pd.word() && m.envelope_pct > thresholds.max_saturation_pct {
        reasons.push(Reason::EnvelopeSaturates {
            joint,
            pct: m.envelope_pct,
            limit: thresholds.max_saturation_pct,
        });
    }
    if let Some(loss) = m.step_loss {
        reasons.push(Reason::LosesSteps { joint, loss });
    }
    if let (Some(Some(t)), Some(steps_lost), Some(position_lost)) = (m.loses_steps_at, m.steps_lost, m.position_lost) {
        reasons.push(Reason::Slips {
            joint,
            t,
            steps_lost,
            position_lost,
            prismatic: prismatic.get(joint.0).copied().unwrap_or(false),
            ringing: m.ringing,
        });
    }
    if let Some((trip, servo)) = m.servo.and_then(|s| Some((s.trip?, s))) {
        reasons.push(Reason::ServoTrips {
            joint,
            trip,
            protective: servo.protective,
        });
    }
    if let Some(continuous) = m.continuous_torque.filter(|&c| m.rms_torque > c) {
        reasons.push(Reason::Overheats {
            joint,
            rms: m.rms_torque,
            continuous,
        });
    }
}

/// The open-loop steppers of `summary` that did not slip but would with less damping.
fn near_slips(summary: &Summary) -> Vec<NearSlip> {
    (JointId::all(summary.dof).zip(summary.motors.iter().flatten()))
        .filter_map(|(joint, m)| {
            let m = m.as_ref()?;
            let ringing = m
                .ringing
                .filter(|r| matches!(r.slips_below, Some(SlipMargin::Below(_))))?;
            m.loses_steps_at
                .flatten()
                .is_none()
                .then_some(NearSlip { joint, ringing })
        })
        .collect()
}

impl fmt::Display for Verdict {
    /// One line: `verdict: follows`; `verdict: collides — ` and the intersecting pairs (then
    /// `; cannot follow — ` and any other reasons); or `verdict: cannot follow — ` and the
    /// reasons.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.follows {
            write!(f, "verdict: follows")?;
        } else {
            let (collides, others): (Vec<&Reason>, Vec<&Reason>) =
                (self.reasons.iter()).partition(|r| matches!(r, Reason::Collides { .. }));
            let others: Vec<String> = others.iter().map(|r| r.to_string()).collect();
            match collides.first() {
                Some(c) if others.is_empty() => write!(f, "verdict: collides — {c}")?,
                Some(c) => write!(f, "verdict: collides — {c}; cannot follow — {}", others.join("; "))?,
                None => write!(f, "verdict: cannot follow — {}", others.join("; "))?,
            }
        }
        if !self.marginal.is_empty() {
            let near: Vec<String> = self.marginal.iter().map(|m| m.to_string()).collect();
            write!(f, "; marginal — {}", near.join("; "))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Diverged, PathDeviation};

    fn summary(saturation: [f64; 2], error: [f64; 2], deviation: Option<f64>) -> Summary {
        Summary {
            dof: 2,
            saturation_pct: saturation.to_vec(),
            max_tracking_error_rad: error.to_vec(),
            path_deviation_mm: deviation.map(|max| PathDeviation { max, mean: max / 2.0 }),
            ..Summary::default()
        }
    }

    #[test]
    fn each_threshold_is_a_reason_and_only_beyond_it() {
        let t = Thresholds::default();
        let at_limits = summary([5.0, 0.0], [0.05, 0.0], Some(5.0));
        assert_eq!(
            Verdict::judge(&at_limits, &t, &[false; 2]).to_string(),
            "verdict: follows"
        );
        let beyond = summary([0.0, 99.04], [0.31, 0.001], Some(564.2));
        let v = Verdict::judge(&beyond, &t, &[false, true]);
        assert!(!v.follows);
        assert_eq!(
            v.to_string(),
            "verdict: cannot follow — J2 saturates 99.0 % of the steps (limit 5 %); J1 tracking error 0.310 rad (limit 0.05 rad); path deviation 564.2 mm (limit 5 mm)"
        );
        let strict = Thresholds {
            max_saturation_pct: 1.0,
            max_error: 0.0005,
            max_deviation_mm: 0.1,
        };
        let v = Verdict::judge(&summary([0.0, 0.0], [0.0, 0.001], None), &strict, &[false, true]);
        assert_eq!(v.reasons.len(), 1);
        assert!(v.to_string().contains("J2 tracking error 0.001 m"), "{v}");
    }

    /// A lost step is shown with the digits that tell the need from the curve: a supply of
    /// 1e-300 V printed "needs 0.0000 N·m … gives (0.0000)".
    #[test]
    fn a_lost_step_shows_its_need_and_its_curve_apart() {
        let lost = |needs: f64, gives: f64| {
            Reason::LosesSteps {
                joint: JointId(0),
                loss: crate::sim::StepLoss {
                    t: 0.0,
                    needs,
                    speed: 5.0,
                    gives,
                },
            }
            .to_string()
        };
        assert!(
            lost(4.237e-7, 0.0).contains("it needs 4.237e-7 N·m at 5 rad/s, all of it more than its curve gives (0)")
        );
        assert_eq!(
            lost(0.1068, 0.0),
            "J1's stepper loses steps at t = 0.00 s: it needs 0.1068 N·m at 5 rad/s, all of it more than its curve gives (0.0000)"
        );
        assert!(
            lost(1.2e-5, 3e-301)
                .contains("it needs 1.200e-5 N·m at 5 rad/s, 4.00e297 % more than its curve gives (3.000e-301)"),
            "{}",
            lost(1.2e-5, 3e-301)
        );
        assert!(
            lost(0.50004, 0.50001)
                .contains("needs 5.000e-1 N·m at 5 rad/s, 0.01 % more than its curve gives (5.000e-1)"),
            "{}",
            lost(0.50004, 0.50001)
        );
    }

    #[test]
    fn a_diverged_run_never_follows() {
        let mut s = summary([0.0, 0.0], [0.0, 0.0], None);
        s.diverged = Some(Diverged {
            t: 0.0016,
            joint: JointId(1),
            stiffness_b: vec![0.4, 0.4],
        });
        let v = Verdict::judge(&s, &Thresholds::default(), &[false; 2]);
        assert_eq!(
            v.to_string(),
            "verdict: cannot follow — the loop diverged at t = 0.0016 s on J2"
        );
        assert_eq!(
            serde_json::to_value(&v).unwrap(),
            serde_json::json!({"follows": false, "collides": false, "reasons": ["the loop diverged at t = 0.0016 s on J2"]})
        );
    }

    #[test]
    fn a_joint_over_its_speed_limit_cannot_follow() {
        let mut s = summary([0.0, 0.0], [0.0, 0.0], None);
        s.max_speed = vec![1.0, 3.5];
        s.velocity_limit = vec![f64::INFINITY, 3.0];
        s.velocity_limit_pct = vec![None, Some(2.5)];
        let v = Verdict::judge(&s, &Thresholds::default(), &[false; 2]);
        assert_eq!(
            v.to_string(),
            "verdict: cannot follow — J2 exceeds its speed limit 3 in 2.50 % of the steps (up to 3.500)"
        );
        s.velocity_limit_pct = vec![None, Some(0.0)];
        assert!(Verdict::judge(&s, &Thresholds::default(), &[false; 2]).follows);
    }

    #[test]
    fn an_intersection_collides_first_and_never_follows() {
        let pair = |a: &str, b: &str, from_t| Intersection {
            links: [a.into(), b.into()],
            from_t,
        };
        let clean = summary([0.0, 0.0], [0.0, 0.0], None);
        let follows = Verdict::judge(&clean, &Thresholds::default(), &[false; 2]);
        assert_eq!(follows.clone().with_intersections(Vec::new()), follows);
        let v = follows.with_intersections(vec![pair("nadlaktica", "podlaktica", 0.0)]);
        assert!(!v.follows && v.collides);
        assert_eq!(
            v.to_string(),
            "verdict: collides — 'nadlaktica'–'podlaktica' intersect from t = 0.00 s"
        );
        assert_eq!(
            serde_json::to_value(&v).unwrap(),
            serde_json::json!({"follows": false, "collides": true, "reasons": ["'nadlaktica'–'podlaktica' intersect from t = 0.00 s"]})
        );
        let saturated = summary([0.0, 99.04], [0.0, 0.0], None);
        let pairs = ["a", "b", "c", "d", "e"].map(|x| pair(x, "z", 1.5)).to_vec();
        let v = Verdict::judge(&saturated, &Thresholds::default(), &[false; 2]).with_intersections(pairs);
        assert_eq!(
            v.to_string(),
            "verdict: collides — 'a'–'z' intersect from t = 1.50 s, 'b'–'z' intersect from t = 1.50 s, 'c'–'z' intersect from t = 1.50 s (and 2 more pairs); cannot follow — J2 saturates 99.0 % of the steps (limit 5 %)"
        );
    }

    #[test]
    fn percentages_read_as_percentages() {
        assert_eq!(percent(0.0), "0 %");
        assert_eq!(percent(0.0067), "< 0.01 %");
        assert_eq!(percent(0.52), "0.52 %");
        assert_eq!(percent(99.04), "99.0 %");
    }
}
