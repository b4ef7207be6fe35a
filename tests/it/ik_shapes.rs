//! Inverse kinematics: the original's shapes solved exactly, the unreachable error, the limits, and
//! the weighted-minimum-change property of the redundancy resolution.
//!
//! `cargo test --test it ik_shapes:: -- --nocapture` prints each shape's figures.

use crate::common;

use common::*;
use faze4::Error;
use faze4::algo::{Data, crba, forward_kinematics};
use faze4::faze4::{BOARD, Q_SEED, SHAPE_FREE_JOINTS, shape_ik_task};
use faze4::ik::{IkTask, IkWeights, IkWorkspace, solve_path, solve_position};
use faze4::model::{FrameId, JointId, Model};
use faze4::spatial::{Mat3, Vec3};
use faze4::traj::shape::Shape;

const POINTS: usize = 240;

fn faze4() -> Model {
    load("urdf/faze4_arm.urdf")
}

/// World position of `frame`'s origin by full forward kinematics.
fn fk(model: &Model, data: &mut Data, q: &[f64], frame: FrameId) -> Vec3 {
    forward_kinematics(model, data, q);
    data.frame_pose[frame.0].pos
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
}

/// Every shape, 240 points from Q_SEED: on target to 1e-6 m, J4 = J6 = 0 exactly, within the
/// limits, and no jump above 0.1 rad between neighbours, the closing pair (last → first)
/// included.
#[test]
fn shapes_are_solved_exactly_smoothly_and_within_limits() {
    let model = faze4();
    let mut data = Data::new(&model);
    let task = shape_ik_task(&model).unwrap();
    assert_eq!(model.frame(task.frame).name, "tool_link");
    for shape in Shape::ALL {
        let targets = shape.targets(POINTS, &BOARD);
        let path = solve_path(&model, &task, &targets, &Q_SEED).unwrap_or_else(|e| panic!("{shape:?}: {e}"));
        assert_eq!(path.q.len(), POINTS);
        let mut max_residual = 0.0_f64;
        let mut tool = Vec::with_capacity(POINTS);
        for (k, q) in path.q.iter().enumerate() {
            assert_eq!(q.len(), model.dof());
            let p = fk(&model, &mut data, q, task.frame);
            let residual = (p - targets[k]).norm();
            assert!(residual < 1e-6, "{shape:?} sample {k}: residual {residual:e} m");
            max_residual = max_residual.max(residual);
            assert!(
                q[3] == 0.0 && q[5] == 0.0,
                "{shape:?} sample {k}: J4, J6 = {}, {}",
                q[3],
                q[5]
            );
            for (j, joint) in model.joints.iter().enumerate() {
                assert!(
                    joint.within_limits(q[j]),
                    "{shape:?} sample {k}: {} = {} outside [{}, {}]",
                    joint.name,
                    q[j],
                    joint.lower,
                    joint.upper
                );
            }
            tool.push(p);
        }
        assert!(path.max_residual_m <= max_residual * 2.0 + 1e-15);
        // neighbour jumps, the loop is periodic
        let jumps: Vec<f64> = (0..POINTS)
            .map(|k| max_abs_diff(&path.q[k], &path.q[(k + 1) % POINTS]))
            .collect();
        let (k_max, max_jump) = jumps
            .iter()
            .copied()
            .enumerate()
            .fold((0, 0.0), |a, (k, x)| if x > a.1 { (k, x) } else { a });
        assert!(max_jump <= 0.1, "{shape:?}: jump {max_jump} rad after sample {k_max}");
        // the report
        let x = range(tool.iter().map(|p| p.x));
        let z = range(tool.iter().map(|p| p.z));
        eprintln!(
            "{:6}: max residual {:.2e} m, max jump {:.4} rad (after sample {k_max}), closing jump {:.4} rad, \
             {} iterations, tool x [{:.4}, {:.4}] z [{:.4}, {:.4}]",
            shape.name(),
            max_residual,
            max_jump,
            jumps[POINTS - 1],
            path.iterations,
            x.0,
            x.1,
            z.0,
            z.1
        );
        for j in 0..model.dof() {
            let (lo, hi) = range(path.q.iter().map(|q| q[j]));
            eprintln!("        J{}: [{lo:+.4}, {hi:+.4}] rad", j + 1);
        }
    }
}

