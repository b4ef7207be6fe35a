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
pub use rnea::{bias, gravity, rnea, rnea_checked};
pub use step::{State, discrete_step, integrate_discrete};

/// An error naming the first input of `inputs` with an entry that is not finite (`algorithm`
/// needs finite inputs).
fn check_finite_inputs(algorithm: &str, inputs: &[(&str, &[f64])]) -> crate::error::Result<()> {
    for (name, x) in inputs {
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(crate::error::Error::argument(
                *name,
                format!(
                    "entry {i} (joint {}) is {}: {algorithm} needs finite inputs",
                    i + 1,
                    x[i]
                ),
            ));
        }
    }
    Ok(())
}

/// The error of a result that is not finite though the inputs are: `quantity` of joint i + 1
/// is `value`. It names the input that overflowed, the largest in magnitude of `inputs` (the
/// first of equals).
fn overflow(algorithm: &str, quantity: &str, i: usize, value: f64, inputs: &[(&str, &[f64])]) -> crate::error::Error {
    let largest = |x: &[f64]| x.iter().copied().map(f64::abs).fold(0.0, f64::max);
    let (name, size) = inputs
        .iter()
        .map(|(name, x)| (*name, largest(x)))
        .fold(("", -1.0), |best, this| if this.1 > best.1 { this } else { best });
    crate::error::Error::argument(
        name,
        format!(
            "{algorithm} overflows: the {quantity} of joint {} is {value} (|{name}| up to {}, too large for the arm's masses)",
            i + 1,
            crate::error::shortest(size)
        ),
    )
}
