//! SPEC §3's PD law with gravity feed-forward and torque clipping.

/// The controller of one run: gains, limits and whether g(q) is fed forward.
#[derive(Clone, Debug)]
pub struct Pd {
    /// Proportional gains, one per joint.
    pub kp: Vec<f64>,
    /// Derivative gains, one per joint.
    pub kd: Vec<f64>,
    /// Torque limits E, one per joint (+∞: unlimited).
    pub effort: Vec<f64>,
    /// Add g(q) to the command (SPEC's feed-forward; `--no-ff` turns it off).
    pub feedforward: bool,
}

impl Pd {
    /// The torque for one zero-order-hold period, into `tau` (clipped) and `tau_raw`
    /// (unclipped); joint i is saturated when `|τ_raw,i| ≥ E_i` (see [`Pd::saturated`]):
    ///
    /// ```text
    ///   τ_raw = kp∘(q_cmd − q) + kd∘(v_cmd − v) + g(q)      (g only with feed-forward)
    ///   τ     = clip(τ_raw, −E, E)
    /// ```
    #[allow(clippy::too_many_arguments)] // the law's seven vectors, named as in SPEC §3
    #[inline]
    pub fn torque(
        &self,
        q: &[f64],
        v: &[f64],
        q_cmd: &[f64],
        v_cmd: &[f64],
        g: &[f64],
        tau_raw: &mut [f64],
        tau: &mut [f64],
    ) {
        for i in 0..q.len() {
            let mut t = self.kp[i] * (q_cmd[i] - q[i]) + self.kd[i] * (v_cmd[i] - v[i]);
            if self.feedforward {
                t += g[i];
            }
            tau_raw[i] = t;
            tau[i] = t.clamp(-self.effort[i], self.effort[i]);
        }
    }

    /// Whether joint i's unclipped torque reaches its limit (`|τ_raw,i| ≥ E_i`).
    #[inline]
    pub fn saturated(&self, i: usize, tau_raw: f64) -> bool {
        tau_raw.abs() >= self.effort[i]
    }
}
