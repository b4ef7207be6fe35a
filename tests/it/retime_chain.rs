//! Chaining retimed segments (issue 46, item 7; docs/retime.md, "Chaining segments"): a timing
//! that starts at `start_velocity` and ends at `end_velocity` writes exactly those velocities
//! with zero acceleration at its ends, keeps every limit as played, and is checked in a closed
//! loop whose arm arrives moving; velocities off the path's tangent, backwards or beyond the
//! limits are refused naming the option; two timings chained at a velocity join continuously and
//! play as one; given zeros change nothing.

use crate::common;

use common::most_asked_as_played;
use faze4::model::Model;
use faze4::retime::{PathSpline, RetimeOptions, Retimed, hold, replay_scenario, retime};
use faze4::sim::{Scenario, ScenarioBuilder, StopFlag, run};
use faze4::traj::TimedTrajectory;

/// The path's tangent q′(s).
fn tangent(path: &PathSpline, s: f64) -> Vec<f64> {
    let n = path.dof();
    let (mut q, mut dq, mut ddq) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    path.eval(s, &mut q, &mut dq, &mut ddq);
    dq
}

/// The joint velocity q′(s)·ṡ, as an option's values.
fn along(path: &PathSpline, s: f64, sd: f64) -> Vec<Option<f64>> {
    tangent(path, s).iter().map(|d| Some(d * sd)).collect()
}

/// The largest path speed of the timing from rest to rest.
fn top_speed(base: &ScenarioBuilder, path: &PathSpline) -> f64 {
    let options = RetimeOptions {
        check: false,
        ..RetimeOptions::default()
    };
    let timed = retime(base, path, &options).unwrap();
    timed.profile.x.iter().fold(0.0_f64, |m, &x| m.max(x.sqrt()))
}

fn base(model: &Model, path: &PathSpline, motors: Option<Vec<Option<faze4::control::JointMotor>>>) -> ScenarioBuilder {
    let mut fitted = model.clone();
    let envelopes = faze4::config::motors::fit(&mut fitted, motors, &[], &[]).unwrap();
    let mut base = Scenario::builder(fitted, hold(path));
    if let Some(envelopes) = envelopes {
        base = base.motors(envelopes);
    }
    base
}

/// The written trajectory's first and last points: velocities the given ones to 1e-9, and
/// s̈ = 0 there: accelerations q″ ṡ² to 1e-9 (0 on a straight path, the centripetal part on a
/// curved one).
fn assert_ends(arm: &str, timed: &Retimed, path: &PathSpline, start: &[Option<f64>], end: &[Option<f64>]) {
    let points = &timed.trajectory.points;
    let n = path.dof();
    for (p, given, s, which) in [
        (&points[0], start, 0.0, "first"),
        (&points[points.len() - 1], end, path.length(), "last"),
    ] {
        let (mut q, mut dq, mut ddq) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        path.eval(s, &mut q, &mut dq, &mut ddq);
        let given: Vec<f64> = (0..n).map(|j| given.get(j).copied().flatten().unwrap_or(0.0)).collect();
        let sd = dq.iter().zip(&given).map(|(d, v)| d * v).sum::<f64>() / dq.iter().map(|d| d * d).sum::<f64>();
        for j in 0..n {
            let (v, a) = (p.velocities[j], p.accelerations[j]);
            assert!(
                (v - given[j]).abs() <= 1e-9,
                "{arm}: the {which} point's J{} velocity {v}, given {}",
                j + 1,
                given[j]
            );
            let want = ddq[j] * sd * sd;
            assert!(
                (a - want).abs() <= 1e-9,
                "{arm}: the {which} point's J{} acceleration {a}, not q″ṡ² = {want}",
                j + 1
            );
        }
    }
}

