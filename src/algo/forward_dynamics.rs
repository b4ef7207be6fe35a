//! Forward dynamics of the continuous equations of motion.

use nalgebra::DVector;

use super::{Data, cholesky_factor, cholesky_solve, compute_all_terms};
use crate::error::{Error, Result};
use crate::model::{JointId, Model};

/// `data.qdd = M(q)⁻¹ (τ − D qd − C(q, qd) qd − g(q))`, D the joint damping; also leaves
/// `data.g`, `data.bias` and `data.m` at (q, qd). Fails only if M(q) is not positive definite.
pub fn forward_dynamics<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
) -> Result<&'d DVector<f64>> {
    compute_all_terms(model, data, q, qd);
    cholesky_factor(&data.m, &mut data.chol).map_err(|(joint, pivot)| Error::Diverged {
        joint: JointId(joint),
        pivot,
    })?;
    for (i, joint) in model.joints.iter().enumerate() {
        data.qdd[i] = tau[i] - joint.damping * qd[i] - data.bias[i];
    }
    cholesky_solve(&data.chol, &mut data.qdd);
    Ok(&data.qdd)
}
