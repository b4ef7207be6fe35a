//! The PD law with a feed-forward (gravity, or computed torque) and torque clipping.

use serde::Serialize;

use super::Gains;

/// What the controller adds to its PD torque (docs/trajectories.md, "Feed-forward").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FeedForward {
    /// Nothing: the PD alone holds the arm up (`--no-ff`).
    None,
    /// g(q) at the measured q (the original's; `--ff gravity`, the default).
    #[default]
    Gravity,
    /// The inverse dynamics of the command, `M(q_cmd) a_cmd + C(q_cmd, v_cmd) v_cmd + g(q_cmd)`
    /// by RNEA, the motors' reflected inertia included, joint damping not (computed torque, what
    /// a drive with velocity and acceleration feed-forward does; `--ff full`).
    Full,
}

crate::choice::choice_words!(FeedForward { Gravity => "gravity", Full => "full" });

impl FeedForward {
    /// `none`, `gravity` or `full`, as the summary spells it (the `ff` option's words, and
    /// `none` for `no_ff`).
    pub fn name(self) -> &'static str {
        match self {
            FeedForward::None => "none",
            other => crate::choice::Choice::word(other),
        }
    }
}

/// The controller of one run: gains and limits, and what it feeds forward.
#[derive(Clone, Debug, PartialEq)]
pub struct Pd {
    /// kp, kd, the torque limits E (+∞: unlimited) and the inertias they were tuned from.
    pub gains: Gains,
    /// What is added to the PD torque.
    pub feedforward: FeedForward,
}

impl Pd {
    /// The controller's torque for one zero-order-hold period, unclipped, into `tau_raw`:
    ///
    /// ```text
    ///   τ_raw = kp∘(q_cmd − q) + kd∘(v_cmd − v) + τ_ff
    /// ```
    ///
    /// τ_ff is `ff`, the torque [`Pd::feedforward`] names (g(q), or the command's inverse
    /// dynamics), added unless it is [`FeedForward::None`].
    #[inline]
    pub fn torque(&self, q: &[f64], v: &[f64], q_cmd: &[f64], v_cmd: &[f64], ff: &[f64], tau_raw: &mut [f64]) {
        let Gains { kp, kd, .. } = &self.gains;
        let with_ff = self.feedforward != FeedForward::None;
        for i in 0..q.len() {
            let mut t = kp[i] * (q_cmd[i] - q[i]) + kd[i] * (v_cmd[i] - v[i]);
            if with_ff {
                t += ff[i];
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
