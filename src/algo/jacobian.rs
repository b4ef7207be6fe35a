//! The frame Jacobian.

use super::Data;
use crate::model::{FrameId, JointKind, Model};

/// `data.jacobian` (6×n): the spatial velocity of frame `frame` from the joint velocities,
/// rows angular ω (3) then the linear velocity of the frame origin (3), both in world
/// coordinates (Drake's `CalcJacobianSpatialVelocity` with the world as measured-in and
/// expressed-in frame). Requires [`forward_kinematics`] at the same q.
///
/// Column j, for joint j between the frame and the root, with world axis `a` and joint
/// origin `o`: `(a, a × (p − o))` for a rotation, `(0, a)` for a translation; zero otherwise.
///
/// [`forward_kinematics`]: crate::algo::forward_kinematics
pub fn frame_jacobian<'d>(model: &Model, data: &'d mut Data, frame: FrameId) -> &'d nalgebra::DMatrix<f64> {
    data.jacobian.fill(0.0);
    let p = data.frame_pose[frame.0].pos;
    let mut body = model.frame(frame).body.map(|b| b.0);
    while let Some(j) = body {
        let pose = &data.body_pose[j];
        let joint = &model.joints[j];
        let a = pose.rot * joint.axis;
        let (ang, lin) = match joint.kind {
            JointKind::Revolute | JointKind::Continuous => (a, a.cross(&(p - pose.pos))),
            JointKind::Prismatic => (Default::default(), a),
        };
        for r in 0..3 {
            data.jacobian[(r, j)] = ang[r];
            data.jacobian[(r + 3, j)] = lin[r];
        }
        body = model.parent[j];
    }
    &data.jacobian
}
