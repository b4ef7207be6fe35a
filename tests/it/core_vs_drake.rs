//! The rigid-body core against Drake: fixtures written by tools/oracle/core_fixtures.py.
//!
//! For each model and 25 random states: every frame pose (1e-12 m), M, C v and g (relative
//! 1e-10, relative to the largest entry), the tool Jacobian (1e-12), and the state after
//! 1,000 discrete steps under a constant torque (1e-10).

use crate::common;

use common::*;
use faze4::algo::{Data, State, bias, crba, discrete_step, forward_kinematics, frame_jacobian, gravity};
use faze4::model::Model;

const FK_TOL: f64 = 1e-12;
const DYN_REL_TOL: f64 = 1e-10;
const STEP_TOL: f64 = 1e-10;

/// The model, and for each of Drake's joint positions the index of the same joint in ours.
fn model_and_order(fx: &serde_json::Value) -> (Model, Vec<usize>) {
    let model = load(fx["urdf"].as_str().unwrap());
    let order: Vec<usize> = fx["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| model.joint_index(n.as_str().unwrap()).expect("joint in our model").0)
        .collect();
    assert_eq!(order.len(), model.dof());
    (model, order)
}

/// A Drake-ordered vector in our order.
fn ours(order: &[usize], drake: &[f64]) -> Vec<f64> {
    let mut v = vec![0.0; drake.len()];
    for (d, &o) in order.iter().enumerate() {
        v[o] = drake[d];
    }
    v
}

fn check_model(fixture_name: &str) {
    let fx = fixture(fixture_name);
    let (model, order) = model_and_order(&fx);
    let mut data = Data::new(&model);
    let n = model.dof();
    let mut worst = [0.0f64; 6];
    for (k, s) in fx["samples"].as_array().unwrap().iter().enumerate() {
        let q = ours(&order, &vec_f64(&s["q"]));
        let v = ours(&order, &vec_f64(&s["v"]));

        // every frame pose
        forward_kinematics(&model, &mut data, &q);
        for (name, pose) in s["frames"].as_object().unwrap() {
            let f = model
                .frame_index(name)
                .unwrap_or_else(|| panic!("frame {name} missing"));
            let ours_pose = &data.frame_pose[f.0];
            let p = vec_f64(&pose["p"]);
            let r = mat_f64(&pose["R"]);
            for a in 0..3 {
                worst[0] = worst[0].max((ours_pose.pos[a] - p[a]).abs());
                for b in 0..3 {
                    worst[0] = worst[0].max((ours_pose.rot[(a, b)] - r[a][b]).abs());
                }
            }
        }

        // M, C v, g
        let m_drake = mat_f64(&s["M"]);
        let scale = m_drake.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
        crba(&model, &mut data, &q);
        for a in 0..n {
            for b in 0..n {
                let e = (data.m[(order[a], order[b])] - m_drake[a][b]).abs() / scale;
                worst[1] = worst[1].max(e);
            }
        }
        let g = gravity(&model, &mut data, &q).clone();
        let g_drake = ours(&order, &vec_f64(&s["g"]));
        worst[2] = worst[2].max(max_abs_diff(g.as_slice(), &g_drake) / max_abs(&g_drake).max(1e-300));
        let cv: Vec<f64> = bias(&model, &mut data, &q, &v)
            .iter()
            .zip(g.iter())
            .map(|(b, g)| b - g)
            .collect();
        let cv_drake = ours(&order, &vec_f64(&s["Cv"]));
        worst[3] = worst[3].max(max_abs_diff(&cv, &cv_drake) / max_abs(&cv_drake).max(1e-300));

        // the Jacobian of the last frame (the tool)
        let tool = model.frame_index(fx["frame_names"].as_array().unwrap().last().unwrap().as_str().unwrap());
        let tool = tool.unwrap();
        forward_kinematics(&model, &mut data, &q);
        let jac = frame_jacobian(&model, &mut data, tool).clone();
        let jac_drake = mat_f64(&s["jacobian_tool"]);
        for r in 0..6 {
            for (d, &o) in order.iter().enumerate() {
                worst[4] = worst[4].max((jac[(r, o)] - jac_drake[r][d]).abs());
            }
        }

        // 1000 discrete steps under a constant torque
        let step = &s["step"];
        let tau = ours(&order, &vec_f64(&step["tau"]));
        let dt = step["dt"].as_f64().unwrap();
        let mut state = State::at(&q, &v, &tau, dt);
        for _ in 0..step["steps"].as_u64().unwrap() {
            discrete_step(&model, &mut data, &mut state).unwrap();
        }
        let (qs, vs) = (state.q, state.v);
        let e = max_abs_diff(&qs, &ours(&order, &vec_f64(&step["q"])))
            .max(max_abs_diff(&vs, &ours(&order, &vec_f64(&step["v"]))));
        worst[5] = worst[5].max(e);
        assert!(
            worst.iter().all(|w| w.is_finite()),
            "{fixture_name} sample {k}: non-finite comparison"
        );
    }
    eprintln!(
        "{fixture_name}: fk {:.1e}, M {:.1e}, g {:.1e}, Cv {:.1e}, J {:.1e}, 1000 steps {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]
    );
    assert!(
        worst[0] <= FK_TOL,
        "{fixture_name}: frame poses differ by {:e}",
        worst[0]
    );
    assert!(
        worst[1] <= DYN_REL_TOL,
        "{fixture_name}: M differs by {:e} (relative)",
        worst[1]
    );
    assert!(
        worst[2] <= DYN_REL_TOL,
        "{fixture_name}: g differs by {:e} (relative)",
        worst[2]
    );
    assert!(
        worst[3] <= DYN_REL_TOL,
        "{fixture_name}: Cv differs by {:e} (relative)",
        worst[3]
    );
    assert!(worst[4] <= FK_TOL, "{fixture_name}: Jacobian differs by {:e}", worst[4]);
    assert!(
        worst[5] <= STEP_TOL,
        "{fixture_name}: state after 1000 steps differs by {:e}",
        worst[5]
    );
}

#[test]
fn faze4_arm_agrees_with_drake() {
    check_model("core_faze4_arm.json");
}

#[test]
fn prismatic_arm_with_a_mid_chain_fixed_joint_agrees_with_drake() {
    check_model("core_arm_prismatic.json");
}

#[test]
fn branched_tree_agrees_with_drake() {
    check_model("core_tree_arm.json");
}
