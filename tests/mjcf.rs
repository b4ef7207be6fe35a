//! MJCF models against MuJoCo (fixtures by tools/oracle/mjcf_fixtures.py, the `mujoco` package):
//! TheRobotStudio's SO-101, Menagerie's UR5e and Panda, and tests/mjcf/feature_arm.xml (ours,
//! every construct faze4 reads). The coordinates, limits, damping, effort limits, armature and
//! home pose; M (armature included) and C v + g at random states to 1e-12 relative; what the
//! reading mapped and left out; the models and constructs it refuses.

mod common;

use common::*;
use faze4::algo::{Data, compute_all_terms};
use faze4::model::{Model, mjcf};
use serde_json::Value;

const MODELS: [&str; 4] = ["so101", "ur5e", "panda", "feature_arm"];
const TOL: f64 = 1e-12;

fn model_of(fx: &Value) -> Model {
    mjcf::read_file(&repo_path(fx["model"].as_str().unwrap())).unwrap()
}

/// A fixture's list of numbers, `null` as `none`.
fn or_inf(v: &Value, none: f64) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap_or(none))
        .collect()
}

fn relative(ours: &[f64], theirs: &[f64]) -> f64 {
    max_abs_diff(ours, theirs) / max_abs(theirs).max(f64::MIN_POSITIVE)
}

#[test]
fn coordinates_limits_damping_effort_armature_and_home_are_mujocos() {
    for name in MODELS {
        let fx = fixture(&format!("mjcf_{name}.json"));
        let model = model_of(&fx);
        let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
        let theirs: Vec<&str> = fx["coordinates"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        assert_eq!(names, theirs, "{name}: coordinates");
        let lower: Vec<f64> = model.joints.iter().map(|j| j.lower).collect();
        let upper: Vec<f64> = model.joints.iter().map(|j| j.upper).collect();
        let n = names.len();
        for (what, ours, theirs) in [
            ("lower", lower, or_inf(&fx["lower"], f64::NEG_INFINITY)),
            ("upper", upper, or_inf(&fx["upper"], f64::INFINITY)),
        ] {
            for (a, b) in ours.iter().zip(&theirs) {
                assert!(
                    a == b || (a - b).abs() <= 1e-15 * b.abs(),
                    "{name}: {what} {ours:?} vs {theirs:?}"
                );
            }
        }
        let diag = |key: &str| (0..n).map(|i| fx[key][i][i].as_f64().unwrap()).collect::<Vec<_>>();
        let damping: Vec<f64> = model.damping().collect();
        assert!(
            relative(&damping, &diag("damping")) <= TOL,
            "{name}: damping {damping:?}"
        );
        let armature: Vec<f64> = model.joints.iter().map(|j| j.reflected_inertia()).collect();
        assert!(
            relative(&armature, &diag("armature")) <= TOL,
            "{name}: armature {armature:?}"
        );
        let effort: Vec<f64> = model.joints.iter().map(|j| j.effort.unwrap_or(f64::INFINITY)).collect();
        assert_eq!(effort, or_inf(&fx["effort"], f64::INFINITY), "{name}: effort");
        match &fx["home"] {
            Value::Null => assert_eq!(model.home, None, "{name}: home"),
            home => assert_eq!(model.home.as_deref(), Some(&vec_f64(home)[..]), "{name}: home"),
        }
    }
}

#[test]
fn mass_matrix_and_bias_equal_mujocos_at_random_states() {
    for name in MODELS {
        let fx = fixture(&format!("mjcf_{name}.json"));
        let model = model_of(&fx);
        let mut data = Data::new(&model);
        let (mut worst_m, mut worst_b) = (0.0f64, 0.0f64);
        for state in fx["states"].as_array().unwrap() {
            compute_all_terms(&model, &mut data, &vec_f64(&state["q"]), &vec_f64(&state["v"]));
            let theirs: Vec<f64> = mat_f64(&state["m"]).concat();
            let ours: Vec<f64> = (0..model.dof())
                .flat_map(|r| (0..model.dof()).map(move |c| (r, c)))
                .map(|(r, c)| data.m[(r, c)])
                .collect();
            worst_m = worst_m.max(relative(&ours, &theirs));
            worst_b = worst_b.max(relative(data.bias.as_slice(), &vec_f64(&state["bias"])));
        }
        eprintln!("{name}: M {worst_m:.1e}, C v + g {worst_b:.1e} (relative, worst of 8 states)");
        assert!(
            worst_m <= TOL,
            "{name}: M differs from MuJoCo's by {worst_m:e} relative"
        );
        assert!(
            worst_b <= TOL,
            "{name}: C v + g differs from MuJoCo's by {worst_b:e} relative"
        );
    }
}
