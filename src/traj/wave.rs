//! `faze4 wave`: q_cmd,i(t) = A·sin(ω t + i·π/3).

use std::f64::consts::FRAC_PI_3;

/// Phase-shifted sines: joint i follows `A sin(ω t + i π/3)`, `v = A ω cos(ω t + i π/3)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Wave {
    /// Amplitude A (rad).
    pub amplitude: f64,
    /// Angular frequency ω (rad/s; the original's `--freq` is in rad/s).
    pub omega: f64,
    /// Number of joints.
    pub dof: usize,
}

impl Wave {
    /// q_cmd(t) into `q`, v_cmd(t) into `v`.
    #[inline]
    pub fn eval(&self, t: f64, q: &mut [f64], v: &mut [f64]) {
        let aw = self.amplitude * self.omega;
        for i in 0..self.dof {
            let (s, c) = (self.omega * t + i as f64 * FRAC_PI_3).sin_cos();
            q[i] = self.amplitude * s;
            v[i] = aw * c;
        }
    }
}
