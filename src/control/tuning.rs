//! The auto-tuning rule (docs/model.md).

use nalgebra::DMatrix;
use serde::Serialize;

use super::{Stability, stabilize};
use crate::algo::{Data, crba};
use crate::model::Model;

/// Per-joint controller gains and the figures they came from. All vectors have one entry per
/// joint.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Gains {
    /// Effective inertia I_i = M_ii(q_start) seen by each joint (kg·m² or kg).
    pub effective_inertia: Vec<f64>,
    /// Proportional gains (N·m/rad or N/m).
    pub kp: Vec<f64>,
    /// Derivative gains (N·m·s/rad or N·s/m).
    pub kd: Vec<f64>,
    /// Torque limits E (N·m or N); +∞ where a joint is not limited.
    pub effort: Vec<f64>,
    /// The coupled loop's figures at the start pose (see [`super::stabilize`]); `None` until
    /// they are assessed (the rule itself sees only M's diagonal).
    pub stability: Option<Stability>,
}

impl Gains {
    /// The discrete stability figure `b_i = Δt²·kp_i / I_i` (the rule keeps it ≤ 0.4; one joint alone diverges near 4 − 2·Δt·kd/I, docs/model.md).
    pub fn stiffness_b(&self, dt: f64) -> Vec<f64> {
        self.kp
            .iter()
            .zip(&self.effective_inertia)
            .map(|(kp, i)| dt * dt * kp / i)
            .collect()
    }
}

/// The rule (docs/model.md): with `inertia` = diag M(q_start) and torque limits `effort`,
///
/// ```text
///   kp_i = min( E_i / 0.05 , 0.4 · I_i / Δt² )
///   kd_i = min( 1.6 · sqrt(kp_i · I_i) , I_i / (2Δt) )
/// ```
///
/// The first kp term keeps a 0.05 rad error inside the torque limit; the second keeps the
/// discrete loop's stiffness b = Δt²·kp/I at 0.4. The kd cap keeps the derivative time
/// constant I/kd at least 2Δt. These bound each joint alone; [`super::stabilize`] then checks
/// the coupled arm.
pub fn auto_tune(inertia: &[f64], effort: &[f64], dt: f64) -> Gains {
    let kp: Vec<f64> = inertia
        .iter()
        .zip(effort)
        .map(|(&i, &e)| (e / 0.05).min(0.4 * i / (dt * dt)))
        .collect();
    let kd = inertia
        .iter()
        .zip(&kp)
        .map(|(&i, &kp)| (1.6 * (kp * i).sqrt()).min(i / (2.0 * dt)))
        .collect();
    Gains {
        effective_inertia: inertia.to_vec(),
        kp,
        kd,
        effort: effort.to_vec(),
        stability: None,
    }
}

/// The tuning recipe at a start pose: [`auto_tune`] from the effective inertias
/// I_i = M_ii(`q_start`) with the torque limits `effort` at step `dt`, then [`stabilize`] for
/// the coupled arm (the gains then carry their `stability`). Returns the gains and M(q_start).
pub fn tune(model: &Model, q_start: &[f64], effort: &[f64], dt: f64) -> (Gains, DMatrix<f64>) {
    let mut data = Data::new(model);
    let m = crba(model, &mut data, q_start).clone();
    let inertia: Vec<f64> = m.diagonal().iter().copied().collect();
    let damping: Vec<f64> = model.damping().collect();
    let mut gains = auto_tune(&inertia, effort, dt);
    stabilize(&mut gains, &m, &damping, dt);
    (gains, m)
}

/// Whether the mass matrix at the start pose `m`, the gains and their stability figures are
/// all finite: inputs too large for f64 (a payload of 1e300 kg, a gear ratio of 1e160) make
/// one of them overflow, and the run would end as "diverged" with a NaN spectral radius.
pub fn arithmetic_holds(m: &DMatrix<f64>, gains: &Gains) -> bool {
    m.iter().chain(&gains.kp).chain(&gains.kd).all(|x| x.is_finite())
        && gains
            .stability
            .is_none_or(|s| s.b_max.is_finite() && s.spectral_radius.is_finite())
}
