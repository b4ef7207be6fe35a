//! The tuning rule's caps for the coupled arm, and the discrete closed loop's spectral radius.
//!
//! The tuning rule bounds each joint alone: `b_i = Δt²·kp_i / M_ii ≤ 0.4` and
//! `Δt·kd_i / M_ii ≤ 0.5`. On an arm whose joints are strongly coupled through M, the loop's
//! modes are the eigenvectors of `M⁻¹Kp`, not the joints, and those caps say nothing about
//! them. Their coupled forms are
//!
//! ```text
//!   b_max = Δt² · λmax(M⁻¹ Kp)      (one joint alone: Δt²·kp/I)
//!   b_kd  = Δt  · λmax(M⁻¹ Kd)      (one joint alone: Δt·kd/I)
//! ```
//!
//! with Kp, Kd the diagonal gain matrices and M = M(q_start). Both are real and ≥ 0: with
//! K diagonal and ≥ 0, `M⁻¹K` has the eigenvalues of the symmetric `K^½ M⁻¹ K^½`.

use nalgebra::{DMatrix, SymmetricEigen};
use serde::Serialize;

use super::Gains;

/// Above this `b_max` the tuned gains are scaled down (to `b_max` = [`TARGET_B_MAX`]).
pub const SCALE_ABOVE_B_MAX: f64 = 0.5;
/// Above this `b_kd` the tuned gains are scaled down.
pub const SCALE_ABOVE_B_KD: f64 = 0.6;
/// The `b_max` the scaled gains are brought to (the rule's own single-joint cap).
pub const TARGET_B_MAX: f64 = 0.4;
/// The `b_kd` the scaled kd are capped to (the rule's own single-joint cap).
pub const TARGET_B_KD: f64 = 0.5;

/// How close the gains are to the discrete loop's limits, at the start pose. Dimensionless.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stability {
    /// `Δt²·λmax(M⁻¹Kp)`: the coupled form of the rule's stiffness cap (0.4 for one joint).
    pub b_max: f64,
    /// `Δt·λmax(M⁻¹Kd)`: the coupled form of the rule's damping cap (0.5 for one joint).
    pub b_kd: f64,
    /// Spectral radius of the linearised discrete closed loop (see [`spectral_radius`]):
    /// below 1 the loop is stable about the start pose; NaN if it could not be computed.
    pub spectral_radius: f64,
    /// Whether the tuning scaled the rule's gains down to keep the coupled loop stable.
    pub scaled: bool,
}

impl Stability {
    /// The figures for gains `kp`, `kd` (one per joint) on the mass matrix `m` = M(q_start)
    /// (n×n) with joint damping `damping` (one per joint) at step `dt` (s); `scaled` false.
    pub fn assess(m: &DMatrix<f64>, damping: &[f64], kp: &[f64], kd: &[f64], dt: f64) -> Stability {
        Stability {
            b_max: dt * dt * lambda_max(m, kp),
            b_kd: dt * lambda_max(m, kd),
            spectral_radius: spectral_radius(m, damping, kp, kd, dt),
            scaled: false,
        }
    }

    /// Whether the linearised loop is stable (ρ < 1).
    pub fn is_stable(&self) -> bool {
        self.spectral_radius < 1.0
    }
}