#[test]
fn a_timing_starts_and_ends_at_the_given_velocities_and_keeps_the_limits() {
    let faze4_arm = faze4::faze4::model();
    let ur5 = common::load("tests/urdf/example_robot_data/ur5_robot.urdf");
    let circle = common::circle_path();
    let cases = [
        (
            "Faze4 circle, steppers",
            &faze4_arm,
            Some(faze4::faze4::motors::faze4(None)),
            circle,
        ),
        ("Faze4, constant", &faze4_arm, None, common::curved(&faze4_arm, 5, 3)),
        ("UR5, constant", &ur5, None, common::curved(&ur5, 5, 1)),
    ];
    for (arm, model, motors, path) in cases {
        let base = base(model, &path, motors);
        let top = top_speed(&base, &path);
        let length = path.length();
        let (start, end) = (along(&path, 0.0, 0.2 * top), along(&path, length, 0.15 * top));
        let options = RetimeOptions {
            start_velocity: start.clone(),
            end_velocity: end.clone(),
            ..RetimeOptions::default()
        };
        let timed = retime(&base, &path, &options).unwrap_or_else(|e| panic!("{arm}: {e}"));
        assert_ends(arm, &timed, &path, &start, &end);
        let scenario = base.clone().build().unwrap();
        let (share, j, t, what) = most_asked_as_played(&scenario, &timed.trajectory);
        let check = timed.check.as_ref().unwrap();
        eprintln!(
            "{arm}: ṡ {:.4} in, {:.4} out: {:.4} s (window {:.4} s), played asks at most {share:.4} of J{}'s {what} limit (t = {t:.4} s); {} check run(s), {}",
            0.2 * top,
            0.15 * top,
            timed.profile.duration(),
            timed.window,
            j + 1,
            check.attempts,
            check.summary.verdict
        );
        assert!(share <= 1.0 + 1e-6, "{arm}: J{}'s {what} at t = {t} s: {share}", j + 1);
        assert!(timed.played.worst <= 1.0 + 1e-6, "{arm}: {:?}", timed.played);
        assert!(check.summary.verdict.follows, "{arm}: {}", check.summary.verdict);
        // the check's arm (and replay's of the written file) arrives moving: its first state is
        // the first point's, velocity included
        let replayed = replay_scenario(&base, &timed.trajectory).unwrap();
        let first = faze4::sim::Step::new(&replayed);
        let given: Vec<f64> = start.iter().map(|v| v.unwrap()).collect();
        assert!(
            common::max_abs_diff(&first.state.v, &given) <= 1e-9,
            "{arm}: the run starts at {:?}, not {given:?}",
            first.state.v
        );
        assert!(common::max_abs_diff(&first.state.q, &timed.trajectory.points[0].positions) <= 1e-12);
    }
}

