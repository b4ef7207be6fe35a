//! The algorithms checked against each other on seeded random states of four differently
//! shaped models (the Faze4, a serial arm with a prismatic joint, a branched tree, an arm whose
//! wrist and second finger are mimic followers).

use crate::common;

use common::*;
use faze4::algo::{
    Data, bias, cholesky_factor, compute_all_terms, crba, forward_dynamics, forward_kinematics, frame_jacobian,
    gravity, rnea, update_joint_transforms,
};
use faze4::model::Model;
use nalgebra::{DMatrix, DVector};

const MODELS: [&str; 4] = [
    "urdf/faze4_arm.urdf",
    "tests/urdf/arm_prismatic.urdf",
    "tests/urdf/tree_arm.urdf",
    "tests/urdf/mimic_gripper_arm.urdf",
];
const STATES: usize = 50;

fn for_each_state(mut check: impl FnMut(&str, &Model, &mut Data, &[f64], &[f64], &[f64])) {
    for (m, path) in MODELS.iter().enumerate() {
        let model = load(path);
        let mut data = Data::new(&model);
        let mut rng = Rng::new(0xFA2E4 + m as u64);
        for _ in 0..STATES {
            let q = rng.configuration(&model);
            let v = rng.vector(model.dof(), -2.0, 2.0);
            let a = rng.vector(model.dof(), -5.0, 5.0);
            check(path, &model, &mut data, &q, &v, &a);
        }
    }
}

#[test]
fn joint_transforms_are_the_joint_motion_composed_with_the_tree_transform() {
    // the loop's shortcut (the axis split, no products by zero or one) against the definition
    for_each_state(|path, model, data, q, _, _| {
        // the bodies' positions (q itself without mimic joints)
        let mut qb = vec![0.0; model.num_bodies()];
        model.expand_positions(q, &mut qb);
        update_joint_transforms(model, data, &qb);
        for i in 0..model.num_bodies() {
            let x = model.bodies[i]
                .motion_pose(qb[i])
                .to_xform()
                .compose(&model.tree_pose[i].to_xform());
            let (de, dr) = ((data.xup[i].e - x.e).amax(), (data.xup[i].r - x.r).amax());
            assert!(de < 1e-15 && dr < 1e-15, "{path}: joint {i}: {de:e}, {dr:e}");
        }
    });
}

#[test]
fn mass_matrix_is_symmetric_positive_definite() {
    for_each_state(|path, model, data, q, _, _| {
        let m = crba(model, data, q).clone();
        assert_eq!(m, m.transpose(), "{path}: M not symmetric");
        let mut l = DMatrix::zeros(model.dof(), model.dof());
        assert!(
            cholesky_factor(&m, &mut l).is_ok(),
            "{path}: M not positive definite at {q:?}"
        );
    });
}

#[test]
fn mass_matrix_and_bias_add_up_to_inverse_dynamics() {
    // M(q) v̇ + C(q, v) v + g(q) = RNEA(q, v, v̇)
    for_each_state(|path, model, data, q, v, a| {
        let m = crba(model, data, q).clone();
        let b = bias(model, data, q, v).clone();
        let tau = rnea(model, data, q, v, a).clone();
        let lhs = &m * DVector::from_column_slice(a) + b;
        let err = (lhs - &tau).amax() / tau.amax().max(1.0);
        assert!(err < 1e-12, "{path}: M v̇ + Cv + g differs from RNEA by {err:e}");
    });
}

#[test]
fn all_terms_agree_with_rnea_and_crba() {
    // one kinematics pass, gravity from composite inertias = separate RNEA and CRBA calls
    for_each_state(|path, model, data, q, v, _| {
        let g = gravity(model, data, q).clone();
        let b = bias(model, data, q, v).clone();
        let m = crba(model, data, q).clone();
        compute_all_terms(model, data, q, v);
        let eg = (&data.g - &g).amax() / g.amax().max(1e-300);
        let eb = (&data.bias - &b).amax() / b.amax().max(1e-300);
        assert!(
            eg < 1e-12 && eb < 1e-12,
            "{path}: g differs by {eg:e}, bias by {eb:e} (relative)"
        );
        assert_eq!(data.m, m, "{path}: M");
    });
}