/// Keeps the rule's gains stable on a coupled arm, and records the figures in
/// `gains.stability`. With `m` = M(q_start) (n×n), `damping` the joint damping and `dt` the
/// step (s):
///
/// ```text
///   if b_max > 0.5 or b_kd > 0.6:
///       s = min(1, 0.4 / b_max);   kp ← s·kp;   kd ← √s·kd
///       if b_kd(kd) > 0.5:  kd ← kd · 0.5 / b_kd(kd)
/// ```
///
/// Scaling kd with √s keeps each mode's damping ratio (kd/√(kp·I)); the derivative term
/// couples the joints as well, so kd needs its own coupled cap. A single joint tuned by the
/// rule has b ≤ 0.4 and Δt·kd/I ≤ 0.5, so this only ever changes coupled arms.
pub fn stabilize(gains: &mut Gains, m: &DMatrix<f64>, damping: &[f64], dt: f64) -> Stability {
    let mut b_max = dt * dt * lambda_max(m, &gains.kp);
    let mut b_kd = dt * lambda_max(m, &gains.kd);
    let scaled = b_max > SCALE_ABOVE_B_MAX || b_kd > SCALE_ABOVE_B_KD;
    if scaled {
        let s = (TARGET_B_MAX / b_max).min(1.0);
        gains.kp.iter_mut().for_each(|k| *k *= s);
        gains.kd.iter_mut().for_each(|k| *k *= s.sqrt());
        b_max *= s;
        b_kd *= s.sqrt();
        if b_kd > TARGET_B_KD {
            let c = TARGET_B_KD / b_kd;
            gains.kd.iter_mut().for_each(|k| *k *= c);
            b_kd = TARGET_B_KD;
        }
    }
    let stability = Stability {
        b_max,
        b_kd,
        spectral_radius: spectral_radius(m, damping, &gains.kp, &gains.kd, dt),
        scaled,
    };
    gains.stability = Some(stability);
    stability
}

/// `λmax(M⁻¹K)` for `K = diag(k)`, `k ≥ 0`: the largest eigenvalue of `K^½ M⁻¹ K^½`. NaN if
/// M is not positive definite; 0 for a model without joints.
pub fn lambda_max(m: &DMatrix<f64>, k: &[f64]) -> f64 {
    if m.is_empty() {
        return 0.0;
    }
    let Some(inverse) = m.clone().cholesky().map(|c| c.inverse()) else {
        return f64::NAN;
    };
    let root: Vec<f64> = k.iter().map(|k| k.max(0.0).sqrt()).collect();
    let scaled = DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| root[i] * inverse[(i, j)] * root[j]);
    SymmetricEigen::new(scaled).eigenvalues.max()
}

