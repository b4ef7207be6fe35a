//! `--motors`: the torque–speed envelopes against Pinocchio (fixtures by
//! tools/oracle/motor_fixtures.py: pin_closed_loop.py's loop with the same envelopes), what the
//! summary, verdict and terminal say about them, and bad motor files refused in one line.

use crate::common;

use common::*;
use serde_json::Value;

const URDF: &str = "tests/urdf/motor_arm.urdf";
/// The trail against Pinocchio's (t, tool xyz, q): the same tolerance as against Drake.
const TRAIL_TOL: f64 = 1e-9;

/// Runs the fixture's wave with its motors and gains; returns the fixture, our summary, trail
/// and terminal output.
fn run_fixture(name: &str) -> (Value, Value, Vec<Vec<f64>>, String) {
    let fx = fixture(name);
    let dir = temp_dir(name);
    let a = &fx["args"];
    let num = |k: &str| a[k].as_f64().unwrap().to_string();
    let list = |k: &str| {
        (vec_f64(&fx[k]).iter())
            .map(|x| format!("{x:?}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    let (urdf, motors) = (
        repo_path(fx["urdf"].as_str().unwrap()).display().to_string(),
        repo_path(fx["motors"].as_str().unwrap()).display().to_string(),
    );
    let (kp, kd, effort) = (list("kp"), list("kd"), list("effort"));
    let args: Vec<String> = [
        "wave",
        "--urdf",
        &urdf,
        "--motors",
        &motors,
        "--freq",
        &num("freq"),
        "--amp-deg",
        &num("amp_deg"),
        "--duration",
        &num("duration"),
        "--dt",
        &num("dt"),
        "--record-period",
        &num("record_period"),
        "--kp",
        &kp,
        "--kd",
        &kd,
        "--effort",
        &effort,
        "--no-collisions",
        "--trail",
        "trail.csv",
        "--summary",
        "summary.json",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = faze4(&dir, &argv);
    assert!(
        run.status.code().is_some_and(|c| c == 0 || c == 3),
        "{argv:?}: {}",
        run.stderr
    );
    let summary: Value = summary(&dir, "summary.json");
    let rows = fixture_trail(&dir, &fx);
    std::fs::remove_dir_all(&dir).unwrap();
    (fx, summary, rows, run.stdout)
}

/// The trail within 1e-9 of Pinocchio's and the same share of steps beyond the envelope.
fn compare(name: &str) -> (Value, String) {
    let (fx, ours, rows, stdout) = run_fixture(name);
    let pin_rows = mat_f64(&fx["trail"]["rows"]);
    assert_eq!(rows.len(), pin_rows.len(), "{name}: trail rows");
    let worst = (rows.iter().zip(&pin_rows))
        .map(|(a, b)| max_abs_diff(a, b))
        .fold(0.0, f64::max);
    eprintln!("{name}: trail worst difference {worst:.1e}");
    assert!(worst <= TRAIL_TOL, "{name}: trail differs from Pinocchio by {worst:e}");
    let steps = ours["steps"].as_f64().unwrap();
    let pin_env = vec_f64(&fx["summary"]["envelope_pct"]);
    let motors = ours["motors"].as_array().unwrap();
    for (j, (m, p)) in motors.iter().zip(&pin_env).enumerate() {
        let e = m["envelope_pct"].as_f64().unwrap();
        assert!(
            (e - p).abs() <= 100.0 / steps,
            "{name} J{}: envelope {e} % vs Pinocchio's {p} %",
            j + 1
        );
    }
    assert!(pin_env.iter().any(|&p| p > 5.0), "{name}: the envelope should clip");
    (ours, stdout)
}

#[test]
fn dc_arm_matches_pinocchio_and_its_shoulder_overheats() {
    let (ours, stdout) = compare("motors_dc_arm.json");
    let motors = ours["motors"].as_array().unwrap();
    assert!(
        motors
            .iter()
            .all(|m| m["kind"] == "dc" && m.get("loses_steps_at").is_none())
    );
    // the shoulder's RMS torque is above its 0.05 N·m rating: the verdict names it
    let rms = motors[1]["rms_torque"].as_f64().unwrap();
    assert!(rms > 0.05, "{rms}");
    let reasons: Vec<&str> = ours["verdict"]["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_str().unwrap())
        .collect();
    assert!(
        reasons
            .iter()
            .any(|r| r.starts_with("J2's motor runs at") && r.contains("above its continuous 0.05 N·m")),
        "{reasons:?}"
    );
    assert!(
        reasons
            .iter()
            .any(|r| r.starts_with("J2 asks its motor for more than its torque–speed envelope"))
    );
    assert!(
        stdout.contains("beyond envelope") && stdout.contains("RMS torque (N·m)"),
        "{stdout}"
    );
}

#[test]
fn stepper_arm_matches_pinocchio_and_its_shoulder_loses_steps() {
    let (ours, stdout) = compare("motors_stepper_arm.json");
    let motors = ours["motors"].as_array().unwrap();
    let shoulder = &motors[1];
    let t = shoulder["loses_steps_at"].as_f64().expect("the shoulder loses steps");
    let loss = &shoulder["step_loss"];
    assert_eq!(loss["t"].as_f64().unwrap(), t);
    // it needed more than the curve gave at its speed
    assert!(
        loss["needs"].as_f64().unwrap() > loss["gives"].as_f64().unwrap(),
        "{loss}"
    );
    assert!(motors[0]["loses_steps_at"].is_null() && motors[2]["loses_steps_at"].is_null());
    let reasons = ours["verdict"]["reasons"].to_string();
    assert!(
        reasons.contains(&format!("J2's stepper loses steps at t = {t:.2} s: it needs")),
        "{reasons}"
    );
    assert!(
        stdout.contains("loses steps at (s)") && stdout.contains("never"),
        "{stdout}"
    );
}

/// Without `--motors` the summary has no `motors`; with a preset every joint has one.
#[test]
fn presets_put_a_motor_on_every_joint_and_no_motors_means_none() {
    let dir = temp_dir("motor-presets");
    let urdf = repo_path(URDF).display().to_string();
    let summary = |extra: &[&str]| -> Value {
        let mut args = vec!["wave", "--urdf", urdf.as_str(), "--duration", "0.05", "--no-collisions"];
        args.extend_from_slice(&["--trail", "none", "--summary", "s.json"]);
        args.extend_from_slice(extra);
        let run = faze4(&dir, &args);
        assert!(run.status.success(), "{args:?}: {}", run.stderr);
        serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap()
    };
    assert!(summary(&[]).get("motors").is_none());
    let sts = summary(&["--motors", "sts3215"]);
    let motors = sts["motors"].as_array().unwrap();
    assert_eq!(motors.len(), 3);
    assert!(
        motors
            .iter()
            .all(|m| m["kind"] == "dc" && m["label"].as_str().unwrap().contains("STS3215"))
    );
    // the joint limit is the servo's 19.5 kg·cm
    for e in vec_f64(&sts["effort"]) {
        assert!((e - 19.5 * 9.80665e-2).abs() < 1e-12, "{e}");
    }
    // twice the voltage, twice the stall torque
    let doubled = summary(&["--motors", "sts3215", "--supply-voltage", "14.8"]);
    assert!((vec_f64(&doubled["effort"])[0] - 2.0 * 19.5 * 9.80665e-2).abs() < 1e-12);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_motor_files_are_refused_in_one_line() {
    let dir = temp_dir("motor-bad");
    let urdf = repo_path(URDF).display().to_string();
    let good = std::fs::read_to_string(repo_path("tests/motors/dc_arm.toml")).unwrap();
    let cases: Vec<(String, Vec<&str>)> = vec![
        (
            good.replace(
                "kind = \"dc\"\nstall_torque = 0.25",
                "kind = \"servo\"\nstall_torque = 0.25",
            ),
            vec!["J2 (shoulder)", "\"servo\""],
        ),
        (
            good.replace("stall_torque = 0.1\n", ""),
            vec!["J3 (elbow)", "needs stall_torque"],
        ),
        (
            good.replace("name = \"elbow\"", "name = \"wrist\""),
            vec!["'wrist'", "not a moving joint"],
        ),
        (
            good.replace(
                "efficiency = 0.9\nrotor_inertia = 4e-6",
                "efficiency = 1.5\nrotor_inertia = 4e-6",
            ),
            vec!["J1 (yaw)", "efficiency 1.5"],
        ),
        (
            good.replace("gear_ratio = 40.0", "gear_ratio = -40.0"),
            vec!["J3 (elbow)", "gear_ratio -40"],
        ),
        (
            good.replace("no_load_speed = 250.0", "no_load_speed = 250.0\nvoltage = 12.0"),
            vec!["voltage"],
        ),
        (
            "[[joint]]\nkind = \"stepper\"\ncurve = [[10.0, 0.3], [20.0, 0.2]]\n".repeat(3),
            vec!["J1 (by order)", "first point must be at 0"],
        ),
        (
            "[[joint]]\nkind = \"stepper\"\ncurve = [[0.0, 0.3]]\n".into(),
            vec!["1 [[joint]] entries", "3 moving joints"],
        ),
        (
            good.replace("no_load_speed = 250.0", "no_load_speed = 250.0\nstep_angle = 1.8"),
            vec!["a dc motor has no step_angle"],
        ),
        (
            "[[joint]]\nkind = \"stepper\"\ncurve = [[0.0, 0.3]]\nstep_angle = 0.0\n".repeat(3),
            vec!["J1 (by order)", "step_angle 0 must be in [0.1, 90] degrees"],
        ),
        (
            "[[joint]]\nkind = \"stepper\"\ncurve = [[0.0, 0.3]]\nmicrosteps = 8\n".repeat(3),
            vec!["J1 (by order)", "need the stepper's step_angle"],
        ),
        ("[[joint]\n".into(), vec!["m.toml"]),
        // a curve point of three values was read as its first two (issue 35)
        (
            "[[joint]]\nkind = \"stepper\"\ncurve = [[0.0, 0.3, 7], [10.0, 0.2]]\n".repeat(3),
            vec![
                "J1 (by order)",
                "curve point 1 has 3 values ([0.0, 0.3, 7.0])",
                "[speed rad/s, torque N·m]",
            ],
        ),
        // one point gives no torque at any speed: it said "needs 0.000 N·m … gives 0.000"
        (
            "[[joint]]\nkind = \"stepper\"\ncurve = [[0.0, 0.3]]\n".repeat(3),
            vec!["J1 (by order)", "curve has one point", "give at least two"],
        ),
    ];
    for (text, parts) in &cases {
        std::fs::write(dir.join("m.toml"), text).unwrap();
        let mut want = vec!["--motors", "m.toml"];
        want.extend(parts.iter().copied());
        refuses_keeping(
            &dir,
            &["wave", "--urdf", &urdf, "--duration", "0.01", "--motors", "m.toml"],
            &want,
        );
    }
    std::fs::remove_file(dir.join("m.toml")).unwrap();
    refuses(
        &dir,
        &["wave", "--urdf", &urdf, "--duration", "0.01", "--motors", "nema99"],
        &["--motors", "'nema99'", "not a preset"],
    );
    refuses(
        &dir,
        &["wave", "--urdf", &urdf, "--duration", "0.01", "--supply-voltage", "24"],
        &["--supply-voltage"],
    );
    refuses(
        &dir,
        &["wave", "--urdf", &urdf, "--duration", "0.01", "--motors", "faze4"],
        &["--motors", "6-joint", "3 joints"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// [`refuses`] where the input file `m.toml` stays in the directory.
fn refuses_keeping(dir: &std::path::Path, args: &[&str], parts: &[&str]) {
    let run = faze4(dir, args);
    assert_eq!(run.status.code(), Some(2), "{args:?}: {}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: one line on stderr, got:\n{}", run.stderr);
    for p in parts {
        assert!(lines[0].contains(p), "{:?} should mention {p:?}", lines[0]);
    }
    let left: Vec<_> = (std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n != "m.toml")
        .collect();
    assert!(left.is_empty(), "{args:?} left files behind: {left:?}");
}

/// Sweeps vary the supply, the efficiency and the motors' torque; the table has the motors'
/// figures per joint; the scales refuse a run without motors.
#[test]
fn sweeps_vary_supply_efficiency_and_stall_torque() {
    let dir = temp_dir("motor-sweep");
    let urdf = repo_path(URDF).display().to_string();
    let stepper = repo_path("tests/motors/stepper_arm.toml").display().to_string();
    let base = [
        "wave",
        "--urdf",
        urdf.as_str(),
        "--freq",
        "3",
        "--amp-deg",
        "60",
        "--duration",
        "1.5",
        "--no-collisions",
    ];
    let sweep = |vary: &[&str], extra: &[&str]| -> Vec<Value> {
        let mut args = vec!["sweep"];
        for v in vary {
            args.extend(["--vary", v]);
        }
        args.extend(["--out", "t.json", "--"]);
        args.extend(base);
        args.extend(extra);
        let run = faze4(&dir, &args);
        assert!(run.status.success(), "{args:?}: {}", run.stderr);
        let table: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("t.json")).unwrap()).unwrap();
        table.as_array().unwrap().clone()
    };
    let num = |row: &Value, k: &str| row[k].as_f64().unwrap_or_else(|| panic!("{k}: {row}"));
    // a stronger stepper on the shoulder: less beyond its curve
    let rows = sweep(&["stall-torque-scale=1,3"], &["--motors", &stepper]);
    assert!(
        num(&rows[1], "motors_envelope_pct_2") < num(&rows[0], "motors_envelope_pct_2"),
        "{rows:?}"
    );
    assert_eq!(rows[0]["motors_kind_2"], "stepper");
    // a less efficient reducer: the shoulder's envelope clips more
    let rows = sweep(&["efficiency-scale=0.5,1"], &["--motors", &stepper]);
    assert!(
        num(&rows[0], "motors_envelope_pct_2") > num(&rows[1], "motors_envelope_pct_2"),
        "{rows:?}"
    );
    // a servo's stall torque and no-load speed follow its supply
    let rows = sweep(&["supply-voltage=5,7.4"], &["--motors", "sts3215"]);
    assert!(num(&rows[0], "effort_1") < num(&rows[1], "effort_1"));
    // no motors to scale: each run fails, naming the scale
    let rows = sweep(&["efficiency-scale=0.5"], &[]);
    let reasons = rows[0]["reasons"].to_string();
    assert!(
        reasons.contains("efficiency-scale") && reasons.contains("--motors"),
        "{rows:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--plot-motors` draws each motored joint's envelope, operating points (given, and apart
/// from them the demands the clip cut), continuous line and RMS point, its axes named with
/// their units, motoring and braking apart; a stepper's panel says why it has no continuous
/// line; it needs `--motors`. `--plot` draws the envelope on the torque panels.
#[test]
fn the_sizing_plot_draws_envelopes_and_needs_motors() {
    let dir = temp_dir("motor-plot");
    let urdf = repo_path(URDF).display().to_string();
    let dc = repo_path("tests/motors/dc_arm.toml").display().to_string();
    // fast enough that the envelope clips the shoulder
    let args = [
        "wave",
        "--urdf",
        urdf.as_str(),
        "--duration",
        "0.5",
        "--freq",
        "8",
        "--no-collisions",
        "--trail",
        "none",
    ];
    let with = |extra: &[&'static str]| -> Vec<&str> { args.iter().copied().chain(extra.iter().copied()).collect() };
    let mut run_args = with(&["--plot-motors", "m.svg", "--plot", "p.svg", "--motors"]);
    run_args.push(&dc);
    let run = faze4(&dir, &run_args);
    assert!(run.status.success(), "{}", run.stderr);
    let svg = std::fs::read_to_string(dir.join("m.svg")).unwrap();
    for part in [
        "J1 yaw",
        "J2 shoulder",
        "J3 elbow",
        "envelope: motoring (above), braking (below)",
        "given (after the clip)",
        "asked (before the clip)",
        "RMS (",
        "continuous ±0.05 N·m",
        "motor speed |ω_m| (rad/s)",
        "torque along the motion τ_m·sgn(ω_m) (N·m)",
    ] {
        assert!(svg.contains(part), "the sizing plot should show {part:?}");
    }
    assert!(!svg.contains("no continuous line"), "DC motors have their line or none");
    let stepper = repo_path("tests/motors/stepper_arm.toml").display().to_string();
    let mut run_args = with(&["--plot-motors", "s.svg", "--motors"]);
    run_args.push(&stepper);
    let run = faze4(&dir, &run_args);
    assert!(run.status.success(), "{}", run.stderr);
    let svg = std::fs::read_to_string(dir.join("s.svg")).unwrap();
    assert!(svg.contains("no continuous line: a constant-current driver heats a stepper alike at any torque"));
    std::fs::remove_file(dir.join("s.svg")).unwrap();
    let plot = std::fs::read_to_string(dir.join("p.svg")).unwrap();
    assert!(
        plot.contains("envelope at q̇ (grey)"),
        "the torque panels should draw the envelope"
    );
    std::fs::remove_file(dir.join("m.svg")).unwrap();
    std::fs::remove_file(dir.join("p.svg")).unwrap();
    refuses(&dir, &with(&["--plot-motors", "m.svg"]), &["--plot-motors", "--motors"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