/// docs/model.md: the solved triangle's tool spans x ∈ [−0.0586, 0.2186], z ∈ [0.47, 0.71]; the sine's
/// x ∈ [−0.110, 0.270]; the circle's x ∈ [−0.080, 0.240], z ∈ [0.39, 0.71].
#[test]
fn solved_tool_ranges_match_the_spec() {
    let model = faze4();
    let mut data = Data::new(&model);
    let task = shape_ik_task(&model).unwrap();
    let expected = [
        (Shape::Tri, (-0.0586, 0.2186), (0.47, 0.71), 1e-4),
        (Shape::Sine, (-0.110, 0.270), (0.43, 0.67), 1e-3),
        (Shape::Circle, (-0.080, 0.240), (0.39, 0.71), 1e-3),
    ];
    for (shape, ex, ez, tol) in expected {
        let path = solve_path(&model, &task, &shape.targets(POINTS, &BOARD), &Q_SEED).unwrap();
        let tool: Vec<Vec3> = path.q.iter().map(|q| fk(&model, &mut data, q, task.frame)).collect();
        let x = range(tool.iter().map(|p| p.x));
        let z = range(tool.iter().map(|p| p.z));
        assert!(
            (x.0 - ex.0).abs() < tol && (x.1 - ex.1).abs() < tol,
            "{shape:?}: x {x:?}"
        );
        assert!(
            (z.0 - ez.0).abs() < tol && (z.1 - ez.1).abs() < tol,
            "{shape:?}: z {z:?}"
        );
        assert!(
            tool.iter().all(|p| (p.y + 0.48).abs() < 1e-9),
            "{shape:?}: off the board"
        );
    }
}

/// The number after "closest distance reached " in an Unreachable message.
fn closest_in(message: &str) -> f64 {
    let tail = message
        .split("closest distance reached ")
        .nth(1)
        .unwrap_or_else(|| panic!("no closest distance in: {message}"));
    tail.split_whitespace().next().unwrap().parse().unwrap()
}

/// A target 2 m from the arm: `Error::Unreachable`, naming the sample and the closest distance
/// reached, which is no worse than the best of many random configurations.
#[test]
fn an_unreachable_target_names_the_sample_and_the_closest_distance() {
    let model = faze4();
    let mut data = Data::new(&model);
    let task = shape_ik_task(&model).unwrap();
    let base = fk(&model, &mut data, &[0.0; 6], FrameId(0));
    let far = base + Vec3::new(1.2, -1.6, 0.0); // 2 m from the base link
    let targets = [Shape::Circle.point(0.0, &BOARD), far];
    let err = solve_path(&model, &task, &targets, &Q_SEED).unwrap_err();
    let Error::Unreachable {
        sample, frame, target, ..
    } = &err
    else {
        panic!("not Unreachable: {err}")
    };
    assert_eq!(
        (*sample, frame.as_str(), *target),
        (Some((1, 2)), "tool_link", far.into())
    );
    let message = &err.to_string();
    eprintln!("{message}");
    assert!(!message.contains('\n'), "one line");
    assert!(message.contains("sample 1 of 2"), "{message}");
    assert!(message.contains("tool_link"), "{message}");
    let closest = closest_in(message);
    // the best of random configurations (same free joints, J4 = J6 = 0)
    let mut rng = Rng::new(7);
    let mut sampled = f64::INFINITY;
    for _ in 0..20000 {
        let mut q = rng.configuration(&model);
        q[3] = 0.0;
        q[5] = 0.0;
        sampled = sampled.min((fk(&model, &mut data, &q, task.frame) - far).norm());
    }
    assert!(closest > 0.5, "closest {closest} m to a target 2 m away");
    assert!(
        closest <= sampled + 1e-3,
        "closest reached {closest} m, random configurations reach {sampled} m"
    );

    // the single-target form names the target
    let mut ws = IkWorkspace::new(&model);
    let err = solve_position(&model, &mut ws, &task, &far, &Q_SEED).unwrap_err();
    let Error::Unreachable { sample: None, .. } = &err else {
        panic!("not a single-target Unreachable: {err}")
    };
    let message = &err.to_string();
    assert!(message.contains(&format!("{:.6}", far.x)), "{message}");
    assert!((closest_in(message) - closest).abs() < 1e-3, "{message}");
}

/// The generalised cross product of the three rows of a 3×4 matrix: its null space direction.
fn null_vector(rows: &[[f64; 4]; 3]) -> [f64; 4] {
    let minor = |skip: usize| {
        let cols: Vec<usize> = (0..4).filter(|&c| c != skip).collect();
        Mat3::from_fn(|r, c| rows[r][cols[c]]).determinant()
    };
    let n = [minor(0), -minor(1), minor(2), -minor(3)];
    let norm = n.iter().map(|x| x * x).sum::<f64>().sqrt();
    n.map(|x| x / norm)
}

/// Linear Jacobian of `frame` on the free joints, by central differences of FK.
fn free_jacobian(model: &Model, data: &mut Data, q: &[f64], frame: FrameId) -> [[f64; 4]; 3] {
    let mut rows = [[0.0; 4]; 3];
    let h = 1e-6;
    for (c, &JointId(j)) in SHAPE_FREE_JOINTS.iter().enumerate() {
        let (mut qp, mut qm) = (q.to_vec(), q.to_vec());
        qp[j] += h;
        qm[j] -= h;
        let d = (fk(model, data, &qp, frame) - fk(model, data, &qm, frame)) / (2.0 * h);
        for r in 0..3 {
            rows[r][c] = d[r];
        }
    }
    rows
}