#[test]
fn two_timings_chained_at_a_velocity_join_continuously_and_play_as_one() {
    let model = faze4::faze4::model();
    let a: Vec<f64> = vec![0.0, 0.3, -0.4, 0.0, 0.3, 0.0];
    let d = [0.25, -0.2, 0.3, 0.15, -0.2, 0.25];
    let b: Vec<f64> = a.iter().zip(&d).map(|(a, d)| a + d).collect();
    let c: Vec<f64> = a.iter().zip(&d).map(|(a, d)| a + 1.8 * d).collect();
    let first = PathSpline::through(&[a.clone(), b.clone()]).unwrap();
    let second = PathSpline::through(&[b.clone(), c.clone()]).unwrap();
    let whole = PathSpline::through(&[a, c]).unwrap();
    let base = base(&model, &whole, None);
    let junction = along(&first, first.length(), 0.5 * top_speed(&base, &first));
    let ab = RetimeOptions {
        end_velocity: junction.clone(),
        ..RetimeOptions::default()
    };
    let bc = RetimeOptions {
        start_velocity: junction.clone(),
        ..RetimeOptions::default()
    };
    let one = retime(&base, &first, &ab).unwrap();
    let two = retime(&base, &second, &bc).unwrap();
    let rest: Vec<Option<f64>> = vec![None; model.dof()];
    assert_ends("A→B", &one, &first, &rest, &junction);
    assert_ends("B→C", &two, &second, &junction, &rest);
    let (end, next) = (one.trajectory.points.last().unwrap(), &two.trajectory.points[0]);
    assert!(common::max_abs_diff(&end.positions, &next.positions) <= 1e-12);
    assert!(common::max_abs_diff(&end.velocities, &next.velocities) <= 1e-9);
    // on the straight junction, zero acceleration on both sides
    assert!(common::max_abs(&end.accelerations) <= 1e-9 && common::max_abs(&next.accelerations) <= 1e-9);
    // the two as one trajectory: the junction's point once
    let offset = end.time_from_start;
    let mut points = one.trajectory.points.clone();
    points.extend(two.trajectory.points[1..].iter().cloned().map(|mut p| {
        p.time_from_start += offset;
        p
    }));
    let mut joined = TimedTrajectory {
        joint_names: one.trajectory.joint_names.clone(),
        points,
    };
    joined.round_times_to_nanoseconds();
    let scenario = replay_scenario(&base, &joined).unwrap();
    let (share, j, t, what) = most_asked_as_played(&scenario, &joined);
    let summary = run(&scenario, &mut [], &StopFlag::new()).unwrap();
    eprintln!(
        "A→B {:.4} s ending at ṡ {:.4}, B→C {:.4} s: together {:.4} s, played asks at most {share:.4} of J{}'s {what} limit (t = {t:.4} s), {}",
        one.profile.duration(),
        one.profile.x.last().unwrap().sqrt(),
        two.profile.duration(),
        joined.points.last().unwrap().time_from_start,
        j + 1,
        summary.verdict
    );
    assert!(share <= 1.0 + 1e-6, "J{}'s {what} at t = {t} s: {share}", j + 1);
    assert!(summary.verdict.follows, "{}", summary.verdict);
    // chained at a speed, the two are faster than two rest-to-rest timings
    let rested = [&first, &second].map(|p| retime(&base, p, &RetimeOptions::default()).unwrap());
    let apart = rested[0].profile.duration() + rested[1].profile.duration();
    assert!(
        joined.points.last().unwrap().time_from_start < apart,
        "chained {} s, stopping between {apart} s",
        joined.points.last().unwrap().time_from_start
    );
}

#[test]
fn velocities_off_the_tangent_backwards_or_beyond_the_limits_are_refused_naming_the_option() {
    let model = faze4::faze4::model();
    let ur5 = common::load("tests/urdf/example_robot_data/ur5_robot.urdf");
    let path = common::curved(&model, 5, 3);
    let ur5_path = common::curved(&ur5, 5, 1);
    let length = path.length();
    let refused = |model: &Model, path: &PathSpline, options: RetimeOptions, parts: &[&str]| {
        let base = base(model, path, None);
        let options = RetimeOptions {
            check: false,
            ..options
        };
        let e = retime(&base, path, &options).expect_err("refused").to_string();
        assert!(e.len() < 600, "a long message: {e}");
        for p in parts {
            assert!(e.contains(p), "{e:?} should mention {p:?}");
        }
    };
    let mut off = along(&path, 0.0, 0.5);
    off[1] = off[1].map(|v| v + 0.01);
    refused(
        &model,
        &path,
        RetimeOptions {
            start_velocity: off,
            ..RetimeOptions::default()
        },
        &["`start_velocity`", "not along the path's tangent at its start", "off"],
    );
    refused(
        &model,
        &path,
        RetimeOptions {
            end_velocity: along(&path, length, -0.5),
            ..RetimeOptions::default()
        },
        &["`end_velocity`", "points back along the path at its end"],
    );
    // the UR5's URDF speed limits
    refused(
        &ur5,
        &ur5_path,
        RetimeOptions {
            start_velocity: along(&ur5_path, 0.0, 50.0),
            ..RetimeOptions::default()
        },
        &["`start_velocity`", "at most ṡ = ", "speed limit binds"],
    );
    // the Faze4's torque limits: no braking to rest from there within the path
    refused(
        &model,
        &path,
        RetimeOptions {
            start_velocity: along(&path, 0.0, 40.0),
            ..RetimeOptions::default()
        },
        &["`start_velocity`", "at most ṡ = ", "torque"],
    );
    refused(
        &model,
        &path,
        RetimeOptions {
            end_velocity: vec![Some(1.0); 2],
            ..RetimeOptions::default()
        },
        &["`end_velocity`"],
    );
    // velocities near f64's largest: their norm and ṡ must not overflow past the tangent's check
    // (a norm of inf let any velocity through it), and a figure is not printed in 155 digits
    for scale in [1e308, -1e308, f64::MAX, -f64::MAX] {
        let mut v = vec![Some(0.0); model.dof()];
        v[0] = Some(scale);
        refused(
            &model,
            &path,
            RetimeOptions {
                start_velocity: v,
                ..RetimeOptions::default()
            },
            &["`start_velocity`", "not along the path's tangent at its start"],
        );
    }
    refused(
        &model,
        &path,
        RetimeOptions {
            end_velocity: along(&path, length, 1e200),
            ..RetimeOptions::default()
        },
        &["`end_velocity`", "is beyond any limit (ṡ² is not a finite number)"],
    );
}

