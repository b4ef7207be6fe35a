//! retime under `drive` stepper (issue 46, item 5): the timing keeps what the open-loop drive
//! can follow (its rotors' ringing within the margin: the smoothing window at least the drive's
//! least window), so the first closed-loop check follows without a lost step on paths whose
//! timing slipped before (the J2 move and the circle at margin 0.1); margin 0 is refused,
//! naming `margin`. Under `drive` servo: a path whose ends the servos cannot stand at (their
//! loop's sag, their overload protection) is refused, naming which.

use crate::common;

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
    let circle = common::circle_path();
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
        assert!(
            timed.window >= least && least > 0.05,
            "{name}: window {} < {least}",
            timed.window
        );
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

/// The SO-101 behind STS3215 servos (`--motors sts3215 --drive servo`), with `payload` kg at
/// its tool, the verdict's tracking threshold `max_error`.
fn servos(path: &PathSpline, payload: f64, max_error: f64) -> ScenarioBuilder {
    use faze4::control::catalog::sts3215;
    let mut model = common::load("tests/urdf/example_robot_data/so101.urdf");
    let motors = vec![Some(sts3215(None)); model.dof()];
    let motors = faze4::config::motors::fit(&mut model, Some(motors), &[], &[])
        .unwrap()
        .unwrap();
    let thresholds = faze4::sim::Thresholds {
        max_error,
        ..faze4::sim::Thresholds::DEFAULT
    };
    Scenario::builder(model, hold(path))
        .motors(motors)
        .drive(Drive::Servo(Default::default()))
        .payload_kg(payload)
        .thresholds(thresholds)
}

/// `base` holding `path`'s point `k` for 4 s: the servos' own verdict on standing there.
fn stand(base: &ScenarioBuilder, path: &PathSpline, k: f64) -> faze4::sim::Summary {
    let mut q = vec![0.0; path.dof()];
    path.position(k, &mut q);
    use faze4::traj::{Interpolated, Trajectory, Wrap};
    let still = Trajectory::Interpolated(Interpolated::new(&[q.clone(), q], 1.0, Wrap::Repeat));
    let sc = base.clone().trajectory(still).duration(4.0).build().unwrap();
    faze4::sim::run(&sc, &mut [], &faze4::sim::StopFlag::new()).unwrap()
}

/// Under `drive` servo retime refuses, before any timing, a path whose ends the servos cannot
/// stand at, naming why, and each refusal is confirmed by the servos standing there alone:
/// at the SO-101's zero pose its shoulder's P-only loop sags past `max_error` 0.05 (no timing
/// follows: before, 8 check runs were spent on such a path); with 0.3 kg at the tool and
/// `max_error` 1, holding the end pose needs more than the protection's 80 % of stall, which
/// trips within 4 s (before, the timing was written with exit 0: its check ended before the
/// trip). With 0.2 kg it is timed, and follows.
#[test]
fn servos_that_cannot_stand_at_the_ends_are_refused_naming_why() {
    let zero = PathSpline::through(&[vec![0.0; 6], vec![0.8, -1.0, 1.0, 0.5, 0.5, 0.0]]).unwrap();
    let options = RetimeOptions::default();
    let base = servos(&zero, 0.0, 0.05);
    let e = retime(&base, &zero, &options).unwrap_err().to_string();
    assert!(
        e.contains("sags") && e.contains("`max_error`") && e.contains("start"),
        "{e}"
    );
    assert!(!stand(&base, &zero, 0.0).verdict.follows);

    let reach = PathSpline::through(&[
        vec![0.0, -1.0, 0.0, 0.0, 0.0, 0.0],
        vec![0.3, 0.3, -1.0, 0.0, 0.0, 0.0],
        vec![0.3, 1.0, -1.5, 0.0, 0.0, 0.0],
    ])
    .unwrap();
    let end = reach.length();
    let heavy = servos(&reach, 0.3, 1.0);
    let e = retime(&heavy, &reach, &options).unwrap_err().to_string();
    assert!(e.contains("overload protection") && e.contains("end"), "{e}");
    let stood = stand(&heavy, &reach, end);
    let j2 = stood.motors.as_ref().unwrap()[1].as_ref().unwrap();
    assert!(j2.servo.as_ref().unwrap().trip.is_some(), "{}", stood.verdict);
    assert!(!stood.verdict.follows);

    let light = servos(&reach, 0.2, 1.0);
    let timed = retime(&light, &reach, &options).unwrap();
    let check = timed.check.unwrap();
    assert!(check.summary.verdict.follows, "{}", check.summary.verdict);
    assert!(stand(&light, &reach, end).verdict.follows);
}
