//! Inverse kinematics: joint positions that put one frame's origin exactly on a world target.
//!
//! Position IK with redundancy. A task ([`IkTask`]) names the frame, the FREE joints the solver
//! may move (every other joint is held exactly at its value in `q_prev`) and a diagonal weight
//! W on the free joints. With m free joints and the 3 position constraints, the m − 3 extra
//! degrees of freedom are resolved by the smallest weighted change from the previous solution:
//!
//! ```text
//!   min ½ (q − q_prev)ᵀ W (q − q_prev)   s.t.   p_frame(q) = target,   lower ≤ q ≤ upper
//! ```
//!
//! [`solve_position`] solves one target from `q_prev`; [`solve_path`] solves a sequence, each
//! sample from the previous sample's solution (the first from a seed). A target that cannot be
//! reached gives [`Error::Unreachable`] naming the target and the closest distance reached.
//! There is no tolerance box: the residual is driven to [`IkTask::tolerance_m`] (1e-12 m by
//! default).
//!
//! The algorithm (see [`solve_position`]): SQP. Each step minimises the objective's quadratic
//! model with the Lagrangian's exact Hessian `W − Σ λ_i ∇²p_i` (falling back to W alone, i.e.
//! the weighted projection of `q_prev` onto the linearised constraint) subject to the
//! linearised constraint and the limits (an active set), with a backtracking line search on an
//! exact penalty; a damped least-squares step on the residual takes over far from a solution.

mod path;
mod position;

pub use path::{PathSolution, solve_path};
pub use position::solve_position;

use nalgebra::{DMatrix, DVector};

use crate::algo::Data;
use crate::error::{Error, Result};
use crate::model::{FrameId, JointId, Model};
use crate::spatial::Vec3;

/// Default position tolerance (m): the residual |p_frame(q) − target| a solution reaches.
pub const DEFAULT_TOLERANCE_M: f64 = 1e-12;

/// Default iteration cap of one position solve.
pub const DEFAULT_MAX_ITERATIONS: usize = 100;

/// The joint weighting W of the redundancy resolution (diagonal; only the free joints' entries
/// matter). W is normalised to mean 1 over the free joints, which does not change the minimiser.
#[derive(Clone, Debug, PartialEq)]
pub enum IkWeights {
    /// W = I: the smallest change in joint space (rad²).
    Identity,
    /// W = diag(w): one weight > 0 per joint of the model (n entries).
    Diagonal(Vec<f64>),
    /// W = diag M(q_prev), the joint-space mass matrix's diagonal at the previous solution:
    /// joints that carry more inertia move less.
    MassDiagonal,
}

/// What to solve: the frame whose origin is placed, the joints that may move, the weighting.
#[derive(Clone, Debug, PartialEq)]
pub struct IkTask {
    /// Index into `model.frames` of the frame whose origin goes on the target.
    pub frame: FrameId,
    /// The free joints (distinct, at least 3). Every other joint is held exactly at its value
    /// in `q_prev`.
    pub free: Vec<JointId>,
    /// The weighting W of the change from `q_prev`.
    pub weights: IkWeights,
    /// Position residual to reach (m), [`DEFAULT_TOLERANCE_M`] by default.
    pub tolerance_m: f64,
    /// Iteration cap of one position solve, [`DEFAULT_MAX_ITERATIONS`] by default.
    pub max_iterations: usize,
}

impl IkTask {
    /// A task for frame `frame` with free joints `free`, identity weights and the default
    /// tolerance. Fails when the frame or a joint index is out of range, a joint is repeated,
    /// or fewer than 3 joints are free (a position needs 3).
    pub fn new(model: &Model, frame: FrameId, free: &[JointId]) -> Result<IkTask> {
        let task = IkTask {
            frame,
            free: free.to_vec(),
            weights: IkWeights::Identity,
            tolerance_m: DEFAULT_TOLERANCE_M,
            max_iterations: DEFAULT_MAX_ITERATIONS,
        };
        task.validate(model)?;
        Ok(task)
    }

    /// This task with weighting `weights`.
    pub fn with_weights(mut self, weights: IkWeights) -> IkTask {
        self.weights = weights;
        self
    }

