//! Rigid-body algorithms, one per file, each a free function of the immutable [`Model`] and
//! the mutable [`Data`] workspace, Pinocchio-style: `rnea(&model, &mut data, q, qd, qdd)`.
//! Nothing here allocates: every buffer lives in `Data`, sized once by [`Data::new`].
//!
//! Notation follows Featherstone (RBDA, spatial_v2): `xup[i] = i_X_λ(i)`, `s[i]` the motion
//! subspace, `v`, `a`, `f` body velocities, accelerations and forces in body coordinates,
//! `ic` composite inertias; forward passes run root to tip (`0..n`), backward passes tip to
//! root (`(0..n).rev()`).
//!
//! [`Model`]: crate::model::Model

mod all_terms;
mod cholesky;
mod contact;
mod crba;
mod data;
mod forward_dynamics;
mod jacobian;
mod kinematics;
mod mimic;
mod rnea;
mod step;

pub use all_terms::compute_all_terms;
pub use cholesky::{cholesky_factor, cholesky_solve};
pub use contact::{ContactPoint, ContactSolver, SIGMA, STICTION_TOLERANCE, integrate_discrete_with_contacts};
pub use crba::crba;
pub use data::Data;
pub use forward_dynamics::forward_dynamics;
pub use jacobian::frame_jacobian;
pub use kinematics::{forward_kinematics, forward_kinematics_from_transforms, frame_position, update_joint_transforms};
pub use rnea::{bias, gravity, rnea};
pub use step::{State, discrete_step, integrate_discrete};
