//! One position target: the weighted-minimum-change solve.

use super::{IkSolution, IkTask, IkWeights, IkWorkspace, Limit};
use crate::algo::{cholesky_factor, cholesky_solve, crba, forward_kinematics, frame_jacobian, frame_position};
use crate::error::{Error, Result};
use crate::model::{JointId, JointKind, Model};
use crate::spatial::{Mat3, Vec3};

/// Below this step (rad, max over joints) a subproblem step is taken whole, without the line
/// search: the linearisation is then exact to rounding (the residual after it is O(step²)).
const LOCAL_STEP: f64 = 1e-6;
/// The weighted minimum is reached when the subproblem step falls below this (rad, max norm).
const STEP_TOLERANCE: f64 = 1e-11;
/// A subproblem solution may cross a limit by this much (rad or m) before the limit becomes
/// active; it is then clamped onto the limit, so solutions never leave the box.
const LIMIT_SLACK: f64 = 1e-12;
/// The line search starts no farther than this along a subproblem step (rad or m, max over
/// joints): the linearisation is not trusted beyond.
const MAX_STEP: f64 = 1.0;
/// Smallest line-search fraction before the damped fallback takes over.
const MIN_STEP_FRACTION: f64 = 1e-6;
/// Armijo sufficient-decrease constant of the line search.
const ARMIJO: f64 = 1e-4;
/// Damping attempts (each 10× stronger) before the residual is declared stalled.
const DAMPING_TRIES: usize = 12;
/// Convexification weights σ tried in the subproblem, relative to W / mean |c_j|² (see
/// [`subproblem`]); σ = 0 first.
const CONVEXIFY: [f64; 5] = [0.0, 1.0, 1e2, 1e4, 1e6];

/// Places frame `task.frame`'s origin on `target` (world, m), moving only `task.free`, by the
/// smallest weighted change from `q_prev` (n joint positions, rad or m) within the joint limits:
///
/// ```text
///   min ½ (q − q_prev)ᵀ W (q − q_prev)   s.t.   p(q) = target,   lower ≤ q ≤ upper
/// ```
///
/// Held joints keep their `q_prev` value exactly; free joints of `q_prev` outside their limits
/// are first clamped into them. Each iteration is an SQP step: p is linearised at the iterate
/// q_k (Jacobian columns c_j), the objective is modelled with the Hessian of the Lagrangian
/// `W − Σ_i λ_i ∇²p_i` (λ from the previous step; plain W, i.e. the weighted projection of
/// `q_prev` onto the linearised constraint, when that model is not convex), the limits enter
/// through an active set, and the step is taken with a backtracking line search on the exact
/// penalty `½ |q − q_prev|²_W + ρ |e|` (e = target − p). When no step of that kind decreases
/// it (near a singularity, or out of reach) a damped least-squares step on |e| alone is taken
/// instead. Converged when |e| ≤ `task.tolerance_m` and the step is below 1e-11 rad.
///
/// Errors: [`Error::InvalidArgument`] for a bad task or `q_prev` (wrong length, not finite, a
/// held joint outside its limits); [`Error::Unreachable`] when the residual cannot be brought
/// below the tolerance, naming the target and the closest distance reached.
pub fn solve_position(
    model: &Model,
    ws: &mut IkWorkspace,
    task: &IkTask,
    target: &Vec3,
    q_prev: &[f64],
) -> Result<IkSolution> {
    check_inputs(model, task, q_prev)?;
    check_target(target)?;
    solve(model, ws, task, target, q_prev).map_err(|closest_m| Error::Unreachable {
        sample: None,
        target: (*target).into(),
        frame: model.frame(task.frame).name.clone(),
        closest_m,
    })
}

/// Checks a task and a start configuration before solving.
pub(super) fn check_inputs(model: &Model, task: &IkTask, q: &[f64]) -> Result<()> {
    task.validate(model)?;
    let n = model.dof();
    if q.len() != n {
        return Err(Error::ik(
            "q_prev",
            format!("{} joint positions given, the model has {n} joints", q.len()),
        ));
    }
    for (j, joint) in model.joints.iter().enumerate() {
        if !q[j].is_finite() {
            return Err(Error::ik("q_prev", format!("joint '{}' is {}", joint.name, q[j])));
        }
        if !task.free.contains(&JointId(j)) && !joint.within_limits(q[j]) {
            return Err(Error::ik(
                "q_prev",
                format!(
                    "held joint '{}' at {} is outside its limits [{}, {}]",
                    joint.name, q[j], joint.lower, joint.upper
                ),
            ));
        }
    }
    Ok(())
}

