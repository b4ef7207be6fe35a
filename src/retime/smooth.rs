//! A timing whose s̈ is continuous (docs/retime.md, "Smooth ends and jerk"): TOPP-RA's
//! profile s(t) (bang-bang in s̈) averaged over a moving window of `w` seconds,
//!
//! ```text
//!   s_w(t) = (1/w) ∫_{t−w}^{t} s(τ) dτ      (s = 0 before the start, L after the end)
//!   ṡ_w(t) = (s(t) − s(t−w)) / w,   s̈_w(t) = (ṡ(t) − ṡ(t−w)) / w,   s⃛_w(t) = (s̈(t) − s̈(t−w)) / w
//! ```
//!
//! Where the profile starts (ends) at a path speed ṡ₀ > 0 (ṡ_N), s(t) is continued before 0
//! (after T) at that speed, s = ṡ₀ t (L + ṡ_N (t − T)), and the timing written is s_w from
//! where it reaches 0 to where it reaches L; when the profile holds ṡ₀ over its first ṡ₀·w/2
//! of path (the solver's `hold`), that is t = w/2, where s_w = 0, ṡ_w = ṡ₀ and s̈_w = 0 exactly
//! (likewise T + w/2 at the end: docs/retime.md, "Chaining segments").
//!
//! s_w runs from rest with s̈ = 0 at t = 0 to rest with s̈ = 0 at T + w; its ṡ and s̈ are
//! averages of TOPP-RA's over the window (so within their ranges), s̈ is continuous (ṡ is), and
//! |s⃛| ≤ (max s̈ − min s̈)/w. On a rest-to-rest move at a speed and acceleration limit (a
//! trapezoid in ṡ) it is the time-optimal jerk-limited profile (Ruckig's) for the jerk
//! A/w, at its duration T + A/J.

use super::Profile;

/// TOPP-RA's profile with the integral of s at each grid time, for the window's average.
pub(crate) struct Averaged<'a> {
    raw: &'a Profile,
    /// ∫₀^{t_i} s dτ at each grid time.
    integral: Vec<f64>,
    /// The window (s), > 0.
    w: f64,
}

/// s, ṡ and ∫s of a profile at a time.
#[derive(Clone, Copy)]
struct State {
    integral: f64,
    s: f64,
    sd: f64,
}

impl<'a> Averaged<'a> {
    /// `raw` (s̈ constant on each interval) averaged over `w` seconds (> 0).
    pub fn new(raw: &'a Profile, w: f64) -> Self {
        let mut integral = vec![0.0; raw.t.len()];
        for i in 0..raw.u.len() {
            let tau = raw.t[i + 1] - raw.t[i];
            let (sd, u) = (raw.x[i].sqrt(), raw.u[i]);
            integral[i + 1] = integral[i] + raw.s[i] * tau + sd * tau * tau / 2.0 + u * tau.powi(3) / 6.0;
        }
        Averaged { raw, integral, w }
    }

    /// The raw profile's state at `t` (any real: before 0 and after its end at its first and
    /// last path speed, 0 when it starts or ends at rest).
    fn raw_at(&self, t: f64) -> State {
        let p = self.raw;
        let end = p.duration();
        let length = *p.s.last().unwrap_or(&0.0);
        if t <= 0.0 {
            let sd = p.x[0].sqrt();
            return State {
                integral: sd * t * t / 2.0,
                s: sd * t,
                sd,
            };
        }
        if t >= end {
            let (sd, tau) = (p.x[p.x.len() - 1].sqrt(), t - end);
            return State {
                integral: self.integral[p.t.len() - 1] + length * tau + sd * tau * tau / 2.0,
                s: length + sd * tau,
                sd,
            };
        }
        let i = p.interval_at(t);
        let tau = t - p.t[i];
        let (sd, u) = (p.x[i].sqrt(), p.u[i]);
        State {
            integral: self.integral[i] + p.s[i] * tau + sd * tau * tau / 2.0 + u * tau.powi(3) / 6.0,
            s: p.s[i] + sd * tau + u * tau * tau / 2.0,
            sd: (sd + u * tau).max(0.0),
        }
    }

