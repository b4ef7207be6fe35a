//! Typed indices: a frame and a joint are different things, so their indices are different types.

use std::fmt;

/// A frame of a model: an index into `Model::frames` (one frame per URDF link, root first,
/// depth-first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FrameId(pub usize);

/// A moving joint of a model: an index into `Model::joints`, which is also its body (body i is
/// moved by joint i) and its coordinate in q. Shown to people as J1…Jn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointId(pub usize);

impl fmt::Display for JointId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "J{}", self.0 + 1)
    }
}

impl JointId {
    /// Every joint of an n-dof model, in q order.
    pub fn all(n: usize) -> impl Iterator<Item = JointId> {
        (0..n).map(JointId)
    }
}
