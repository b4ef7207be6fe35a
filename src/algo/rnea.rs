//! The recursive Newton–Euler algorithm (RBDA §5.3): inverse dynamics, and with it the
//! gravity forces g(q) and the bias forces C(q, v) v + g(q).

use nalgebra::DVector;

use super::{Data, update_joint_transforms};
use crate::model::Model;
use crate::spatial::Motion;

/// Inverse dynamics: `data.tau = M(q) qdd + C(q, qd) qd + g(q)` (joint damping excluded; the
/// motors' reflected inertia included, as in M).
pub fn rnea<'d>(model: &Model, data: &'d mut Data, q: &[f64], qd: &[f64], qdd: &[f64]) -> &'d DVector<f64> {
    update_joint_transforms(model, data, q);
    rnea_passes(model, data, Some(qd), Some(qdd), true);
    &data.tau
}

/// Gravity forces: `data.g = g(q)`, the joint forces that hold the arm still at q.
pub fn gravity<'d>(model: &Model, data: &'d mut Data, q: &[f64]) -> &'d DVector<f64> {
    update_joint_transforms(model, data, q);
    rnea_passes(model, data, None, None, true);
    data.g.copy_from(&data.tau);
    &data.g
}

/// Bias forces: `data.bias = C(q, qd) qd + g(q)` (RNEA with zero acceleration).
pub fn bias<'d>(model: &Model, data: &'d mut Data, q: &[f64], qd: &[f64]) -> &'d DVector<f64> {
    update_joint_transforms(model, data, q);
    rnea_passes(model, data, Some(qd), None, true);
    data.bias.copy_from(&data.tau);
    &data.bias
}

/// `data.bias = C(q, qd) qd` alone (no gravity) from the current `data.xup`.
pub(crate) fn velocity_bias_from_transforms(model: &Model, data: &mut Data, qd: &[f64]) {
    rnea_passes(model, data, Some(qd), None, false);
    data.bias.copy_from(&data.tau);
}

/// The two RNEA passes on the current `data.xup`, into `data.tau`. `None` stands for a zero
/// vector (and skips its terms); `with_gravity: false` leaves gravity out.
fn rnea_passes(model: &Model, data: &mut Data, qd: Option<&[f64]>, qdd: Option<&[f64]>, with_gravity: bool) {
    let n = model.dof();
    // The base accelerates upwards at −g instead of gravity pulling every body (RBDA §5.3).
    let a0 = if with_gravity {
        Motion::new(Default::default(), -model.gravity)
    } else {
        Motion::ZERO
    };
    // Forward pass, root to tip:
    //   v_i = X_i v_λ + s_i qd_i
    //   a_i = X_i a_λ + s_i qdd_i + v_i ×ₘ s_i qd_i
    //   f_i = I_i a_i + v_i ×* I_i v_i
    for i in 0..n {
        let xup = &data.xup[i];
        let s = &model.s[i];
        let (v_parent, a_parent) = match model.parent[i] {
            Some(p) => (data.v[p], data.a[p]),
            None => (Motion::ZERO, a0),
        };
        let mut a = xup.apply_motion(&a_parent);
        if let Some(qdd) = qdd {
            a += *s * qdd[i];
        }
        let inertia = &model.inertia[i];
        match qd {
            Some(qd) => {
                let vj = *s * qd[i];
                let v = xup.apply_motion(&v_parent) + vj;
                a += v.cross_motion(&vj);
                data.f[i] = inertia.mul_motion(&a) + v.cross_force(&inertia.mul_motion(&v));
                data.v[i] = v;
            }
            None => {
                data.f[i] = inertia.mul_motion(&a);
                data.v[i] = Motion::ZERO;
            }
        }
        data.a[i] = a;
    }
    // Backward pass, tip to root:
    //   tau_i = s_i · f_i (+ r_i²·I_rotor,i · qdd_i, the motor's own inertia),   f_λ += X_iᵀ f_i
    for i in (0..n).rev() {
        data.tau[i] = model.s[i].dot(&data.f[i]);
        if let Some(qdd) = qdd {
            data.tau[i] += model.joints[i].reflected_inertia() * qdd[i];
        }
        if let Some(p) = model.parent[i] {
            let fp = data.xup[i].transpose_apply_force(&data.f[i]);
            data.f[p] += fp;
        }
    }
}