/// Checks that a target is a finite point.
pub(super) fn check_target(target: &Vec3) -> Result<()> {
    if target.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(Error::ik("target", format!("{target:?} is not a finite point")))
    }
}

/// The solve on checked inputs; `Err` carries the closest distance reached (m).
pub(super) fn solve(
    model: &Model,
    ws: &mut IkWorkspace,
    task: &IkTask,
    target: &Vec3,
    q_prev: &[f64],
) -> std::result::Result<IkSolution, f64> {
    set_weights(model, ws, task, q_prev);
    ws.on_branch.fill(false);
    let mut body = model.frame(task.frame).body.map(|b| b.0);
    while let Some(j) = body {
        ws.on_branch[model.bodies[j].coordinate] = true;
        body = model.parent[j];
    }
    // q_0 = q_prev, free joints clamped into their limits
    ws.q.copy_from_slice(q_prev);
    for &JointId(j) in &task.free {
        let joint = &model.joints[j];
        ws.q[j] = ws.q[j].clamp(joint.lower, joint.upper);
        ws.active[j] = None;
    }
    ws.lambda = Vec3::zeros();
    let mut e = target - linearise(model, ws, task);
    let mut closest = e.norm();
    // ν: damping of the fallback step, relative to |e|²
    let mut nu = 1.0_f64;
    let mut iterations = 0;
    while iterations < task.max_iterations {
        let e_norm = e.norm();
        // the SQP step with the Lagrangian's Hessian, else with W alone (λ = 0 in the model)
        let mut sqp_step = None;
        for exact in [true, false] {
            if !exact && ws.lambda == Vec3::zeros() {
                break; // the same model again
            }
            match subproblem(model, ws, task, q_prev, &e, exact) {
                Some(lambda) => {
                    // ρ = 2|λ| of this subproblem: the step is a descent direction of φ
                    sqp_step = line_search(model, ws, task, target, q_prev, e_norm, 2.0 * lambda.norm());
                    if sqp_step.is_some() {
                        ws.lambda = lambda;
                        break;
                    }
                }
                // no active set settled: start the next subproblem from none
                None => task.free.iter().for_each(|&JointId(j)| ws.active[j] = None),
            }
        }
        if sqp_step.is_none() && !damped_step(model, ws, task, target, e_norm, &mut nu) {
            break; // |e| cannot decrease: on the target, or at a local minimum of the distance
        }
        iterations += 1;
        std::mem::swap(&mut ws.q, &mut ws.q_try);
        e = target - linearise(model, ws, task);
        closest = closest.min(e.norm());
        if e.norm() <= task.tolerance_m && sqp_step.is_some_and(|s| s <= STEP_TOLERANCE) {
            return Ok(solution(ws, &e, iterations));
        }
    }
    if e.norm() <= task.tolerance_m {
        // on the target, but the weighted minimum is not confirmed to STEP_TOLERANCE
        return Ok(solution(ws, &e, iterations));
    }
    Err(closest)
}

fn solution(ws: &IkWorkspace, e: &Vec3, iterations: usize) -> IkSolution {
    IkSolution {
        q: ws.q.clone(),
        residual_m: e.norm(),
        iterations,
    }
}

/// The weights w_j of the free joints, normalised to mean 1 (the minimiser does not change).
fn set_weights(model: &Model, ws: &mut IkWorkspace, task: &IkTask, q_prev: &[f64]) {
    match &task.weights {
        IkWeights::Identity => ws.w.fill(1.0),
        IkWeights::Diagonal(w) => ws.w.copy_from_slice(w),
        IkWeights::MassDiagonal => {
            let m = crba(model, &mut ws.data, q_prev);
            for j in 0..model.dof() {
                ws.w[j] = m[(j, j)];
            }
        }
    }
    let mean = task.free.iter().map(|&JointId(j)| ws.w[j]).sum::<f64>() / task.free.len() as f64;
    for &JointId(j) in &task.free {
        ws.w[j] /= mean;
    }
}

