//! Whether an open-loop stepper's slip survives the uncertainty of its damping (docs/motors.md,
//! "Robust and marginal slips"): the run again with the joint's damping changed.
//!
//! A stepper's damping is partly sourced (the joint's own, its driver's current loop on the
//! winding) and partly not (the rotor's iron losses, the reducer's friction: published for none
//! of the Faze4's motors). A slip that comes from the load (the curve cannot carry it) stays
//! whatever the damping; one that comes from the rotor ringing at its resonance goes once the
//! ringing is damped enough. So for each joint that slipped, the run is made again with that
//! joint's damping ratio raised to [`ROBUST_DAMPING_RATIO`]: if it still slips the slip is
//! robust; if not, the least damping ratio that keeps it from slipping is bisected between the
//! model's and that one, and the verdict says the slip is marginal: it happens only below that
//! ratio. A stepper that did not slip but rang past its curve's peak is tried the other way:
//! the damping ratio below which it would slip, and the verdict says it follows, marginally.

use super::{Scenario, Summary};

/// The damping ratio a slip must survive to be called robust: a rotor whose ringing falls to a
/// half in 1.1 periods (e^(−2π·0.1) = 0.53 a period), more than the sourced damping gives any
/// of the Faze4's steppers (docs/motors.md).
pub const ROBUST_DAMPING_RATIO: f64 = 0.1;

/// Bisections of the damping ratio between the model's and [`ROBUST_DAMPING_RATIO`] (in its
/// logarithm: the threshold to about 3 %).
const BISECTIONS: usize = 6;

/// The factor below the model's damping ratio down to which a stepper that did not slip but
/// rang past its curve's peak is tried: a rotor that still holds at a quarter of its damping is
/// not near a slip.
const HOLDS_FACTOR: f64 = 0.25;

/// Where an open-loop stepper's slip begins, as its damping ratio goes down (in the summary's
/// JSON `"robust"` or the ratio).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SlipMargin {
    /// It slips even with its damping ratio at [`ROBUST_DAMPING_RATIO`]: the slip is robust.
    Robust,
    /// It slips only with a damping ratio below this one.
    Below(f64),
}

/// For each open-loop stepper of `sc` that slipped in `summary` (its `loses_steps_at`), or that
/// did not but rang past its torque–angle curve's peak (a lag over one full step): where its
/// slip begins as the damping goes down, or `None` (for a joint that neither slipped nor came
/// near, or that holds down to [`HOLDS_FACTOR`] of its damping). Each probe is the run again
/// with joint i's damping set, without recorders or self-clearance, made by `run_again` (the
/// closed loop's own run, given by its caller so that this file stays below it).
pub fn margins(
    sc: &Scenario,
    summary: &Summary,
    run_again: impl Fn(&Scenario) -> Option<Summary>,
) -> Vec<Option<SlipMargin>> {
    let n = sc.model.dof();
    let Some(motors) = &summary.motors else {
        return vec![None; n];
    };
    (0..n)
        .map(|i| {
            let drive = sc.drives.get(i)?.stepper()?;
            let m = motors.get(i)?.as_ref()?;
            let slipped = m.loses_steps_at.flatten().is_some();
            let near = m.ringing.is_some_and(|r| r.max_lag_steps > 1.0);
            let zeta = drive.damping.ratio;
            let slips = |ratio: f64| slips_with(sc, i, drive.damping.critical * ratio, &run_again);
            let (lo, hi) = match (slipped, near) {
                (true, _) if zeta >= ROBUST_DAMPING_RATIO || slips(ROBUST_DAMPING_RATIO) => {
                    return Some(SlipMargin::Robust);
                }
                (true, _) => (zeta, ROBUST_DAMPING_RATIO),
                (false, true) if !slips(HOLDS_FACTOR * zeta) => return None,
                (false, true) => (HOLDS_FACTOR * zeta, zeta),
                (false, false) => return None,
            };
            let (mut lo, mut hi) = (lo.ln(), hi.ln());
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (lo + hi);
                match slips(mid.exp()) {
                    true => lo = mid,
                    false => hi = mid,
                }
            }
            Some(SlipMargin::Below(hi.exp()))
        })
        .collect()
}

/// Whether joint `i`'s stepper slips when the joint's damping is `damping` (N·m·s/rad).
fn slips_with(sc: &Scenario, i: usize, damping: f64, run_again: impl Fn(&Scenario) -> Option<Summary>) -> bool {
    let mut probe = sc.clone();
    probe.slip_margins = false;
    probe.model.joints[i].damping = damping;
    if probe.self_contact.is_none() {
        probe.collision_set = None;
        probe.path_clearance = None;
    }
    let Some(summary) = run_again(&probe) else {
        return true;
    };
    let motor = summary.motors.as_ref().and_then(|m| m[i].as_ref());
    motor.is_some_and(|m| m.loses_steps_at.flatten().is_some())
}

impl serde::Serialize for SlipMargin {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            SlipMargin::Robust => s.serialize_str("robust"),
            SlipMargin::Below(ratio) => s.serialize_f64(ratio),
        }
    }
}
