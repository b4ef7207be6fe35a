//! Forward dynamics of the continuous equations of motion.

use nalgebra::DVector;

use super::{Data, cholesky_factor, cholesky_solve, compute_all_terms};
use crate::error::{Error, Result};
use crate::model::{JointId, Model};

/// `data.qdd = M(q)⁻¹ (τ − D qd − C(q, qd) qd − g(q))`, D the joint damping; also leaves
/// `data.g`, `data.bias` and `data.m` at (q, qd).
///
/// Fails if an input is not finite ([`Error::InvalidArgument`] naming it, `q`, `qd` or `tau`,
/// and its entry), if M(q) is not positive definite, or if the accelerations are not finite
/// though the inputs are (a torque or speed too large for the arm's masses: the error names the
/// largest input).
pub fn forward_dynamics<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
) -> Result<&'d DVector<f64>> {
    super::check_finite_inputs("forward dynamics", &[("q", q), ("qd", qd), ("tau", tau)])?;
    compute_all_terms(model, data, q, qd);
    cholesky_factor(&data.m, &mut data.chol).map_err(|(joint, pivot)| Error::Diverged {
        joint: JointId(joint),
        pivot,
    })?;
    for (i, joint) in model.joints.iter().enumerate() {
        data.qdd[i] = tau[i] - joint.damping * qd[i] - data.bias[i];
    }
    cholesky_solve(&data.chol, &mut data.qdd);
    if let Some(i) = data.qdd.iter().position(|a| !a.is_finite()) {
        let inputs = [("tau", tau), ("qd", qd)];
        return Err(super::overflow(
            "forward dynamics",
            "acceleration",
            i,
            data.qdd[i],
            &inputs,
        ));
    }
    Ok(&data.qdd)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `robot.aba(q, v, tau=1e308)` gave NaN: a result that is not finite is an error naming
    /// the input, as is an input that is not finite.
    #[test]
    fn overflowing_or_non_finite_inputs_are_errors_naming_them() {
        let model = crate::faze4::model();
        let mut data = Data::new(&model);
        let zero = vec![0.0; model.dof()];
        assert!(forward_dynamics(&model, &mut data, &zero, &zero, &zero).is_ok());
        let huge = vec![1e308; model.dof()];
        let e = forward_dynamics(&model, &mut data, &zero, &zero, &huge)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("tau: forward dynamics overflows: the acceleration of joint"),
            "{e}"
        );
        assert!(e.contains("|tau| up to 1e308"), "{e}");
        let mut nan = zero.clone();
        nan[2] = f64::NAN;
        let e = forward_dynamics(&model, &mut data, &zero, &nan, &zero)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "qd: entry 2 (joint 3) is NaN: forward dynamics needs finite inputs");
    }
}
