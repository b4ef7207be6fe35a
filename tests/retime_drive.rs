//! retime under `drive` stepper (issue 46, item 5): the timing keeps what the open-loop drive
//! can follow (its rotors' ringing within the margin: the smoothing window at least the drive's
//! least window), so the first closed-loop check follows without a lost step on paths whose
//! timing slipped before (the J2 move and the circle at margin 0.1); margin 0 is refused,
//! naming `margin`.

mod common;

use common::repo_path;
use faze4::retime::{PathSpline, RetimeOptions, hold, retime};
use faze4::sim::{Drive, Scenario, ScenarioBuilder};

/// The Faze4 behind its steppers (`--motors faze4`), driven open loop (`--drive stepper`).
fn open_loop(path: &PathSpline) -> ScenarioBuilder {
    let mut model = faze4::faze4::model();
    let motors = faze4::config::motors::fit(&mut model, Some(faze4::faze4::motors::faze4(None)), &[], &[]);
    Scenario::builder(model, hold(path))
        .motors(motors.unwrap().unwrap())
        .drive(Drive::Stepper(Default::default()))
}

/// 4(1 − m)/(m·ω_n) of the slowest-ringing stepper, from the built scenario's drives: the
/// window docs/retime.md ("The drive's own limits") asks for.
fn least_window(base: &ScenarioBuilder, margin: f64) -> f64 {
    let scenario = base.clone().build().unwrap();
    (scenario.drives.iter())
        .filter_map(|d| d.stepper())
        .map(|d| 4.0 * (1.0 - margin) / (margin * d.damping.natural_frequency))
        .fold(0.0, f64::max)
}

/// J2 moved 0.5 rad alone and the Faze4's circle, at margin 0.1: before, the first timing of
/// each slipped (J2 at t = 0.052 s, 448 full steps; J3 at 0.059 s, 1004) and the J2 move
/// needed 3 checks; now the first check follows, no stepper loses a step, and the window is at
/// least the drive's.
#[test]
fn the_first_timing_under_the_stepper_drive_loses_no_step() {
    let j2 = PathSpline::through(&[vec![0.0; 6], vec![0.0, 0.5, 0.0, 0.0, 0.0, 0.0]]).unwrap();
    let circle = {
        let points = faze4::traj::npy::read_samples(&repo_path("tests/fixtures/shape_circle_q.npy")).unwrap();
        PathSpline::through(&points).unwrap()
    };
    let margin = 0.1;
    let options = RetimeOptions {
        margin,
        ..RetimeOptions::default()
    };
    for (name, path) in [("J2 0.5 rad", j2), ("circle", circle)] {
        let base = open_loop(&path);
        let timed = retime(&base, &path, &options).unwrap_or_else(|e| panic!("{name}: {e}"));
        let check = timed.check.as_ref().unwrap();
        let least = least_window(&base, margin);
        eprintln!(
            "{name}: {:.4} s, window {:.4} s (the drive's least {least:.4} s), {} check run(s): {}",
            timed.profile.duration(),
            timed.window,
            check.attempts,
            check.summary.verdict
        );
        assert!(timed.window >= least && least > 0.05, "{name}: window {} < {least}", timed.window);
        assert_eq!(check.attempts, 1, "{name}: {}", check.summary.verdict);
        assert!(check.summary.verdict.follows, "{name}: {}", check.summary.verdict);
        let motors = check.summary.motors.as_ref().unwrap();
        for (j, m) in motors.iter().enumerate() {
            let lost = m.as_ref().and_then(|m| m.steps_lost);
            assert_eq!(lost, Some(0), "{name}: J{} lost steps", j + 1);
        }
    }
}

/// Margin 0 leaves an open-loop stepper nothing for its ringing: refused before any timing,
/// naming `margin`; under the PD the same path and margin are timed.
#[test]
fn margin_zero_under_the_stepper_drive_is_refused_naming_margin() {
    let path = PathSpline::through(&[vec![0.0; 6], vec![0.3, 0.0, 0.0, 0.0, 0.0, 0.0]]).unwrap();
    let options = RetimeOptions {
        margin: 0.0,
        check: false,
        ..RetimeOptions::default()
    };
    let e = retime(&open_loop(&path), &path, &options).unwrap_err().to_string();
    assert!(e.contains("`margin`") && e.contains("ringing"), "{e}");
    let pd = open_loop(&path).drive(Drive::Pd);
    let timed = retime(&pd, &path, &options).unwrap();
    assert!(timed.window > 0.0 && timed.window < least_window(&open_loop(&path), 0.3));
}