/// FK and the frame Jacobian at `ws.q`: stores the free joints' linear columns
/// c_j = ∂p/∂q_j (world, m/rad) in `ws.col` and world rotation axes in `ws.axis`, and returns p
/// (world, m).
fn linearise(model: &Model, ws: &mut IkWorkspace, task: &IkTask) -> Vec3 {
    forward_kinematics(model, &mut ws.data, &ws.q);
    let jac = frame_jacobian(model, &mut ws.data, task.frame);
    for &JointId(j) in &task.free {
        // rows 3..6 of the 6×n spatial Jacobian: the origin's linear velocity
        ws.col[j] = Vec3::new(jac[(3, j)], jac[(4, j)], jac[(5, j)]);
        ws.axis[j] = match model.joints[j].kind {
            JointKind::Revolute | JointKind::Continuous => Vec3::new(jac[(0, j)], jac[(1, j)], jac[(2, j)]),
            JointKind::Prismatic => Vec3::zeros(),
        };
    }
    ws.data.frame_pose[task.frame.0].pos
}

/// ∂²p/∂q_j∂q_k (world, m/rad²) for joints j, k on the frame's branch: ω_a × c_b, with a the
/// one nearer the root (rotating joint a turns the whole lever c_b of the other; a prismatic
/// joint turns nothing, ω = 0). Zero when either joint does not move the frame.
fn second_derivative(ws: &IkWorkspace, j: usize, k: usize) -> Vec3 {
    if !(ws.on_branch[j] && ws.on_branch[k]) {
        return Vec3::zeros();
    }
    // on one branch, the smaller index is the ancestor (parent[i] < i)
    let (a, b) = if j <= k { (j, k) } else { (k, j) };
    ws.axis[a].cross(&ws.col[b])
}

