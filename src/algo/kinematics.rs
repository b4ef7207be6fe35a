//! Forward kinematics: joint transforms, and world poses of bodies and frames.

use super::Data;
use crate::model::{FrameId, JointId, JointKind, Model};
use crate::spatial::{Pose, Vec3, Xform};

/// Computes `data.xup[i] = i_X_λ(i)(q)` for every body, `q` the bodies' positions (nb; the
/// coordinates themselves without mimic joints, else [`Model::expand_positions`]): the joint's own motion composed with
/// its fixed tree transform `X_T(i) = (E_T, r_T)` (`tree_pose[i]` = `(E_Tᵀ, r_T)`),
/// `X_J(q_i) · X_T(i)`:
///
/// ```text
///   revolute:   X = (R(a, q)ᵀ E_T,  r_T)     (R(a, q)ᵀ E_T from the model's axis split)
///   prismatic:  X = (E_T,  r_T + E_Tᵀ a q)
/// ```
#[inline]
pub fn update_joint_transforms(model: &Model, data: &mut Data, q: &[f64]) {
    for i in 0..model.num_bodies() {
        let (joint, tree) = (&model.bodies[i], &model.tree_pose[i]);
        data.xup[i] = match joint.kind {
            JointKind::Revolute | JointKind::Continuous => {
                let (s, c) = q[i].sin_cos();
                Xform {
                    e: model.axis_split[i].rotation(s, c),
                    r: tree.pos,
                }
            }
            JointKind::Prismatic => Xform {
                e: tree.rot.transpose(),
                r: tree.pos + tree.rot * (joint.axis * q[i]),
            },
        };
    }
}

/// World placements of every body (`data.body_pose`) and every frame (`data.frame_pose`) at
/// the coordinates `q` (a mimic follower's body at `m·q_leader + o`).
pub fn forward_kinematics(model: &Model, data: &mut Data, q: &[f64]) {
    // o_T_i = o_T_λ · λ_T_joint · X_J(q_i)
    for i in 0..model.num_bodies() {
        let body = &model.bodies[i];
        let local = model.tree_pose[i].compose(&body.motion_pose(body.position(q)));
        data.body_pose[i] = match model.parent[i] {
            Some(p) => data.body_pose[p].compose(&local),
            None => local,
        };
    }
    frame_poses(model, data);
}

/// [`forward_kinematics`] from the joint transforms `data.xup` already at q (e.g. after
/// [`crate::algo::compute_all_terms`]), without trigonometry: `xup[i] = (E_i, r_i)` is the
/// placement `λ_T_i = (E_iᵀ, r_i)`, so `o_T_i = o_T_λ · (E_iᵀ, r_i)`.
pub fn forward_kinematics_from_transforms(model: &Model, data: &mut Data) {
    for i in 0..model.num_bodies() {
        let local = Pose::new(data.xup[i].e.transpose(), data.xup[i].r);
        data.body_pose[i] = match model.parent[i] {
            Some(p) => data.body_pose[p].compose(&local),
            None => local,
        };
    }
    frame_poses(model, data);
}

/// Every frame's world pose from its body's, `data.body_pose` already at q.
fn frame_poses(model: &Model, data: &mut Data) {
    // o_T_frame = o_T_body · body_T_frame
    for (k, frame) in model.frames.iter().enumerate() {
        data.frame_pose[k] = match frame.body {
            Some(b) => data.body_pose[b.0].compose(&frame.placement),
            None => frame.placement,
        };
    }
}

/// World position of frame `frame`'s origin at the coordinates `q`, computed along its own branch only, tip to root
/// (cheap enough to call at every recorded sample; no workspace needed).
pub fn frame_position(model: &Model, q: &[f64], frame: FrameId) -> Vec3 {
    let f = model.frame(frame);
    let Some(JointId(body)) = f.body else {
        return f.placement.pos;
    };
    // walk up to the root, then compose root to tip
    let mut p = f.placement.pos;
    let mut i = body;
    loop {
        let body = &model.bodies[i];
        let local = model.tree_pose[i].compose(&body.motion_pose(body.position(q)));
        p = local.transform_point(&p);
        match model.parent[i] {
            Some(parent) => i = parent,
            None => return p,
        }
    }
}
