//! A time-stamped trajectory played as ros2_control's `joint_trajectory_controller` plays it
//! (`joint_trajectory_controller/src/trajectory.cpp`, `Trajectory::sample` and
//! `Trajectory::interpolate_between_points`; docs/trajectories.md).

use serde::Serialize;

use super::{Interpolation, TimedTrajectory};

/// How a time-stamped trajectory is played, as joint_trajectory_controller plays a message it
/// receives (docs/trajectories.md): from the state the arm is in, to the first point at its
/// time, then through the points.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Playback {
    /// How the points are joined (the summary's `interpolation`, beside it).
    #[serde(skip)]
    pub interpolation: Interpolation,
    /// Whether `interpolation` was given (`--interpolation`) rather than chosen by what the
    /// points give.
    pub interpolation_forced: bool,
    /// Where the arm starts, at rest (rad or m per degree of freedom): the start given
    /// (`--start`), else the first point's positions.
    pub start: Vec<f64>,
    /// Whether `start` was given.
    pub start_given: bool,
    /// The first point's time (s): the arm goes from the start to the first point over it
    /// (held there when the start is the first point); 0: no approach.
    pub approach_s: f64,
    /// The trajectory's own points (the approach's start not counted).
    pub points: usize,
}

impl Playback {
    /// Whether the arm starts at rest at [`Playback::start`] rather than in the command's state
    /// at t = 0: with an approach, or a start given (then a first point at t = 0 is a step).
    pub fn starts_at_rest(&self) -> bool {
        self.approach_s > 0.0 || self.start_given
    }
}

/// The points of a [`TimedTrajectory`] joined by polynomials, times shifted so that the first
/// point is at t = 0. Between points i and i + 1, with τ = t − tᵢ and T = tᵢ₊₁ − tᵢ, each joint
/// follows `q(τ) = Σₖ cₖ τᵏ`, the coefficients of `interpolate_between_points`:
///
/// ```text
///   linear:  c₀ = qᵢ, c₁ = (qᵢ₊₁ − qᵢ)/T
///   cubic:   c₀ = qᵢ, c₁ = vᵢ,
///            c₂ = (−3qᵢ + 3qᵢ₊₁ − 2vᵢT − vᵢ₊₁T)/T²,  c₃ = (2qᵢ − 2qᵢ₊₁ + vᵢT + vᵢ₊₁T)/T³
///   quintic: c₀ = qᵢ, c₁ = vᵢ, c₂ = aᵢ/2,
///            c₃ = (−20qᵢ + 20qᵢ₊₁ − 3aᵢT² + aᵢ₊₁T² − 12vᵢT − 8vᵢ₊₁T)/(2T³)
///            c₄ = (30qᵢ − 30qᵢ₊₁ + 3aᵢT² − 2aᵢ₊₁T² + 16vᵢT + 14vᵢ₊₁T)/(2T⁴)
///            c₅ = (−12qᵢ + 12qᵢ₊₁ − aᵢT² + aᵢ₊₁T² − 6vᵢT − 6vᵢ₊₁T)/(2T⁵)
/// ```
///
/// v and a are the polynomial's derivatives (linear: v = c₁, a = 0). Segment i holds
/// tᵢ ≤ t < tᵢ₊₁; from the last point's time on, the command holds its position with zero
/// velocity and acceleration. Each expression is evaluated in the controller's order of
/// operations (powers by repeated products, sums left to right), which
/// `tools/oracle/pin_closed_loop.py` repeats.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    /// Point times from the first (s), `times[0] = 0`, increasing.
    times: Vec<f64>,
    /// Per segment and joint (`segment · joints + joint`), c₀…c₅ (unused ones 0).
    coefficients: Vec<[f64; 6]>,
    /// The last point's positions (rad or m), held after the last time.
    last: Vec<f64>,
    interpolation: Interpolation,
    /// How it is played, when it is a message's playback ([`Spline::played`]).
    playback: Option<Playback>,
}

impl Spline {
    /// The spline through `trajectory`'s points, in its joint order; the trajectory must pass
    /// [`TimedTrajectory::check`] (this panics on no points; one point is held from t = 0).
    pub fn new(trajectory: &TimedTrajectory) -> Spline {
        let points = &trajectory.points;
        assert!(!points.is_empty());
        let n = trajectory.joint_names.len();
        let interpolation = trajectory.interpolation();
        let t0 = points[0].time_from_start;
        let times: Vec<f64> = points.iter().map(|p| p.time_from_start - t0).collect();
        let mut coefficients = Vec::with_capacity((points.len() - 1) * n);
        for (i, pair) in points.windows(2).enumerate() {
            let (a, b) = (&pair[0], &pair[1]);
            let duration = times[i + 1] - times[i];
            for j in 0..n {
                coefficients.push(match interpolation {
                    Interpolation::Linear => linear(a.positions[j], b.positions[j], duration),
                    Interpolation::Cubic => cubic(
                        [a.positions[j], a.velocities[j]],
                        [b.positions[j], b.velocities[j]],
                        duration,
                    ),
                    Interpolation::Quintic => quintic(
                        [a.positions[j], a.velocities[j], a.accelerations[j]],
                        [b.positions[j], b.velocities[j], b.accelerations[j]],
                        duration,
                    ),
                });
            }
        }
        Spline {
            last: points[points.len() - 1].positions.clone(),
            times,
            coefficients,
            interpolation,
            playback: None,
        }
    }

