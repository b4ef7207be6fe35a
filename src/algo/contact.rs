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
//! Newton's method: gradient `∇ℓ = A v − A v* − Jᵀ γ`, Hessian `H = A + Jᵀ G J` (J the
//! contacts' Jacobians stacked, 3m×n; G block-diagonal, `G_c = −∂γ_c/∂v_c`: tangential block
//! `μ n₀ (I − t tᵀ)/√(‖v_t‖² + ε²)`, t = v_t/√(‖v_t‖²+ε²); normal `−n'(v_n)`), an exact line
//! search on α ∈ [0, 1.5]; it stops when `‖D ∇ℓ‖ ≤ 1e-14 + 1e-6 max(‖D A v‖, ‖D Jᵀγ‖)`,
//! D = diag(A)^−½.
//!
//! The iterates are kept in the affine space that holds the optimum, `v = v* + Y λ` with
//! `Y = A⁻¹ Jᵀ` (n×3m; A's Cholesky factor is the free step's), so that every Newton step is
//! a 3m×3m problem: with `W = J Y` (the Delassus operator) and `v_c = J v* + W λ`,
//!
//! ```text
//!   ∇ℓ = Jᵀ (λ − γ),    H⁻¹ Jᵀ r = Y (I + G W)⁻¹ r     (Woodbury),
//!   Δλ = −(I + G W)⁻¹ (λ − γ),   Δv_c = W Δλ,
//!   dℓ(λ + αΔλ)/dα = Δv_cᵀ (λ + αΔλ − γ(v_c + αΔv_c)),   d²ℓ/dα² = Δv_cᵀ Δλ + Σ Δv_cᵀ G_c Δv_c
//! ```
//!
//! — the same Newton steps and line search as in v, at O(m³ + m n) per iteration. The first
//! iterate is the Newton step in v from the velocity the step starts from (Drake's start),
//! which lands in that space; the optimum is unique (ℓ is strictly convex).
//!
//! Joint limits join the same problem (`lower ≤ q + Δt v ≤ upper`) by step.rs's active set:
//! for a clamped set C, held at the velocities v_C that land them on their limits, the free
//! joints F and the contacts solve the problem above with `A_FF v*_F = b_F − A_FC v_C` and
//! `Y = A⁻¹ P Jᵀ` (P zeroes C's columns, so `W = J_F A_FF⁻¹ J_Fᵀ`); a clamped joint's
//! multiplier is `λᵢ = (A v⁺ − b − Jᵀγ)ᵢ`.

use nalgebra::DVector;

use super::cholesky::cholesky_solve;
use super::step::{advance, change_active_set, free_velocity, land, leaves_limits, solve_clamped};
use super::{Data, State};
use crate::error::{Error, Result};
use crate::model::Model;

/// Drake's stiction tolerance v_s (m/s): the friction regularisation's smallest slip scale.
pub const STICTION_TOLERANCE: f64 = 1e-4;
/// SAP's regularisation factor σ of the friction scale from the Delassus estimate.
pub const SIGMA: f64 = 1e-3;
/// Newton iterations before the step gives up (`Error::ContactNotConverged`).
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
    /// G x.
    fn apply(&self, x: &[f64]) -> [f64; 3] {
        let [g00, g01, g11] = self.g_t;
        [g00 * x[0] + g01 * x[1], g01 * x[0] + g11 * x[1], self.g_n * x[2]]
    }
}