/// Spectral radius of the discrete closed loop, linearised about a pose held at rest with
/// gravity compensated (the feed-forward). The PD torque `τ = −Kp e − Kd v` (e = q − q_cmd) is
/// held over the step `v⁺ = (M + Δt·D)⁻¹[M v + Δt(τ − C v − g)]`, `q⁺ = q + Δt v⁺`; at rest C v
/// is second order and the feed-forward cancels g, so with `A = M + Δt·D`:
///
/// ```text
///   v⁺ = B v − P e,      B = A⁻¹(M − Δt·Kd),   P = Δt·A⁻¹Kp
///   e⁺ = e + Δt v⁺
///
///   [e⁺]   [ 1 − Δt·P   Δt·B ] [e]
///   [v⁺] = [   −P         B  ] [v]
/// ```
///
/// ρ is the largest modulus of that 2n×2n matrix's eigenvalues (from its real Schur form).
/// NaN if `A` is not positive definite or the Schur iteration does not converge; 0 for a model
/// without joints (nothing moves).
pub fn spectral_radius(m: &DMatrix<f64>, damping: &[f64], kp: &[f64], kd: &[f64], dt: f64) -> f64 {
    let n = m.nrows();
    if n == 0 {
        return 0.0;
    }
    let mut a = m.clone();
    for i in 0..n {
        a[(i, i)] += dt * damping[i];
    }
    let Some(a) = a.cholesky() else {
        return f64::NAN;
    };
    let b = a.solve(&DMatrix::from_fn(n, n, |i, j| {
        m[(i, j)] - if i == j { dt * kd[i] } else { 0.0 }
    }));
    let p = a.solve(&DMatrix::from_fn(n, n, |i, j| if i == j { dt * kp[i] } else { 0.0 }));
    let t = DMatrix::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => f64::from(u8::from(i == j)) - dt * p[(i, j)],
        (true, false) => dt * b[(i, j - n)],
        (false, true) => -p[(i - n, j)],
        (false, false) => b[(i - n, j - n)],
    });
    match nalgebra::linalg::Schur::try_new(t, f64::EPSILON, 10_000) {
        Some(schur) => schur.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max),
        None => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One joint alone: the coupled figures are the single-joint ones, and ρ is the root of
    /// the 2×2 loop's characteristic polynomial z² − (2 − b − c) z + (1 − c), c = Δt·kd/I.
    #[test]
    fn one_joint_matches_the_single_joint_figures() {
        let (i, kp, kd, dt) = (0.3, 1200.0, 9.0, 2e-3);
        let m = DMatrix::from_element(1, 1, i);
        let s = Stability::assess(&m, &[0.0], &[kp], &[kd], dt);
        let (b, c) = (dt * dt * kp / i, dt * kd / i);
        assert!((s.b_max - b).abs() < 1e-15 * b.max(1.0));
        assert!((s.b_kd - c).abs() < 1e-15);
        let (tr, det) = (2.0 - b - c, 1.0 - c);
        let disc = tr * tr - 4.0 * det;
        let rho = if disc < 0.0 {
            det.sqrt()
        } else {
            (tr.abs() + disc.sqrt()) / 2.0
        };
        assert!(
            (s.spectral_radius - rho).abs() < 1e-12,
            "{} vs {rho}",
            s.spectral_radius
        );
    }

    /// Two strongly coupled joints, each tuned alone at b = 0.4: unstable as tuned,
    /// stable after [`stabilize`], which brings b_max to 0.4 and b_kd to at most 0.5.
    #[test]
    fn stabilize_brings_a_coupled_pair_below_one() {
        let dt = 2e-4;
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.98, 0.98, 1.0]);
        let kp = vec![0.4 / (dt * dt); 2];
        let kd = vec![0.5 / dt; 2];
        let before = Stability::assess(&m, &[0.0, 0.0], &kp, &kd, dt);
        assert!(before.spectral_radius > 1.0, "{before:?}");
        let mut gains = Gains {
            effective_inertia: vec![1.0; 2],
            kp,
            kd,
            effort: vec![f64::INFINITY; 2],
            stability: None,
        };
        let after = stabilize(&mut gains, &m, &[0.0, 0.0], dt);
        assert!(after.scaled);
        assert!(after.spectral_radius < 1.0, "{after:?}");
        assert!((after.b_max - TARGET_B_MAX).abs() < 1e-12);
        assert!(after.b_kd <= TARGET_B_KD + 1e-12);
        let again = Stability::assess(&m, &[0.0, 0.0], &gains.kp, &gains.kd, dt);
        assert!((again.b_max - after.b_max).abs() < 1e-12 && (again.b_kd - after.b_kd).abs() < 1e-12);
    }

    /// A model without joints has nothing to assess, and no eigenvalue problem to fail on.
    #[test]
    fn no_joints_no_figures() {
        let s = Stability::assess(&DMatrix::zeros(0, 0), &[], &[], &[], 2e-4);
        assert_eq!((s.b_max, s.b_kd, s.spectral_radius), (0.0, 0.0, 0.0));
    }

    /// Gains within the single-joint caps on a decoupled (diagonal) M are never scaled.
    #[test]
    fn decoupled_gains_are_left_alone() {
        let dt = 1e-3;
        let m = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![0.5, 0.02, 3.0]));
        let mut gains = super::super::auto_tune(&[0.5, 0.02, 3.0], &[f64::INFINITY; 3], dt);
        let tuned = gains.clone();
        let s = stabilize(&mut gains, &m, &[0.0; 3], dt);
        assert!(!s.scaled);
        assert_eq!(gains.kp, tuned.kp);
        assert_eq!(gains.kd, tuned.kd);
        assert!(s.is_stable());
    }
}
