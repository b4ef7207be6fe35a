//! The discrete step with compliant point contact solved inside it (docs/contact.md): the
//! convex problem of Castro et al. 2022 ("An unconstrained convex formulation of compliant
//! contact", SAP), with the "lagged" Hunt–Crossley constraint Drake's discrete
//! `MultibodyPlant` uses by default.
//!
//! ```text
//!   v⁺ = argmin_v  ℓ(v) = ½ (v − v*)ᵀ A (v − v*) + Σ_c ℓ_c(J_c v)
//!   A = M + Δt·D,   v* = the step without contact (step.rs),   q⁺ = q + Δt v⁺
//! ```
//!
//! For contact c, `J_c` (3×n) maps joint velocities to the relative velocity of the two bodies
//! at the contact point, in the contact frame (rows: two tangents t₁, t₂, then the normal from
//! the first object to the second), `v_c = J_c v = (v_t, v_n)`, `v_n > 0` separating. With the
//! penetration `x₀ = −φ₀ > 0`, the stiffness k, the Hunt–Crossley dissipation d and friction μ:
//!
//! ```text
//!   f_e0 = k x₀,                                    n₀ = Δt f_e0 (1 − d v_n0)₊   (v_n0: at v)
//!   n(v_n) = Δt (f_e0 − Δt k v_n)₊ (1 − d v_n)₊     normal impulse
//!   N(v_n) = ∫ n = Δt [v (f_e0 + ½Δf) − ½ d v² (f_e0 + ⅔Δf)],  Δf = −Δt k v,  v = min(v_n, v̂),
//!            v̂ = min(f_e0/(Δt k), 1/d)
//!   ℓ_c = −N(v_n) + μ n₀ ‖v_t‖_ε,   ‖v_t‖_ε = √(‖v_t‖² + ε²) − ε
//!   γ_c = −∂ℓ_c/∂v_c = (−μ n₀ v_t/√(‖v_t‖² + ε²),  n(v_n))       the contact impulse
//!   ε = max(v_s, μ σ w n₀),   v_s = 1e-4 m/s,  σ = 1e-3,  w = ‖J_c diag(A)⁻¹ J_cᵀ‖_F / 3
//! ```
//!
//! ℓ is convex (the friction term uses the impulse n₀ of the previous velocity: "lagged").
//! Newton's method: gradient `A v − A v* − Σ J_cᵀ γ_c`, Hessian `A + Σ J_cᵀ G_c J_c` with
//! `G_c = −∂γ_c/∂v_c` (tangential block `μ n₀ (I − t tᵀ)/√(‖v_t‖² + ε²)`, t = v_t/√(‖v_t‖²+ε²);
//! normal `−n'(v_n)`), an exact line search on α ∈ [0, 1.5], from the previous velocity; it
//! stops when `‖D ∇ℓ‖ ≤ 1e-14 + 1e-6 max(‖D A v‖, ‖D Σ J_cᵀ γ_c‖)`, D = diag(A)^−½.
//!
//! Joint limits are kept by step.rs's active set afterwards, with the contact impulses held
//! (added to the step's right-hand side): limits and contacts are not solved as one problem.

use nalgebra::{DMatrix, DVector};

use super::Data;
use super::cholesky::{cholesky_factor, cholesky_solve};
use super::step::{free_velocity, land};
use crate::error::{Error, Result};
use crate::model::{JointId, Model};

/// Drake's stiction tolerance v_s (m/s): the friction regularisation's smallest slip scale.
pub const STICTION_TOLERANCE: f64 = 1e-4;
/// SAP's regularisation factor σ of the friction scale from the Delassus estimate.
pub const SIGMA: f64 = 1e-3;
/// Newton iterations before the step gives up (it then fails as diverged).
const MAX_ITERATIONS: usize = 100;
/// Convergence tolerances on the scaled gradient (absolute, relative).
const ABS_TOL: f64 = 1e-14;
const REL_TOL: f64 = 1e-6;
/// The line search's largest step.
const ALPHA_MAX: f64 = 1.5;

/// One contact's parameters (the rows of its Jacobian are given through
/// [`ContactSolver::push`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// Signed distance φ₀ at the start of the step (m; negative: penetration).
    pub phi: f64,
    /// Stiffness k (N/m): the two objects' stiffnesses in series.
    pub stiffness: f64,
    /// Hunt–Crossley dissipation d (s/m).
    pub dissipation: f64,
    /// Coulomb friction μ (≥ 0).
    pub friction: f64,
}

