//! `--drive stepper` (the open-loop stepper drive), `--microsteps` and `--sizing` on the
//! binary: slips in whole electrical cycles where the wave is too fast, none where it is slow,
//! the summary's and the verdict's account of them, the sizing report, and bad input refused
//! in one line.

use crate::common;

use common::*;
use serde_json::Value;

/// The Faze4's reducer ratios, J1..J6.
const RATIO: [f64; 6] = [25.0, 27.0, 15.0, 11.846, 11.0, 19.19];

/// Runs `args` (plus no clearance, no trail, a summary) in a fresh directory; returns the
/// run and its summary.
fn run(name: &str, args: &[&str]) -> (Run, Value) {
    let dir = temp_dir(name);
    let mut all = args.to_vec();
    all.extend(["--no-collisions", "--trail", "none", "--summary", "s.json"]);
    let out = faze4(&dir, &all);
    assert!(out.status.code().is_some_and(|c| c == 0), "{all:?}: {}", out.stderr);
    let s = summary(&dir, "s.json");
    std::fs::remove_dir_all(&dir).unwrap();
    (out, s)
}

/// A refused run: exit status 2 and one line on stderr containing `wanted`.
fn refused(name: &str, args: &[&str], wanted: &str) {
    let dir = temp_dir(name);
    let out = faze4(&dir, args);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {}", out.stderr);
    assert_eq!(out.stderr.lines().count(), 1, "{}", out.stderr);
    assert!(out.stderr.contains(wanted), "{args:?}: {}", out.stderr);
}

/// At `--freq 12.566` (2 Hz, 25°) the Faze4's NEMA17s cannot keep step: a joint loses whole
/// electrical cycles (a multiple of 4 full steps), the offset it carries is that many full
/// steps through its reducer, the time of the first slip is in the summary, and the verdict
/// names the joint, the time and the offset.
#[test]
fn a_fast_wave_slips_by_whole_electrical_cycles() {
    let (out, s) = run(
        "drive_fast",
        &[
            "wave",
            "--motors",
            "faze4",
            "--drive",
            "stepper",
            "--freq",
            "12.566",
            "--duration",
            "0.5",
        ],
    );
    let motors = s["motors"].as_array().unwrap();
    let mut slipped = 0;
    for (j, m) in motors.iter().enumerate() {
        assert_eq!(m["drive"], "stepper");
        let lost = m["steps_lost"].as_u64().unwrap();
        assert_eq!(lost % 4, 0, "J{}: {lost}", j + 1);
        // 4 full steps of a 1.8° motor are 7.2° at the shaft, 7.2°/r at the joint
        let offset = m["position_lost"].as_f64().unwrap();
        let want = lost as f64 * 1.8f64.to_radians() / RATIO[j];
        assert!((offset.abs() - want).abs() < 1e-12, "J{}: {offset} vs ±{want}", j + 1);
        if lost > 0 {
            slipped += 1;
            let t = m["loses_steps_at"].as_f64().unwrap();
            assert!(t > 0.0 && t < 0.5);
            assert!(
                out.stdout.contains(&format!(
                    "J{}'s stepper slips at t = {t:.3} s: {lost} full steps lost",
                    j + 1
                )),
                "{}",
                out.stdout
            );
        }
        assert!(m.get("step_loss").is_none(), "no demand under the open-loop drive");
    }
    assert!(slipped > 0, "{}", out.stdout);
    assert_eq!(s["verdict"]["follows"], false);
}

/// A slow wave at 16 microsteps keeps step on every joint; the command and the lag stay
/// within a fraction of a full step at the shaft (the joints' tracking error under 0.2 full
/// step through the reducer, plus the wave's lag).
#[test]
fn a_slow_wave_at_fine_microsteps_loses_nothing() {
    let (out, s) = run(
        "drive_slow",
        &[
            "wave",
            "--motors",
            "faze4",
            "--drive",
            "stepper",
            "--freq",
            "0.5",
            "--microsteps",
            "16",
            "--duration",
            "4",
        ],
    );
    for m in s["motors"].as_array().unwrap() {
        assert_eq!(m["steps_lost"].as_u64(), Some(0), "{m}");
        assert!(m["loses_steps_at"].is_null());
    }
    for (j, e) in vec_f64(&s["max_tracking_error_rad"]).iter().enumerate() {
        let full_step = 1.8f64.to_radians() / RATIO[j];
        assert!(*e < 2.0 * full_step, "J{}: {e} rad, a full step is {full_step}", j + 1);
    }
    assert!(out.stdout.ends_with("verdict: follows\n"), "{}", out.stdout);
}

/// `--drive pd` is the default: the summary says so and has no open-loop figures.
#[test]
fn the_pd_drive_is_the_default() {
    let (_, s) = run("drive_pd", &["wave", "--motors", "faze4", "--duration", "0.2"]);
    for m in s["motors"].as_array().unwrap() {
        assert_eq!(m["drive"], "pd");
        assert!(m.get("steps_lost").is_none() && m.get("position_lost").is_none());
    }
}