#[test]
fn an_end_speed_no_timing_reaches_is_refused_as_such_not_as_a_path_nothing_follows() {
    // a speed within the last point's own limits that the path cannot accelerate to from rest:
    // the backward pass is stuck mid-path, which read "nothing follows … at any path speed"
    let model = faze4::faze4::model();
    let path = common::curved(&model, 5, 3);
    let base = base(&model, &path, None);
    let top = top_speed(&base, &path);
    let length = path.length();
    let mut unreachable = 0;
    for fiftieths in 10..=50 {
        let options = RetimeOptions {
            check: false,
            end_velocity: along(&path, length, top * fiftieths as f64 / 50.0),
            ..RetimeOptions::default()
        };
        let Err(e) = retime(&base, &path, &options) else {
            continue;
        };
        let e = e.to_string();
        assert!(e.contains("`end_velocity`") && !e.contains("nothing follows"), "{e}");
        unreachable += e.contains("cannot be reached from the start at rest") as usize;
        // the figures agree with the claim: a speed refused as above the top is above it, one
        // refused as outside a range is outside it
        let number = |after: &str| -> f64 {
            let rest = &e[e.find(after).unwrap_or_else(|| panic!("{e}")) + after.len()..];
            rest.split([' ', ',']).next().unwrap().parse().unwrap()
        };
        let asked = number("its path speed ṡ = ");
        if e.contains("at most ṡ = ") {
            assert!(asked > number("at most ṡ = "), "{e}");
        }
        if e.contains("ṡ from ") {
            let (from, to) = (number("ṡ from "), number(" to "));
            assert!(asked < from || asked > to, "{e}");
        }
    }
    assert!(
        unreachable > 0,
        "no end speed between 0.2 and 1 times the top was unreachable"
    );
}

#[test]
fn given_zeros_change_nothing() {
    let model = faze4::faze4::model();
    let path = common::curved(&model, 5, 3);
    let base = base(&model, &path, None);
    let options = RetimeOptions {
        check: false,
        ..RetimeOptions::default()
    };
    let at_rest = retime(&base, &path, &options).unwrap();
    let zeros = RetimeOptions {
        start_velocity: vec![Some(0.0); model.dof()],
        end_velocity: vec![None; model.dof()],
        ..options
    };
    let given = retime(&base, &path, &zeros).unwrap();
    assert_eq!(at_rest.trajectory, given.trajectory);
}

#[test]
fn the_command_line_names_the_flag() {
    let dir = common::temp_dir("retime_chain_flag");
    let circle = common::repo_path("tests/fixtures/shape_circle_q.npy");
    let out = dir.join("c.yaml");
    common::refuses(
        &dir,
        &[
            "retime",
            "--q-traj",
            circle.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--start-velocity",
            "1,0,0,0,0,0",
        ],
        &["--start-velocity", "not along the path's tangent"],
    );
}