/// Per contact, what stays fixed over the Newton iterations.
#[derive(Clone, Copy, Debug, Default)]
struct Invariant {
    /// Elastic force f_e0 = k x₀ (N).
    fe0: f64,
    /// Friction's normal impulse n₀ (N·s).
    n0: f64,
    /// Regularisation ε (m/s).
    eps: f64,
}

/// Per contact, at one velocity: the impulse γ (tangents, normal) and G = −∂γ/∂v_c.
#[derive(Clone, Copy, Debug, Default)]
struct Response {
    gamma: [f64; 3],
    /// Tangential block of G (2×2, symmetric: [g00, g01, g11]).
    g_t: [f64; 3],
    /// Normal entry of G.
    g_n: f64,
}

impl Response {
    /// xᵀ G x.
    fn quadratic(&self, x: [f64; 3]) -> f64 {
        let [g00, g01, g11] = self.g_t;
        g00 * x[0] * x[0] + 2.0 * g01 * x[0] * x[1] + g11 * x[1] * x[1] + self.g_n * x[2] * x[2]
    }
}

/// The contacts of one step and the solver's workspace. Sized for a model by
/// [`ContactSolver::new`]; its contact buffers grow only when a step has more contacts than
/// any before (no allocation in a steady run).
#[derive(Clone, Debug)]
pub struct ContactSolver {
    n: usize,
    points: Vec<ContactPoint>,
    /// Contact c's Jacobian J_c, row-major: rows t₁, t₂, normal at `3n·c .. 3n·(c+1)`.
    jacobian: Vec<f64>,
    invariant: Vec<Invariant>,
    response: Vec<Response>,
    /// J_c v and J_c Δv per contact.
    vc: Vec<[f64; 3]>,
    dvc: Vec<[f64; 3]>,
    v: DVector<f64>,
    grad: DVector<f64>,
    dv: DVector<f64>,
    a_v: DVector<f64>,
    impulse: DVector<f64>,
    hessian: DMatrix<f64>,
    chol: DMatrix<f64>,
    /// Newton iterations of the last solve (0: no contact, or the previous velocity was
    /// already optimal).
    pub iterations: usize,
}

impl ContactSolver {
    /// A workspace for `model`, with no contacts.
    pub fn new(model: &Model) -> ContactSolver {
        let n = model.dof();
        ContactSolver {
            n,
            points: Vec::new(),
            jacobian: Vec::new(),
            invariant: Vec::new(),
            response: Vec::new(),
            vc: Vec::new(),
            dvc: Vec::new(),
            v: DVector::zeros(n),
            grad: DVector::zeros(n),
            dv: DVector::zeros(n),
            a_v: DVector::zeros(n),
            impulse: DVector::zeros(n),
            hessian: DMatrix::zeros(n, n),
            chol: DMatrix::zeros(n, n),
            iterations: 0,
        }
    }

    /// Forgets the contacts (before the next step's are pushed).
    pub fn clear(&mut self) {
        self.points.clear();
        self.jacobian.clear();
        self.response.clear();
    }

    /// Adds a contact; returns its Jacobian (3×n, row-major, zeroed) for the caller to fill:
    /// rows 0 and 1 the tangents, row 2 the normal, each the relative velocity of the second
    /// object with respect to the first at the contact point (m/s per joint velocity).
    pub fn push(&mut self, point: ContactPoint) -> &mut [f64] {
        self.points.push(point);
        let start = self.jacobian.len();
        self.jacobian.resize(start + 3 * self.n, 0.0);
        &mut self.jacobian[start..]
    }

    /// The number of contacts pushed since the last [`ContactSolver::clear`].
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether no contact was pushed.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Contact c's impulse γ at the last solve (N·s): tangents, then normal.
    pub fn impulse(&self, c: usize) -> [f64; 3] {
        self.response[c].gamma
    }
}

/// J_c x for every contact (`jacobian` as in [`ContactSolver`], n columns), into `out`.
fn project(jacobian: &[f64], n: usize, x: &DVector<f64>, out: &mut Vec<[f64; 3]>) {
    out.clear();
    for block in jacobian.chunks_exact(3 * n) {
        let dot = |r: usize| {
            block[r * n..(r + 1) * n]
                .iter()
                .zip(x.iter())
                .map(|(j, x)| j * x)
                .sum::<f64>()
        };
        out.push([dot(0), dot(1), dot(2)]);
    }
}