    /// Checks the task against `model` (the fields are public, so the solvers check again).
    pub fn validate(&self, model: &Model) -> Result<()> {
        let n = model.dof();
        if self.frame.0 >= model.frames.len() {
            return Err(Error::ik(
                "frame",
                format!(
                    "frame index {} out of range ({} frames)",
                    self.frame.0,
                    model.frames.len()
                ),
            ));
        }
        if self.free.len() < 3 {
            return Err(Error::ik(
                "free joints",
                format!("{} free joints given, a position needs at least 3", self.free.len()),
            ));
        }
        for (k, &JointId(j)) in self.free.iter().enumerate() {
            if j >= n {
                return Err(Error::ik(
                    "free joints",
                    format!("joint index {j} out of range ({n} joints)"),
                ));
            }
            if self.free[..k].contains(&JointId(j)) {
                return Err(Error::ik(
                    "free joints",
                    format!("joint {j} ('{}') listed twice", model.joints[j].name),
                ));
            }
        }
        if let IkWeights::Diagonal(w) = &self.weights {
            if w.len() != n {
                return Err(Error::ik(
                    "weights",
                    format!("{} weights given, the model has {n} joints", w.len()),
                ));
            }
            if let Some(&JointId(j)) = (self.free.iter()).find(|&&JointId(j)| !(w[j] > 0.0 && w[j].is_finite())) {
                return Err(Error::ik(
                    "weights",
                    format!(
                        "weight of free joint {j} ('{}') is {}, must be > 0",
                        model.joints[j].name, w[j]
                    ),
                ));
            }
        }
        if self.tolerance_m.is_nan() || self.tolerance_m <= 0.0 {
            return Err(Error::ik("tolerance", format!("{} m, must be > 0", self.tolerance_m)));
        }
        Ok(())
    }
}

/// One solved target.
#[derive(Clone, Debug, PartialEq)]
pub struct IkSolution {
    /// The joint positions (n; rad or m). Held joints equal `q_prev` exactly.
    pub q: Vec<f64>,
    /// |p_frame(q) − target| (m).
    pub residual_m: f64,
    /// Accepted steps taken.
    pub iterations: usize,
}

/// The workspace of the IK solvers: the kinematics [`Data`] and the solver's buffers, sized
/// once for a model by [`IkWorkspace::new`]; a solve then allocates only its result.
#[derive(Clone, Debug)]
pub struct IkWorkspace {
    /// Kinematics workspace (FK, Jacobian, mass matrix).
    pub data: Data,
    /// Current iterate q_k (n).
    q: Vec<f64>,
    /// Trial point of the line search (n).
    q_try: Vec<f64>,
    /// Step Δ from q_k (n; zero on held joints).
    step: Vec<f64>,
    /// Normalised weights w_j (n; only free entries used).
    w: Vec<f64>,
    /// Linear-velocity Jacobian columns c_j = ∂p_frame/∂q_j, world (m/rad; n).
    col: Vec<Vec3>,
    /// World rotation axis ω_j of joint j (unit; zero for a prismatic joint; n).
    axis: Vec<Vec3>,
    /// Whether joint j lies between the frame and the root (moves the frame; n).
    on_branch: Vec<bool>,
    /// Multiplier λ of the position constraint from the last subproblem (rad²/m, W-scaled).
    lambda: Vec3,
    /// Hessian of the Lagrangian on the free joints, W − Σ_i λ_i ∇²p_i (n×n).
    hess: DMatrix<f64>,
    /// The subproblem's reduced matrix, and its Cholesky factor (n×n).
    reduced: DMatrix<f64>,
    chol: DMatrix<f64>,
    /// Solves with the reduced matrix: M⁻¹ c_i (rows of C, i = x, y, z) and M⁻¹ h (n each).
    m_inv_c: [DVector<f64>; 3],
    m_inv_h: DVector<f64>,
    /// Active set of the subproblem: the limit free joint j is held at, if any (n).
    active: Vec<Option<Limit>>,
    /// The limit free joint j is held at in the damped step, if any (n).
    held: Vec<Option<Limit>>,
}

impl IkWorkspace {
    /// A workspace for `model`.
    pub fn new(model: &Model) -> Self {
        let n = model.dof();
        IkWorkspace {
            data: Data::new(model),
            q: vec![0.0; n],
            q_try: vec![0.0; n],
            step: vec![0.0; n],
            w: vec![1.0; n],
            col: vec![Vec3::zeros(); n],
            axis: vec![Vec3::zeros(); n],
            on_branch: vec![false; n],
            lambda: Vec3::zeros(),
            hess: DMatrix::zeros(n, n),
            reduced: DMatrix::zeros(n, n),
            chol: DMatrix::zeros(n, n),
            m_inv_c: std::array::from_fn(|_| DVector::zeros(n)),
            m_inv_h: DVector::zeros(n),
            active: vec![None; n],
            held: vec![None; n],
        }
    }
}

/// Which of a joint's two position limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Limit {
    Lower,
    Upper,
}
