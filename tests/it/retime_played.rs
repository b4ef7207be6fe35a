//! The timing as a controller plays it (issue 46, item 2): the trajectory retime writes,
//! joined between its points as `joint_trajectory_controller` joins it (a quintic when
//! positions, velocities and accelerations are written, as retime writes them), keeps every
//! speed and torque limit, less the margin, at 21 times per interval (every 1/20 of it): not only at the grid
//! points. Checked here from the command `faze4 replay` makes of the written trajectory, with
//! inverse dynamics, damping and each motor's envelope computed apart from retime's own code.

use crate::common;

use common::most_asked_as_played;
use faze4::retime::{RetimeOptions, hold, retime};
use faze4::sim::Scenario;

#[test]
fn the_played_trajectory_keeps_every_limit_between_its_points() {
    use faze4::control::catalog::sts3215;
    let faze4_arm = faze4::faze4::model();
    let ur5 = common::load("tests/urdf/example_robot_data/ur5_robot.urdf");
    let panda = common::load("tests/urdf/example_robot_data/panda.urdf");
    let so101 = common::load("tests/urdf/example_robot_data/so101.urdf");
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
        ("Panda, constant", &panda, None, common::curved(&panda, 5, 2)),
        (
            "SO-101, sts3215",
            &so101,
            Some(vec![Some(sts3215(None)); so101.dof()]),
            common::curved(&so101, 9, 4),
        ),
    ];
    // the default timing (no check run): kept as played by default, not by a flag
    let options = RetimeOptions {
        check: false,
        ..RetimeOptions::default()
    };
    for (arm, model, motors, path) in cases {
        let mut fitted = model.clone();
        let envelopes = faze4::config::motors::fit(&mut fitted, motors, &[], &[]).unwrap();
        let mut base = Scenario::builder(fitted, hold(&path));
        if let Some(envelopes) = envelopes {
            base = base.motors(envelopes);
        }
        let timed = retime(&base, &path, &options).unwrap_or_else(|e| panic!("{arm}: {e}"));
        let scenario = base.clone().build().unwrap();
        let (share, j, t, what) = most_asked_as_played(&scenario, &timed.trajectory);
        eprintln!(
            "{arm}: {:.4} s, played asks at most {share:.4} of J{}'s {what} limit (t = {t:.4} s); retime's own figure {:.4}",
            timed.profile.duration(),
            j + 1,
            timed.played.worst
        );
        assert!(
            share <= 1.0 + 1e-6,
            "{arm}: J{}'s {what} at t = {t} s is {share} of its limit less the margin",
            j + 1
        );
        // retime's own share is τ/(k·hi − d·q̇), this one (τ + d·q̇)/(k·hi): both ≤ 1 together
        assert!(
            timed.played.worst <= 1.0 + 1e-6,
            "{arm}: retime says {}",
            timed.played.worst
        );
        assert!(
            (share - timed.played.worst).abs() < 1e-2,
            "{arm}: {share} vs {}",
            timed.played.worst
        );
        // it starts and stops at rest with zero acceleration
        for p in [&timed.trajectory.points[0], timed.trajectory.points.last().unwrap()] {
            assert!(
                (p.velocities.iter().chain(&p.accelerations)).all(|v| v.abs() < 1e-12),
                "{arm}: not at rest with zero acceleration at t = {}: {p:?}",
                p.time_from_start
            );
        }
        eprintln!(
            "   TOPP-RA (bang-bang s̈, at the grid points only): {:.4} s; window {:.4} s",
            timed.toppra.duration(),
            timed.window
        );
    }
}
