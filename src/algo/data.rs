//! The mutable workspace of the algorithms.

use nalgebra::{DMatrix, DVector};

use crate::model::Model;
use crate::spatial::{Force, Inertia, Motion, Pose, Xform};

/// Every buffer the algorithms write, sized for one model. Create it once per model with
/// [`Data::new`]; the algorithms then run without allocating. n = `model.dof()`.
#[derive(Clone, Debug)]
pub struct Data {
    /// `xup[i] = i_X_λ(i)`: Plücker transform from the parent body's frame to body i's frame
    /// at the current q. n entries.
    pub xup: Vec<Xform>,
    /// `v[i]`: spatial velocity of body i, in body i's frame. n entries.
    pub v: Vec<Motion>,
    /// `a[i]`: spatial acceleration of body i minus gravity (the base accelerates at −g),
    /// in body i's frame. n entries.
    pub a: Vec<Motion>,
    /// `f[i]`: spatial force body i receives across joint i, in body i's frame. n entries.
    pub f: Vec<Force>,
    /// `ic[i]`: composite inertia of the subtree rooted at body i, in body i's frame. n entries.
    pub ic: Vec<Inertia>,
    /// `tau`: joint forces from the last RNEA pass (N·m or N). n.
    pub tau: DVector<f64>,
    /// `g`: gravity forces g(q) (N·m or N), `M v̇ + C v + g = τ`. n.
    pub g: DVector<f64>,
    /// `bias`: C(q, v) v + g(q) (N·m or N). n.
    pub bias: DVector<f64>,
    /// `m`: joint-space mass matrix M(q), symmetric n×n (kg·m² / kg).
    pub m: DMatrix<f64>,
    /// `qdd`: joint accelerations from forward dynamics. n.
    pub qdd: DVector<f64>,
    /// `body_pose[i] = o_T_i`: world placement of body i (from [`forward_kinematics`]). n.
    ///
    /// [`forward_kinematics`]: crate::algo::forward_kinematics
    pub body_pose: Vec<Pose>,
    /// `frame_pose[k] = o_T_k`: world placement of frame k. One per model frame.
    pub frame_pose: Vec<Pose>,
    /// `jacobian`: 6×n frame Jacobian, rows angular (3) then linear (3), world-aligned.
    pub jacobian: DMatrix<f64>,
    /// Step workspace: `M + Δt·D` (n×n).
    pub(crate) step_matrix: DMatrix<f64>,
    /// Cholesky factor workspace (n×n, lower triangle).
    pub(crate) chol: DMatrix<f64>,
    /// Right-hand side / solution workspace (n).
    pub(crate) rhs: DVector<f64>,
    /// Joint-limit solve workspace: the step's right-hand side b (n), the reduced matrix
    /// (n×n), and per joint the velocity it is clamped at, if any (n).
    pub(crate) limit_rhs: DVector<f64>,
    pub(crate) limit_matrix: DMatrix<f64>,
    pub(crate) limit_at: Vec<Option<f64>>,
}

impl Data {
    /// A workspace for `model`.
    pub fn new(model: &Model) -> Self {
        let n = model.dof();
        Data {
            xup: vec![Xform::IDENTITY; n],
            v: vec![Motion::ZERO; n],
            a: vec![Motion::ZERO; n],
            f: vec![Force::ZERO; n],
            ic: vec![Inertia::ZERO; n],
            tau: DVector::zeros(n),
            g: DVector::zeros(n),
            bias: DVector::zeros(n),
            m: DMatrix::zeros(n, n),
            qdd: DVector::zeros(n),
            body_pose: vec![Pose::IDENTITY; n],
            frame_pose: vec![Pose::IDENTITY; model.frames.len()],
            jacobian: DMatrix::zeros(6, n),
            step_matrix: DMatrix::zeros(n, n),
            chol: DMatrix::zeros(n, n),
            rhs: DVector::zeros(n),
            limit_rhs: DVector::zeros(n),
            limit_matrix: DMatrix::zeros(n, n),
            limit_at: vec![None; n],
        }
    }
}
