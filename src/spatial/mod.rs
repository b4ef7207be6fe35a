//! Spatial (6D) algebra in Featherstone's notation.
//!
//! Motion and force vectors are different types ([`Motion`], [`Force`]): adding one to the
//! other does not compile, and the only product between them is the power `m · f`.
//! Both are stored angular part first, as in Featherstone's *Rigid Body Dynamics Algorithms*
//! (RBDA) and spatial_v2: a motion is `(ω, v)`, a force is `(n, f)`.
//!
//! * [`Xform`] is a Plücker transform `B_X_A` (coordinates of frame A to frame B).
//! * [`Pose`] is a rigid placement `a_T_b` (where frame b is, seen from frame a); kinematics
//!   reports poses, dynamics runs on Plücker transforms.
//! * [`Inertia`] is a rigid-body spatial inertia about a frame's origin.

mod inertia;
mod motion;
mod transform;

pub use inertia::Inertia;
pub use motion::{Force, Motion};
pub use transform::{Pose, Xform, rotation_about_axis, rotation_from_rpy, skew};

/// 3-vector of `f64`.
pub type Vec3 = nalgebra::Vector3<f64>;
/// 3×3 matrix of `f64`.
pub type Mat3 = nalgebra::Matrix3<f64>;
