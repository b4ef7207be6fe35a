//! The discrete step (docs/model.md): Drake's discrete `MultibodyPlant` (SAP, no contact) with
//! implicit joint damping and joint limits kept.

use super::{Data, cholesky_factor, cholesky_solve, compute_all_terms};
use crate::error::{Error, Result};
use crate::model::{JointId, Model};

/// What one discrete step advances, MuJoCo's `qpos`, `qvel` and `qfrc` with its `timestep`:
/// the joint positions `q` and velocities `v`, the joint forces `tau` held over the step, and
/// the step's length `dt`. The step reads `tau` and `dt` and writes `q` and `v`; the run's
/// actuation stage writes `tau`.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Joint positions (rad or m), one per moving joint.
    pub q: Vec<f64>,
    /// Joint velocities (rad/s or m/s).
    pub v: Vec<f64>,
    /// Joint forces held over the step (N·m or N).
    pub tau: Vec<f64>,
    /// The step's length Δt (s).
    pub dt: f64,
}

impl State {
    /// At rest at q = 0, no force, for `model`, steps of `dt`.
    pub fn new(model: &Model, dt: f64) -> State {
        let n = model.dof();
        State {
            q: vec![0.0; n],
            v: vec![0.0; n],
            tau: vec![0.0; n],
            dt,
        }
    }

    /// At (q, v) under the forces `tau`, steps of `dt`.
    pub fn at(q: &[f64], v: &[f64], tau: &[f64], dt: f64) -> State {
        State {
            q: q.to_vec(),
            v: v.to_vec(),
            tau: tau.to_vec(),
            dt,
        }
    }
}

/// Advances `state` by one step: [`compute_all_terms`] at (q, v), then [`integrate_discrete`].
pub fn discrete_step(model: &Model, data: &mut Data, state: &mut State) -> Result<()> {
    compute_all_terms(model, data, &state.q, &state.v);
    integrate_discrete(model, data, state)
}

/// The step itself, from `data.m` and `data.bias` already at (q, v) of `state`:
///
/// ```text
///   v⁺ = (M + Δt·D)⁻¹ [ M v + Δt (τ − C v − g) ]
///   q⁺ = q + Δt v⁺
/// ```
///
/// If q⁺ would leave a joint's limits, v⁺ instead solves the same problem with the bound
/// `lower ≤ q + Δt v⁺ ≤ upper` (the minimum of `½ v⁺ᵀ A v⁺ − v⁺ᵀ b` over the box, A and b the
/// matrix and vector above): the joint stops exactly at its limit, and the impulse that stops
/// it acts on the others through M. Fails if `M + Δt·D` is not positive definite.
pub fn integrate_discrete(model: &Model, data: &mut Data, state: &mut State) -> Result<()> {
    free_velocity(model, data, state)?;
    land(model, data, state);
    Ok(())
}

/// The step's matrix `A = M + Δt·D` into `data.step_matrix` (its Cholesky factor in
/// `data.chol`), `b = M v + Δt (τ − bias)` into `data.limit_rhs`, and the free velocity
/// `v* = A⁻¹ b` into `data.rhs`.
pub(super) fn free_velocity(model: &Model, data: &mut Data, state: &State) -> Result<()> {
    let n = model.dof();
    let State { v, tau, dt, .. } = state;
    let dt = *dt;
    // A = M + Δt·D,  b = M v + Δt (τ − bias); M is column-major, so M v is summed column by
    // column (`max(1)`: a model without moving joints has no columns at all)
    data.step_matrix.copy_from(&data.m);
    for (i, joint) in model.joints.iter().enumerate() {
        data.step_matrix[(i, i)] += dt * joint.damping;
    }
    let rhs = data.rhs.as_mut_slice();
    for ((b, &t), &bias) in rhs.iter_mut().zip(tau).zip(data.bias.as_slice()) {
        *b = dt * (t - bias);
    }
    for (column, &vk) in data.m.as_slice().chunks_exact(n.max(1)).zip(v.iter()) {
        for (b, &mik) in rhs.iter_mut().zip(column) {
            *b += mik * vk;
        }
    }
    data.limit_rhs.copy_from(&data.rhs);
    cholesky_factor(&data.step_matrix, &mut data.chol).map_err(|(joint, pivot)| Error::Diverged {
        joint: JointId(joint),
        pivot,
    })?;
    cholesky_solve(&data.chol, &mut data.rhs);
    Ok(())
}