/// γ and G of one contact at contact velocity `v` (the module's formulas).
fn response(p: &ContactPoint, inv: &Invariant, v: [f64; 3], dt: f64) -> Response {
    let (k, d, mu) = (p.stiffness, p.dissipation, p.friction);
    let vn = v[2];
    let fe = inv.fe0 - dt * k * vn;
    let damping = 1.0 - d * vn;
    let (n, dn) = if fe > 0.0 && damping > 0.0 {
        (dt * fe * damping, -dt * (k * dt * damping + d * fe))
    } else {
        (0.0, 0.0)
    };
    let soft = (v[0] * v[0] + v[1] * v[1] + inv.eps * inv.eps).sqrt();
    let (t0, t1) = (v[0] / soft, v[1] / soft);
    let scale = mu * inv.n0 / soft;
    Response {
        gamma: [-mu * inv.n0 * t0, -mu * inv.n0 * t1, n],
        g_t: [scale * (1.0 - t0 * t0), -scale * t0 * t1, scale * (1.0 - t1 * t1)],
        g_n: -dn,
    }
}

/// The invariants of each contact at the velocity `v` the step starts from, and the friction
/// regularisation from the Delassus estimate `W = J diag(A)⁻¹ Jᵀ`.
fn prepare(s: &mut ContactSolver, a: &DMatrix<f64>, dt: f64) {
    let n = s.n;
    project(&s.jacobian, n, &s.v, &mut s.vc);
    s.invariant.clear();
    for (c, p) in s.points.iter().enumerate() {
        let block = &s.jacobian[3 * n * c..3 * n * (c + 1)];
        let mut w2 = 0.0;
        for r in 0..3 {
            for t in 0..3 {
                let w: f64 = (0..n).map(|i| block[r * n + i] * block[t * n + i] / a[(i, i)]).sum();
                w2 += w * w;
            }
        }
        let fe0 = p.stiffness * (-p.phi).max(0.0);
        let n0 = (dt * fe0).max(0.0) * (1.0 - p.dissipation * s.vc[c][2]).max(0.0);
        let eps = STICTION_TOLERANCE.max(p.friction * SIGMA * w2.sqrt() / 3.0 * n0);
        s.invariant.push(Invariant { fe0, n0, eps });
    }
}

