//! retime against TOPP-RA (toppra 0.6, the reference implementation of Pham & Pham 2018) on the
//! same spline and grid: fixtures by tools/oracle/retime_fixtures.py.
//!
//! * Constant limits on ur5, panda (example-robot-data) and the Faze4: the spline and the
//!   torque coefficients equal toppra's (Pinocchio's RNEA) to round-off; without a margin the
//!   duration equals toppra's within 1e-3 and so does the profile; with the default margin it
//!   is within 1.25× of toppra's and the result follows in faze4's loop.
//! * The Faze4's circle with its stepper motors: toppra given the holding torque as a
//!   constant loses steps in faze4's loop; toppra given the envelope at the best single top
//!   speed follows but is slower than retime, which follows. At its grid points the
//!   holding-torque timing asks a motor for more than its envelope gives at its speed; retime's
//!   never asks more than 1 − margin of it.
//!
//! `FAZE4_UPDATE_DOCS=1 cargo test --release --test it retime_vs_toppra::` rewrites the two tables
//! of docs/retime.md between their markers.

use crate::common;

use common::{fixture, mat_f64, most_asked, repo_path, vec_f64};
use faze4::algo::{Data, gravity, rnea};
use faze4::model::{Model, PackagePaths, urdf};
use faze4::retime::{DEFAULT_MARGIN, PathSpline, Profile, RetimeOptions, hold, play, retime};
use faze4::sim::{Scenario, ScenarioBuilder, StopFlag, Summary};
use serde_json::Value;