/// From the velocity in `data.rhs` (the solution of `A v⁺ = b`, b in `data.limit_rhs`): if
/// q + Δt v⁺ would leave a joint's limits, the box-constrained solution instead; then
/// `v = v⁺`, `q += Δt v⁺`.
pub(super) fn land(model: &Model, data: &mut Data, state: &mut State) {
    if leaves_limits(model, data, state) {
        solve_with_limits(model, data, state);
    }
    advance(data, state);
}

/// Whether q + Δt v⁺ (v⁺ in `data.rhs`) would leave a joint's limits.
pub(super) fn leaves_limits(model: &Model, data: &Data, state: &State) -> bool {
    let State { q, dt, .. } = state;
    (0..model.dof()).any(|i| !model.joints[i].within_limits(q[i] + dt * data.rhs[i]))
}

/// `v = v⁺` (in `data.rhs`), `q⁺ = q + Δt v⁺`.
pub(super) fn advance(data: &Data, state: &mut State) {
    let dt = state.dt;
    for ((q, v), &v_plus) in state.q.iter_mut().zip(state.v.iter_mut()).zip(data.rhs.iter()) {
        *v = v_plus;
        *q += dt * v_plus;
    }
}

/// Active-set solution of the box-constrained problem into `data.rhs`. Joints in
/// `data.limit_at` are held at the velocity that lands them on their limit; the rest solve
/// `A_FF v_F = b_F − A_FC v_C`. A joint is added when it would cross a limit and released when
/// its constraint would have to pull instead of push.
fn solve_with_limits(model: &Model, data: &mut Data, state: &State) {
    let n = model.dof();
    data.limit_at.fill(None);
    for _ in 0..4 * n {
        if !change_active_set(model, data, state) {
            return;
        }
        solve_clamped(data, n);
    }
}

/// One change of the joint-limit active set `data.limit_at` at the velocity in `data.rhs`: the
/// most violating free joint is clamped to the velocity that lands it on its limit, or else a
/// clamped joint whose multiplier `λᵢ = (A v − b)ᵢ` (b in `data.limit_rhs`) would have to pull
/// instead of push is released. Returns false if there was nothing to change (the optimum).
pub(super) fn change_active_set(model: &Model, data: &mut Data, state: &State) -> bool {
    let n = model.dof();
    let State { q, dt, .. } = state;
    let dt = *dt;
    let bound = |i: usize, v: f64| -> Option<f64> {
        let (lo, hi) = ((model.joints[i].lower - q[i]) / dt, (model.joints[i].upper - q[i]) / dt);
        if v < lo {
            Some(lo)
        } else if v > hi {
            Some(hi)
        } else {
            None
        }
    };
    let worst = (0..n)
        .filter(|&i| data.limit_at[i].is_none())
        .filter_map(|i| bound(i, data.rhs[i]).map(|b| (i, b, (data.rhs[i] - b).abs())))
        .max_by(|x, y| x.2.total_cmp(&y.2));
    if let Some((i, b, _)) = worst {
        data.limit_at[i] = Some(b);
        return true;
    }
    let release = (0..n).find(|&i| {
        data.limit_at[i].is_some_and(|vb| {
            let lambda: f64 = (0..n).map(|k| data.step_matrix[(i, k)] * data.rhs[k]).sum::<f64>() - data.limit_rhs[i];
            let at_lower = vb <= (model.joints[i].lower - q[i]) / dt;
            if at_lower { lambda < 0.0 } else { lambda > 0.0 }
        })
    });
    match release {
        Some(i) => {
            data.limit_at[i] = None;
            true
        }
        None => false,
    }
}

/// Solves `A v = b` with the clamped joints' rows and columns replaced by identity, i.e. free
/// joints get `A_FF v_F = b_F − A_FC v_C` and clamped joints their bound (v into `data.rhs`,
/// the factor of that matrix into `data.chol`).
pub(super) fn solve_clamped(data: &mut Data, n: usize) {
    for i in 0..n {
        data.rhs[i] = match data.limit_at[i] {
            Some(vb) => vb,
            None => {
                let mut r = data.limit_rhs[i];
                for k in 0..n {
                    if let Some(vk) = data.limit_at[k] {
                        r -= data.step_matrix[(i, k)] * vk;
                    }
                }
                r
            }
        };
    }
    // A with identity on the clamped rows and columns
    for i in 0..n {
        for k in 0..n {
            data.limit_matrix[(i, k)] = match (data.limit_at[i], data.limit_at[k]) {
                (None, None) => data.step_matrix[(i, k)],
                _ if i == k => 1.0,
                _ => 0.0,
            };
        }
    }
    // a principal submatrix of a positive-definite A is positive definite
    if cholesky_factor(&data.limit_matrix, &mut data.chol).is_ok() {
        cholesky_solve(&data.chol, &mut data.rhs);
    }
}
