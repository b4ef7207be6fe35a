//! `faze4 wave`: q_cmd,i(t) = c_i + A_i·sin(ω t + i·π/3).

/// Phase-shifted sines about a centre pose: joint i follows `c_i + A_i sin(ω t + i π/3)`,
/// `v = A_i ω cos(ω t + i π/3)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Wave {
    /// Amplitude A_i per joint, in the joint's unit (rad for a revolute joint, m for a
    /// prismatic one).
    pub amplitude: Vec<f64>,
    /// Angular frequency ω (rad/s; the original's `--freq` is in rad/s).
    pub omega: f64,
    /// The pose the joints wave about, c (rad or m), one entry per joint: zero for the
    /// original's wave.
    pub center: Vec<f64>,
}

impl Wave {
    /// q_cmd(t) into `q`, v_cmd(t) into `v`.
    ///
    /// One sine and cosine per call: joint i + 1's phase is joint i's turned by π/3,
    /// `(sin, cos)(θ + π/3) = (s cos π/3 + c sin π/3, c cos π/3 − s sin π/3)`; the rounding this
    /// adds is below the rounding of the argument `ω t + i π/3` itself (see the tests).
    #[inline]
    pub fn eval(&self, t: f64, q: &mut [f64], v: &mut [f64]) {
        self.eval_into(t, q, v, None);
    }

    /// [`Wave::eval`], and a_cmd(t) = −A_i ω² sin(ω t + i π/3) into `a`.
    #[inline]
    pub fn eval_with_acceleration(&self, t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) {
        self.eval_into(t, q, v, Some(a));
    }

    #[inline]
    fn eval_into(&self, t: f64, q: &mut [f64], v: &mut [f64], mut acc: Option<&mut [f64]>) {
        const COS_STEP: f64 = 0.5;
        let sin_step = 0.75f64.sqrt();
        let (mut s, mut c) = (self.omega * t).sin_cos();
        for (i, (&c_i, &a)) in self.center.iter().zip(&self.amplitude).enumerate() {
            q[i] = c_i + a * s;
            v[i] = a * self.omega * c;
            if let Some(acc) = acc.as_deref_mut() {
                acc[i] = -(a * self.omega * self.omega) * s;
            }
            (s, c) = (s * COS_STEP + c * sin_step, c * COS_STEP - s * sin_step);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_3;

    use super::*;

    #[test]
    fn eval_matches_the_phase_shifted_sines() {
        let wave = Wave {
            amplitude: vec![25f64.to_radians(); 6],
            omega: 0.5,
            center: vec![0.0; 6],
        };
        let (mut q, mut v) = ([0.0; 6], [0.0; 6]);
        for k in 0..2000 {
            let t = k as f64 * 0.0137;
            wave.eval(t, &mut q, &mut v);
            for i in 0..6 {
                // the direct formula rounds its argument to within ulp(ω t + i π/3)
                let tol = 4.0 * f64::EPSILON * (wave.omega * t + i as f64 * FRAC_PI_3);
                let (s, c) = (wave.omega * t + i as f64 * FRAC_PI_3).sin_cos();
                assert!((q[i] - wave.amplitude[i] * s).abs() <= tol, "q{i} at t = {t}");
                assert!(
                    (v[i] - wave.amplitude[i] * wave.omega * c).abs() <= tol,
                    "v{i} at t = {t}"
                );
            }
        }
    }

    #[test]
    fn acceleration_is_the_derivative_of_v_and_q_v_are_evals() {
        let wave = Wave {
            amplitude: vec![0.4, 0.3, 0.2],
            omega: 1.7,
            center: vec![0.1, 0.0, -0.2],
        };
        let (mut q, mut v, mut a) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        let (mut q0, mut v0, mut vp, mut vm, mut scratch) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        let h = 1e-6;
        for k in 0..50 {
            let t = k as f64 * 0.13;
            wave.eval_with_acceleration(t, &mut q, &mut v, &mut a);
            wave.eval(t, &mut q0, &mut v0);
            assert_eq!((q, v), (q0, v0));
            wave.eval(t + h, &mut scratch, &mut vp);
            wave.eval(t - h, &mut scratch, &mut vm);
            for i in 0..3 {
                assert!(
                    ((vp[i] - vm[i]) / (2.0 * h) - a[i]).abs() < 1e-7,
                    "joint {i} at t = {t}"
                );
            }
        }
    }

    #[test]
    fn a_centre_shifts_q_and_leaves_v() {
        let about_zero = Wave {
            amplitude: vec![0.3; 3],
            omega: 2.0,
            center: vec![0.0; 3],
        };
        let centred = Wave {
            center: vec![0.5, -1.0, 2.0],
            ..about_zero.clone()
        };
        let (mut q0, mut v0, mut q, mut v) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        for k in 0..100 {
            let t = k as f64 * 0.05;
            about_zero.eval(t, &mut q0, &mut v0);
            centred.eval(t, &mut q, &mut v);
            assert_eq!(v, v0);
            for i in 0..3 {
                assert_eq!(q[i], centred.center[i] + q0[i]);
            }
        }
    }
}
