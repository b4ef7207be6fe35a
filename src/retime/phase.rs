//! The phase plane (ṡ against s) as TOPP users draw it: the speed-limit curve, each joint's
//! torque-limit curve, the controllable sets' upper edge and the chosen profile.
//!
//! Joint j's torque-limit curve is the highest ṡ at which j's torque range, at the speed the
//! path then runs it (the true envelope, not retime's linear bounds), still leaves a path
//! acceleration s̈ that every other joint's range allows: with
//! U_k(x) = { u : lo_k ≤ a_k u + b_k x + c_k ≤ hi_k }, the largest x with U_j ∩ U_k ≠ ∅ for
//! every k. The lowest of them is the maximum velocity curve of the torque limits (the pair of
//! joints whose ranges part there are the two lowest curves).

use super::Profile;
use super::grid::PathGrid;
use super::limits::Limits;

/// The curves of the phase plane, per grid point s_i (ṡ in path units per second; +∞ where a
/// curve has no bound).
#[derive(Clone, Debug, PartialEq)]
pub struct PhasePlane {
    /// s_i (rad or m of path length).
    pub s: Vec<f64>,
    /// ṡ of the chosen timing.
    pub profile: Vec<f64>,
    /// The highest ṡ the speed limits allow (the lowest over the joints).
    pub speed_limit: Vec<f64>,
    /// Per joint, its torque-limit curve (see the module doc).
    pub torque_limit: Vec<Vec<f64>>,
    /// √ of the controllable sets' upper ends: the fastest ṡ from which the end can still be
    /// reached at rest under retime's bounds.
    pub controllable: Vec<f64>,
}

/// Bisection steps for a torque-limit curve's point (relative precision 2⁻⁶⁰ of the bracket).
const BISECTIONS: usize = 60;
/// Above this x (ṡ²) a curve is taken as unbounded.
const UNBOUNDED: f64 = 1e12;

/// The phase plane of `profile` on `grid` under `limits`, with the controllable sets
/// `controllable` ([lo, hi] of x per point).
pub(crate) fn phase_plane(
    grid: &PathGrid,
    limits: &Limits,
    profile: &Profile,
    controllable: &[[f64; 2]],
) -> PhasePlane {
    let (n, dof) = (grid.points(), grid.dof);
    PhasePlane {
        s: grid.s.clone(),
        profile: profile.x.iter().map(|x| x.sqrt()).collect(),
        speed_limit: (0..n)
            .map(|i| {
                (0..dof)
                    .map(|j| limits.speed[j] / grid.dq[i * dof + j].abs())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect(),
        torque_limit: (0..dof)
            .map(|j| (0..n).map(|i| torque_limit(grid, limits, i, j).sqrt()).collect())
            .collect(),
        controllable: controllable.iter().map(|k| k[1].sqrt()).collect(),
    }
}

/// Joint j's torque-limit x at grid point i (see the module doc).
fn torque_limit(grid: &PathGrid, limits: &Limits, i: usize, j: usize) -> f64 {
    let admissible = |x: f64| {
        let (lo_j, hi_j) = interval(grid, limits, i, j, x);
        (0..grid.dof).all(|k| {
            let (lo_k, hi_k) = interval(grid, limits, i, k, x);
            lo_j.max(lo_k) <= hi_j.min(hi_k)
        })
    };
    if !admissible(0.0) {
        return 0.0;
    }
    let mut hi = 1.0;
    while admissible(hi) {
        if hi > UNBOUNDED {
            return f64::INFINITY;
        }
        hi *= 4.0;
    }
    let mut lo = 0.0;
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        match admissible(mid) {
            true => lo = mid,
            false => hi = mid,
        }
    }
    lo
}

/// U_j(x) at grid point i: the s̈ for which joint j's torque is within its range at x = ṡ².
/// Empty as (+∞, −∞); the whole line when a_j = 0 and the torque is within.
fn interval(grid: &PathGrid, limits: &Limits, i: usize, j: usize, x: f64) -> (f64, f64) {
    let p = i * grid.dof + j;
    let (a, b, c) = (grid.a[p], grid.b[p], grid.c[p]);
    let (lo, hi) = limits.torque[j].range(grid.dq[p] * x.sqrt());
    let rest = b * x + c;
    if a == 0.0 {
        return match lo <= rest && rest <= hi {
            true => (f64::NEG_INFINITY, f64::INFINITY),
            false => (f64::INFINITY, f64::NEG_INFINITY),
        };
    }
    let (u0, u1) = ((lo - rest) / a, (hi - rest) / a);
    (u0.min(u1), u0.max(u1))
}
