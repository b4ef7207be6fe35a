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
/// A body moved by a mimic follower adds m times its column to its leader's (`J G`).
///
/// [`forward_kinematics`]: crate::algo::forward_kinematics
pub fn frame_jacobian<'d>(model: &Model, data: &'d mut Data, frame: FrameId) -> &'d nalgebra::DMatrix<f64> {
    data.jacobian.fill(0.0);
    let p = data.frame_pose[frame.0].pos;
    let mut body = model.frame(frame).body.map(|b| b.0);
    let mimic = model.has_mimic();
    while let Some(j) = body {
        let pose = &data.body_pose[j];
        let moved = &model.bodies[j];
        let a = pose.rot * moved.axis;
        let (ang, lin) = match moved.kind {
            JointKind::Revolute | JointKind::Continuous => (a, a.cross(&(p - pose.pos))),
            JointKind::Prismatic => (Default::default(), a),
        };
        let (c, m) = (moved.coordinate, moved.multiplier);
        for r in 0..3 {
            match mimic {
                false => {
                    data.jacobian[(r, c)] = ang[r];
                    data.jacobian[(r + 3, c)] = lin[r];
                }
                // a leader and its followers may share a branch: their columns add up
                true => {
                    data.jacobian[(r, c)] += m * ang[r];
                    data.jacobian[(r + 3, c)] += m * lin[r];
                }
            }
        }
        body = model.parent[j];
    }
    &data.jacobian
}
