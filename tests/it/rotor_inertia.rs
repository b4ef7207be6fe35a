//! The motors' reflected inertia against Drake reading the same URDF (fixture by
//! tools/oracle/rotor_fixtures.py): M within 1e-12 relative, the closed-loop trail within 1e-9;
//! the command-line overrides give the same; bad motors are refused in one line.

use crate::common;

use common::*;
use faze4::algo::{Data, crba, rnea};
use serde_json::Value;

const URDF: &str = "tests/urdf/rotor_arm.urdf";

fn rotor_arm() -> faze4::model::Model {
    load(URDF)
}

#[test]
fn reflected_inertia_and_mass_matrix_match_drake() {
    let fx = fixture("rotor_arm.json");
    let model = rotor_arm();
    let reflected: Vec<f64> = model.joints.iter().map(|j| j.reflected_inertia()).collect();
    let expected = vec_f64(&fx["reflected_inertia"]);
    assert!(
        max_abs_diff(&reflected, &expected) <= 1e-15,
        "{reflected:?} vs {expected:?}"
    );
    assert!(expected.iter().filter(|&&r| r > 0.0).count() == 3);

    let mut data = Data::new(&model);
    for sample in fx["mass_matrix"].as_array().unwrap() {
        let q = vec_f64(&sample["q"]);
        let drake = mat_f64(&sample["m"]);
        let m = crba(&model, &mut data, &q).clone();
        let scale = drake.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
        for (i, row) in drake.iter().enumerate() {
            for (j, &x) in row.iter().enumerate() {
                assert!(
                    (m[(i, j)] - x).abs() <= 1e-12 * scale,
                    "M[{i},{j}] at {q:?}: {} vs {x}",
                    m[(i, j)]
                );
            }
        }
        // inverse dynamics sees the same inertia: τ(q, 0, qdd) − g(q) = M qdd
        let qdd: Vec<f64> = (0..model.dof()).map(|i| 1.0 + i as f64).collect();
        let zero = vec![0.0; model.dof()];
        let tau = rnea(&model, &mut data, &q, &zero, &qdd).clone();
        let g = rnea(&model, &mut data, &q, &zero, &zero).clone();
        let m_qdd = &m * nalgebra::DVector::from_vec(qdd);
        for i in 0..model.dof() {
            assert!((tau[i] - g[i] - m_qdd[i]).abs() <= 1e-12 * scale * 4.0, "joint {i}");
        }
    }
}

/// Runs the fixture's wave through the binary with `extra` options on `urdf`; the trail.
fn wave_trail(dir: &std::path::Path, urdf: &str, extra: &[&str]) -> (Value, Vec<Vec<f64>>) {
    let fx = fixture("rotor_arm.json");
    let a = &fx["closed_loop"]["args"];
    let num = |k: &str| a[k].as_f64().unwrap().to_string();
    let mut args: Vec<String> = ["wave", "--urdf", urdf].iter().map(|s| s.to_string()).collect();
    for (option, key) in [
        ("--amp-deg", "amp_deg"),
        ("--freq", "freq"),
        ("--duration", "duration"),
        ("--dt", "dt"),
        ("--record-period", "record_period"),
    ] {
        args.extend([option.to_string(), num(key)]);
    }
    // the fixture waves the prismatic slide by the same amplitude as the other joints, the
    // degrees in radians read as metres (docs/model.md 4.1: without --amp-m a quarter of its range)
    let amp_m = a["amp_deg"].as_f64().unwrap().to_radians().to_string();
    args.extend(["--amp-m".to_string(), amp_m]);
    args.extend(["--trail", "trail.csv", "--summary", "s.json"].map(String::from));
    args.extend(extra.iter().map(|s| s.to_string()));
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = faze4(dir, &argv);
    assert!(run.status.success(), "{argv:?}: {}", run.stderr);
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
    (summary, read_csv(&dir.join("trail.csv")).1)
}

fn assert_trail_matches(trail: &[Vec<f64>], fx: &Value) {
    let drake = mat_f64(&fx["closed_loop"]["trail"]["rows"]);
    assert_eq!(trail.len(), drake.len());
    let worst = trail
        .iter()
        .zip(&drake)
        .map(|(a, b)| max_abs_diff(a, b))
        .fold(0.0, f64::max);
    println!("rotor_arm closed loop: max |faze4 − Drake| over the trail = {worst:.2e}");
    assert!(worst <= 1e-9, "trail differs from Drake by {worst}");
}