/// The subproblem at q_k, in the step Δ = q − q_k over the free joints:
///
/// ```text
///   min ½ Δᵀ H Δ + gᵀ Δ   s.t.   Σ c_j Δ_j = e_k,   lower − q_k ≤ Δ ≤ upper − q_k
/// ```
///
/// g_j = w_j (q_k,j − q_prev,j), H = W − Σ_i λ_i ∇²p_i when `exact` (λ from the previous step),
/// else H = W (then the solution is the weighted projection of q_prev onto the linearised
/// constraint). Joints in the active set sit on a limit; for the others
/// `H_RR Δ_R = C_Rᵀ λ − h_R`, solved through the 3×3 Schur complement. When H_RR is not
/// positive definite, σ C_RᵀC_R is added to it (σ |C Δ − e|² vanishes on the constraint, so
/// the solution is unchanged), for growing σ; none working means the model is not convex on
/// the constraint. Stores Δ in `ws.step` and returns the new λ, or `None` (not convex, rank
/// deficient, or no active set settled).
fn subproblem(
    model: &Model,
    ws: &mut IkWorkspace,
    task: &IkTask,
    q_prev: &[f64],
    e: &Vec3,
    exact: bool,
) -> Option<Vec3> {
    let free = &task.free;
    // H_jk = w_j δ_jk − λ · ∂²p/∂q_j∂q_k
    let lambda_model = if exact { ws.lambda } else { Vec3::zeros() };
    ws.hess.fill(0.0);
    for &JointId(j) in free {
        for &JointId(k) in free {
            let w = if j == k { ws.w[j] } else { 0.0 };
            ws.hess[(j, k)] = w - lambda_model.dot(&second_derivative(ws, j, k));
        }
    }
    let grad = |ws: &IkWorkspace, j: usize| ws.w[j] * (ws.q[j] - q_prev[j]);
    let bound = |ws: &IkWorkspace, j: usize, limit: Limit| match limit {
        Limit::Lower => model.joints[j].lower - ws.q[j],
        Limit::Upper => model.joints[j].upper - ws.q[j],
    };
    for _ in 0..2 * free.len() + 2 {
        // Δ_A on the limits; R the joints off them
        ws.step.fill(0.0);
        for &JointId(j) in free {
            if let Some(limit) = ws.active[j] {
                ws.step[j] = bound(ws, j, limit);
            }
        }
        let mean_c2 = free
            .iter()
            .filter(|&&JointId(j)| ws.active[j].is_none())
            .map(|&JointId(j)| ws.col[j].norm_squared())
            .sum::<f64>()
            / free.len() as f64;
        // M = H_RR + σ C_RᵀC_R, the identity outside R (those rows decouple)
        let mut sigma = None;
        for scale in CONVEXIFY {
            let s = if scale == 0.0 { 0.0 } else { scale / mean_c2 };
            ws.reduced.fill_with_identity();
            for &JointId(j) in free.iter().filter(|&&JointId(j)| ws.active[j].is_none()) {
                for &JointId(k) in free.iter().filter(|&&JointId(k)| ws.active[k].is_none()) {
                    ws.reduced[(j, k)] = ws.hess[(j, k)] + s * ws.col[j].dot(&ws.col[k]);
                }
            }
            if cholesky_factor(&ws.reduced, &mut ws.chol).is_ok() {
                sigma = Some(s);
                break;
            }
        }
        let sigma = sigma?;
        // h_R = g_R + H_RA Δ_A + σ C_Rᵀ (C_A Δ_A − e),  C_A Δ_A = Σ_A c_j Δ_j
        let ca: Vec3 = free
            .iter()
            .filter(|&&JointId(j)| ws.active[j].is_some())
            .map(|&JointId(j)| ws.col[j] * ws.step[j])
            .sum();
        for i in 0..3 {
            ws.m_inv_c[i].fill(0.0);
        }
        ws.m_inv_h.fill(0.0);
        for &JointId(j) in free.iter().filter(|&&JointId(j)| ws.active[j].is_none()) {
            let h_ra: f64 = free
                .iter()
                .filter(|&&JointId(k)| ws.active[k].is_some())
                .map(|&JointId(k)| ws.hess[(j, k)] * ws.step[k])
                .sum();
            ws.m_inv_h[j] = grad(ws, j) + h_ra + sigma * ws.col[j].dot(&(ca - e));
            for i in 0..3 {
                ws.m_inv_c[i][j] = ws.col[j][i];
            }
        }
        // Y = M⁻¹ C_Rᵀ, z = M⁻¹ h
        for i in 0..3 {
            cholesky_solve(&ws.chol, &mut ws.m_inv_c[i]);
        }
        cholesky_solve(&ws.chol, &mut ws.m_inv_h);
        // (C_R Y) λ = e − C_A Δ_A + C_R z,  then Δ_R = Y λ − z
        let mut schur = Mat3::zeros();
        let mut rhs = e - ca;
        for &JointId(j) in free.iter().filter(|&&JointId(j)| ws.active[j].is_none()) {
            for i in 0..3 {
                for l in 0..3 {
                    schur[(i, l)] += ws.col[j][i] * ws.m_inv_c[l][j];
                }
            }
            rhs += ws.col[j] * ws.m_inv_h[j];
        }
        let lambda = schur.cholesky()?.solve(&rhs);
        if !lambda.iter().all(|x| x.is_finite()) {
            return None;
        }
        for &JointId(j) in free.iter().filter(|&&JointId(j)| ws.active[j].is_none()) {
            ws.step[j] = (0..3).map(|i| ws.m_inv_c[i][j] * lambda[i]).sum::<f64>() - ws.m_inv_h[j];
        }
        // the joint crossing its limit the most becomes active
        let mut worst: Option<(usize, Limit, f64)> = None;
        for &JointId(j) in free.iter().filter(|&&JointId(j)| ws.active[j].is_none()) {
            let (lo, hi) = (bound(ws, j, Limit::Lower), bound(ws, j, Limit::Upper));
            let (limit, excess) = if ws.step[j] < lo {
                (Limit::Lower, lo - ws.step[j])
            } else {
                (Limit::Upper, ws.step[j] - hi)
            };
            if excess > LIMIT_SLACK && worst.is_none_or(|(_, _, x)| excess > x) {
                worst = Some((j, limit, excess));
            }
        }
        if let Some((j, limit, _)) = worst {
            ws.active[j] = Some(limit);
            continue;
        }
        // an active limit whose multiplier μ_j = (H Δ)_j + g_j − c_j·λ pulls out of the box
        // (μ < 0 at a lower limit, μ > 0 at an upper one) is released, the worst first
        let mut release: Option<(usize, f64)> = None;
        for &JointId(j) in free {
            let Some(limit) = ws.active[j] else { continue };
            let h_delta: f64 = free.iter().map(|&JointId(k)| ws.hess[(j, k)] * ws.step[k]).sum();
            let mu = h_delta + grad(ws, j) - ws.col[j].dot(&lambda);
            let wrong = if limit == Limit::Lower { -mu } else { mu };
            if wrong > 0.0 && release.is_none_or(|(_, x)| wrong > x) {
                release = Some((j, wrong));
            }
        }
        if let Some((j, _)) = release {
            ws.active[j] = None;
            continue;
        }
        // Δ clamped onto the limits it may cross by LIMIT_SLACK
        for &JointId(j) in free {
            ws.step[j] = ws.step[j].clamp(bound(ws, j, Limit::Lower), bound(ws, j, Limit::Upper));
        }
        return Some(lambda);
    }
    None
}