/// Moves `q` back onto p(q) = target by Gauss–Newton with the pseudo-inverse (free joints).
fn project(model: &Model, data: &mut Data, q: &mut [f64], target: &Vec3, frame: FrameId) {
    for _ in 0..20 {
        let e = target - fk(model, data, q, frame);
        if e.norm() < 1e-14 {
            return;
        }
        let j = free_jacobian(model, data, q, frame);
        let jjt = Mat3::from_fn(|r, c| (0..4).map(|k| j[r][k] * j[c][k]).sum());
        let y = jjt.try_inverse().unwrap() * e;
        for (c, &JointId(jj)) in SHAPE_FREE_JOINTS.iter().enumerate() {
            q[jj] += (0..3).map(|r| j[r][c] * y[r]).sum::<f64>();
        }
    }
    panic!("projection did not converge");
}

/// Weighted distance ½ Σ w_j (q_j − q_prev,j)² over the free joints.
fn weighted_distance(q: &[f64], q_prev: &[f64], w: &[f64]) -> f64 {
    SHAPE_FREE_JOINTS
        .iter()
        .map(|&JointId(j)| 0.5 * w[j] * (q[j] - q_prev[j]).powi(2))
        .sum()
}

/// Checks that `q` is a local minimum of the weighted distance to `q_prev` on the manifold
/// p(q) = target: moving along the null space of the free Jacobian (both ways, several sizes)
/// and back onto the manifold never gets closer to `q_prev`.
fn assert_weighted_minimum(model: &Model, q: &[f64], q_prev: &[f64], target: &Vec3, frame: FrameId, w: &[f64]) {
    let mut data = Data::new(model);
    let f0 = weighted_distance(q, q_prev, w);
    let n = null_vector(&free_jacobian(model, &mut data, q, frame));
    for eps in [3e-2, 1e-2, 1e-3, 1e-4, -1e-4, -1e-3, -1e-2, -3e-2] {
        let mut qe = q.to_vec();
        for (c, &JointId(j)) in SHAPE_FREE_JOINTS.iter().enumerate() {
            qe[j] += eps * n[c];
        }
        project(model, &mut data, &mut qe, target, frame);
        let f = weighted_distance(&qe, q_prev, w);
        assert!(
            f >= f0 - 1e-15,
            "moving {eps} rad along the null space lowers ½|Δq|²_W from {f0:e} to {f:e}"
        );
    }
}

/// The redundancy is resolved by the smallest weighted change: identity weights on a large
/// first move from Q_SEED, and diag M(q_prev) weights mid-path.
#[test]
fn the_solution_is_the_weighted_minimum_change() {
    let model = faze4();
    let mut ws = IkWorkspace::new(&model);
    let task = shape_ik_task(&model).unwrap();
    let targets = Shape::Circle.targets(POINTS, &BOARD);

    // identity: the first circle sample is 0.23 m from the seed's tool position
    let sol = solve_position(&model, &mut ws, &task, &targets[0], &Q_SEED).unwrap();
    assert!(sol.residual_m < 1e-10, "{sol:?}");
    assert_weighted_minimum(&model, &sol.q, &Q_SEED, &targets[0], task.frame, &[1.0; 6]);

    // diag M(q_prev): a generic previous configuration, target 3 cm away
    let q_prev = vec![0.3, 0.4, -0.9, 0.0, 0.5, 0.0];
    let mut data = Data::new(&model);
    let target = fk(&model, &mut data, &q_prev, task.frame) + Vec3::new(0.02, 0.01, -0.02);
    let weighted = task.clone().with_weights(IkWeights::MassDiagonal);
    let sol_m = solve_position(&model, &mut ws, &weighted, &target, &q_prev).unwrap();
    let m = crba(&model, &mut data, &q_prev).clone();
    let w: Vec<f64> = (0..6).map(|j| m[(j, j)]).collect();
    assert_weighted_minimum(&model, &sol_m.q, &q_prev, &target, task.frame, &w);
    // and it differs from the identity-weighted answer (the weighting does something)
    let sol_i = solve_position(&model, &mut ws, &task, &target, &q_prev).unwrap();
    assert!(
        max_abs_diff(&sol_m.q, &sol_i.q) > 1e-4,
        "{:?} vs {:?}",
        sol_m.q,
        sol_i.q
    );
    assert_weighted_minimum(&model, &sol_i.q, &q_prev, &target, task.frame, &[1.0; 6]);
}

