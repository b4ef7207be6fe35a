//! The contact step's solver on its own (docs/contact.md): at the v⁺ it returns, the
//! optimality condition of the convex problem and the contact law hold, on arms of our own
//! (branched, prismatic, coupled) and the Faze4, with random states and random contacts; and a
//! poisoned contact ends the step with an error instead of a hang or a NaN state.

use crate::common;

use common::*;
use faze4::algo::{
    ContactPoint, ContactSolver, Data, SIGMA, STICTION_TOLERANCE, State, compute_all_terms,
    integrate_discrete_with_contacts,
};
use faze4::error::Error;
use faze4::model::Model;
use nalgebra::{DMatrix, DVector};

const DT: f64 = 2e-4;

/// One random contact problem on `model`: a state well inside the limits, torques, and
/// `contacts` contacts with random Jacobians (m/rad or m/m) and penetrations.
struct Problem {
    q: Vec<f64>,
    v: Vec<f64>,
    tau: Vec<f64>,
    points: Vec<ContactPoint>,
    /// Row-major 3m×n: per contact t₁, t₂, n̂.
    jacobian: Vec<f64>,
}

impl Problem {
    fn random(model: &Model, contacts: usize, friction: f64, rng: &mut Rng) -> Problem {
        let n = model.dof();
        let q = (model.joints.iter())
            .map(|j| {
                let (lo, hi) = (j.lower.max(-3.0), j.upper.min(3.0));
                rng.uniform(lo + 0.3 * (hi - lo), hi - 0.3 * (hi - lo))
            })
            .collect();
        let points = (0..contacts)
            .map(|_| ContactPoint {
                phi: rng.uniform(-3e-3, -1e-5),
                stiffness: 5e5,
                dissipation: 50.0,
                friction,
            })
            .collect();
        Problem {
            q,
            v: rng.vector(n, -0.5, 0.5),
            tau: rng.vector(n, -2.0, 2.0),
            points,
            jacobian: rng.vector(3 * n * contacts, -0.4, 0.4),
        }
    }

    /// Pushes the contacts into a cleared `solver`.
    fn load(&self, solver: &mut ContactSolver, n: usize) {
        solver.clear();
        for (c, &point) in self.points.iter().enumerate() {
            solver
                .push(point)
                .copy_from_slice(&self.jacobian[3 * n * c..3 * n * (c + 1)]);
        }
    }
}

/// The impulse of contact `c` by docs/contact.md's law at contact velocity `vc` (tangents,
/// normal), for a step that started at joint velocity `v`; `a` is the step matrix M + Δt·D.
fn law(p: &ContactPoint, rows: &[f64], a: &DMatrix<f64>, v: &[f64], vc: [f64; 3]) -> [f64; 3] {
    let n = v.len();
    let row = |r: usize| &rows[r * n..(r + 1) * n];
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
    let (k, d, mu) = (p.stiffness, p.dissipation, p.friction);
    // the values frozen at the start of the step: f_e0 = k·max(−φ, 0), n₀, ε
    let fe0 = k * (-p.phi).max(0.0);
    let n0 = (DT * fe0) * (1.0 - d * dot(row(2), v)).max(0.0);
    let mut w2 = 0.0;
    for r in 0..3 {
        for t in 0..3 {
            let w: f64 = (0..n).map(|i| row(r)[i] * row(t)[i] / a[(i, i)]).sum();
            w2 += w * w;
        }
    }
    let eps = STICTION_TOLERANCE.max(mu * SIGMA * w2.sqrt() / 3.0 * n0);
    // normal: Δt (f_e0 − Δt k v_n)₊ (1 − d v_n)₊; friction: −μ n₀ v_t / √(|v_t|² + ε²)
    let normal = DT * (fe0 - DT * k * vc[2]).max(0.0) * (1.0 - d * vc[2]).max(0.0);
    let soft = (vc[0] * vc[0] + vc[1] * vc[1] + eps * eps).sqrt();
    [-mu * n0 * vc[0] / soft, -mu * n0 * vc[1] / soft, normal]
}