/// Backtracking along the subproblem step (from at most [`MAX_STEP`] out) on the merit
/// φ(q) = ½ Σ w_j (q_j − q_prev,j)² + ρ|e(q)|. On success `ws.q_try` holds the accepted point
/// and the accepted step's size (rad, max norm) is returned.
fn line_search(
    model: &Model,
    ws: &mut IkWorkspace,
    task: &IkTask,
    target: &Vec3,
    q_prev: &[f64],
    e_norm: f64,
    rho: f64,
) -> Option<f64> {
    let size = task.free.iter().map(|&JointId(j)| ws.step[j].abs()).fold(0.0, f64::max);
    let merit = |w: &[f64], q: &[f64], e: f64| {
        let d2: f64 = task
            .free
            .iter()
            .map(|&JointId(j)| w[j] * (q[j] - q_prev[j]).powi(2))
            .sum();
        0.5 * d2 + rho * e
    };
    // slope of φ along Δ at α = 0: Σ w_j (q_k,j − q_prev,j) Δ_j − ρ|e_k| (the linearised
    // residual vanishes at α = 1)
    let slope: f64 = task
        .free
        .iter()
        .map(|&JointId(j)| ws.w[j] * (ws.q[j] - q_prev[j]) * ws.step[j])
        .sum::<f64>()
        - rho * e_norm;
    let phi0 = merit(&ws.w, &ws.q, e_norm);
    let mut alpha = (MAX_STEP / size).min(1.0);
    while alpha >= MIN_STEP_FRACTION {
        trial_point(model, ws, task, alpha);
        if size <= LOCAL_STEP {
            return Some(size);
        }
        let e_try = (target - frame_position(model, &ws.q_try, task.frame)).norm();
        if slope < 0.0 && merit(&ws.w, &ws.q_try, e_try) <= phi0 + ARMIJO * alpha * slope {
            return Some(alpha * size);
        }
        alpha *= 0.5;
    }
    None
}

/// `ws.q_try = ws.q + α·ws.step`, free joints clamped into their limits (against rounding).
fn trial_point(model: &Model, ws: &mut IkWorkspace, task: &IkTask, alpha: f64) {
    ws.q_try.copy_from_slice(&ws.q);
    for &JointId(j) in &task.free {
        let joint = &model.joints[j];
        ws.q_try[j] = (ws.q[j] + alpha * ws.step[j]).clamp(joint.lower, joint.upper);
    }
}

