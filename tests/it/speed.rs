//! Joint speeds in the summary: `max_speed`, and the share of steps over a speed limit (from
//! the URDF's `velocity`, or `--max-speed`), through the real binary.

use crate::common;

use common::*;
use serde_json::Value;

fn run_summary(dir: &std::path::Path, args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.extend(["--trail", "none", "--summary", "s.json"]);
    let run = faze4(dir, &all);
    assert!(run.status.success(), "{all:?}: {}", run.stderr);
    serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap()
}

fn options(v: &Value) -> Vec<Option<f64>> {
    v.as_array().unwrap().iter().map(Value::as_f64).collect()
}

#[test]
fn the_bundled_faze4_has_no_speed_limit_unless_given() {
    let dir = temp_dir("speed-faze4");
    // 25° at 0.5 rad/s: each joint's commanded speed peaks at A·ω = 0.218 rad/s
    let s = run_summary(&dir, &["wave", "--duration", "8", "--no-collisions"]);
    let peak = 25f64.to_radians() * 0.5;
    for (i, &w) in vec_f64(&s["max_speed"]).iter().enumerate() {
        assert!((w - peak).abs() < 0.01 * peak || w < peak, "J{} max speed {w}", i + 1);
    }
    assert!(vec_f64(&s["max_speed"]).iter().any(|&w| (w - peak).abs() < 1e-3 * peak));
    assert!(
        options(&s["velocity_limit"]).iter().all(Option::is_none),
        "{}",
        s["velocity_limit"]
    );
    assert!(options(&s["velocity_limit_pct"]).iter().all(Option::is_none));

    // a limit below J6's peak: over it for part of the run, not all of it
    let s = run_summary(
        &dir,
        &[
            "wave",
            "--duration",
            "8",
            "--max-speed",
            "auto,auto,auto,auto,auto,0.2",
            "--no-collisions",
        ],
    );
    let pct = options(&s["velocity_limit_pct"]);
    assert!(pct[..5].iter().all(Option::is_none));
    let over = pct[5].unwrap();
    assert!(over > 1.0 && over < 50.0, "{over}");
    assert_eq!(options(&s["velocity_limit"])[5], Some(0.2));
    // a limit above every speed: 0 %
    let s = run_summary(
        &dir,
        &[
            "wave",
            "--duration",
            "8",
            "--max-speed",
            "1,1,1,1,1,1",
            "--no-collisions",
        ],
    );
    assert!(options(&s["velocity_limit_pct"]).iter().all(|p| *p == Some(0.0)));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn another_arm_takes_its_urdf_velocity_and_the_option_overrides_it() {
    let dir = temp_dir("speed-urdf");
    let arm = repo_path("tests/urdf/rotor_arm.urdf").display().to_string();
    let s = run_summary(&dir, &["wave", "--urdf", &arm, "--duration", "2"]);
    assert_eq!(
        options(&s["velocity_limit"]),
        [Some(2.0), Some(2.0), Some(0.5), Some(4.0)]
    );
    let s = run_summary(
        &dir,
        &[
            "wave",
            "--urdf",
            &arm,
            "--duration",
            "2",
            "--max-speed",
            "auto,0.05,auto,auto",
        ],
    );
    let pct = options(&s["velocity_limit_pct"]);
    assert_eq!(pct[0], Some(0.0));
    assert!(pct[1].unwrap() > 0.0, "J2 peaks at about 0.11 rad/s: {pct:?}");

    for (value, parts) in [
        ("1,2,3", vec!["--max-speed", "3 values"]),
        ("1,0,1,1", vec!["--max-speed", "J2", "> 0"]),
    ] {
        let run = faze4(
            &dir,
            &["wave", "--urdf", &arm, "--duration", "0.1", "--max-speed", value],
        );
        assert_eq!(run.status.code(), Some(2), "{}", run.stderr);
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
        for p in parts {
            assert!(run.stderr.contains(p), "{} lacks {p}", run.stderr);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
