//! `faze4 wave` and `faze4 replay`, run as the real binary, against the Drake reference loop
//! (fixtures by tools/oracle/closed_loop_fixtures.py): the whole 8 s trail within 1e-9 m / rad,
//! and the summary. Plus the regression figures of SPEC §3–4.

mod common;

use common::*;
use serde_json::Value;

const TRAIL_TOL: f64 = 1e-9;

/// Runs the fixture's experiment and returns (our summary, our trail rows).
fn run_fixture(name: &str) -> (Value, Value, Vec<Vec<f64>>) {
    let fx = fixture(name);
    let dir = temp_dir(name);
    let a = &fx["args"];
    let num = |k: &str| a[k].as_f64().unwrap().to_string();
    let mut args: Vec<String> = vec![fx["command"].as_str().unwrap().to_string()];
    match fx["command"].as_str().unwrap() {
        "wave" => args.extend(["--freq".into(), num("freq"), "--amp-deg".into(), num("amp_deg")]),
        "replay" => args.extend([
            "--q-traj".into(),
            repo_path(a["q_traj"].as_str().unwrap()).display().to_string(),
            "--traj-period".into(),
            num("traj_period"),
        ]),
        other => panic!("unknown command {other}"),
    }
    args.extend(["--duration".into(), num("duration"), "--dt".into(), num("dt")]);
    args.extend(["--record-period".into(), num("record_period")]);
    if a["no_ff"].as_bool().unwrap_or(false) {
        args.push("--no-ff".into());
    }
    if a["no_gravity"].as_bool().unwrap_or(false) {
        args.push("--no-gravity".into());
    }
    args.extend([
        "--trail".into(),
        "trail.csv".into(),
        "--summary".into(),
        "summary.json".into(),
    ]);
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = faze4(&dir, &argv);
    assert!(run.status.success(), "faze4 {argv:?} failed: {}", run.stderr);
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let (header, rows) = read_csv(&dir.join("trail.csv"));
    let columns: Vec<String> = fx["trail"]["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap().into())
        .collect();
    assert_eq!(header, columns);
    std::fs::remove_dir_all(&dir).unwrap();
    (fx, summary, rows)
}

fn compare(name: &str) -> Value {
    let (fx, ours, rows) = run_fixture(name);
    let drake_rows = mat_f64(&fx["trail"]["rows"]);
    assert_eq!(rows.len(), drake_rows.len(), "{name}: trail rows");
    let mut worst = 0.0f64;
    for (r, d) in rows.iter().zip(&drake_rows) {
        assert_eq!(r[0], d[0], "{name}: sample times");
        worst = worst.max(max_abs_diff(&r[1..], &d[1..]));
    }
    eprintln!("{name}: trail worst difference {worst:.1e}");
    assert!(worst <= TRAIL_TOL, "{name}: trail differs from Drake by {worst:e}");

    let drake = &fx["summary"];
    for key in ["dof", "steps", "diverged"] {
        assert_eq!(ours[key], drake[key], "{name}: {key}");
    }
    for key in ["effective_inertia", "kp", "kd", "effort"] {
        let e = max_abs_diff(&vec_f64(&ours[key]), &vec_f64(&drake[key])) / max_abs(&vec_f64(&drake[key]));
        assert!(e < 1e-12, "{name}: {key} differs (relative {e:e})");
    }
    let e = max_abs_diff(
        &vec_f64(&ours["max_tracking_error_rad"]),
        &vec_f64(&drake["max_tracking_error_rad"]),
    );
    assert!(e < TRAIL_TOL, "{name}: max tracking error differs by {e:e}");
    assert_eq!(ours["saturation_pct"], drake["saturation_pct"], "{name}: saturation");
    for axis in ["x", "y", "z"] {
        let e = max_abs_diff(
            &vec_f64(&ours["tool_range_m"][axis]),
            &vec_f64(&drake["tool_range_m"][axis]),
        );
        assert!(e < TRAIL_TOL, "{name}: tool range {axis} differs by {e:e}");
    }
    ours
}

#[test]
fn default_wave_matches_drake_and_tracks_within_5e_4() {
    let s = compare("closed_loop_wave_default.json");
    let err = vec_f64(&s["max_tracking_error_rad"]);
    assert!(err.iter().all(|&e| e <= 5e-4), "max error {err:?}");
    assert!(vec_f64(&s["saturation_pct"]).iter().all(|&p| p == 0.0));
    // SPEC §3: the Faze4 gains at Δt = 2e-4
    let kp = vec_f64(&s["kp"]);
    let kd = vec_f64(&s["kd"]);
    let spec_kp = [158.0, 170.0, 94.0, 74.0, 70.0, 64.52];
    let spec_kd = [5.506, 12.456, 3.237, 0.515, 0.2157, 0.01613];
    for i in 0..6 {
        assert!((kp[i] - spec_kp[i]).abs() <= 5e-3 * spec_kp[i], "kp {kp:?}");
        assert!((kd[i] - spec_kd[i]).abs() <= 5e-3 * spec_kd[i], "kd {kd:?}");
    }
}

#[test]
fn wave_without_feed_forward_matches_drake_and_sags_as_published() {
    let s = compare("closed_loop_wave_no_ff.json");
    let err = vec_f64(&s["max_tracking_error_rad"]);
    assert!((err[1] - 0.0412).abs() <= 5e-4, "J2 {}", err[1]);
    assert!((err[2] - 0.0195).abs() <= 5e-4, "J3 {}", err[2]);
}

#[test]
fn wave_without_gravity_matches_drake() {
    let s = compare("closed_loop_wave_no_gravity.json");
    assert!(vec_f64(&s["max_tracking_error_rad"]).iter().all(|&e| e <= 5e-4));
}

#[test]
fn replay_matches_drake() {
    compare("closed_loop_replay.json");
}
