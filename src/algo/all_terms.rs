//! Everything one simulation step needs, from one kinematics pass.

use super::crba::crba_from_transforms;
use super::mimic::{Terms, on_bodies};
use super::rnea::velocity_bias_from_transforms;
use super::{Data, update_joint_transforms};
use crate::model::Model;
use crate::spatial::Motion;

/// At (q, qd), with the joint transforms computed once: `data.m = M(q)`, `data.g = g(q)` and
/// `data.bias = C(q, qd) qd + g(q)`.
///
/// Gravity is a uniform field, so once CRBA has the composite inertias `IC_i`, the force
/// gravity puts on the subtree at i is `IC_i a_g,i`, with `a_g,i` the base's −g seen from body
/// i (a pure rotation of the world vector):
///
/// ```text
///   a_g,i = X_i a_g,λ   (a_g,world = (0, −g)),    g_i = s_i · (IC_i a_g,i)
/// ```
///
/// This replaces a second RNEA pass; [`crate::algo::gravity`] (RNEA) checks it in the tests.
/// With mimic joints the terms are the bodies', reduced (`Gᵀ M_b G`, `Gᵀ g_b`, `Gᵀ bias_b`);
/// `data.xup` is left at the bodies' q either way.
pub fn compute_all_terms(model: &Model, data: &mut Data, q: &[f64], qd: &[f64]) {
    match model.has_mimic() {
        false => all_body_terms(model, data, q, qd),
        true => {
            let terms = Terms {
                tau: false,
                g: true,
                bias: true,
                m: true,
            };
            on_bodies(model, data, (q, Some(qd), None), terms, |model, data, q, qd, _| {
                all_body_terms(model, data, q, qd.unwrap_or_default())
            })
        }
    }
}

/// [`compute_all_terms`] on the bodies' q and qd.
fn all_body_terms(model: &Model, data: &mut Data, q: &[f64], qd: &[f64]) {
    update_joint_transforms(model, data, q);
    crba_from_transforms(model, data);
    // forward: gravity seen from each body, root to tip
    let a0 = Motion::new(Default::default(), -model.gravity);
    for i in 0..model.num_bodies() {
        let a_parent = match model.parent[i] {
            Some(p) => data.a[p],
            None => a0,
        };
        // only the linear part is non-zero: X (0, a) = (0, E a)
        let a_g = data.xup[i].e * a_parent.lin;
        data.a[i] = Motion::new(Default::default(), a_g);
        data.g[i] = model.s[i].dot(&data.ic[i].mul_translation(&a_g));
    }
    // C(q, qd) qd by RNEA without gravity, then add g
    velocity_bias_from_transforms(model, data, qd);
    for i in 0..model.num_bodies() {
        data.bias[i] += data.g[i];
    }
}