/// The step with the contacts in `solver` (pushed at the current q): [`free_velocity`], then
/// the contact problem of this module, then the joint limits and q⁺ = q + Δt v⁺. With no
/// contact it is exactly [`super::integrate_discrete`]. `data.m` and `data.bias` must be at
/// (q, v). Fails if `M + Δt·D` or the Newton Hessian is not positive definite, or Newton does
/// not converge in 100 iterations.
pub fn integrate_discrete_with_contacts(
    model: &Model,
    data: &mut Data,
    q: &mut [f64],
    v: &mut [f64],
    tau: &[f64],
    dt: f64,
    solver: &mut ContactSolver,
) -> Result<()> {
    free_velocity(model, data, v, tau, dt)?;
    solver.iterations = 0;
    if solver.is_empty() {
        land(model, data, q, v, dt);
        return Ok(());
    }
    let s = solver;
    let n = s.n;
    let (a, b) = (&data.step_matrix, &data.limit_rhs);
    s.v.copy_from_slice(v);
    prepare(s, a, dt);
    // ‖D x‖ with D = diag(A)^−½
    let scaled = |x: &DVector<f64>| (0..n).map(|i| x[i] * x[i] / a[(i, i)]).sum::<f64>().sqrt();
    loop {
        // γ at v, the generalized impulse Σ Jᵀγ, the gradient A v − b − Σ Jᵀγ
        project(&s.jacobian, n, &s.v, &mut s.vc);
        s.response.clear();
        for ((p, inv), vc) in s.points.iter().zip(&s.invariant).zip(&s.vc) {
            s.response.push(response(p, inv, *vc, dt));
        }
        s.impulse.fill(0.0);
        for (block, r) in s.jacobian.chunks_exact(3 * n).zip(&s.response) {
            for (row, g) in block.chunks_exact(n).zip(r.gamma) {
                for (x, j) in s.impulse.iter_mut().zip(row) {
                    *x += j * g;
                }
            }
        }
        a.mul_to(&s.v, &mut s.a_v);
        s.grad.copy_from(&s.a_v);
        s.grad -= b;
        s.grad -= &s.impulse;
        if scaled(&s.grad) <= ABS_TOL + REL_TOL * scaled(&s.a_v).max(scaled(&s.impulse)) {
            break;
        }
        if s.iterations == MAX_ITERATIONS {
            return Err(Error::Diverged {
                joint: JointId(0),
                pivot: f64::NAN,
            });
        }
        s.iterations += 1;
        // Newton direction: (A + Σ Jᵀ G J) Δv = −∇ℓ
        s.hessian.copy_from(a);
        for (block, r) in s.jacobian.chunks_exact(3 * n).zip(&s.response) {
            let g = [[r.g_t[0], r.g_t[1], 0.0], [r.g_t[1], r.g_t[2], 0.0], [0.0, 0.0, r.g_n]];
            for i in 0..n {
                for j in 0..n {
                    let mut h = 0.0;
                    for (x, gx) in g.iter().enumerate() {
                        for (y, gxy) in gx.iter().enumerate() {
                            h += block[x * n + i] * gxy * block[y * n + j];
                        }
                    }
                    s.hessian[(i, j)] += h;
                }
            }
        }
        cholesky_factor(&s.hessian, &mut s.chol).map_err(|(joint, pivot)| Error::Diverged {
            joint: JointId(joint),
            pivot,
        })?;
        s.dv.copy_from(&s.grad);
        s.dv.neg_mut();
        cholesky_solve(&s.chol, &mut s.dv);
        let alpha = line_search(s, a, dt);
        s.v.axpy(alpha, &s.dv, 1.0);
    }
    // the impulses act on the limit solve as given forces
    data.rhs.copy_from(&s.v);
    data.limit_rhs += &s.impulse;
    land(model, data, q, v, dt);
    Ok(())
}

/// The exact line search: the α ∈ (0, 1.5] minimising ℓ(v + α Δv), by safeguarded Newton on
/// dℓ/dα (a convex function of α). Uses `s.grad` (∇ℓ at v) and `s.impulse`.
fn line_search(s: &mut ContactSolver, a: &DMatrix<f64>, dt: f64) -> f64 {
    let n = s.n;
    project(&s.jacobian, n, &s.dv, &mut s.dvc);
    // dℓ/dα = Δvᵀ(A v − b) + α Δvᵀ A Δv − Σ γ_c(v_c + α Δv_c)·Δv_c
    let r0 = s.dv.dot(&s.grad) + s.dv.dot(&s.impulse);
    a.mul_to(&s.dv, &mut s.a_v);
    let quad = s.dv.dot(&s.a_v);
    let derivatives = |alpha: f64| -> (f64, f64) {
        let (mut d1, mut d2) = (r0 + alpha * quad, quad);
        for ((p, inv), (vc, dvc)) in s.points.iter().zip(&s.invariant).zip(s.vc.iter().zip(&s.dvc)) {
            let at = [vc[0] + alpha * dvc[0], vc[1] + alpha * dvc[1], vc[2] + alpha * dvc[2]];
            let r = response(p, inv, at, dt);
            d1 -= r.gamma[0] * dvc[0] + r.gamma[1] * dvc[1] + r.gamma[2] * dvc[2];
            d2 += r.quadratic(*dvc);
        }
        (d1, d2)
    };
    let d0 = derivatives(0.0).0;
    if d0 >= 0.0 {
        // not a descent direction: only round-off at the optimum does this
        return 1.0;
    }
    if derivatives(ALPHA_MAX).0 <= 0.0 {
        return ALPHA_MAX;
    }
    let (mut lo, mut hi, mut alpha) = (0.0, ALPHA_MAX, 1.0);
    for _ in 0..100 {
        let (d1, d2) = derivatives(alpha);
        if d1.abs() <= 1e-12 * d0.abs() {
            break;
        }
        if d1 < 0.0 {
            lo = alpha;
        } else {
            hi = alpha;
        }
        if hi - lo <= 1e-14 {
            break;
        }
        let newton = alpha - d1 / d2;
        alpha = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    alpha
}
