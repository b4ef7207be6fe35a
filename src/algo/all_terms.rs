//! Everything one simulation step needs, from one kinematics pass.

use super::crba::crba_from_transforms;
use super::rnea::{bias_from_transforms, gravity_from_transforms};
use super::{Data, update_joint_transforms};
use crate::model::Model;

/// At (q, qd), with the joint transforms computed once: `data.g = g(q)`,
/// `data.bias = C(q, qd) qd + g(q)` and `data.m = M(q)`.
pub fn compute_all_terms(model: &Model, data: &mut Data, q: &[f64], qd: &[f64]) {
    update_joint_transforms(model, data, q);
    gravity_from_transforms(model, data);
    bias_from_transforms(model, data, qd);
    crba_from_transforms(model, data);
}
