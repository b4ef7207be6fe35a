//! The PD law with gravity feed-forward and torque clipping.

use super::Gains;

/// The controller of one run: gains and limits, and whether g(q) is fed forward.
#[derive(Clone, Debug, PartialEq)]
pub struct Pd {
    /// kp, kd, the torque limits E (+∞: unlimited) and the inertias they were tuned from.
    pub gains: Gains,
    /// Add g(q) to the command (gravity feed-forward; `--no-ff` turns it off).
    pub feedforward: bool,
}

impl Pd {
    /// The controller's torque for one zero-order-hold period, unclipped, into `tau_raw`:
    ///
    /// ```text
    ///   τ_raw = kp∘(q_cmd − q) + kd∘(v_cmd − v) + g(q)      (g only with feed-forward)
    /// ```
    #[inline]
    pub fn torque(&self, q: &[f64], v: &[f64], q_cmd: &[f64], v_cmd: &[f64], g: &[f64], tau_raw: &mut [f64]) {
        let Gains { kp, kd, .. } = &self.gains;
        for i in 0..q.len() {
            let mut t = kp[i] * (q_cmd[i] - q[i]) + kd[i] * (v_cmd[i] - v[i]);
            if self.feedforward {
                t += g[i];
            }
            tau_raw[i] = t;
        }
    }

    /// The torque the joints get, `τ = clip(τ_raw, −E, E)`, into `tau`; joint i is saturated
    /// when `|τ_raw,i| ≥ E_i` (see [`Pd::saturated`]).
    #[inline]
    pub fn clip(&self, tau_raw: &[f64], tau: &mut [f64]) {
        for ((t, &raw), &e) in tau.iter_mut().zip(tau_raw).zip(&self.gains.effort) {
            *t = raw.clamp(-e, e);
        }
    }

    /// Whether joint i's unclipped torque reaches its limit (`|τ_raw,i| ≥ E_i`).
    #[inline]
    pub fn saturated(&self, i: usize, tau_raw: f64) -> bool {
        tau_raw.abs() >= self.gains.effort[i]
    }
}