/// A target that the unconstrained weighted minimum would reach by driving J5 past its upper
/// limit (J5 is made cheap to move, so the minimum change leans on it): the solution holds J5
/// exactly on the limit, reaches the target, and is the smallest change among the
/// configurations with J5 on that limit.
#[test]
fn a_target_next_to_a_joint_limit_is_solved_within_the_limit() {
    let model = faze4();
    let mut data = Data::new(&model);
    let w = [1.0, 1.0, 1.0, 1.0, 1e-3, 1.0];
    let task = shape_ik_task(&model)
        .unwrap()
        .with_weights(IkWeights::Diagonal(w.to_vec()));
    let j5 = 4;
    let upper = model.joints[j5].upper;
    let mut q_prev = Q_SEED.to_vec();
    q_prev[j5] = upper - 0.01;
    // push the tool along J5's own column: the minimum change moves J5 up by more than 0.01
    let jac = free_jacobian(&model, &mut data, &q_prev, task.frame);
    let c5 = Vec3::new(jac[0][3], jac[1][3], jac[2][3]);
    let target = fk(&model, &mut data, &q_prev, task.frame) + c5 * 0.05;

    let mut unlimited = model.clone();
    unlimited.joints[j5].upper = f64::INFINITY;
    let mut ws = IkWorkspace::new(&model);
    let free = solve_position(&unlimited, &mut ws, &task, &target, &q_prev).unwrap();
    assert!(
        free.q[j5] > upper + 1e-3,
        "the set-up must cross the limit: J5 = {}",
        free.q[j5]
    );

    let sol = solve_position(&model, &mut ws, &task, &target, &q_prev).unwrap();
    assert_eq!(sol.q[j5], upper, "J5 held exactly on its limit");
    assert!(
        (fk(&model, &mut data, &sol.q, task.frame) - target).norm() < 1e-10,
        "{sol:?}"
    );
    for (j, joint) in model.joints.iter().enumerate() {
        assert!(joint.within_limits(sol.q[j]), "{}: {}", joint.name, sol.q[j]);
    }
    assert!(sol.q[3] == 0.0 && sol.q[5] == 0.0);
    // with J5 on the limit, J1–J3 place the tool uniquely nearby: the weighted minimum is
    // the same configuration as the three-joint solve holding J5 there
    let mut q_at_limit = q_prev.clone();
    q_at_limit[j5] = upper;
    let three = IkTask::new(&model, task.frame, &[JointId(0), JointId(1), JointId(2)]).unwrap();
    let sol3 = solve_position(&model, &mut ws, &three, &target, &q_at_limit).unwrap();
    assert!(max_abs_diff(&sol.q, &sol3.q) < 1e-9, "{:?} vs {:?}", sol.q, sol3.q);
    // the limit costs something: the limited solution is farther from q_prev
    assert!(weighted_distance(&sol.q, &q_prev, &w) > weighted_distance(&free.q, &q_prev, &w));
}

/// Bad tasks and inputs are argument errors, not panics.
#[test]
fn bad_tasks_and_inputs_are_rejected() {
    let model = faze4();
    let tool = model.default_tool_frame();
    let joints = |ids: &[usize]| ids.iter().map(|&j| JointId(j)).collect::<Vec<_>>();
    assert!(
        IkTask::new(&model, tool, &joints(&[0, 1])).is_err(),
        "fewer than 3 free joints"
    );
    assert!(
        IkTask::new(&model, tool, &joints(&[0, 1, 1])).is_err(),
        "a repeated joint"
    );
    assert!(
        IkTask::new(&model, tool, &joints(&[0, 1, 9])).is_err(),
        "joint out of range"
    );
    assert!(
        IkTask::new(&model, FrameId(99), &joints(&[0, 1, 2])).is_err(),
        "frame out of range"
    );
    let task = shape_ik_task(&model).unwrap();
    let target = Shape::Circle.point(0.0, &BOARD);
    let mut ws = IkWorkspace::new(&model);
    assert!(solve_position(&model, &mut ws, &task, &target, &Q_SEED[..5]).is_err());
    let mut q = Q_SEED;
    q[3] = 4.0; // held J4 outside ±π
    assert!(matches!(
        solve_position(&model, &mut ws, &task, &target, &q),
        Err(Error::InvalidIk { field: "q_prev", .. })
    ));
    let bad = task
        .clone()
        .with_weights(IkWeights::Diagonal(vec![1.0, 1.0, 0.0, 1.0, 1.0, 1.0]));
    assert!(
        solve_position(&model, &mut ws, &bad, &target, &Q_SEED).is_err(),
        "zero weight"
    );
    let nan = Vec3::new(f64::NAN, 0.0, 0.0);
    assert!(solve_path(&model, &task, &[target, nan], &Q_SEED).is_err());
}