/// The arm of a constant-limit fixture, its damping zeroed (toppra's torque has none).
fn arm(f: &Value) -> Model {
    let mut model = match (f["urdf"].as_str(), f["urdf_text"].as_str()) {
        (Some(rel), _) => urdf::read_file(&repo_path(rel), &PackagePaths::default()),
        (None, Some(text)) => urdf::read_str(text, f["robot"].as_str().unwrap(), None, &PackagePaths::default()),
        _ => panic!("the fixture names no URDF"),
    }
    .unwrap();
    model.joints.iter_mut().for_each(|j| j.damping = 0.0);
    let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    let theirs: Vec<&str> = f["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert_eq!(names, theirs, "joint order");
    model
}

/// The scenario of a constant-limit fixture: its torque and speed limits.
fn constant_base(model: &Model, path: &PathSpline, f: &Value) -> ScenarioBuilder {
    Scenario::builder(model.clone(), hold(path))
        .effort(vec_f64(&f["torque_limit"]))
        .max_speed(vec_f64(&f["velocity_limit"]).into_iter().map(Some).collect())
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Our spline and faze4's inverse dynamics give toppra's torque coefficients (Pinocchio's
/// RNEA on SciPy's spline) at the fixture's grid points.
fn coefficients_match(model: &Model, path: &PathSpline, f: &Value) {
    let grid = vec_f64(&f["gridpoints"]);
    let n = model.dof();
    let mut data = Data::new(model);
    let (mut q, mut dq, mut ddq) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for entry in f["coefficients"].as_array().unwrap() {
        let i = entry["i"].as_u64().unwrap() as usize;
        path.eval(grid[i], &mut q, &mut dq, &mut ddq);
        let c = gravity(model, &mut data, &q).as_slice().to_vec();
        let a: Vec<f64> = (rnea(model, &mut data, &q, &vec![0.0; n], &dq).iter().zip(&c))
            .map(|(t, g)| t - g)
            .collect();
        let b: Vec<f64> = (rnea(model, &mut data, &q, &dq, &ddq).iter().zip(&c))
            .map(|(t, g)| t - g)
            .collect();
        for (name, ours, theirs) in [("a", &a, &entry["a"]), ("b", &b, &entry["b"]), ("c", &c, &entry["c"])] {
            for (j, (x, y)) in ours.iter().zip(vec_f64(theirs)).enumerate() {
                assert!(
                    (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
                    "{} {name} J{} at grid point {i}: {x} vs toppra {y}",
                    f["robot"],
                    j + 1
                );
            }
        }
    }
}

/// Checks the constant-limit fixture `name` (`retime_toppra_{name}.json`) and returns its row of
/// the constant table and how far its profile is from toppra's (share of the top speed).
fn constant_limits(name: &str, arm_name: &str) -> (String, f64) {
    let f = fixture(&format!("retime_toppra_{name}.json"));
    let model = arm(&f);
    let path = PathSpline::through(&mat_f64(&f["waypoints"])).unwrap();
    coefficients_match(&model, &path, &f);
    let base = constant_base(&model, &path, &f);
    let bare = RetimeOptions {
        margin: 0.0,
        check: false,
        intervals: f["intervals"].as_u64().unwrap() as usize,
        ..RetimeOptions::default()
    };
    let ours = retime(&base, &path, &bare).unwrap();
    let theirs = f["duration"].as_f64().unwrap();
    // TOPP-RA's own profile, before retime averages it (the timing written)
    let duration = ours.toppra.duration();
    assert!(
        relative(duration, theirs) < 1e-6,
        "{name}: {duration} s vs toppra's {theirs} s"
    );
    let x = vec_f64(&f["x"]);
    let top = x.iter().copied().fold(0.0, f64::max);
    let worst = (ours.toppra.x.iter().zip(&x))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6 * top, "{name}: profiles differ by {worst} (top {top})");

    let margined = retime(&base, &path, &RetimeOptions::default()).unwrap();
    let check = margined.check.as_ref().unwrap();
    assert!(check.summary.verdict.follows, "{name}: {}", check.summary.verdict);
    eprintln!(
        "{name}: toppra {theirs:.6} s, retime without margin {duration:.6} s ({:+.2e}), profiles within {:.1e} of the top; with the margin {:.4} s ({:.3}×), {} check run(s): {}",
        (duration - theirs) / theirs,
        worst / top,
        margined.profile.duration(),
        margined.profile.duration() / theirs,
        check.attempts,
        check.summary.verdict
    );
    assert!(
        margined.profile.duration() <= 1.25 * theirs,
        "{name}: with the margin {} s, toppra without {theirs} s",
        margined.profile.duration()
    );
    let apart = (duration - theirs) / theirs;
    let sign = if apart < 0.0 { "−" } else { "+" };
    let row = format!(
        "| {arm_name} | {theirs:.6} | {duration:.6} | {sign}{:.1e} | {:.4} | {:.3} | {} | {} |\n",
        apart.abs(),
        margined.profile.duration(),
        margined.profile.duration() / theirs,
        check.attempts,
        check.summary.verdict.to_string().trim_start_matches("verdict: ")
    );
    (row, worst / top)
}

#[test]
fn constant_limits_as_toppra() {
    let arms = [
        ("ur5", "UR5 (example-robot-data)"),
        ("panda", "Panda (example-robot-data)"),
        ("faze4_arm", "Faze4 (constant limits)"),
    ];
    let mut table = String::from(
        "| arm | toppra (s) | retime, no margin (s) | relative | retime, margin 0.3, checked (s) | × toppra | check runs | verdict |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut worst: f64 = 0.0;
    for (name, arm_name) in arms {
        let (row, apart) = constant_limits(name, arm_name);
        table.push_str(&row);
        worst = worst.max(apart);
    }
    table.push_str(&format!("\nProfiles agree within {worst:.1e} of the top speed.\n"));
    if std::env::var_os("FAZE4_UPDATE_DOCS").is_some() {
        replace_between("<!-- constant table -->\n", "<!-- /constant table -->", &table);
    }
}

/// One row of the stepper table.
struct Row {
    timing: &'static str,
    duration: f64,
    summary: Summary,
}

#[test]
fn circle_with_steppers_beats_toppra_constants() {
    let f = fixture("retime_toppra_circle.json");
    assert_eq!(
        f["margin"].as_f64(),
        Some(DEFAULT_MARGIN),
        "the fixture's margin is retime's default"
    );
    let model = faze4::faze4::model();
    let points = faze4::traj::npy::read_samples(&repo_path(f["path"].as_str().unwrap())).unwrap();
    let path = PathSpline::through(&points).unwrap();
    let motors = faze4::faze4::motors::faze4(None);
    // the fixture's constants are faze4's envelope: the holding torque, and the torque at ω
    let keep = 1.0 - DEFAULT_MARGIN;
    for (case, omega) in [
        ("holding", 0.0),
        ("top_speed", f["top_speed"]["omega"].as_f64().unwrap()),
    ] {
        for (j, (m, &tau)) in motors.iter().zip(&vec_f64(&f[case]["torque_limit"])).enumerate() {
            let m = m.as_ref().unwrap();
            let ratio = m.gear_ratio.unwrap();
            let ours = keep * m.motor.joint_bounds(ratio, omega / ratio).1;
            assert!(relative(tau, ours) < 1e-9, "{case} J{}: {tau} vs faze4's {ours}", j + 1);
        }
    }
    let mut motored = model;
    let fitted = faze4::config::motors::fit(&mut motored, Some(motors.clone()), &[], &[])
        .unwrap()
        .unwrap();
    let base = Scenario::builder(motored.clone(), hold(&path)).motors(fitted);
    let grid = vec_f64(&f["gridpoints"]);
    let toppra = |case: &str| Profile::from_x(grid.clone(), vec_f64(&f[case]["x"]));
    let stop = StopFlag::new();
    let ours = retime(&base, &path, &RetimeOptions::default()).unwrap();
    let mut rows = Vec::new();
    for (timing, case) in [
        ("toppra, holding torque", "holding"),
        ("toppra, envelope at the best top speed", "top_speed"),
    ] {
        let profile = toppra(case);
        assert!(relative(profile.duration(), f[case]["duration"].as_f64().unwrap()) < 1e-12);
        rows.push(Row {
            timing,
            duration: profile.duration(),
            summary: play(&base, &path, &profile, &stop).unwrap(),
        });
    }
    rows.push(Row {
        timing: "faze4 retime",
        duration: ours.profile.duration(),
        summary: ours.check.as_ref().unwrap().summary.clone(),
    });
    let [holding, top, retimed] = &rows[..] else {
        unreachable!()
    };
    let lost = |s: &Summary| s.motors.iter().flatten().flatten().any(|m| m.step_loss.is_some());
    assert!(lost(&holding.summary), "holding torque: {}", holding.summary.verdict);
    assert!(!holding.summary.verdict.follows);
    assert!(top.summary.verdict.follows, "top speed: {}", top.summary.verdict);
    assert!(retimed.summary.verdict.follows, "retime: {}", retimed.summary.verdict);
    assert!(
        retimed.duration < top.duration,
        "retime {} s, toppra at the top speed {} s",
        retimed.duration,
        top.duration
    );
    // toppra's holding-torque timing asks a motor for more than its envelope; retime's keeps
    // 1 − margin of every envelope at every grid point
    let toppra_asks = most_asked(&motored, &motors, &path, &toppra("holding"));
    let retime_asks = most_asked(&motored, &motors, &path, &ours.profile);
    assert!(
        toppra_asks.0 > 1.0,
        "toppra, holding torque, asks at most {toppra_asks:?}"
    );
    assert!(retime_asks.0 <= keep * (1.0 + 1e-9), "retime asks {retime_asks:?}");
    if std::env::var_os("FAZE4_UPDATE_DOCS").is_some() {
        update_docs(
            &rows,
            &ours,
            f["top_speed"]["omega"].as_f64().unwrap(),
            [toppra_asks, retime_asks],
        );
    }
}

/// Rewrites docs/retime.md's stepper table between its markers.
fn update_docs(rows: &[Row], ours: &faze4::retime::Retimed, omega: f64, asks: [(f64, usize, usize, f64); 2]) {
    let mut table = String::from("| timing | duration (s) | in faze4's loop (`--motors faze4`) |\n|---|---|---|\n");
    for r in rows {
        let verdict = r.summary.verdict.to_string();
        let verdict = verdict
            .strip_prefix("verdict: ")
            .unwrap_or(&verdict)
            .replace('|', "\\|");
        table.push_str(&format!("| {} | {:.3} | {} |\n", r.timing, r.duration, verdict));
    }
    table.push_str(&format!(
        "\nThe best single top speed was ω = {omega:.1} rad/s at the motors. retime: {} envelope rounds, {} check run(s); with each motor's holding torque as a constant (the relaxed bound) no timing can be faster than {:.3} s.\n",
        ours.iterations,
        ours.check.as_ref().map_or(0, |c| c.attempts),
        ours.relaxed_duration
    ));
    let [(toppra, tj, ti, tw), (retime, rj, ri, rw)] = asks;
    table.push_str(&format!(
        "\nAt the grid points, inverse dynamics and the joint's damping against each motor's envelope at its speed: toppra's holding-torque timing asks J{}'s motor for {toppra:.2}× what its envelope gives (grid point {ti}, the motor at {tw:.0} rad/s, past the pull-out curve's knee, where the holding torque is no bound); retime's asks at most {retime:.2}× (J{}, grid point {ri}, {rw:.0} rad/s).\n",
        tj + 1,
        rj + 1
    ));
    replace_between("<!-- circle table -->\n", "<!-- /circle table -->", &table);
}

/// Rewrites docs/retime.md between the markers `open` and `close` with `table`.
fn replace_between(open: &str, close: &str, table: &str) {
    let doc = repo_path("docs/retime.md");
    let text = std::fs::read_to_string(&doc).unwrap();
    let start = text.find(open).expect("the opening marker") + open.len();
    let end = text.find(close).expect("the closing marker");
    std::fs::write(&doc, format!("{}{table}{}", &text[..start], &text[end..])).unwrap();
}