/// `--sizing` prints the report before the verdict; the summary holds it: the inertia ratio
/// is at least the start pose's ((M_ii/r² − J_rotor)/J_rotor from the summary's effective
/// inertia), the peak torque at least the RMS, the mean supply current the winding's R·I²/V
/// less what braking returned and more at most the peak power's worth.
#[test]
fn the_sizing_report_is_printed_and_in_the_summary() {
    let (out, s) = run(
        "sizing",
        &["wave", "--motors", "faze4", "--duration", "1", "--sizing", "-q"],
    );
    let lines: Vec<&str> = out.stdout.lines().collect();
    assert!(lines[0].starts_with("[sizing at the motor]"), "{}", out.stdout);
    assert!(lines.last().unwrap().starts_with("verdict: "));
    let rotor = 54e-7;
    let inertia = vec_f64(&s["effective_inertia"]);
    for (j, m) in s["motors"].as_array().unwrap().iter().enumerate() {
        let z = &m["sizing"];
        let at_start = (inertia[j] / (RATIO[j] * RATIO[j]) - rotor) / rotor;
        let ratio = z["inertia_ratio"].as_f64().unwrap();
        assert!(ratio >= at_start * (1.0 - 1e-12), "J{}: {ratio} < {at_start}", j + 1);
        assert!(z["peak_torque"].as_f64().unwrap() >= m["rms_torque"].as_f64().unwrap());
        let (v, duration) = (24.0, 1.0);
        let copper = 1.1 * 2.0 * 2.0 / v;
        let (peak, mean) = (
            z["supply_current_a"]["peak"].as_f64().unwrap(),
            z["supply_current_a"]["mean"].as_f64().unwrap(),
        );
        let braking = z["braking_energy_j"].as_f64().unwrap() / (v * duration);
        let motoring = z["peak_power_w"].as_f64().unwrap() / v;
        assert!(peak >= mean, "J{}: {peak} {mean}", j + 1);
        assert!(
            mean >= copper - braking - 1e-9 && mean <= copper + motoring + 1e-9,
            "J{}: {mean}",
            j + 1
        );
        assert_eq!(z["winding_loss_w"]["at_rating"].as_f64(), Some(2.0 * 1.1 * 4.0));
    }
}

/// A motors file's stepper drives open loop once it gives its step angle.
#[test]
fn a_file_stepper_needs_its_step_angle() {
    let dir = temp_dir("drive_file");
    let entry = |extra: &str| {
        format!(
            "[[joint]]\nname = \"hvataljka\"\ngear_ratio = 19.19\nrotor_inertia = 54e-7\nkind = \"stepper\"\ncurve = [[0, 0.3], [100, 0.2], [200, 0.0]]\n{extra}"
        )
    };
    std::fs::write(dir.join("bare.toml"), entry("")).unwrap();
    std::fs::write(dir.join("angle.toml"), entry("step_angle = 1.8\nmicrosteps = 16\n")).unwrap();
    let args = |file: &str| {
        [
            "wave",
            "--motors",
            file,
            "--drive",
            "stepper",
            "--duration",
            "0.2",
            "--no-collisions",
            "--trail",
            "none",
            "--summary",
            "s.json",
        ]
        .map(String::from)
    };
    let a = args("bare.toml");
    let out = faze4(&dir, &a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stderr.contains("--drive") && out.stderr.contains("J6") && out.stderr.contains("step_angle"));
    let a = args("angle.toml");
    let out = faze4(&dir, &a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(out.status.code(), Some(0), "{}", out.stderr);
    let s = summary(&dir, "s.json");
    let motors = s["motors"].as_array().unwrap();
    assert!(motors[..5].iter().all(Value::is_null));
    assert_eq!(motors[5]["drive"], "stepper");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_drive_options_are_refused_in_one_line() {
    refused("no_motors", &["wave", "--drive", "stepper"], "--drive");
    refused(
        "no_stepper",
        &["wave", "--motors", "sts3215", "--drive", "stepper"],
        "none of the joints' motors is a stepper",
    );
    refused(
        "pd_microsteps",
        &["wave", "--motors", "faze4", "--microsteps", "8"],
        "--microsteps",
    );
    refused(
        "zero",
        &["wave", "--motors", "faze4", "--drive", "stepper", "--microsteps", "0"],
        "--microsteps",
    );
    refused(
        "half",
        &["wave", "--motors", "faze4", "--drive", "stepper", "--microsteps", "1.5"],
        "whole number",
    );
    refused(
        "count",
        &["wave", "--motors", "faze4", "--drive", "stepper", "--microsteps", "8,8"],
        "--microsteps",
    );
    refused("no_sizing", &["wave", "--sizing"], "--sizing");
    refused("drive_word", &["wave", "--drive", "servo"], "--drive");
}

/// A step too coarse for the steppers' ringing is said (once, on stderr); a fine one is not.
#[test]
fn a_step_too_coarse_for_the_ringing_is_warned() {
    let base = ["wave", "--motors", "faze4", "--drive", "stepper", "--duration", "0.01"];
    let (out, _) = run("drive_coarse", &base);
    let lines: Vec<&str> = out.stderr.lines().filter(|l| l.contains("rings at")).collect();
    assert_eq!(lines.len(), 1, "{}", out.stderr);
    assert!(
        lines[0].contains("J6 ('hvataljka')") && lines[0].contains("--dt 0.00005"),
        "{}",
        lines[0]
    );
    let mut fine = base.to_vec();
    fine.extend(["--dt", "5e-5"]);
    let (out, _) = run("drive_fine", &fine);
    assert!(!out.stderr.contains("rings at"), "{}", out.stderr);
}
