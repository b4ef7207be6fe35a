//! retime's smooth timing against Ruckig's time-optimal jerk-limited single segments
//! (tools/oracle/retime_ruckig_fixtures.py writes tests/fixtures/retime_ruckig.json): a straight
//! move of one joint from rest to rest, or from and to a given velocity (`start_velocity`,
//! `end_velocity`: docs/retime.md, "Chaining segments"), under a speed, acceleration and jerk
//! limit (torque limits that do not bind), on the UR5 and the Panda. No timing that keeps the three limits is faster
//! than Ruckig's, so retime's is no shorter (to the 21 samples per interval at which it keeps
//! them), and it is within [`FACTOR`] of it (docs/retime.md, "Smooth ends and jerk").

use crate::common;

use faze4::model::Model;
use faze4::retime::{PathSpline, RetimeOptions, hold, retime};
use faze4::sim::Scenario;

/// The most retime's duration may exceed Ruckig's (the speed limit not reached: the window
/// averages a triangle in ṡ, 1.261×; the chained jerk-bound move from 0.5 rad/s, 1.235×, the
/// start's speed held over half a window: measured, docs/retime.md).
const FACTOR: f64 = 1.3;

#[test]
fn a_jerk_limited_straight_move_is_no_faster_than_ruckig() {
    let fixture: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(common::repo_path("tests/fixtures/retime_ruckig.json")).unwrap())
            .unwrap();
    let ur5 = common::load("tests/urdf/example_robot_data/ur5_robot.urdf");
    let panda = common::load("tests/urdf/example_robot_data/panda.urdf");
    for (arm, model) in [("UR5", &ur5), ("Panda", &panda)] {
        for case in fixture["cases"].as_array().unwrap() {
            let name = case["name"].as_str().unwrap();
            let value = |k: &str| case[k].as_f64().unwrap();
            let ruckig = value("duration");
            let path = straight(model, value("distance"));
            let per_joint = |v: f64| {
                let mut limits = vec![None; model.dof()];
                limits[0] = Some(v);
                limits
            };
            // torque limits far from binding: a slow move of J1 (a vertical axis on both)
            let base = Scenario::builder(model.clone(), hold(&path))
                .max_speed(per_joint(value("max_speed")))
                .effort(vec![1e4; model.dof()]);
            // a velocity along J1's axis, J1 alone moving (absent in the rest-to-rest cases: 0)
            let speed = |k: &str| case[k].as_f64().unwrap_or(0.0);
            let options = RetimeOptions {
                check: false,
                max_acceleration: per_joint(value("max_accel")),
                max_jerk: per_joint(value("max_jerk")),
                start_velocity: per_joint(speed("start_velocity")),
                end_velocity: per_joint(speed("end_velocity")),
                ..RetimeOptions::default()
            };
            let timed = retime(&base, &path, &options).unwrap_or_else(|e| panic!("{arm}, {name}: {e}"));
            let ours = timed.profile.duration();
            eprintln!(
                "{arm}, {name}: Ruckig {ruckig:.4} s, retime {ours:.4} s ({:.3}x; TOPP-RA {:.4} s, window {:.4} s), played asks {:.4} of J{}'s {} limit",
                ours / ruckig,
                timed.toppra.duration(),
                timed.window,
                timed.played.worst,
                timed.played.joint + 1,
                timed.played.limit
            );
            assert!(timed.played.worst <= 1.0 + 1e-6, "{arm}, {name}: {:?}", timed.played);
            let ends = [&timed.trajectory.points[0], timed.trajectory.points.last().unwrap()];
            for (p, k) in ends.into_iter().zip(["start_velocity", "end_velocity"]) {
                assert!((p.velocities[0] - speed(k)).abs() <= 1e-9, "{arm}, {name}: {k} {p:?}");
                assert!(p.accelerations[0].abs() <= 1e-9, "{arm}, {name}: {k} {p:?}");
            }
            assert!(
                ours >= ruckig * (1.0 - 1e-3),
                "{arm}, {name}: {ours} s is faster than Ruckig's {ruckig} s"
            );
            assert!(
                ours <= FACTOR * ruckig,
                "{arm}, {name}: {ours} s, {}x Ruckig's",
                ours / ruckig
            );
        }
    }
}

/// J1 moved by `distance` from the middle of every joint's range, the others still.
fn straight(model: &Model, distance: f64) -> PathSpline {
    let start: Vec<f64> = (model.joints.iter())
        .map(|j| 0.5 * (j.lower.max(-3.0) + j.upper.min(3.0)))
        .collect();
    let mut end = start.clone();
    end[0] += distance;
    PathSpline::through(&[start, end]).unwrap()
}
