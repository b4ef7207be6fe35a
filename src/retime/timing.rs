//! From the profile on the grid to times and joint values: the path played with s̈ constant on
//! each grid interval (TOPP-RA's own reading of its profile, toppra's `ParametrizeConstAccel`).
//!
//! On [s_i, s_i+1] with x_i = ṡ_i², u_i = s̈:
//!
//! ```text
//!   t_{i+1} − t_i = 2Δ_i / (√x_i + √x_{i+1}),     s(t) = s_i + ṡ_i τ + u_i τ²/2   (τ = t − t_i)
//!   q̇ = q'(s) ṡ,     q̈ = q'(s) s̈ + q''(s) ṡ²
//! ```

use super::Profile;
use super::spline::PathSpline;
use crate::traj::{TimedTrajectory, TrajectoryPoint};

impl Profile {
    /// The timing with squared path speeds `x` (≥ 0, 0 at both ends) at the grid points `s`
    /// (increasing): s̈ = (x_{i+1} − x_i)/(2Δ_i) on each interval, and the times. A profile
    /// that another retimer found on the same grid, read as retime reads its own.
    pub fn from_x(s: Vec<f64>, x: Vec<f64>) -> Profile {
        let n = s.len();
        let mut u = vec![0.0; n.saturating_sub(1)];
        let mut t = vec![0.0; n];
        for i in 0..n.saturating_sub(1) {
            let delta = s[i + 1] - s[i];
            u[i] = (x[i + 1] - x[i]) / (2.0 * delta);
            t[i + 1] = t[i] + 2.0 * delta / (x[i].max(0.0).sqrt() + x[i + 1].max(0.0).sqrt());
        }
        let sdd = (0..n).map(|i| u[i.min(n.saturating_sub(2))]).collect();
        Profile { s, x, u, t, sdd }
    }

    /// The duration of the timing (s).
    pub fn duration(&self) -> f64 {
        self.t.last().copied().unwrap_or(0.0)
    }

    /// s, ṡ, s̈ at time `t` (s), clamped into [0, duration]: s̈ is the interval's u (at a grid
    /// point, the interval that starts there).
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let t = t.clamp(0.0, self.duration());
        let i = self.interval_at(t);
        self.within(i, t - self.t[i])
    }

    /// s, ṡ, s̈ at `tau` seconds into interval `i`.
    #[inline]
    fn within(&self, i: usize, tau: f64) -> (f64, f64, f64) {
        let (sd, u) = (self.x[i].sqrt(), self.u[i]);
        let s = (self.s[i] + sd * tau + 0.5 * u * tau * tau).min(self.s[i + 1]);
        (s, (sd + u * tau).max(0.0), u)
    }

    /// The interval holding time `t` (s), the last one from the duration on.
    pub fn interval_at(&self, t: f64) -> usize {
        (self.t.partition_point(|&ti| ti <= t).max(1) - 1).min(self.u.len() - 1)
    }
}

/// The timing at its grid points as a trajectory of `joint_names`, as a controller is given it
/// and `faze4 replay` plays it (a quintic between the points): positions q(s_i), velocities
/// q'(s_i) ṡ_i and accelerations q'(s_i) s̈ + q''(s_i) ṡ_i², with s̈ at a point that of the
/// interval starting there in TOPP-RA's own profile, [`Profile::sdd`]). Times are rounded to whole nanoseconds, as the ROS formats
/// hold them, so the file written plays what the check played.
pub fn timed_trajectory(profile: &Profile, spline: &PathSpline, joint_names: Vec<String>) -> TimedTrajectory {
    let dof = spline.dof();
    let n = profile.x.len();
    let (mut q, mut dq, mut ddq) = (vec![0.0; dof], vec![0.0; dof], vec![0.0; dof]);
    let points = (0..n)
        .map(|i| {
            spline.eval(profile.s[i], &mut q, &mut dq, &mut ddq);
            let (x, sd, sdd) = (profile.x[i], profile.x[i].sqrt(), profile.sdd[i]);
            TrajectoryPoint {
                time_from_start: profile.t[i],
                positions: q.clone(),
                velocities: dq.iter().map(|d| d * sd).collect(),
                accelerations: dq.iter().zip(&ddq).map(|(d1, d2)| d1 * sdd + d2 * x).collect(),
            }
        })
        .collect();
    let mut trajectory = TimedTrajectory { joint_names, points };
    trajectory.round_times_to_nanoseconds();
    trajectory
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile() -> Profile {
        // s̈ = 2 then −2 over s in [0, 2]: ṡ² = 4s, then 4(2 − s)
        let s = vec![0.0, 0.5, 1.0, 1.5, 2.0];
        let x: Vec<f64> = s.iter().map(|&s: &f64| 4.0 * s.min(2.0 - s)).collect();
        let u = vec![2.0, 2.0, -2.0, -2.0];
        let mut t = vec![0.0; 5];
        for i in 0..4 {
            t[i + 1] = t[i] + 2.0 * 0.5 / (f64::sqrt(x[i]) + f64::sqrt(x[i + 1]));
        }
        let sdd = vec![2.0, 2.0, -2.0, -2.0, -2.0];
        Profile { s, x, u, t, sdd }
    }

    /// Constant s̈ = ±2 from rest over s = 1 then back to rest: 1 s each way, s(t) = t².
    #[test]
    fn constant_acceleration_reads_as_the_closed_form() {
        let p = profile();
        assert!((p.duration() - 2.0).abs() < 1e-15, "{}", p.duration());
        let (s, sd, sdd) = p.at(0.5);
        assert!((s - 0.25).abs() < 1e-15 && (sd - 1.0).abs() < 1e-15 && sdd == 2.0);
        let (s, sd, _) = p.at(1.5);
        assert!((s - 1.75).abs() < 1e-14 && (sd - 1.0).abs() < 1e-14, "{s} {sd}");
        assert_eq!(p.at(5.0).0, 2.0);
    }
}