#[test]
fn forward_dynamics_inverts_inverse_dynamics() {
    // FD(q, v, RNEA(q, v, v̇) + D v) = v̇
    for_each_state(|path, model, data, q, v, a| {
        let mut tau = rnea(model, data, q, v, a).clone();
        for (i, d) in model.damping().enumerate() {
            tau[i] += d * v[i];
        }
        let qdd = forward_dynamics(model, data, q, v, tau.as_slice()).unwrap();
        let err = max_abs_diff(qdd.as_slice(), a);
        assert!(err < 1e-9, "{path}: forward dynamics misses v̇ by {err:e}");
    });
}

#[test]
fn jacobian_is_the_derivative_of_forward_kinematics() {
    let h = 1e-6;
    for_each_state(|path, model, data, q, _, _| {
        for frame in 0..model.frames.len() {
            forward_kinematics(model, data, q);
            let jac = frame_jacobian(model, data, faze4::model::FrameId(frame)).clone();
            for j in 0..model.dof() {
                let mut qp = q.to_vec();
                let mut qm = q.to_vec();
                qp[j] += h;
                qm[j] -= h;
                forward_kinematics(model, data, &qp);
                let (pp, rp) = (data.frame_pose[frame].pos, data.frame_pose[frame].rot);
                forward_kinematics(model, data, &qm);
                let (pm, rm) = (data.frame_pose[frame].pos, data.frame_pose[frame].rot);
                // linear: dp/dq; angular: the axial vector of (dR/dq) Rᵀ
                let dp = (pp - pm) / (2.0 * h);
                let dr = (rp - rm) / (2.0 * h);
                forward_kinematics(model, data, q);
                let w = dr * data.frame_pose[frame].rot.transpose();
                let omega = [w[(2, 1)], w[(0, 2)], w[(1, 0)]];
                for r in 0..3 {
                    let e_ang = (jac[(r, j)] - omega[r]).abs();
                    let e_lin = (jac[(r + 3, j)] - dp[r]).abs();
                    assert!(
                        e_ang < 1e-8 && e_lin < 1e-8,
                        "{path}: frame {} column {j}: angular {e_ang:e}, linear {e_lin:e}",
                        model.frames[frame].name
                    );
                }
            }
        }
    });
}

#[test]
fn kinetic_energy_is_conserved_without_damping_gravity_or_torque() {
    for path in MODELS {
        let mut model = load(path);
        model.gravity = Default::default();
        for j in &mut model.joints {
            j.damping = 0.0;
        }
        let mut data = Data::new(&model);
        let n = model.dof();
        let mut rng = Rng::new(7);
        let zero = vec![0.0; n];
        let energy = |data: &mut Data, q: &[f64], v: &[f64]| {
            let m = crba(&model, data, q);
            let v = DVector::from_column_slice(v);
            0.5 * v.dot(&(m * &v))
        };
        let accel = |data: &mut Data, q: &[f64], v: &[f64]| -> Vec<f64> {
            forward_dynamics(&model, data, q, v, &zero).unwrap().as_slice().to_vec()
        };
        let mut q = rng.configuration(&model);
        let mut v = rng.vector(n, -1.5, 1.5);
        let e0 = energy(&mut data, &q, &v);
        // classical RK4 on (q, v), 0.5 s at h = 1e-3
        let h = 1e-3;
        for _ in 0..500 {
            let axpy = |x: &[f64], k: &[f64], s: f64| -> Vec<f64> { x.iter().zip(k).map(|(a, b)| a + s * b).collect() };
            let k1q = v.clone();
            let k1v = accel(&mut data, &q, &v);
            let k2q = axpy(&v, &k1v, h / 2.0);
            let k2v = accel(&mut data, &axpy(&q, &k1q, h / 2.0), &k2q);
            let k3q = axpy(&v, &k2v, h / 2.0);
            let k3v = accel(&mut data, &axpy(&q, &k2q, h / 2.0), &k3q);
            let k4q = axpy(&v, &k3v, h);
            let k4v = accel(&mut data, &axpy(&q, &k3q, h), &k4q);
            for i in 0..n {
                q[i] += h / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i]);
                v[i] += h / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i]);
            }
        }
        let e1 = energy(&mut data, &q, &v);
        let drift = (e1 - e0).abs() / e0;
        assert!(
            drift < 1e-8,
            "{path}: kinetic energy drifted by {drift:e} (from {e0} J to {e1} J)"
        );
        // and the motion was not trivial
        assert!(v.iter().any(|x| x.abs() > 0.1));
    }
}
