//! The mutable workspace of the algorithms.

use nalgebra::{DMatrix, DVector};

use crate::model::Model;
use crate::spatial::{Force, Inertia, Motion, Pose, Xform};

/// Every buffer the algorithms write, sized for one model. Create it once per model with
/// [`Data::new`]; the algorithms then run without allocating. n = `model.dof()` (coordinates),
/// nb = `model.num_bodies()` (bodies; nb = n without mimic joints).
#[derive(Clone, Debug)]
pub struct Data {
    /// `xup[i] = i_X_λ(i)`: Plücker transform from the parent body's frame to body i's frame
    /// at the current q. nb entries.
    pub xup: Vec<Xform>,
    /// `v[i]`: spatial velocity of body i, in body i's frame. nb entries.
    pub v: Vec<Motion>,
    /// `a[i]`: spatial acceleration of body i minus gravity (the base accelerates at −g),
    /// in body i's frame. nb entries.
    pub a: Vec<Motion>,
    /// `f[i]`: spatial force body i receives across joint i, in body i's frame. nb entries.
    pub f: Vec<Force>,
    /// `ic[i]`: composite inertia of the subtree rooted at body i, in body i's frame. nb entries.
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
    /// `body_pose[i] = o_T_i`: world placement of body i (from [`forward_kinematics`]). nb.
    ///
    /// [`forward_kinematics`]: crate::algo::forward_kinematics
    pub body_pose: Vec<Pose>,
    /// With mimic joints only (else empty): the bodies' twins of q, qd, qdd (nb) and of `tau`,
    /// `g`, `bias` (nb) and `m` (nb×nb), which the algorithms fill before reducing them to the
    /// coordinates (`model.reduce_forces`, `model.reduce_matrix`).
    pub(crate) body: BodyTerms,
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

/// The bodies' terms of a model with mimic joints (see [`Data`]).
#[derive(Clone, Debug)]
pub(crate) struct BodyTerms {
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    pub tau: DVector<f64>,
    pub g: DVector<f64>,
    pub bias: DVector<f64>,
    pub m: DMatrix<f64>,
}

impl BodyTerms {
    fn new(nb: usize) -> Self {
        BodyTerms {
            q: vec![0.0; nb],
            qd: vec![0.0; nb],
            qdd: vec![0.0; nb],
            tau: DVector::zeros(nb),
            g: DVector::zeros(nb),
            bias: DVector::zeros(nb),
            m: DMatrix::zeros(nb, nb),
        }
    }
}

impl Data {
    /// A workspace for `model`.
    pub fn new(model: &Model) -> Self {
        let n = model.dof();
        let nb = model.num_bodies();
        Data {
            xup: vec![Xform::IDENTITY; nb],
            v: vec![Motion::ZERO; nb],
            a: vec![Motion::ZERO; nb],
            f: vec![Force::ZERO; nb],
            ic: vec![Inertia::ZERO; nb],
            tau: DVector::zeros(n),
            g: DVector::zeros(n),
            bias: DVector::zeros(n),
            m: DMatrix::zeros(n, n),
            qdd: DVector::zeros(n),
            body_pose: vec![Pose::IDENTITY; nb],
            body: BodyTerms::new(if model.has_mimic() { nb } else { 0 }),
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
