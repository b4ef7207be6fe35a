//! The timing as a controller plays it (docs/retime.md, "Between the grid points"): the
//! trajectory written (positions, velocities, accelerations at the grid points) joined as
//! `joint_trajectory_controller` joins it, a quintic per joint between two points, sampled
//! [`SAMPLES`] times per interval: the most it asks of a speed, torque, acceleration or jerk
//! limit, and per interval the share of x = ṡ² that would have kept them.
//!
//! The quintic matches q, q̇ and q̈ at both ends but is not the path: where s̈ steps between
//! two intervals (TOPP-RA's profile is bang-bang), the quintic blends the two accelerations
//! and its acceleration, and so its torque, overshoots both ends' between them; retime's
//! smooth timing (`smooth.rs`) has no such step.

use super::limits::Limits;
use crate::algo::{Data, gravity, rnea};
use crate::model::Model;
use crate::traj::Trajectory;

/// Steps per grid interval at which the played trajectory is checked: each interval at
/// `SAMPLES + 1` evenly spaced times, both ends included.
pub const SAMPLES: usize = 20;

/// Most rounds of capping and solving again before the timing is taken as it is.
pub(crate) const ROUNDS: usize = 200;

/// A sample beyond a limit caps x at this share below the one that would have kept it there.
const HEADROOM: f64 = 0.97;

/// The lowest share of x one round keeps: where the estimate asks for less (a torque range
/// nearly empty at the played speed, so the motion's part would have to vanish), the next
/// round's sampling says how much more.
const FLOOR: f64 = 0.5;

/// Where a sample asks the most of a limit in a played timing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Played {
    /// The largest share of a limit (speed, or torque range less the margin) the played
    /// trajectory asks at any sample: ≤ 1 where every limit is kept.
    pub worst: f64,
    /// The time of that sample (s).
    pub t: f64,
    /// Its joint.
    pub joint: usize,
    /// Which limit: `speed`, `torque`, `acceleration` or `jerk`.
    pub limit: &'static str,
}