    /// s_w, ṡ_w and s̈_w at `t`.
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let (now, before) = (self.raw_at(t), self.raw_at(t - self.w));
        (
            (now.integral - before.integral) / self.w,
            (now.s - before.s) / self.w,
            (now.sd - before.sd) / self.w,
        )
    }

    /// The time (s, on the raw profile's clock) where s_w reaches `s`, searched from `*lo` (by
    /// bisection: s_w increases), which is left at the bracket's last lower end (where the next
    /// point's search starts).
    fn reaching(&self, s: f64, lo: &mut f64) -> f64 {
        let mut hi = self.raw.duration() + self.w;
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (*lo + hi);
            match self.at(mid).0 < s {
                true => *lo = mid,
                false => hi = mid,
            }
        }
        0.5 * (*lo + hi)
    }

    /// Where the timing written starts on the raw profile's clock (s): 0 from rest, else
    /// where s_w reaches 0 (w/2 when the start's speed is held over ṡ₀·w/2 of path).
    pub fn offset(&self) -> f64 {
        match self.raw.x[0] > 0.0 {
            true => self.reaching(0.0, &mut 0.0),
            false => 0.0,
        }
    }

    /// The averaged timing on the raw profile's grid, from [`Averaged::offset`] on (its
    /// clock's 0): each grid point's time (s_w(t_i) = s_i, by bisection: s_w increases),
    /// x = ṡ_w² and s̈_w there; at an end at rest, 0 and 0.
    pub fn profile(&self) -> Profile {
        let p = self.raw;
        let n = p.s.len();
        let last = n - 1;
        let mut t = vec![0.0; n];
        t[0] = self.offset();
        t[last] = match p.x[last] > 0.0 {
            true => self.reaching(p.s[last], &mut t[0].clone()),
            false => p.duration() + self.w,
        };
        let mut lo = t[0];
        for i in 1..last {
            t[i] = self.reaching(p.s[i], &mut lo);
        }
        let (mut x, mut sdd) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            if (i == 0 && p.x[0] == 0.0) || (i == last && p.x[last] == 0.0) {
                continue;
            }
            let (_, sd, a) = self.at(t[i]);
            (x[i], sdd[i]) = (sd * sd, a);
        }
        let start = t[0];
        t.iter_mut().for_each(|t| *t -= start);
        let u = (0..n - 1)
            .map(|i| (x[i + 1] - x[i]) / (2.0 * (p.s[i + 1] - p.s[i])))
            .collect();
        Profile {
            s: p.s.clone(),
            x,
            u,
            t,
            sdd,
        }
    }
}

/// Bisection steps for a grid point's time (2⁻⁶⁰ of the duration).
const BISECTIONS: usize = 60;

#[cfg(test)]
mod tests {
    use super::*;

    /// A trapezoid in ṡ (s̈ = ±1, top speed 1, length 2) averaged over w: a jerk-limited
    /// S-curve, ending at T + w at rest with s̈ = 0 and never faster than the trapezoid.
    #[test]
    fn a_trapezoid_averaged_is_an_s_curve() {
        let m = 400;
        let s: Vec<f64> = (0..=m).map(|i| 2.0 * i as f64 / m as f64).collect();
        let x = s
            .iter()
            .map(|&s: &f64| (2.0 * s).min(1.0).min(2.0 * (2.0 - s)).max(0.0))
            .collect();
        let raw = Profile::from_x(s, x);
        assert!((raw.duration() - 3.0).abs() < 1e-9, "{}", raw.duration());
        let w = 0.5;
        let avg = Averaged::new(&raw, w);
        let smooth = avg.profile();
        assert!((smooth.duration() - 3.5).abs() < 1e-9);
        assert_eq!(
            (smooth.x[0], smooth.sdd[0], smooth.x[m], smooth.sdd[m]),
            (0.0, 0.0, 0.0, 0.0)
        );
        // the ramps: s̈ = t/w for t ≤ w, then 1 until 1, then falls over w
        for (t, a) in [(0.25, 0.5), (0.5, 1.0), (0.9, 1.0), (1.25, 0.5), (1.6, 0.0)] {
            let (_, _, sdd) = avg.at(t);
            assert!((sdd - a).abs() < 1e-9, "s̈({t}) = {sdd}, not {a}");
        }
        assert!(smooth.x.iter().all(|&x| x <= 1.0 + 1e-12));
        for i in 1..m {
            let (s_i, _, _) = avg.at(smooth.t[i]);
            assert!((s_i - smooth.s[i]).abs() < 1e-12);
        }
    }
}