    /// The spline through `trajectory` (its first point at t = 0, the approach's start when
    /// there is one), played as `playback` says: the run starts in the state
    /// [`Spline::start_state`] gives. A trajectory of one point holds it.
    pub fn played(trajectory: &TimedTrajectory, playback: Playback) -> Spline {
        let mut spline = Spline::new(trajectory);
        spline.playback = Some(playback);
        spline
    }

    /// How it is played, when it is a message's playback.
    pub fn playback(&self) -> Option<&Playback> {
        self.playback.as_ref()
    }

    /// The state the run starts in: at rest at the start when the playback says so
    /// ([`Playback::starts_at_rest`]), else the command's own at t = 0.
    pub fn start_state(&self, q: &mut [f64], v: &mut [f64]) {
        match &self.playback {
            Some(p) if p.starts_at_rest() => {
                q.copy_from_slice(&p.start);
                v.fill(0.0);
            }
            _ => self.eval(0.0, q, v),
        }
    }

    /// Number of joints commanded.
    pub fn columns(&self) -> usize {
        self.last.len()
    }

    /// The last point's time from the first (s): the run's default duration.
    pub fn duration(&self) -> f64 {
        self.times[self.times.len() - 1]
    }

    /// The last point at or before time `t` (s) and its time (the first before it, the last
    /// after the end).
    pub fn frame(&self, t: f64) -> (u64, f64) {
        let i = self.times.partition_point(|&ti| ti <= t).saturating_sub(1);
        (i as u64, self.times[i])
    }

    /// How the points are joined.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// q_cmd(t) into `q`, v_cmd(t) into `v`.
    #[inline]
    pub fn eval(&self, t: f64, q: &mut [f64], v: &mut [f64]) {
        self.eval_into(t, q, v, None);
    }

    /// q_cmd(t), v_cmd(t) and a_cmd(t).
    #[inline]
    pub fn eval_with_acceleration(&self, t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) {
        self.eval_into(t, q, v, Some(a));
    }

    #[inline]
    fn eval_into(&self, t: f64, q: &mut [f64], v: &mut [f64], mut acc: Option<&mut [f64]>) {
        let n = self.last.len();
        // after the last point: hold it
        if t >= self.duration() {
            q.copy_from_slice(&self.last);
            v.fill(0.0);
            if let Some(acc) = acc {
                acc.fill(0.0);
            }
            return;
        }
        // the segment i with times[i] ≤ t < times[i + 1] (segment 0 before the start)
        let i = self.times.partition_point(|&ti| ti <= t).saturating_sub(1);
        let tau = t - self.times[i];
        // powers as generate_powers makes them: p[k] = p[k − 1]·τ
        let p1 = 1.0 * tau;
        let p2 = p1 * tau;
        let p3 = p2 * tau;
        let p4 = p3 * tau;
        let coefficients = &self.coefficients[i * n..(i + 1) * n];
        for (j, c) in coefficients.iter().enumerate() {
            let (qj, vj, aj) = match self.interpolation {
                Interpolation::Linear => (1.0 * c[0] + p1 * c[1], 1.0 * c[1], 0.0),
                Interpolation::Cubic => (
                    1.0 * c[0] + p1 * c[1] + p2 * c[2] + p3 * c[3],
                    1.0 * c[1] + p1 * 2.0 * c[2] + p2 * 3.0 * c[3],
                    1.0 * 2.0 * c[2] + p1 * 6.0 * c[3],
                ),
                Interpolation::Quintic => (
                    1.0 * c[0] + p1 * c[1] + p2 * c[2] + p3 * c[3] + p4 * c[4] + p4 * tau * c[5],
                    1.0 * c[1] + p1 * 2.0 * c[2] + p2 * 3.0 * c[3] + p3 * 4.0 * c[4] + p4 * 5.0 * c[5],
                    1.0 * 2.0 * c[2] + p1 * 6.0 * c[3] + p2 * 12.0 * c[4] + p3 * 20.0 * c[5],
                ),
            };
            q[j] = qj;
            v[j] = vj;
            if let Some(acc) = acc.as_deref_mut() {
                acc[j] = aj;
            }
        }
    }
}