/// The fallback: a damped least-squares step on the residual alone,
/// Δ = W⁻¹Cᵀ (C W⁻¹ Cᵀ + ν|e|² I)⁻¹ e, joints that would cross a limit held on it; the damping
/// grows 10× until |e| decreases. On success `ws.q_try` holds the new point and `nu` is relaxed.
fn damped_step(model: &Model, ws: &mut IkWorkspace, task: &IkTask, target: &Vec3, e_norm: f64, nu: &mut f64) -> bool {
    let e = target - ws.data.frame_pose[task.frame.0].pos;
    // bounds on Δ_j: lower_j − q_k,j ≤ Δ_j ≤ upper_j − q_k,j
    let bound = |q: &[f64], j: usize, limit: Limit| match limit {
        Limit::Lower => model.joints[j].lower - q[j],
        Limit::Upper => model.joints[j].upper - q[j],
    };
    if e_norm == 0.0 {
        return false;
    }
    'tries: for _ in 0..DAMPING_TRIES {
        let damping = *nu * e_norm * e_norm;
        for &JointId(j) in &task.free {
            ws.held[j] = None;
        }
        for _ in 0..=task.free.len() {
            // (Σ_free c_j c_jᵀ / w_j + μ² I) λ = e − Σ_held c_j Δ_j,  Δ_j = c_j·λ / w_j
            let mut a = Mat3::identity() * damping;
            let mut b = e;
            for &JointId(j) in &task.free {
                match ws.held[j] {
                    None => a += ws.col[j] * ws.col[j].transpose() / ws.w[j],
                    Some(limit) => b -= ws.col[j] * bound(&ws.q, j, limit),
                }
            }
            let Some(chol) = a.cholesky() else {
                *nu *= 10.0;
                continue 'tries;
            };
            let lambda = chol.solve(&b);
            let mut crossed = false;
            for &JointId(j) in &task.free {
                if let Some(limit) = ws.held[j] {
                    ws.step[j] = bound(&ws.q, j, limit);
                    continue;
                }
                let s = ws.col[j].dot(&lambda) / ws.w[j];
                ws.step[j] = s;
                if s < bound(&ws.q, j, Limit::Lower) {
                    ws.held[j] = Some(Limit::Lower);
                    crossed = true;
                } else if s > bound(&ws.q, j, Limit::Upper) {
                    ws.held[j] = Some(Limit::Upper);
                    crossed = true;
                }
            }
            if !crossed {
                break;
            }
        }
        trial_point(model, ws, task, 1.0);
        let e_try = (target - frame_position(model, &ws.q_try, task.frame)).norm();
        if e_try < e_norm {
            *nu = (*nu * 0.1).max(1e-6);
            return true;
        }
        *nu *= 10.0;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::FrameId;
    use crate::model::PackagePaths;

    fn load(rel: &str) -> Model {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
        Model::from_urdf_file(&path, &PackagePaths::default()).unwrap()
    }

    /// ∂²p/∂q_j∂q_k against central differences of the Jacobian columns, for every joint pair
    /// and every frame: revolute and prismatic joints, and a branching tree.
    #[test]
    fn second_derivatives_match_finite_differences() {
        for rel in [
            "urdf/faze4_arm.urdf",
            "tests/urdf/arm_prismatic.urdf",
            "tests/urdf/tree_arm.urdf",
        ] {
            let model = load(rel);
            let n = model.dof();
            let mut ws = IkWorkspace::new(&model);
            let q: Vec<f64> = (0..n)
                .map(|i| 0.3 + 0.17 * i as f64 * if i % 2 == 0 { 1.0 } else { -1.0 })
                .collect();
            for frame in 1..model.frames.len() {
                let frame = FrameId(frame);
                let task = IkTask {
                    frame,
                    free: JointId::all(n).collect(),
                    ..IkTask::new(&model, frame, &[JointId(0), JointId(1), JointId(2)]).unwrap()
                };
                ws.on_branch.fill(false);
                let mut body = model.frame(frame).body.map(|b| b.0);
                while let Some(j) = body {
                    ws.on_branch[model.bodies[j].coordinate] = true;
                    body = model.parent[j];
                }
                let h = 1e-6;
                for j in 0..n {
                    // c_k(q ± h e_j)
                    ws.q.copy_from_slice(&q);
                    ws.q[j] += h;
                    linearise(&model, &mut ws, &task);
                    let plus = ws.col.clone();
                    ws.q[j] -= 2.0 * h;
                    linearise(&model, &mut ws, &task);
                    let minus = ws.col.clone();
                    ws.q.copy_from_slice(&q);
                    linearise(&model, &mut ws, &task);
                    for k in 0..n {
                        let fd = (plus[k] - minus[k]) / (2.0 * h);
                        let exact = second_derivative(&ws, j, k);
                        assert!(
                            (fd - exact).norm() < 1e-8,
                            "{rel} frame {} ({j}, {k}): {exact:?} vs {fd:?}",
                            frame.0
                        );
                    }
                }
            }
        }
    }
}
