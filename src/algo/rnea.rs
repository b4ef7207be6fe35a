//! The recursive Newton–Euler algorithm (RBDA §5.3): inverse dynamics, and with it the
//! gravity forces g(q) and the bias forces C(q, v) v + g(q).

use nalgebra::DVector;

use super::mimic::{Terms, on_bodies};
use super::{Data, update_joint_transforms};
use crate::error::Result;
use crate::model::Model;
use crate::spatial::Motion;

/// Inverse dynamics: `data.tau = M(q) qdd + C(q, qd) qd + g(q)` (joint damping excluded; the
/// motors' reflected inertia included, as in M). With mimic joints `Gᵀ τ_b` at the bodies'
/// `G q + o`, `G qd`, `G qdd`.
pub fn rnea<'d>(model: &Model, data: &'d mut Data, q: &[f64], qd: &[f64], qdd: &[f64]) -> &'d DVector<f64> {
    let terms = Terms {
        tau: true,
        g: false,
        bias: false,
        m: false,
    };
    run(model, data, (q, Some(qd), Some(qdd)), terms, true, |_| {});
    &data.tau
}

/// [`rnea`], for inputs from outside (Python's `Robot.rnea`): fails if an input is not finite
/// ([`Error::InvalidArgument`] naming it, `q`, `qd` or `qdd`, and its entry), or if a torque is
/// not finite though the inputs are (a speed or acceleration too large for the arm's masses:
/// the error names the largest).
///
/// [`Error::InvalidArgument`]: crate::error::Error::InvalidArgument
pub fn rnea_checked<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<&'d DVector<f64>> {
    super::check_finite_inputs("inverse dynamics", &[("q", q), ("qd", qd), ("qdd", qdd)])?;
    rnea(model, data, q, qd, qdd);
    if let Some(i) = data.tau.iter().position(|t| !t.is_finite()) {
        let inputs = [("qdd", qdd), ("qd", qd)];
        return Err(super::overflow("inverse dynamics", "torque", i, data.tau[i], &inputs));
    }
    Ok(&data.tau)
}

/// Gravity forces: `data.g = g(q)`, the joint forces that hold the arm still at q.
pub fn gravity<'d>(model: &Model, data: &'d mut Data, q: &[f64]) -> &'d DVector<f64> {
    let terms = Terms {
        tau: false,
        g: true,
        bias: false,
        m: false,
    };
    run(model, data, (q, None, None), terms, true, |data| {
        data.g.copy_from(&data.tau)
    });
    &data.g
}

/// Bias forces: `data.bias = C(q, qd) qd + g(q)` (RNEA with zero acceleration).
pub fn bias<'d>(model: &Model, data: &'d mut Data, q: &[f64], qd: &[f64]) -> &'d DVector<f64> {
    let terms = Terms {
        tau: false,
        g: false,
        bias: true,
        m: false,
    };
    run(model, data, (q, Some(qd), None), terms, true, |data| {
        data.bias.copy_from(&data.tau)
    });
    &data.bias
}

/// The joint transforms and the RNEA passes at the bodies' q, then `keep` (which copies `tau`
/// where it belongs); with mimic joints on the bodies' twins, reduced to `terms`.
fn run(
    model: &Model,
    data: &mut Data,
    state: (&[f64], Option<&[f64]>, Option<&[f64]>),
    terms: Terms,
    with_gravity: bool,
    keep: fn(&mut Data),
) {
    let pass = |model: &Model, data: &mut Data, q: &[f64], qd: Option<&[f64]>, qdd: Option<&[f64]>| {
        update_joint_transforms(model, data, q);
        rnea_passes(model, data, qd, qdd, with_gravity);
        keep(data);
    };
    match model.has_mimic() {
        false => pass(model, data, state.0, state.1, state.2),
        true => on_bodies(model, data, state, terms, pass),
    }
}

/// `data.bias = C(q, qd) qd` alone (no gravity) from the current `data.xup` (bodies' qd).
pub(crate) fn velocity_bias_from_transforms(model: &Model, data: &mut Data, qd: &[f64]) {
    rnea_passes(model, data, Some(qd), None, false);
    data.bias.copy_from(&data.tau);
}

/// The two RNEA passes on the current `data.xup`, into `data.tau`. `None` stands for a zero
/// vector (and skips its terms); `with_gravity: false` leaves gravity out.
fn rnea_passes(model: &Model, data: &mut Data, qd: Option<&[f64]>, qdd: Option<&[f64]>, with_gravity: bool) {
    let n = model.num_bodies();
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
            data.tau[i] += model.body_reflected_inertia(i) * qdd[i];
        }
        if let Some(p) = model.parent[i] {
            let fp = data.xup[i].transpose_apply_force(&data.f[i]);
            data.f[p] += fp;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `robot.rnea(q, v=1e200, a)` gave NaN: a torque that is not finite is an error naming
    /// the input that overflowed, as is an input that is not finite.
    #[test]
    fn overflowing_or_non_finite_inputs_are_errors_naming_them() {
        let model = crate::faze4::model();
        let mut data = Data::new(&model);
        let zero = vec![0.0; model.dof()];
        let checked = rnea_checked(&model, &mut data, &zero, &zero, &zero).unwrap().clone();
        assert_eq!(checked, rnea(&model, &mut data, &zero, &zero, &zero).clone());
        let huge_speed = vec![1e200; model.dof()];
        let e = rnea_checked(&model, &mut data, &zero, &huge_speed, &zero)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("qd: inverse dynamics overflows: the torque of joint"),
            "{e}"
        );
        assert!(e.contains("(|qd| up to 1e200, too large for the arm's masses)"), "{e}");
        let huge_acceleration = vec![1e308; model.dof()];
        let e = rnea_checked(&model, &mut data, &zero, &zero, &huge_acceleration)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("qdd: inverse dynamics overflows"), "{e}");
        let mut nan = zero.clone();
        nan[4] = f64::NAN;
        let e = rnea_checked(&model, &mut data, &zero, &zero, &nan)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "qdd: entry 4 (joint 5) is NaN: inverse dynamics needs finite inputs");
    }
}
