//! The composite-rigid-body algorithm (RBDA §6.2): the joint-space mass matrix.

use nalgebra::DMatrix;

use super::mimic::{Terms, on_bodies};
use super::{Data, update_joint_transforms};
use crate::model::Model;

/// `data.m = M(q)`, the motors' reflected inertia on its diagonal; `Gᵀ M_b G` with mimic joints.
pub fn crba<'d>(model: &Model, data: &'d mut Data, q: &[f64]) -> &'d DMatrix<f64> {
    let pass = |model: &Model, data: &mut Data, q: &[f64], _: Option<&[f64]>, _: Option<&[f64]>| {
        update_joint_transforms(model, data, q);
        crba_from_transforms(model, data);
    };
    match model.has_mimic() {
        false => pass(model, data, q, None, None),
        true => {
            let terms = Terms {
                tau: false,
                g: false,
                bias: false,
                m: true,
            };
            on_bodies(model, data, (q, None, None), terms, pass)
        }
    }
    &data.m
}

/// `data.m` (the bodies' M, nb×nb) from the current `data.xup`.
pub(crate) fn crba_from_transforms(model: &Model, data: &mut Data) {
    let n = model.num_bodies();
    data.ic.copy_from_slice(&model.inertia);
    // Backward pass, tip to root. A joint's motor adds its reflected inertia r²·I_rotor to
    // M_ii alone (see `Joint::reflected_inertia`; a follower has none). When body i is reached its composite inertia is complete:
    //   F = IC_i s_i;  M_ii = s_iᵀ F;  walking up, F = X_jᵀ F, M_ij = M_ji = s_jᵀ F
    //   IC_λ += X_iᵀ IC_i X_i
    for i in (0..n).rev() {
        let mut force = data.ic[i].mul_motion(&model.s[i]);
        data.m[(i, i)] = model.s[i].dot(&force) + model.body_reflected_inertia(i);
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