#[test]
fn the_closed_loop_matches_drake_with_rotors_from_the_urdf() {
    let fx = fixture("rotor_arm.json");
    let dir = temp_dir("rotor-urdf");
    let (summary, trail) = wave_trail(&dir, &repo_path(URDF).display().to_string(), &[]);
    assert_trail_matches(&trail, &fx);
    let drake = &fx["closed_loop"]["summary"];
    for key in ["effective_inertia", "kp", "kd"] {
        let (ours, theirs) = (vec_f64(&summary[key]), vec_f64(&drake[key]));
        assert!(
            max_abs_diff(&ours, &theirs) <= 1e-12 * max_abs(&theirs),
            "{key}: {ours:?} vs {theirs:?}"
        );
    }
    assert_eq!(summary["stability"]["scaled"], false);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The same motors given on the command line to the arm without its transmissions.
#[test]
fn rotor_options_override_the_urdf() {
    let fx = fixture("rotor_arm.json");
    let dir = temp_dir("rotor-options");
    let text = std::fs::read_to_string(repo_path(URDF)).unwrap();
    let bare = text[..text.find("  <transmission").unwrap()].to_string() + "</robot>\n";
    std::fs::write(dir.join("bare.urdf"), &bare).unwrap();
    let motors = [
        "--rotor-inertia",
        "6.8e-6,5.4e-6,auto,3.4e-6",
        "--gear-ratio",
        "50,30,auto,20",
    ];
    let (_, trail) = wave_trail(&dir, "bare.urdf", &motors);
    assert_trail_matches(&trail, &fx);
    // and they override the URDF's own: doubling a ratio moves the run away from Drake's
    let (_, doubled) = wave_trail(
        &dir,
        &repo_path(URDF).display().to_string(),
        &["--gear-ratio", "100,auto,auto,auto"],
    );
    let rows = mat_f64(&fx["closed_loop"]["trail"]["rows"]);
    let moved = doubled
        .iter()
        .zip(&rows)
        .map(|(a, b)| max_abs_diff(a, b))
        .fold(0.0, f64::max);
    assert!(moved > 1e-6, "a doubled J1 ratio changed nothing ({moved})");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_motors_are_refused_in_one_line() {
    let dir = temp_dir("rotor-bad");
    let text = std::fs::read_to_string(repo_path(URDF)).unwrap();
    let cases = [
        (
            text.replace("<joint name=\"roll\"><hardware", "<joint name=\"nope\"><hardware"),
            vec!["transmission 'roll_drive'", "'nope'", "not a moving joint"],
        ),
        (
            text.replace("<drake:gear_ratio value=\"30\"/>", "<drake:gear_ratio value=\"0\"/>"),
            vec!["transmission 'pitch_drive'", "gear ratio 0"],
        ),
        (
            text.replace(
                "<drake:rotor_inertia value=\"6.8e-6\"/>",
                "<drake:rotor_inertia value=\"-1e-6\"/>",
            ),
            vec!["transmission 'yaw_drive'", "rotor inertia -1e-6"],
        ),
        (
            text.replace("<drake:gear_ratio value=\"20\"/>", "<drake:gear_ratio value=\"fast\"/>"),
            vec!["roll_drive", "'fast' is not a number"],
        ),
    ];
    for (k, (urdf, parts)) in cases.iter().enumerate() {
        let name = format!("bad{k}.urdf");
        std::fs::write(dir.join(&name), urdf).unwrap();
        refuses(&dir, &["wave", "--urdf", &name, "--duration", "0.01"], parts);
    }
    let arm = repo_path(URDF).display().to_string();
    let wave = ["wave", "--urdf", arm.as_str(), "--duration", "0.01"];
    let with = |extra: &[&'static str]| -> Vec<&str> { wave.iter().copied().chain(extra.iter().copied()).collect() };
    refuses(
        &dir,
        &with(&["--gear-ratio", "1,2,3"]),
        &["--gear-ratio", "3 values", "4 joints"],
    );
    refuses(
        &dir,
        &with(&["--gear-ratio", "1,0,3,4"]),
        &["--gear-ratio", "J2", "> 0"],
    );
    refuses(
        &dir,
        &with(&["--rotor-inertia", "1e-6,1e-6,-1e-6,auto"]),
        &["--rotor-inertia", "J3", "> 0"],
    );
    refuses(
        &dir,
        &with(&["--motors", "faze4"]),
        &["--motors", "6-joint", "4 joints"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--motors faze4`: limits K·I × ratio (the 17HS16-2004S1's standstill torque at its rated
/// current, 0.45/√2 N·m) and the rotors on M's diagonal; `--gear-ratio` moves a joint's limit
/// and its reflected inertia together.
#[test]
fn faze4_motors_set_limits_and_inertia_from_the_ratios() {
    let dir = temp_dir("rotor-faze4");
    let summary = |extra: &[&str]| -> Value {
        let mut args = vec!["wave", "--duration", "0.01", "--trail", "none", "--summary", "s.json"];
        args.extend_from_slice(extra);
        let run = faze4(&dir, &args);
        assert!(run.status.success(), "{args:?}: {}", run.stderr);
        serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap()
    };
    let bare = summary(&[]);
    let motors = summary(&["--motors", "faze4"]);
    let geared = summary(&["--motors", "faze4", "--gear-ratio", "50,auto,auto,auto,auto,auto"]);
    let ratios = [25.0, 27.0, 15.0, 11.846, 11.0, 19.19];
    let rotor = 5.4e-6;
    let (e0, e1, e2) = (
        vec_f64(&bare["effort"]),
        vec_f64(&motors["effort"]),
        vec_f64(&geared["effort"]),
    );
    let (i0, i1, i2) = (
        vec_f64(&bare["effective_inertia"]),
        vec_f64(&motors["effective_inertia"]),
        vec_f64(&geared["effective_inertia"]),
    );
    assert_eq!(e0, [7.9, 8.5, 4.7, 3.7, 3.5, 6.0]);
    let standstill = 0.45 / 2f64.sqrt();
    for j in 0..6 {
        assert!(
            (e1[j] - standstill * ratios[j]).abs() < 1e-12,
            "J{} limit {}",
            j + 1,
            e1[j]
        );
        let reflected = ratios[j] * ratios[j] * rotor;
        assert!((i1[j] - i0[j] - reflected).abs() < 1e-12, "J{} inertia", j + 1);
    }
    assert!((e2[0] - standstill * 50.0).abs() < 1e-12);
    assert!((i2[0] - i0[0] - 2500.0 * rotor).abs() < 1e-12);
    assert_eq!(e2[1..], e1[1..]);
    std::fs::remove_dir_all(&dir).unwrap();
}
