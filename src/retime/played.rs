//! The timing as a controller plays it (docs/retime.md, "Between the grid points"): the
//! trajectory written (positions, velocities, accelerations at the grid points) joined as
//! `joint_trajectory_controller` joins it, a quintic per joint between two points, sampled
//! [`SAMPLES`] times per interval; where a sample asks a joint for more speed or torque than
//! its limit less the margin, the x = ṡ² at both ends of that interval is capped and the
//! profile found again.
//!
//! The quintic matches q, q̇ and q̈ at both ends but is not the spline: where s̈ steps between
//! two intervals (TOPP-RA's profile is bang-bang), the quintic blends the two accelerations
//! and its acceleration, and so its torque, overshoots both ends' between them.

use super::Profile;
use super::limits::Limits;
use crate::algo::{Data, rnea};
use crate::model::Model;
use crate::traj::Trajectory;

/// Steps per grid interval at which the played trajectory is checked: each interval at
/// `SAMPLES + 1` evenly spaced times, both ends included.
pub const SAMPLES: usize = 20;

/// Most rounds of capping and solving again before the timing is taken as it is.
pub(crate) const ROUNDS: usize = 200;

/// A sample beyond a limit caps x at this share below the one that would have kept it there.
const HEADROOM: f64 = 0.97;

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
    /// Whether it is a speed (else a torque).
    pub speed: bool,
}

/// What one sample asks of joint j's limits: the share of the speed limit and of the torque
/// range at that speed (the side the torque is on; >1 beyond it), and the share of x to keep
/// there (1 where within).
struct Asked {
    speed: f64,
    torque: f64,
    keep: f64,
}

/// What one played sample asks of joint `j`: its speed `v`, the torque `tau` the motion needs
/// (inverse dynamics), `gravity` the torque at rest at that pose (computed only where `tau`
/// is beyond its range).
fn asked(limits: &Limits, j: usize, v: f64, tau: f64, gravity: impl Fn() -> f64) -> Asked {
    let speed = v.abs() / limits.speed[j];
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
    if !within {
        // the motion's part scales about with x: g + f (τ − g) at the bound
        let g = gravity();
        let f = (bound - g) / (tau - g);
        keep = keep.min(match f > 0.0 && f < 1.0 {
            true => HEADROOM * f,
            false => super::SLOWDOWN,
        });
    }
    Asked { speed, torque, keep }
}

/// Samples `command` [`SAMPLES`] times on each interval of `profile` (times `times`, the
/// trajectory's points) and caps `cap` at both ends of every interval where a sample is
/// beyond a limit. Returns the worst sample and how many points it capped lower.
pub(crate) fn tighten(
    model: &Model,
    limits: &Limits,
    command: &Trajectory,
    times: &[f64],
    profile: &Profile,
    cap: &mut [f64],
) -> (Played, usize) {
    let dof = model.dof();
    let mut data = Data::new(model);
    let (mut q, mut v, mut a) = (vec![0.0; dof], vec![0.0; dof], vec![0.0; dof]);
    let zero = vec![0.0; dof];
    let mut worst = Played {
        worst: 0.0,
        t: 0.0,
        joint: 0,
        speed: false,
    };
    let mut capped = 0;
    for (i, w) in times.windows(2).enumerate() {
        let mut keep: f64 = 1.0;
        for k in 0..=SAMPLES {
            let t = w[0] + (w[1] - w[0]) * k as f64 / SAMPLES as f64;
            command.eval_with_acceleration(t, &mut q, &mut v, &mut a);
            let tau = rnea(model, &mut data, &q, &v, &a).clone();
            for j in 0..dof {
                let gravity = || rnea(model, &mut Data::new(model), &q, &zero, &zero)[j];
                let asked = asked(limits, j, v[j], tau[j], gravity);
                for (share, speed) in [(asked.speed, true), (asked.torque, false)] {
                    if share > worst.worst {
                        worst = Played {
                            worst: share,
                            t,
                            joint: j,
                            speed,
                        };
                    }
                }
                keep = keep.min(asked.keep);
            }
        }
        if keep < 1.0 {
            for p in [i, i + 1] {
                let limit = keep * profile.x[p];
                if limit < cap[p] && profile.x[p] > 0.0 {
                    cap[p] = limit;
                    capped += 1;
                }
            }
        }
    }
    (worst, capped)
}