/// What one sample asks of joint j's limits: the share of each (speed, torque range at that
/// speed on the side the torque is on, acceleration, jerk; >1 beyond it), and the share of x
/// to keep there (1 where within).
struct Asked {
    shares: [(f64, &'static str); 4],
    keep: f64,
}

/// What one played sample asks of joint `j`: its speed, acceleration and jerk `[v, a, jerk]`,
/// the torque `tau` the motion needs (inverse dynamics), `gravity` the torque at rest at that
/// pose (computed only where `tau` is beyond its range).
fn asked(limits: &Limits, j: usize, [v, a, jerk]: [f64; 3], tau: f64, gravity: impl FnOnce() -> f64) -> Asked {
    let speed = v.abs() / limits.speed[j];
    let acceleration = a.abs() / limits.acceleration[j];
    let jerk = jerk.abs() / limits.jerk[j];
    let (lo, hi) = limits.torque[j].range(v);
    let (bound, torque) = match tau >= 0.0 {
        true => (hi, if hi > 0.0 { tau / hi } else { f64::INFINITY }),
        false => (lo, if lo < 0.0 { tau / lo } else { f64::INFINITY }),
    };
    let within = tau >= lo && tau <= hi;
    let torque = match within && !torque.is_finite() {
        true => 1.0,
        false => torque,
    };
    let mut keep: f64 = 1.0;
    if speed > 1.0 {
        keep = keep.min(HEADROOM / (speed * speed));
    }
    // an acceleration scales about with x, a jerk with ṡ³
    if acceleration > 1.0 {
        keep = keep.min(HEADROOM / acceleration);
    }
    if jerk > 1.0 {
        keep = keep.min(HEADROOM * jerk.powf(-2.0 / 3.0));
    }
    if !within {
        // the motion's part scales about with x: g + f (τ − g) at the bound
        let g = gravity();
        let f = (bound - g) / (tau - g);
        keep = keep.min(match f > 0.0 && f < 1.0 {
            true => HEADROOM * f,
            false => super::SLOWDOWN,
        });
    }
    Asked {
        keep: keep.max(FLOOR),
        shares: [
            (speed, "speed"),
            (torque, "torque"),
            (acceleration, "acceleration"),
            (jerk, "jerk"),
        ],
    }
}

/// A jerk is taken by central differences of the quintic's acceleration over this share of
/// the interval (a cubic: exact but for round-off).
const JERK_STEP: f64 = 1e-4;

/// Samples `command` [`SAMPLES`] times on each interval between `times` (the trajectory's
/// points) and writes into `keep` (one per interval) the share of x = ṡ² that would have kept
/// every limit there (1 where every sample is within). Returns the worst sample, and the most
/// asked of a jerk limit (0 where none is given).
pub(crate) fn sample(
    model: &Model,
    limits: &Limits,
    command: &Trajectory,
    times: &[f64],
    keep: &mut [f64],
) -> (Played, f64) {
    let dof = model.dof();
    // workspaces, made once: the motion's torque at a sample, and the torque at rest at its
    // pose (computed at most once a sample, where a joint's torque is beyond its range)
    let (mut data, mut still) = (Data::new(model), Data::new(model));
    let (mut tau, mut at_rest) = (vec![0.0; dof], vec![0.0; dof]);
    let (mut q, mut v, mut a) = (vec![0.0; dof], vec![0.0; dof], vec![0.0; dof]);
    let (mut a_plus, mut a_minus) = (vec![0.0; dof], vec![0.0; dof]);
    let (mut q_near, mut v_near) = (vec![0.0; dof], vec![0.0; dof]);
    let jerk_limited = limits.jerk.iter().any(|j| j.is_finite());
    let mut worst = Played {
        worst: 0.0,
        t: 0.0,
        joint: 0,
        limit: "speed",
    };
    let mut most_jerk: f64 = 0.0;
    for (i, w) in times.windows(2).enumerate() {
        keep[i] = 1.0;
        let dt = w[1] - w[0];
        for k in 0..=SAMPLES {
            let t = w[0] + dt * k as f64 / SAMPLES as f64;
            command.eval_with_acceleration(t, &mut q, &mut v, &mut a);
            if jerk_limited {
                // within the interval's own quintic (the last one's end excluded: from there the
                // command holds the last point, its acceleration 0, which a moving end's is not)
                let h = JERK_STEP * dt;
                let end = match i + 2 == times.len() {
                    true => 2.0 * h,
                    false => h,
                };
                let at = t.clamp(w[0] + h, w[1] - end);
                command.eval_with_acceleration(at + h, &mut q_near, &mut v_near, &mut a_plus);
                command.eval_with_acceleration(at - h, &mut q_near, &mut v_near, &mut a_minus);
            }
            tau.copy_from_slice(rnea(model, &mut data, &q, &v, &a).as_slice());
            let mut at_rest_known = false;
            for j in 0..dof {
                let resting = || {
                    if !at_rest_known {
                        at_rest.copy_from_slice(gravity(model, &mut still, &q).as_slice());
                        at_rest_known = true;
                    }
                    at_rest[j]
                };
                let jerk = match jerk_limited {
                    true => (a_plus[j] - a_minus[j]) / (2.0 * JERK_STEP * dt),
                    false => 0.0,
                };
                let asked = asked(limits, j, [v[j], a[j], jerk], tau[j], resting);
                most_jerk = most_jerk.max(asked.shares[3].0);
                for (share, limit) in asked.shares {
                    if share > worst.worst {
                        worst = Played {
                            worst: share,
                            t,
                            joint: j,
                            limit,
                        };
                    }
                }
                keep[i] = keep[i].min(asked.keep);
            }
        }
    }
    (worst, most_jerk)
}