/// The contacts of one step and the solver's workspace. Sized for a model by
/// [`ContactSolver::new`]; its contact buffers grow only when a step has more contacts than
/// any before (no allocation in a steady run).
#[derive(Clone, Debug)]
pub struct ContactSolver {
    n: usize,
    points: Vec<ContactPoint>,
    /// J (3m×n), row-major: contact c's rows t₁, t₂, normal at `3n·c .. 3n·(c+1)`.
    jacobian: Vec<f64>,
    /// Y = A⁻¹ Jᵀ, one column of n per row of J.
    y: Vec<f64>,
    /// W = J Y (3m×3m, row-major).
    w: Vec<f64>,
    /// I + G W (3m×3m, row-major), factored in place.
    system: Vec<f64>,
    invariant: Vec<Invariant>,
    response: Vec<Response>,
    /// J v*, v_c, λ, Δλ, Δv_c and a right-hand side (3m each).
    vc_star: Vec<f64>,
    vc: Vec<f64>,
    lambda: Vec<f64>,
    dlambda: Vec<f64>,
    dvc: Vec<f64>,
    residual: Vec<f64>,
    /// n-vector scratch.
    column: DVector<f64>,
    /// 1/A_ii.
    inverse_diagonal: DVector<f64>,
    /// The free step's b = M v + Δt (τ − bias), kept while the joint limits are solved.
    momentum: DVector<f64>,
    /// Newton iterations of the last step (0: no contact; the first is the seed's; with the
    /// re-solves of the joint-limit active set when a limit was in reach).
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
            y: Vec::new(),
            w: Vec::new(),
            system: Vec::new(),
            invariant: Vec::new(),
            response: Vec::new(),
            vc_star: Vec::new(),
            vc: Vec::new(),
            lambda: Vec::new(),
            dlambda: Vec::new(),
            dvc: Vec::new(),
            residual: Vec::new(),
            column: DVector::zeros(n),
            inverse_diagonal: DVector::zeros(n),
            momentum: DVector::zeros(n),
            iterations: 0,
        }
    }

    /// Forgets the contacts (before the next step's are pushed).
    pub fn clear(&mut self) {
        self.points.clear();
        self.jacobian.clear();
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

    /// γ and G of every contact at v_c, into `response`.
    fn respond(&mut self, dt: f64) {
        self.response.clear();
        for ((p, inv), v) in self.points.iter().zip(&self.invariant).zip(self.vc.chunks_exact(3)) {
            self.response.push(response(p, inv, [v[0], v[1], v[2]], dt));
        }
    }

    /// Jᵀ x (x of length 3m) into `out`.
    fn transpose_times(&self, x: &[f64], out: &mut DVector<f64>) {
        out.fill(0.0);
        for (row, xr) in self.jacobian.chunks_exact(self.n).zip(x) {
            for (o, j) in out.iter_mut().zip(row) {
                *o += j * xr;
            }
        }
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

/// Row r of `x` (rows of length n).
fn row(x: &[f64], n: usize, r: usize) -> &[f64] {
    &x[r * n..(r + 1) * n]
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// ‖D x‖ with D = diag(A)^−½ (`inverse_diagonal` = 1/A_ii).
fn scaled_norm(x: &DVector<f64>, inverse_diagonal: &DVector<f64>) -> f64 {
    x.iter()
        .zip(inverse_diagonal.iter())
        .map(|(x, d)| x * x * d)
        .sum::<f64>()
        .sqrt()
}

/// The step with the contacts in `solver` (pushed at the current q): `free_velocity`, then
/// the contact problem of this module, then q⁺ = q + Δt v⁺. If q⁺ would leave a joint's limits,
/// the contact problem is solved again with the joint-limit active set (docs/contact.md): the
/// clamped joints held at the velocity that lands them on their limit, the contacts and the
/// free joints solved together, until no free joint crosses a limit and no clamped joint is
/// held by a pull. With no contact it is exactly [`super::integrate_discrete`]. `data.m` and
/// `data.bias` must be at (q, v). Fails if `M + Δt·D` is not positive definite, or with
/// `Error::ContactNotConverged` if Newton does not converge in 100 iterations.
pub fn integrate_discrete_with_contacts(
    model: &Model,
    data: &mut Data,
    state: &mut State,
    solver: &mut ContactSolver,
) -> Result<()> {
    free_velocity(model, data, state)?;
    let s = solver;
    s.iterations = 0;
    if s.is_empty() {
        s.response.clear();
        land(model, data, state);
        return Ok(());
    }
    let (v, dt) = (&state.v, state.dt);
    let rows = 3 * s.points.len();
    prepare(s, data, v, dt);
    operators(s, data, |_| false);
    seed(s, v, rows, dt);
    s.iterations = 1;
    newton(s, data, rows, dt, 1)?;
    // v⁺ = v* + Y λ
    add_y_lambda(s, data);
    if leaves_limits(model, data, state) {
        solve_with_limits(model, data, state, s)?;
    }
    advance(data, state);
    Ok(())
}

/// The joint-limit active set with the contacts in the problem: each change of the clamped
/// set (step.rs's rule, with the multiplier `λᵢ = (A v − b − Jᵀγ)ᵢ`) is followed by the contact
/// problem over the free joints, `A` and `v*` those of the clamped step (identity rows for the
/// clamped joints, `A_FF v*_F = b_F − A_FC v_C`) and J's clamped columns set aside in `Y`,
/// Newton starting from the last λ. Leaves v⁺ in `data.rhs` and `b` in `data.limit_rhs`.
fn solve_with_limits(model: &Model, data: &mut Data, state: &State, s: &mut ContactSolver) -> Result<()> {
    let (n, rows, dt) = (s.n, 3 * s.points.len(), state.dt);
    s.momentum.copy_from(&data.limit_rhs);
    data.limit_at.fill(None);
    for _ in 0..4 * n {
        // the multiplier's b + Jᵀγ
        impulses_into(s, &mut data.limit_rhs);
        data.limit_rhs += &s.momentum;
        let changed = change_active_set(model, data, state);
        data.limit_rhs.copy_from(&s.momentum);
        if !changed {
            break;
        }
        solve_clamped(data, n);
        let clamped = std::mem::take(&mut data.limit_at);
        operators(s, data, |i| clamped[i].is_some());
        data.limit_at = clamped;
        newton(s, data, rows, dt, 0)?;
        add_y_lambda(s, data);
    }
    Ok(())
}

/// `data.rhs += Y λ`.
fn add_y_lambda(s: &ContactSolver, data: &mut Data) {
    for (r, l) in s.lambda.iter().enumerate() {
        for (x, y) in data.rhs.iter_mut().zip(row(&s.y, s.n, r)) {
            *x += y * l;
        }
    }
}

/// Jᵀγ (the contacts' impulses in joint space, N·m·s) at the last responses into `out`.
fn impulses_into(s: &mut ContactSolver, out: &mut DVector<f64>) {
    for (c, resp) in s.response.iter().enumerate() {
        s.dvc[3 * c..3 * c + 3].copy_from_slice(&resp.gamma);
    }
    s.transpose_times(&s.dvc, out);
}

/// Newton's iterations from the λ in `s.lambda` until the module's stopping rule holds;
/// `iterations` counts those already spent on this solve (the seed's) towards the limit.
fn newton(s: &mut ContactSolver, data: &Data, rows: usize, dt: f64, mut iterations: usize) -> Result<()> {
    loop {
        // v_c = J v* + W λ; γ, G there; the residual λ − γ
        for r in 0..rows {
            s.vc[r] = s.vc_star[r] + dot(row(&s.w, rows, r), &s.lambda);
        }
        s.respond(dt);
        for (c, resp) in s.response.iter().enumerate() {
            for k in 0..3 {
                s.residual[3 * c + k] = s.lambda[3 * c + k] - resp.gamma[k];
            }
        }
        // ‖D ∇ℓ‖ = ‖D Jᵀ(λ − γ)‖ against ‖D A v‖ = ‖D (b + Jᵀλ)‖ and ‖D Jᵀγ‖
        let mut column = std::mem::take(&mut s.column);
        s.transpose_times(&s.residual, &mut column);
        let gradient = scaled_norm(&column, &s.inverse_diagonal);
        s.transpose_times(&s.lambda, &mut column);
        column += &data.limit_rhs;
        let momentum = scaled_norm(&column, &s.inverse_diagonal);
        impulses_into(s, &mut column);
        let impulse = scaled_norm(&column, &s.inverse_diagonal);
        s.column = column;
        if gradient <= ABS_TOL + REL_TOL * momentum.max(impulse) {
            return Ok(());
        }
        if iterations == MAX_ITERATIONS {
            return Err(Error::ContactNotConverged {
                iterations: MAX_ITERATIONS,
                residual: gradient,
            });
        }
        iterations += 1;
        s.iterations += 1;
        newton_direction(s, rows);
        let alpha = line_search(s, rows, dt);
        for (l, d) in s.lambda.iter_mut().zip(&s.dlambda) {
            *l += alpha * d;
        }
    }
}

/// The first λ: one Newton step in v from the velocity `v` the step starts from (Drake's
/// start), which lands in the affine space: with γ₀, G₀ at v_c0 = J v,
/// `λ = γ₀ + (I + G₀ W)⁻¹ G₀ (v_c0 − J v* − W γ₀)` (v* + Y λ = v − H⁻¹ ∇ℓ(v), by Woodbury).
fn seed(s: &mut ContactSolver, v: &[f64], rows: usize, dt: f64) {
    let n = s.n;
    for r in 0..rows {
        s.vc[r] = dot(row(&s.jacobian, n, r), v);
    }
    s.respond(dt);
    s.lambda.resize(rows, 0.0);
    for (c, resp) in s.response.iter().enumerate() {
        s.lambda[3 * c..3 * c + 3].copy_from_slice(&resp.gamma);
    }
    // residual = v_c0 − J v* − W γ₀, then G₀ times it, solved against I + G₀ W
    for r in 0..rows {
        s.residual[r] = s.vc[r] - s.vc_star[r] - dot(row(&s.w, rows, r), &s.lambda);
    }
    fill_system(s, rows);
    for (c, resp) in s.response.iter().enumerate() {
        let g = resp.apply(&s.residual[3 * c..3 * c + 3]);
        s.dlambda[3 * c..3 * c + 3].copy_from_slice(&g);
    }
    solve_dense(&mut s.system, &mut s.dlambda);
    for (l, d) in s.lambda.iter_mut().zip(&s.dlambda) {
        *l += d;
    }
}

/// The invariants of each contact at the velocity `v` the step starts from (the friction
/// regularisation from the Delassus estimate `J diag(A)⁻¹ Jᵀ`). Sizes the 3m buffers.
fn prepare(s: &mut ContactSolver, data: &Data, v: &[f64], dt: f64) {
    let (n, rows) = (s.n, 3 * s.points.len());
    let a = &data.step_matrix;
    for (d, i) in s.inverse_diagonal.iter_mut().zip(0..n) {
        *d = 1.0 / a[(i, i)];
    }
    for buffer in [&mut s.vc_star, &mut s.vc, &mut s.dlambda, &mut s.dvc, &mut s.residual] {
        buffer.resize(rows, 0.0);
    }
    s.y.resize(rows * n, 0.0);
    s.w.resize(rows * rows, 0.0);
    s.system.resize(rows * rows, 0.0);
    s.invariant.clear();
    for (c, p) in s.points.iter().enumerate() {
        let block = &s.jacobian[3 * n * c..3 * n * (c + 1)];
        let mut w2 = 0.0;
        for r in 0..3 {
            for t in 0..3 {
                let w: f64 = (0..n)
                    .map(|i| block[r * n + i] * block[t * n + i] * s.inverse_diagonal[i])
                    .sum();
                w2 += w * w;
            }
        }
        let vn0 = dot(row(block, n, 2), v);
        let fe0 = p.stiffness * (-p.phi).max(0.0);
        let n0 = (dt * fe0).max(0.0) * (1.0 - p.dissipation * vn0).max(0.0);
        let eps = STICTION_TOLERANCE.max(p.friction * SIGMA * w2.sqrt() / 3.0 * n0);
        s.invariant.push(Invariant { fe0, n0, eps });
    }
}

/// J v* (v* in `data.rhs`), `Y = A⁻¹ Jᵀ` (A's factor in `data.chol`) with the columns of the
/// joints `held` set aside (zero in Jᵀ: the contacts do not move a joint held on its limit)
/// and `W = J Y`.
fn operators(s: &mut ContactSolver, data: &Data, held: impl Fn(usize) -> bool) {
    let (n, rows) = (s.n, 3 * s.points.len());
    for r in 0..rows {
        let jr = row(&s.jacobian, n, r);
        s.vc_star[r] = dot(jr, data.rhs.as_slice());
        for (i, (x, j)) in s.column.iter_mut().zip(jr).enumerate() {
            *x = if held(i) { 0.0 } else { *j };
        }
        cholesky_solve(&data.chol, &mut s.column);
        s.y[r * n..(r + 1) * n].copy_from_slice(s.column.as_slice());
    }
    for r in 0..rows {
        for t in 0..rows {
            s.w[r * rows + t] = dot(row(&s.jacobian, n, r), row(&s.y, n, t));
        }
    }
}

/// Δλ = −(I + G W)⁻¹ (λ − γ) (Gaussian elimination with partial pivoting; I + G W is
/// invertible, G and W being positive semi-definite), and Δv_c = W Δλ.
fn newton_direction(s: &mut ContactSolver, rows: usize) {
    fill_system(s, rows);
    for (d, r) in s.dlambda.iter_mut().zip(&s.residual) {
        *d = -r;
    }
    solve_dense(&mut s.system, &mut s.dlambda);
    for r in 0..rows {
        s.dvc[r] = dot(row(&s.w, rows, r), &s.dlambda);
    }
}

/// `s.system` = I + G W at the responses in `s.response`.
fn fill_system(s: &mut ContactSolver, rows: usize) {
    for (c, resp) in s.response.iter().enumerate() {
        for t in 0..rows {
            let column = [
                s.w[3 * c * rows + t],
                s.w[(3 * c + 1) * rows + t],
                s.w[(3 * c + 2) * rows + t],
            ];
            let gw = resp.apply(&column);
            for k in 0..3 {
                s.system[(3 * c + k) * rows + t] = gw[k] + if 3 * c + k == t { 1.0 } else { 0.0 };
            }
        }
    }
}

/// Solves `m x = b` in place (`m` square, row-major, overwritten; `x` holds b on entry) by
/// Gaussian elimination with partial pivoting. Returns false, leaving `x` meaningless, if a
/// pivot is below 1e-12 of the largest entry of `m` (singular).
fn solve_dense(m: &mut [f64], x: &mut [f64]) -> bool {
    let rows = x.len();
    let tiny = 1e-12 * m.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    for k in 0..rows {
        let pivot = (k..rows)
            .max_by(|&i, &j| m[i * rows + k].abs().total_cmp(&m[j * rows + k].abs()))
            .expect("rows");
        if m[pivot * rows + k].abs() <= tiny {
            return false;
        }
        if pivot != k {
            for t in 0..rows {
                m.swap(k * rows + t, pivot * rows + t);
            }
            x.swap(k, pivot);
        }
        for i in k + 1..rows {
            let f = m[i * rows + k] / m[k * rows + k];
            for t in k..rows {
                m[i * rows + t] -= f * m[k * rows + t];
            }
            x[i] -= f * x[k];
        }
    }
    for k in (0..rows).rev() {
        let tail: f64 = (k + 1..rows).map(|t| m[k * rows + t] * x[t]).sum();
        x[k] = (x[k] - tail) / m[k * rows + k];
    }
    true
}

/// The exact line search: the α ∈ (0, 1.5] minimising ℓ along Δλ, by safeguarded Newton on
/// dℓ/dα (increasing: ℓ is convex).
fn line_search(s: &ContactSolver, rows: usize, dt: f64) -> f64 {
    let curvature = dot(&s.dvc, &s.dlambda);
    let derivatives = |alpha: f64| -> (f64, f64) {
        let (mut d1, mut d2) = (0.0, curvature);
        for r in 0..rows {
            d1 += s.dvc[r] * (s.lambda[r] + alpha * s.dlambda[r]);
        }
        for (c, (p, inv)) in s.points.iter().zip(&s.invariant).enumerate() {
            let at = |k: usize| s.vc[3 * c + k] + alpha * s.dvc[3 * c + k];
            let resp = response(p, inv, [at(0), at(1), at(2)], dt);
            let dvc = &s.dvc[3 * c..3 * c + 3];
            d1 -= dot(&resp.gamma, dvc);
            d2 += dot(&resp.apply(dvc), dvc);
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