/// Solves `problem` on `model` and checks the solution: the gradient of ℓ at v⁺,
/// `A v⁺ − b − Jᵀγ`, within the solver's own stopping rule, the impulses equal to the law at
/// J v⁺, and the friction inside its cone `|γ_t| ≤ μ n₀`. Returns the impulses' largest normal
/// component (to check the problems are not trivial).
fn solve_and_check(model: &Model, problem: &Problem) -> f64 {
    let n = model.dof();
    let mut data = Data::new(model);
    let mut solver = ContactSolver::new(model);
    let mut state = State::at(&problem.q, &problem.v, &problem.tau, DT);
    compute_all_terms(model, &mut data, &state.q, &state.v);
    let mut a = data.m.clone();
    for (i, joint) in model.joints.iter().enumerate() {
        a[(i, i)] += DT * joint.damping;
    }
    let b =
        &data.m * DVector::from_column_slice(&problem.v) + DT * (DVector::from_column_slice(&problem.tau) - &data.bias);
    problem.load(&mut solver, n);
    integrate_discrete_with_contacts(model, &mut data, &mut state, &mut solver).unwrap();
    let State { q, v, .. } = state;
    for (j, (&qj, joint)) in q.iter().zip(&model.joints).enumerate() {
        assert!(
            qj > joint.lower && qj < joint.upper,
            "joint {j} reached a limit: not this test's case"
        );
    }

    let v_plus = DVector::from_column_slice(&v);
    let jac = DMatrix::from_row_slice(3 * problem.points.len(), n, &problem.jacobian);
    let vc = &jac * &v_plus;
    let mut gamma = DVector::zeros(3 * problem.points.len());
    let mut deepest = 0.0_f64;
    for (c, p) in problem.points.iter().enumerate() {
        let got = solver.impulse(c);
        let rows = &problem.jacobian[3 * n * c..3 * n * (c + 1)];
        let want = law(p, rows, &a, &problem.v, [vc[3 * c], vc[3 * c + 1], vc[3 * c + 2]]);
        let scale = want.iter().fold(1e-12_f64, |m, x| m.max(x.abs()));
        assert!(
            max_abs_diff(&got, &want) <= 1e-6 * scale,
            "contact {c}: impulse {got:?}, the law at J v⁺ says {want:?}"
        );
        let vn0: f64 = rows[2 * n..].iter().zip(&problem.v).map(|(j, v)| j * v).sum();
        let n0 = DT * p.stiffness * (-p.phi) * (1.0 - p.dissipation * vn0).max(0.0);
        assert!(
            got[0].hypot(got[1]) <= p.friction * n0 * (1.0 + 1e-12),
            "contact {c} outside its cone"
        );
        assert!(got[2] >= 0.0);
        deepest = deepest.max(got[2]);
        gamma.rows_mut(3 * c, 3).copy_from_slice(&got);
    }
    // ‖D ∇ℓ‖ ≤ 1e-14 + 1e-6 max(‖D A v⁺‖, ‖D Jᵀγ‖) with D = diag(A)^−½, and some slack for the
    // impulses read at the last iterate rather than at λ
    let scaled = |x: &DVector<f64>| (0..n).map(|i| x[i] * x[i] / a[(i, i)]).sum::<f64>().sqrt();
    let jt_gamma = jac.transpose() * &gamma;
    let gradient = scaled(&(&a * &v_plus - &b - &jt_gamma));
    let reference = scaled(&(&a * &v_plus)).max(scaled(&jt_gamma));
    assert!(
        gradient <= 1e-13 + 1e-5 * reference,
        "‖D ∇ℓ‖ = {gradient:e} against {reference:e}"
    );
    deepest
}

#[test]
fn the_step_solves_the_contact_problem_on_every_arm() {
    let mut rng = Rng::new(0x5EED_C0A7);
    for rel in [
        "tests/urdf/contact_arm.urdf",
        "tests/urdf/coupled_two_link.urdf",
        "tests/urdf/tree_arm.urdf",
        "tests/urdf/arm_prismatic.urdf",
        "urdf/faze4_real.urdf",
    ] {
        let model = load(rel);
        let mut pressed = 0;
        for trial in 0..40 {
            let friction = [0.0, 0.3, 1.0][trial % 3];
            let problem = Problem::random(&model, 1 + trial % 4, friction, &mut rng);
            let deepest = std::panic::catch_unwind(|| solve_and_check(&model, &problem))
                .unwrap_or_else(|_| panic!("{rel}, trial {trial} (μ {friction})"));
            pressed += usize::from(deepest > 0.0);
        }
        // most random contacts push (some start separating fast enough to let go)
        assert!(pressed > 20, "{rel}: only {pressed} of 40 problems pushed");
    }
}

/// A contact whose Jacobian is not a number cannot converge: the step fails with
/// `ContactNotConverged` after its iterations, and leaves q and v as they were.
#[test]
fn a_poisoned_contact_fails_the_step_and_leaves_the_state() {
    let model = load("tests/urdf/tree_arm.urdf");
    let n = model.dof();
    let mut problem = Problem::random(&model, 2, 1.0, &mut Rng::new(7));
    problem.jacobian[3 * n + 4] = f64::NAN;
    let mut data = Data::new(&model);
    let mut solver = ContactSolver::new(&model);
    let mut state = State::at(&problem.q, &problem.v, &problem.tau, DT);
    compute_all_terms(&model, &mut data, &state.q, &state.v);
    problem.load(&mut solver, n);
    let result = integrate_discrete_with_contacts(&model, &mut data, &mut state, &mut solver);
    match result {
        Err(Error::ContactNotConverged { iterations, .. }) => assert!(iterations >= 10, "{iterations}"),
        other => panic!("expected ContactNotConverged, got {other:?}"),
    }
    assert_eq!((state.q, state.v), (problem.q.clone(), problem.v.clone()));
}
