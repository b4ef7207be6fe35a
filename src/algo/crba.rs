//! The composite-rigid-body algorithm (RBDA §6.2): the joint-space mass matrix.

use nalgebra::DMatrix;

use super::{Data, update_joint_transforms};
use crate::model::Model;

/// `data.m = M(q)`, the motors' reflected inertia on its diagonal.
pub fn crba<'d>(model: &Model, data: &'d mut Data, q: &[f64]) -> &'d DMatrix<f64> {
    update_joint_transforms(model, data, q);
    crba_from_transforms(model, data);
    &data.m
}

/// `data.m` from the current `data.xup`.
pub(crate) fn crba_from_transforms(model: &Model, data: &mut Data) {
    let n = model.dof();
    data.ic.copy_from_slice(&model.inertia);
    // Backward pass, tip to root. A joint's motor adds its reflected inertia r²·I_rotor to
    // M_ii alone (see `Joint::reflected_inertia`). When body i is reached its composite inertia is complete:
    //   F = IC_i s_i;  M_ii = s_iᵀ F;  walking up, F = X_jᵀ F, M_ij = M_ji = s_jᵀ F
    //   IC_λ += X_iᵀ IC_i X_i
    for i in (0..n).rev() {
        let mut force = data.ic[i].mul_motion(&model.s[i]);
        data.m[(i, i)] = model.s[i].dot(&force) + model.joints[i].reflected_inertia();
        let mut j = i;
        while let Some(p) = model.parent[j] {
            force = data.xup[j].transpose_apply_force(&force);
            j = p;
            let mij = model.s[j].dot(&force);
            data.m[(i, j)] = mij;
            data.m[(j, i)] = mij;
        }
        if let Some(p) = model.parent[i] {
            let ic = data.ic[i].transform_to_source(&data.xup[i]);
            data.ic[p] += ic;
        }
    }
}