/// Powers of T as `generate_powers` makes them: `[1, T, T², T³, T⁴, T⁵]`.
fn powers(duration: f64) -> [f64; 6] {
    let mut p = [1.0; 6];
    for k in 1..6 {
        p[k] = p[k - 1] * duration;
    }
    p
}

/// `interpolate_between_points`' linear coefficients.
fn linear(start: f64, end: f64, duration: f64) -> [f64; 6] {
    [start, (end - start) / duration, 0.0, 0.0, 0.0, 0.0]
}

/// Its cubic coefficients from `[q, v]` at both ends.
fn cubic([sp, sv]: [f64; 2], [ep, ev]: [f64; 2], duration: f64) -> [f64; 6] {
    let t = powers(duration);
    [
        sp,
        sv,
        (-3.0 * sp + 3.0 * ep - 2.0 * sv * t[1] - ev * t[1]) / t[2],
        (2.0 * sp - 2.0 * ep + sv * t[1] + ev * t[1]) / t[3],
        0.0,
        0.0,
    ]
}

/// Its quintic coefficients from `[q, v, a]` at both ends.
fn quintic([sp, sv, sa]: [f64; 3], [ep, ev, ea]: [f64; 3], duration: f64) -> [f64; 6] {
    let t = powers(duration);
    [
        sp,
        sv,
        0.5 * sa,
        (-20.0 * sp + 20.0 * ep - 3.0 * sa * t[2] + ea * t[2] - 12.0 * sv * t[1] - 8.0 * ev * t[1]) / (2.0 * t[3]),
        (30.0 * sp - 30.0 * ep + 3.0 * sa * t[2] - 2.0 * ea * t[2] + 16.0 * sv * t[1] + 14.0 * ev * t[1])
            / (2.0 * t[4]),
        (-12.0 * sp + 12.0 * ep - sa * t[2] + ea * t[2] - 6.0 * sv * t[1] - 6.0 * ev * t[1]) / (2.0 * t[5]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::TrajectoryPoint;

    fn trajectory(v: bool, a: bool) -> TimedTrajectory {
        let point = |t: f64, q: f64, qd: f64, qdd: f64| TrajectoryPoint {
            time_from_start: t,
            positions: vec![q, -q],
            velocities: if v { vec![qd, -qd] } else { Vec::new() },
            accelerations: if a { vec![qdd, -qdd] } else { Vec::new() },
        };
        TimedTrajectory {
            joint_names: vec!["a".into(), "b".into()],
            points: vec![
                point(2.0, 0.5, 0.0, 0.0),
                point(2.5, 1.0, 2.0, -1.0),
                point(3.25, 0.0, 0.0, 0.0),
            ],
        }
    }

    fn at(s: &Spline, t: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let (mut q, mut v, mut a) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        s.eval_with_acceleration(t, &mut q, &mut v, &mut a);
        (q, v, a)
    }

    #[test]
    fn points_are_met_with_what_they_give() {
        for (v, a) in [(false, false), (true, false), (true, true)] {
            let s = Spline::new(&trajectory(v, a));
            assert_eq!(s.duration(), 1.25);
            let (q, qd, qdd) = at(&s, 0.5);
            assert!((q[0] - 1.0).abs() < 1e-15 && q[1] == -q[0], "{v} {a}: {q:?}");
            if v {
                assert!((qd[0] - 2.0).abs() < 1e-12, "{qd:?}");
            }
            if a {
                assert!((qdd[0] + 1.0).abs() < 1e-12, "{qdd:?}");
            }
            assert_eq!(at(&s, 0.0).0, [0.5, -0.5]);
            // held after the last point
            assert_eq!(at(&s, 1.25), ([0.0, -0.0], [0.0; 2], [0.0; 2]));
            assert_eq!(at(&s, 9.0).1, [0.0; 2]);
        }
    }

    #[test]
    fn linear_steps_the_velocity_and_derivatives_match() {
        let s = Spline::new(&trajectory(false, false));
        assert_eq!(at(&s, 0.25).1, [1.0, -1.0]);
        assert_eq!(at(&s, 0.75).1[0], -1.0 / 0.75);
        assert_eq!(at(&s, 0.75).2, [0.0; 2]);
        // v and a are q's derivatives (central differences)
        for s in [
            Spline::new(&trajectory(true, false)),
            Spline::new(&trajectory(true, true)),
        ] {
            let h = 1e-6;
            for t in [0.1, 0.3, 0.6, 1.1] {
                let (q0, v0, a0) = at(&s, t);
                let (qm, vm, _) = at(&s, t - h);
                let (qp, vp, _) = at(&s, t + h);
                assert!(((qp[0] - qm[0]) / (2.0 * h) - v0[0]).abs() < 1e-6, "t {t}");
                assert!(((vp[0] - vm[0]) / (2.0 * h) - a0[0]).abs() < 1e-5, "t {t}");
                assert!(q0[0].is_finite());
            }
        }
    }
}
