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

/// The fixture's wave on an MJCF model, run as the binary: the trail within 1e-9 of MuJoCo's
/// dynamics stepped as docs/model.md steps (frictionloss left out on both sides), the gains
/// tuned from the same inertia and effort limits, the same errors and saturation.
#[test]
fn closed_loop_wave_matches_mujocos_dynamics() {
    for name in ["so101", "feature_arm"] {
        let fx = fixture(&format!("mjcf_{name}.json"));
        let cl = &fx["closed_loop"];
        let a = &cl["args"];
        let num = |k: &str| a[k].as_f64().unwrap().to_string();
        let dir = temp_dir(&format!("mjcf-wave-{name}"));
        let model = repo_path(fx["model"].as_str().unwrap()).display().to_string();
        let run = faze4(
            &dir,
            &[
                "wave",
                "--urdf",
                &model,
                "--center",
                "mid",
                "--amp-deg",
                &num("amp_deg"),
                "--amp-m",
                &num("amp_m"),
                "--freq",
                &num("freq"),
                "--duration",
                &num("duration"),
                "--dt",
                &num("dt"),
                "--record-period",
                &num("record_period"),
                "--tool-link",
                a["tool_link"].as_str().unwrap(),
                "--no-collisions",
                "--trail",
                "trail.csv",
                "--summary",
                "summary.json",
            ],
        );
        assert!(run.status.success(), "{}", run.stderr);
        assert!(
            run.stderr.contains("frictionloss of") && run.stderr.contains("not simulated"),
            "{name}: the friction left out is said: {}",
            run.stderr
        );
        let rows = fixture_trail(&dir, cl);
        let ours: Value = summary(&dir, "summary.json");
        std::fs::remove_dir_all(&dir).unwrap();
        let theirs = mat_f64(&cl["trail"]["rows"]);
        assert_eq!(rows.len(), theirs.len());
        let mut worst = 0.0f64;
        for (r, p) in rows.iter().zip(&theirs) {
            assert_eq!(r[0], p[0], "sample times");
            worst = worst.max(max_abs_diff(&r[1..], &p[1..]));
        }
        eprintln!("{name} wave: trail worst difference {worst:.1e}");
        assert!(worst <= 1e-9, "{name}: trail differs from MuJoCo's by {worst:e}");
        let mj = &cl["summary"];
        assert_eq!(ours["steps"], mj["steps"]);
        for key in ["effective_inertia", "kp", "kd", "effort"] {
            let e = relative(&vec_f64(&ours[key]), &vec_f64(&mj[key]));
            assert!(e < 1e-12, "{name}: {key} differs (relative {e:e})");
        }
        let e = max_abs_diff(
            &vec_f64(&ours["max_tracking_error_rad"]),
            &vec_f64(&mj["max_tracking_error_rad"]),
        );
        assert!(e < 1e-9, "{name}: max tracking error differs by {e:e}");
        assert_eq!(ours["saturation_pct"], mj["saturation_pct"]);
        assert_eq!(ours["format"], "mjcf");
    }
}
