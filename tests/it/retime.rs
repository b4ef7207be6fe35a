//! retime from the library: what it promises about its timing (the envelopes kept at every grid
//! point, the phase plane, the trajectory it hands the writers), the closed-loop check slowing
//! what fails, the figure, and the one-line errors for bad paths and limits nothing follows.

use crate::common;

use common::{most_asked, repo_path};
use faze4::Error;
use faze4::algo::Data;
use faze4::model::Model;
use faze4::retime::{DEFAULT_MARGIN, PathSpline, RetimeOptions, Retimed, hold, retime};
use faze4::sim::{Scenario, ScenarioBuilder};
use faze4::viz::PhasePlot;

/// `model` behind the Faze4's steppers (`--motors faze4`): their ratios and rotors fitted to it.
fn with_motors(model: &Model, path: &PathSpline) -> ScenarioBuilder {
    let mut motored = model.clone();
    let motors = faze4::config::motors::fit(&mut motored, Some(faze4::faze4::motors::faze4(None)), &[], &[]);
    Scenario::builder(motored, hold(path)).motors(motors.unwrap().unwrap())
}

fn no_check() -> RetimeOptions {
    RetimeOptions {
        check: false,
        ..RetimeOptions::default()
    }
}

/// At every grid point s_i, with the path speed there and the path acceleration of the interval
/// that starts there (TOPP-RA's collocation: the pair its stage i keeps), the torque the motion
/// needs (inverse dynamics plus damping) is within what each motor gives at the joint's speed
/// there, less the margin: the envelope is kept, not its linear bound.
#[test]
fn the_timing_keeps_every_envelope_at_every_grid_point() {
    let model = faze4::faze4::model();
    let path = common::circle_path();
    let timed = retime(&with_motors(&model, &path), &path, &no_check()).unwrap();
    let motors = faze4::faze4::motors::faze4(None);
    let mut motored = model.clone();
    for (joint, m) in motored.joints.iter_mut().zip(&motors) {
        let m = m.as_ref().unwrap();
        joint.gear_ratio = m.gear_ratio.unwrap();
        joint.rotor_inertia = m.rotor_inertia.unwrap();
    }
    // the inverse dynamics and the damping at each grid point, within 1 − margin of the
    // envelope on their side (the lines below the envelopes are sound)
    let keep = 1.0 - DEFAULT_MARGIN;
    let (share, j, i, speed) = most_asked(&motored, &motors, &path, &timed.profile);
    assert!(
        share <= keep * (1.0 + 1e-9),
        "J{} at grid point {i} (the motor at {speed} rad/s) needs {share} of its envelope; the timing may use {keep}",
        j + 1
    );
    // what binds, binds: no constraint is beyond its limit, and every segment names one
    assert!(
        timed.bindings.iter().all(|b| b.slack >= -1e-9),
        "a constraint is violated"
    );
    assert!(timed.bindings.iter().filter(|b| b.binds()).count() > timed.bindings.len() / 2);
}

/// The relaxed bound (each motor's holding torque, constant) is faster; the envelope rounds
/// are slower by what the motors lose with speed, and never faster than the bound.
#[test]
fn the_relaxed_duration_bounds_the_timing_from_below() {
    let model = faze4::faze4::model();
    let path = common::circle_path();
    let timed = retime(&with_motors(&model, &path), &path, &no_check()).unwrap();
    assert!(timed.iterations >= 2);
    assert!(timed.relaxed_duration < timed.profile.duration());
    // the holding-torque timing as constant limits (the motors' standstill torque as effort)
    let holding: Vec<f64> = (faze4::faze4::motors::faze4(None).iter())
        .map(|m| {
            let m = m.as_ref().unwrap();
            m.motor.joint_limit(m.gear_ratio.unwrap())
        })
        .collect();
    let constant = retime(&with_motors(&model, &path).effort(holding.clone()), &path, &no_check()).unwrap();
    assert!((constant.relaxed_duration - timed.relaxed_duration).abs() < 1e-9 * timed.relaxed_duration);
}

/// The phase plane: the profile is under every joint's torque-limit curve (the true envelope)
/// and the speed-limit curve. (The profile is TOPP-RA's averaged over a window, so not within
/// TOPP-RA's controllable sets at every point: an average of speeds before and after.)
#[test]
fn the_phase_plane_holds_the_profile_under_its_limits() {
    let model = faze4::faze4::model();
    let path = common::circle_path();
    let timed = retime(&with_motors(&model, &path), &path, &no_check()).unwrap();
    let plane = timed.phase_plane();
    assert_eq!(plane.s.len(), timed.profile.s.len());
    assert_eq!(plane.torque_limit.len(), 6);
    for i in 0..plane.s.len() {
        let sd = plane.profile[i];
        assert!(sd <= plane.speed_limit[i] * (1.0 + 1e-9), "speed at {i}");

        for (j, curve) in plane.torque_limit.iter().enumerate() {
            assert!(
                sd <= curve[i] * (1.0 + 1e-6) + 1e-9,
                "J{} torque limit at {i}: {sd} > {}",
                j + 1,
                curve[i]
            );
        }
    }
    // the profile comes near the torque limits somewhere (a switch point of the time-optimal
    // profile, averaged over the window)
    let touches = (1..plane.s.len() - 1).any(|i| {
        let lowest = plane.torque_limit.iter().map(|c| c[i]).fold(f64::INFINITY, f64::min);
        plane.profile[i] > 0.95 * lowest
    });
    assert!(touches);
}

/// The trajectory for the writers: one point per grid point, times increasing from 0 (the
/// profile's, to the nanosecond the ROS formats hold), the spline's positions, velocities q'ṡ,
/// at rest at both ends.
#[test]
fn the_trajectory_is_the_timing_at_the_grid_points() {
    let model = faze4::faze4::model();
    let path = common::circle_path();
    let timed = retime(&with_motors(&model, &path), &path, &no_check()).unwrap();
    let t = &timed.trajectory;
    let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(t.joint_names, names);
    assert_eq!(t.points.len(), 201);
    assert_eq!(t.points[0].time_from_start, 0.0);
    assert!(t.points.windows(2).all(|w| w[1].time_from_start > w[0].time_from_start));
    for (point, &ti) in t.points.iter().zip(&timed.profile.t) {
        assert!(
            (point.time_from_start - ti).abs() <= 0.5e-9,
            "{} vs {ti}",
            point.time_from_start
        );
        let ns = faze4::traj::timed::nanoseconds(point.time_from_start);
        assert_eq!(point.time_from_start, faze4::traj::timed::seconds_from_nanoseconds(ns));
    }
    let (mut q, mut dq, mut ddq) = (vec![0.0; 6], vec![0.0; 6], vec![0.0; 6]);
    for (i, point) in t.points.iter().enumerate() {
        path.eval(timed.profile.s[i], &mut q, &mut dq, &mut ddq);
        assert_eq!(point.positions, q);
        for j in 0..6 {
            assert!((point.velocities[j] - dq[j] * timed.profile.x[i].sqrt()).abs() < 1e-12);
        }
    }
    assert!(
        t.points[0]
            .velocities
            .iter()
            .chain(&t.points[200].velocities)
            .all(|v| *v == 0.0)
    );
}

/// Without a margin the circle's first timing asks the steppers for all they give, and the
/// loop's feedback asks for more: the check sees steps lost, slows those segments and tries
/// again until the loop follows.
#[test]
fn the_check_slows_what_fails_until_it_follows() {
    let model = faze4::faze4::model();
    let path = common::circle_path();
    let base = with_motors(&model, &path);
    let bare = RetimeOptions {
        margin: 0.0,
        ..RetimeOptions::default()
    };
    let unchecked = retime(
        &base,
        &path,
        &RetimeOptions {
            check: false,
            ..bare.clone()
        },
    )
    .unwrap();
    let first = retime(
        &base,
        &path,
        &RetimeOptions {
            attempts: 1,
            ..bare.clone()
        },
    )
    .unwrap();
    let first_check = first.check.as_ref().unwrap();
    assert!(!first_check.summary.verdict.follows);
    assert_eq!(first.profile, unchecked.profile);
    let checked = retime(&base, &path, &bare).unwrap();
    let check = checked.check.as_ref().unwrap();
    assert!(check.summary.verdict.follows, "{}", check.summary.verdict);
    assert!(check.attempts > 1 && check.slowed_points > 0);
    assert!(checked.profile.duration() > unchecked.profile.duration());
    assert!(checked.bindings.iter().any(|b| b.limit == faze4::retime::Limit::Slowed));
}

/// What a recorder is handed, bit for bit: the run's command and steps, each sample (its step,
/// time, joint vectors, tool, intersections) and the summary but for its wall times.
#[derive(Debug, PartialEq)]
struct Handed {
    period: f64,
    begun: Option<(String, usize, usize)>,
    samples: Vec<Vec<u64>>,
    summary: Option<serde_json::Value>,
}

impl Handed {
    fn new(period: f64) -> Self {
        Handed {
            period,
            begun: None,
            samples: Vec::new(),
            summary: None,
        }
    }
}

impl faze4::sim::Recorder for Handed {
    fn period(&self) -> f64 {
        self.period
    }

    fn reads_intersections(&self) -> bool {
        true
    }

    fn begin(&mut self, run: &faze4::sim::RunInfo) -> faze4::Result<()> {
        self.begun = Some((run.command.to_string(), run.steps, run.collision_pairs.len()));
        Ok(())
    }

    fn record(&mut self, s: &faze4::sim::Sample) -> faze4::Result<()> {
        let mut bits = vec![s.step as u64, s.t.to_bits()];
        for v in [s.q, s.v, s.q_cmd, s.v_cmd, s.tau, s.tau_raw, s.g] {
            bits.extend(v.iter().map(|x| x.to_bits()));
        }
        bits.extend([s.tool.x, s.tool.y, s.tool.z].map(f64::to_bits));
        bits.extend(s.intersecting.iter().map(|&b| u64::from(b)));
        self.samples.push(bits);
        Ok(())
    }

    fn finish(&mut self, summary: &faze4::sim::Summary) -> faze4::Result<()> {
        let mut json = serde_json::to_value(summary).unwrap();
        for wall in ["wall_time_s", "dynamics_wall_time_s", "clearance_wall_time_s"] {
            json.as_object_mut().unwrap().remove(wall);
        }
        self.summary = Some(json);
        Ok(())
    }
}

/// The outputs are handed the check's last run from its tape (issue 46 item 6), not a run
/// played again: the Faze4's circle without a margin (several check runs, the last one taped),
/// its collision geometry loaded, handed to recorders at the trail's period, at one that does
/// not divide the run (13 ms) and at every step, gives each exactly what a run of the written
/// timing as `replay` plays it gives them, sample for sample, bit for bit, and the same summary.
#[test]
fn the_outputs_are_the_last_check_run_bit_for_bit() {
    use faze4::sim::Recorder;
    // the Faze4 with its real meshes, as the binary loads it
    let robot = faze4::geometry::Robot::from_urdf_file(
        &repo_path("urdf/faze4_real.urdf"),
        &faze4::model::PackagePaths::new(vec![common::shared_description()]),
    )
    .unwrap();
    let path = common::circle_path();
    let base = with_motors(&robot.model, &path).geometry(robot.geometry);
    let options = RetimeOptions {
        margin: 0.0,
        tape: Some(true),
        ..RetimeOptions::default()
    };
    let timed = retime(&base, &path, &options).unwrap();
    let check = timed.check.as_ref().unwrap();
    assert!(check.attempts > 1, "{} check runs", check.attempts);
    let tape = check.tape.as_ref().unwrap();
    let scenario = faze4::retime::replay_scenario(&base, &timed.trajectory).unwrap();
    assert!(scenario.collision_set.is_some());
    assert_eq!(tape.len(), scenario.steps + 1);
    // taped because it fits the budget; an hour of the same arm would not, and is played again
    let duration = scenario.steps as f64 * scenario.dt;
    assert!(faze4::sim::Tape::fits(&scenario, duration));
    assert!(!faze4::sim::Tape::fits(&scenario, 3600.0));
    let periods = [0.01, 0.013, 0.0];
    let mut taped = periods.map(Handed::new);
    let mut played = periods.map(Handed::new);
    let mut recorders: Vec<&mut dyn Recorder> = taped.iter_mut().map(|h| h as &mut dyn Recorder).collect();
    tape.play(&scenario, &mut recorders, &check.summary).unwrap();
    let mut recorders: Vec<&mut dyn Recorder> = played.iter_mut().map(|h| h as &mut dyn Recorder).collect();
    let summary = faze4::sim::run(&scenario, &mut recorders, &faze4::sim::StopFlag::new()).unwrap();
    assert!(summary.verdict.follows);
    for (a, b) in taped.iter().zip(&played) {
        assert!(b.samples.len() > 2 && b.begun.as_ref().unwrap().2 > 0, "{:?}", b.begun);
        assert_eq!(a.begun, b.begun, "period {}", a.period);
        assert_eq!(a.samples.len(), b.samples.len(), "period {}", a.period);
        assert!(a.samples == b.samples, "period {}: the samples differ", a.period);
        assert_eq!(a.summary, b.summary, "period {}", a.period);
    }
}

/// The figure as SVG (with its title and the joints' names) and as PNG.
#[test]
fn the_phase_plane_figure_is_written() {
    let model = faze4::faze4::model();
    let path = common::circle_path();
    let timed: Retimed = retime(&with_motors(&model, &path), &path, &no_check()).unwrap();
    let dir = common::temp_dir("retime_plot");
    let names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
    let svg = dir.join("phase.svg");
    PhasePlot::new(&svg)
        .unwrap()
        .write(&timed, &model.name, &names, DEFAULT_MARGIN)
        .unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("phase plane") && text.contains("J2 nadlaktica torque"));
    let png = dir.join("phase.png");
    PhasePlot::new(&png)
        .unwrap()
        .write(&timed, &model.name, &names, DEFAULT_MARGIN)
        .unwrap();
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let wrong = PhasePlot::new(dir.join("phase.jpg")).unwrap_err();
    assert!(wrong.to_string().starts_with("`plot`"), "{wrong}");
}

/// Each bad input: its error, one line naming the cause.
#[test]
fn bad_paths_and_limits_give_one_line() {
    let model = faze4::faze4::model();
    let one_line = |e: Error| {
        let text = e.to_string();
        assert!(!text.contains('\n'), "{text}");
        text
    };
    // fewer than two (distinct) points
    let e = PathSpline::through(&[vec![0.0; 6]]).unwrap_err();
    assert!(matches!(e, Error::BadPath { point: None, .. }));
    assert!(one_line(e).contains("at least two distinct points"));
    let e = PathSpline::through(&[vec![0.1; 6], vec![0.1; 6]]).unwrap_err();
    assert!(one_line(e).contains("2 points (1 distinct, points within 1e-9 of the one before being one)"));
    // a step too small to divide by is no step: 1e-300 rad said the masses were too large
    let mut nearly = vec![vec![0.1; 6], vec![0.1; 6], vec![0.1; 6]];
    nearly[1][0] += 1e-300;
    nearly[2][0] += 5e-10;
    let e = PathSpline::through(&nearly).unwrap_err();
    assert!(one_line(e).contains("3 points (1 distinct"));
    // a length that overflows: its spline was NaN, reported as masses too large to simulate
    let e = PathSpline::through(&[vec![0.0, 0.0], vec![1e200, 0.0]]).unwrap_err();
    assert!(matches!(e, Error::BadPath { point: Some(1), .. }));
    assert!(one_line(e).contains("point 1: the path's length up to here overflows"));
    // points closer than that merge with the point kept before them, not with each other
    let creeping: Vec<Vec<f64>> = (0..4).map(|k| vec![0.1 + 3e-10 * k as f64; 6]).collect();
    let path = PathSpline::through(&creeping).unwrap();
    assert_eq!(path.knots().len(), 2, "{:?}", path.knots());
    assert!(one_line(PathSpline::through(&[]).unwrap_err()).contains("no points"));
    // NaN
    let mut points = vec![vec![0.0; 6], vec![0.1; 6], vec![0.2; 6]];
    points[1][2] = f64::NAN;
    let e = PathSpline::through(&points).unwrap_err();
    assert!(matches!(e, Error::BadPath { point: Some(1), .. }));
    assert_eq!(one_line(e), "retime: path point 1: J3 is NaN, not a finite number");
    // rows of different lengths
    let e = PathSpline::through(&[vec![0.0; 6], vec![0.0; 5]]).unwrap_err();
    assert!(one_line(e).contains("point 1: has 5 values; the first point has 6"));
    // a point beyond a joint limit (J2 'nadlaktica' is limited to ±2.094 rad)
    let mut points = vec![vec![0.0; 6], vec![0.1; 6], vec![0.2; 6]];
    points[2][1] = 2.5;
    let path = PathSpline::through(&points).unwrap();
    let base = Scenario::builder(model.clone(), hold(&path));
    let e = retime(&base, &path, &no_check()).unwrap_err();
    assert!(matches!(e, Error::BadPath { point: Some(2), .. }));
    let text = one_line(e);
    assert!(
        text.contains("J2 ('nadlaktica') = 2.5 rad is beyond its limits"),
        "{text}"
    );
    // points inside whose spline leaves the limits between them
    let points: Vec<Vec<f64>> = [0.0, 2.0, 2.09, 0.0]
        .iter()
        .map(|&x| vec![0.0, x, 0.0, 0.0, 0.0, 0.0])
        .collect();
    let path = PathSpline::through(&points).unwrap();
    let e = retime(&Scenario::builder(model.clone(), hold(&path)), &path, &no_check()).unwrap_err();
    let text = one_line(e);
    assert!(
        text.contains("the spline between points") && text.contains("J2"),
        "{text}"
    );
    // points of another arm
    let path = PathSpline::through(&[vec![0.0; 5], vec![0.1; 5]]).unwrap();
    let e = retime(
        &Scenario::builder(
            model.clone(),
            hold(&PathSpline::through(&[vec![0.0; 6], vec![0.1; 6]]).unwrap()),
        ),
        &path,
        &no_check(),
    )
    .unwrap_err();
    assert!(one_line(e).contains("points have 5 values; the model has 6 joints"));
    // limits so tight nothing follows: 0.5 N·m cannot hold the Faze4's shoulder out of vertical
    let points = vec![vec![0.0, 0.3, 0.0, 0.0, 0.0, 0.0], vec![0.0, 0.8, 0.0, 0.0, 0.0, 0.0]];
    let path = PathSpline::through(&points).unwrap();
    let weak = Scenario::builder(model.clone(), hold(&path)).effort(vec![0.5; 6]);
    let e = retime(&weak, &path, &no_check()).unwrap_err();
    assert!(
        matches!(
            e,
            Error::NothingFollows {
                joint: Some(faze4::id::JointId(1)),
                ..
            }
        ),
        "{e:?}"
    );
    let text = one_line(e);
    assert!(
        text.starts_with("retime: nothing follows at s = ") && text.contains("): J2 needs "),
        "{text}"
    );
    // bad options
    let path = PathSpline::through(&[vec![0.0; 6], vec![0.1; 6]]).unwrap();
    let base = Scenario::builder(model.clone(), hold(&path));
    for (options, option) in [
        (
            RetimeOptions {
                margin: 1.0,
                ..no_check()
            },
            "`margin`",
        ),
        (
            RetimeOptions {
                margin: f64::NAN,
                ..no_check()
            },
            "`margin`",
        ),
        (
            RetimeOptions {
                intervals: 0,
                ..no_check()
            },
            "`grid`",
        ),
        (
            RetimeOptions {
                attempts: 0,
                ..no_check()
            },
            "`attempts`",
        ),
    ] {
        let text = one_line(retime(&base, &path, &options).unwrap_err());
        assert!(text.starts_with(option), "{text}");
    }
    // limits so small the timing outlasts what can be written (whole nanoseconds in an i64,
    // about 292 years) or checked (10^12 steps of dt): refused naming the limit, not as the
    // written file's times (they saturated and read "times must increase")
    let tiny = |v: f64| vec![Some(v); 6];
    for (options, option, words) in [
        (
            RetimeOptions {
                max_acceleration: tiny(1e-21),
                ..no_check()
            },
            "`max_accel`",
            "(times in whole nanoseconds)",
        ),
        (
            RetimeOptions {
                max_acceleration: tiny(1e-17),
                ..RetimeOptions::default()
            },
            "`max_accel`",
            "10^12 steps of `dt`",
        ),
        (
            RetimeOptions {
                max_jerk: tiny(1e-15),
                ..no_check()
            },
            "`max_jerk`",
            "(times in whole nanoseconds)",
        ),
    ] {
        let Err(e) = retime(&base, &path, &options) else {
            panic!("{option} timed");
        };
        let text = one_line(e);
        assert!(text.starts_with(option) && text.contains(words), "{text}");
        assert!(
            text.contains("the timing would take ") && !text.contains("times must increase"),
            "{text}"
        );
    }
}

/// A straight line between two points (the spline is the line, q'' = 0) under a constant torque
/// limit on the one joint that moves: a constant acceleration limit a = E/M_11, bang-bang,
/// duration 2√(L/a).
#[test]
fn a_line_under_a_constant_acceleration_is_bang_bang() {
    // J1 alone turns: without gravity and damping only its inertia M_11 resists, constant (the
    // joints that set it stay put); the other joints' limits out of reach
    let mut model = faze4::faze4::model();
    model.joints.iter_mut().for_each(|j| j.damping = 0.0);
    let points = vec![vec![-0.5, 0.0, 0.0, 0.0, 0.0, 0.0], vec![0.5, 0.0, 0.0, 0.0, 0.0, 0.0]];
    let path = PathSpline::through(&points).unwrap();
    let base = Scenario::builder(model.clone(), hold(&path))
        .effort(vec![2.0, 100.0, 100.0, 100.0, 100.0, 100.0])
        .gravity(false);
    let timed = retime(
        &base,
        &path,
        &RetimeOptions {
            margin: 0.0,
            ..no_check()
        },
    )
    .unwrap();
    let m11 = faze4::algo::crba(&model, &mut Data::new(&model), &[0.0; 6])[(0, 0)];
    let a = 2.0 / m11;
    let expected = 2.0 * (1.0_f64 / a).sqrt(); // L = 1 rad: accelerate over 0.5, brake over 0.5
    let got = timed.toppra.duration();
    assert!((got - expected).abs() < 1e-9 * expected, "{got} vs {expected}");
    // the timing written: TOPP-RA's averaged over its window, that much longer
    let written = timed.profile.duration();
    assert!(timed.window >= faze4::retime::WINDOW * got * (1.0 - 1e-12));
    assert!(
        written >= got + timed.window * (1.0 - 1e-9),
        "{written} vs {got} + {}",
        timed.window
    );
}

/// The walk-through on the real binary: `retime` of the circle's samples under the
/// Faze4's steppers writes a timing that `replay` plays to "follows", as the same run as retime's
/// check (the summaries agree, and the trails byte for byte: retime's is its check's last run,
/// taped); every output format plays back alike; a bad path is one line
/// with status 2; a path nothing follows is its reason, status 3 with or without `--strict`.
#[test]
fn retime_then_replay_follows_on_the_binary() {
    let dir = common::temp_dir("retime-cli");
    let circle = repo_path("tests/fixtures/shape_circle_q.npy");
    let circle = circle.to_str().unwrap();
    let run = common::faze4(
        &dir,
        &[
            "retime",
            "--q-traj",
            circle,
            "--motors",
            "faze4",
            "--out",
            "circle.yaml",
            "--summary",
            "retimed.json",
            "--trail",
            "retimed.csv",
            "--plot",
            "phase.svg",
        ],
    );
    assert!(run.status.success(), "{}{}", run.stdout, run.stderr);
    let last = run.stdout.lines().last().unwrap();
    assert_eq!(last, "verdict: follows", "{}", run.stdout);
    // the run's own lines (a trail is asked for: its run is shown), then retime's
    assert!(run.stdout.starts_with("[faze4] replay (retimed)"), "{}", run.stdout);
    assert!(run.stdout.lines().any(|l| l.starts_with("retime: ")), "{}", run.stdout);
    // the timing, played as ros2_control plays it, keeps every limit between the points too
    // (docs/retime.md, "Between the grid points"), and says so
    let played_line = (run.stdout.lines())
        .find_map(|l| {
            l.strip_prefix(
                "as played (quintic between the written points, checked every 1/20 of an interval): every limit kept, at most ",
            )
        })
        .unwrap_or_else(|| panic!("no played line: {}", run.stdout));
    let share: f64 = played_line.split(' ').next().unwrap().parse().unwrap();
    assert!(share > 0.9 && share <= 1.0, "{played_line}");
    assert!(std::fs::read_to_string(dir.join("phase.svg")).unwrap().contains("<svg"));
    let retimed = common::summary(&dir, "retimed.json");
    let played = common::faze4(
        &dir,
        &[
            "replay",
            "--q-traj",
            "circle.yaml",
            "--motors",
            "faze4",
            "--summary",
            "replayed.json",
            "--trail",
            "replayed.csv",
            "--quiet",
        ],
    );
    assert!(played.status.success(), "{}", played.stderr);
    assert_eq!(played.stdout.trim(), "verdict: follows");
    let replayed = common::summary(&dir, "replayed.json");
    assert_eq!(retimed["verdict"], replayed["verdict"]);
    assert_eq!(retimed["joints"], replayed["joints"], "the check is the replay's run");
    // retime's trail is its check's run, taped: the replay's, byte for byte
    let trail = std::fs::read(dir.join("retimed.csv")).unwrap();
    assert!(trail.len() > 5_000, "{} bytes", trail.len());
    assert!(
        trail == std::fs::read(dir.join("replayed.csv")).unwrap(),
        "the trails differ"
    );
    // the other formats hold the same timing
    let timed = faze4::traj::files::read(&dir.join("circle.yaml"), &Default::default()).unwrap();
    for out in ["circle.json", "circle.csv", "circle.mcap"] {
        let run = common::faze4(
            &dir,
            &[
                "retime", "--q-traj", circle, "--motors", "faze4", "--out", out, "--trail", "none", "--quiet",
            ],
        );
        assert!(run.status.success(), "{out}: {}", run.stderr);
        let again = faze4::traj::files::read(&dir.join(out), &Default::default()).unwrap();
        assert_eq!(again.points.len(), timed.points.len(), "{out}");
        let (a, b) = (&again.points.last().unwrap(), &timed.points.last().unwrap());
        assert_eq!(a.time_from_start, b.time_from_start, "{out}");
    }
    // bad paths: one line, status 2
    faze4::traj::npy::write_samples(&dir.join("one.npy"), &[vec![0.0; 6]]).unwrap();
    let bad = common::faze4(&dir, &["retime", "--q-traj", "one.npy", "--out", "x.yaml"]);
    assert_eq!(bad.status.code(), Some(2), "{}", bad.stderr);
    assert_eq!(bad.stderr.lines().count(), 1, "{}", bad.stderr);
    assert!(!dir.join("x.yaml").exists());
    // nothing follows: a payload the motors cannot hold up
    for strict in [true, false] {
        let mut args = vec![
            "retime",
            "--q-traj",
            circle,
            "--motors",
            "faze4",
            "--payload-kg",
            "30",
            "--out",
            "x.yaml",
        ];
        if strict {
            args.push("--strict");
        }
        let run = common::faze4(&dir, &args);
        assert_eq!(run.status.code(), Some(3), "strict {strict}: {}", run.stderr);
        assert!(!dir.join("x.yaml").exists());
        assert!(run.stderr.contains("nothing follows"), "{}", run.stderr);
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    }
}

/// A straight move of one joint from `start` by `amount` (toward its upper limit if there is
/// room, else its lower), the other joints held: the path of the refused moves.
fn straight(model: &Model, start: &[f64], j: usize, amount: f64) -> PathSpline {
    let joint = &model.joints[j];
    let step = match start[j] + amount <= joint.upper {
        true => amount,
        false => -amount,
    };
    let mut end = start.to_vec();
    end[j] += step;
    PathSpline::through(&[start.to_vec(), end]).unwrap()
}

/// Each joint's zero, or the middle of its limits where zero is outside them.
fn rest_pose(model: &Model) -> Vec<f64> {
    (model.joints.iter())
        .map(|j| match (j.lower..=j.upper).contains(&0.0) {
            true => 0.0,
            false => 0.5 * (j.lower + j.upper),
        })
        .collect()
}

/// No false "nothing follows" (issue 46): a straight move of 0.1 and 0.5 rad of every joint
/// alone (less on a joint whose range is shorter), and two seeded curved 5-point paths, are
/// timed on five arms (the Faze4, the UR5, the Panda, our rotor_arm, the SO-101) under
/// constant limits (with the URDF's damping), steppers (`--motors faze4`) and DC servos
/// (`sts3215`, `xm540-w270`). A straight move is never refused; a curved path only at a point
/// where holding the arm still needs more than the joint named may use (gravity beyond its
/// range at rest, less the margin). Every timing found is no faster than its relaxed bound,
/// keeps every limit as a controller plays it (the played share at most 1), and, with motors,
/// keeps each envelope at every grid point less the margin.
#[test]
fn straight_moves_of_every_joint_and_curved_paths_are_timed_on_five_arms() {
    use faze4::control::catalog::{sts3215, xm540_w270};
    let faze4_arm = faze4::faze4::model();
    let ur5 = common::load("tests/urdf/example_robot_data/ur5_robot.urdf");
    let so101 = common::load("tests/urdf/example_robot_data/so101.urdf");
    let panda = common::load("tests/urdf/example_robot_data/panda.urdf");
    let ours = common::load("tests/urdf/rotor_arm.urdf");
    let every = |m: fn(Option<f64>) -> faze4::control::JointMotor, n: usize| Some(vec![Some(m(None)); n]);
    let cases = [
        ("Faze4, constant", &faze4_arm, None),
        ("Faze4, steppers", &faze4_arm, Some(faze4::faze4::motors::faze4(None))),
        ("UR5, constant", &ur5, None),
        ("Panda, constant", &panda, None),
        ("rotor_arm (ours), constant", &ours, None),
        ("SO-101, sts3215", &so101, every(sts3215, so101.dof())),
        ("SO-101, xm540-w270", &so101, every(xm540_w270, so101.dof())),
    ];
    let keep = 1.0 - DEFAULT_MARGIN;
    for (arm, model, motors) in cases {
        let start = rest_pose(model);
        let mut fitted = model.clone();
        let envelopes = faze4::config::motors::fit(&mut fitted, motors.clone(), &[], &[]).unwrap();
        let moves = (0..model.dof()).flat_map(|j| {
            // within a short joint's range (the Panda's fingers move 4 cm)
            let range = model.joints[j].upper - model.joints[j].lower;
            [0.1, 0.5].map(|amount: f64| {
                let amount = amount.min(0.5 * range);
                (format!("J{} by {amount}", j + 1), straight(model, &start, j, amount))
            })
        });
        let curved = (1..=2).map(|seed| (format!("curved path {seed}"), common::curved(model, 5, seed)));
        for (what, path) in moves.chain(curved) {
            let mut base = Scenario::builder(fitted.clone(), hold(&path));
            if let Some(envelopes) = envelopes.clone() {
                base = base.motors(envelopes);
            }
            let timed = match retime(&base, &path, &no_check()) {
                Ok(timed) => timed,
                // refused only where holding the arm still needs more than the joint may use
                Err(Error::NothingFollows {
                    s, joint: Some(joint), ..
                }) if what.starts_with("curved") => {
                    let scenario = base.clone().build().unwrap();
                    let mut q = vec![0.0; model.dof()];
                    path.position(s, &mut q);
                    let zero = vec![0.0; model.dof()];
                    let g = faze4::algo::rnea(&fitted, &mut Data::new(&fitted), &q, &zero, &zero)[joint.0];
                    let (lo, hi) = match &scenario.motors {
                        Some(m) => m[joint.0]
                            .as_ref()
                            .unwrap()
                            .joint_bounds(fitted.joints[joint.0].gear_ratio, 0.0),
                        None => (
                            -scenario.controller.gains.effort[joint.0],
                            scenario.controller.gains.effort[joint.0],
                        ),
                    };
                    assert!(
                        g > keep * hi || g < keep * lo,
                        "{arm}: {what}: refused at s = {s} but {joint} holds with {g}"
                    );
                    continue;
                }
                Err(e) => panic!("{arm}: {what}: {e}"),
            };
            let duration = timed.profile.duration();
            assert!(duration.is_finite() && duration > 0.0, "{arm}: {what}");
            assert!(
                timed.relaxed_duration <= duration * (1.0 + 1e-9),
                "{arm}: {what}: {duration} vs {}",
                timed.relaxed_duration
            );
            // as a controller plays it, every limit kept between the points too
            assert!(timed.played.worst <= 1.0 + 1e-6, "{arm}: {what}: {:?}", timed.played);
            if let Some(motors) = &motors {
                let (share, worst, i, _) = most_asked(&fitted, motors, &path, &timed.profile);
                assert!(
                    share <= keep * (1.0 + 1e-9),
                    "{arm}: {what}: J{} needs {share} of its envelope at grid point {i}",
                    worst + 1
                );
            }
        }
    }
}

/// A path whose poses collide is refused before it is timed (slowing cannot fix a collision):
/// the Faze4's elbow (J3) folded from 0 to 2.6 rad brings the upper arm ('nadlaktica') into
/// the wrist ('saka') near J3 = 1.18 rad; retime names the pair and the path position, exits 3
/// and writes nothing, `--force` or not, and prints no timing. Without the self-clearance
/// (`--no-collisions`) the same path is timed: the refusal is the clearance's.
#[test]
fn a_colliding_path_is_refused_before_it_is_timed() {
    let dir = common::temp_dir("retime-collides");
    let fold: Vec<Vec<f64>> = [0.0, 1.3, 2.6]
        .iter()
        .map(|&q3| vec![0.0, 0.0, q3, 0.0, 0.0, 0.0])
        .collect();
    faze4::traj::npy::write_samples(&dir.join("fold.npy"), &fold).unwrap();
    for force in [false, true] {
        let mut args = vec![
            "retime",
            "--q-traj",
            "fold.npy",
            "--out",
            "fold.yaml",
            "--trail",
            "none",
        ];
        if force {
            args.push("--force");
        }
        let run = common::faze4(&dir, &args);
        assert_eq!(run.status.code(), Some(3), "force {force}: {}", run.stderr);
        assert!(!dir.join("fold.yaml").exists(), "force {force}");
        assert_eq!(run.stdout, "", "no timing is found: {}", run.stdout);
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
        assert!(
            run.stderr
                .contains("the path collides: 'nadlaktica' and 'saka' intersect at s = 1.1839 of 2.6000"),
            "{}",
            run.stderr
        );
        assert!(
            run.stderr
                .contains("checked at 2707 positions of the path, each joint moving at most 0.001 rad"),
            "{}",
            run.stderr
        );
    }
    let free = common::faze4(
        &dir,
        &[
            "retime",
            "--q-traj",
            "fold.npy",
            "--out",
            "fold.yaml",
            "--trail",
            "none",
            "--no-collisions",
        ],
    );
    assert!(free.status.success(), "{}{}", free.stdout, free.stderr);
    assert!(dir.join("fold.yaml").exists());
}

/// A timing whose check does not follow (the circle under the Faze4's steppers driven as
/// steppers, `--drive stepper`, judged against a tracking threshold of 0.5 mrad, one check
/// run: the rotors' lag alone passes it) exits 3 and is written only with `--force`; the lines
/// say which. (At the default threshold this timing follows under `--drive stepper`, at every
/// margin from 0.05 on: tests/it/retime_drive.rs.)
#[test]
fn a_timing_that_does_not_follow_is_written_only_with_force() {
    let dir = common::temp_dir("retime-force");
    let circle = repo_path("tests/fixtures/shape_circle_q.npy");
    let circle = circle.to_str().unwrap();
    for force in [false, true] {
        let mut args = vec![
            "retime",
            "--q-traj",
            circle,
            "--motors",
            "faze4",
            "--drive",
            "stepper",
            "--out",
            "c.yaml",
            "--trail",
            "none",
            "--max-error",
            "0.0005",
            "--attempts",
            "1",
        ];
        if force {
            args.push("--force");
        }
        let run = common::faze4(&dir, &args);
        assert_eq!(
            run.status.code(),
            Some(3),
            "force {force}: {}{}",
            run.stdout,
            run.stderr
        );
        let verdict = run.stdout.lines().last().unwrap();
        assert!(
            verdict.starts_with("verdict: cannot follow") && verdict.contains("tracking error"),
            "{verdict}"
        );
        assert_eq!(dir.join("c.yaml").exists(), force);
        let said = match force {
            true => "; wrote c.yaml\n",
            false => "; it does not follow: nothing is written to c.yaml (--force writes it)\n",
        };
        assert!(run.stdout.contains(said), "{}", run.stdout);
    }
}

/// A stop asked for while the path is timed (Ctrl-C in Python, a flag raised by hand) ends the
/// timing with `Error::Stopped` instead of finishing it (in Python it waited out the timing: a
/// second at the default grid with jerk limits, 20 s on a grid of 100,000).
#[test]
fn a_stop_ends_the_timing() {
    let model = faze4::faze4::model();
    let path = common::circle_path();
    let stop = faze4::sim::StopFlag::new();
    stop.raise();
    let options = RetimeOptions { stop, ..no_check() };
    let stopped = retime(&with_motors(&model, &path), &path, &options);
    assert!(
        matches!(stopped, Err(Error::Stopped { .. })),
        "{:?}",
        stopped.map(|r| r.profile.duration())
    );
}

/// A check a signal ends early has no verdict, and nothing is written, not even under
/// `--force`: the line said "wrote c.yaml" though no file was written.
#[test]
fn a_check_a_signal_stops_writes_nothing_and_says_so() {
    let dir = common::temp_dir("retime-stopped-check");
    let circle = repo_path("tests/fixtures/shape_circle_q.npy");
    let circle = circle.to_str().unwrap();
    // jerk limits this small time the circle over about 5,400 s: the check runs for minutes,
    // the timing itself takes under a second
    let jerk = ["1e-3"; 6].join(",");
    let args = [
        "retime",
        "--q-traj",
        circle,
        "--motors",
        "faze4",
        "--max-jerk",
        &jerk,
        "--out",
        "c.yaml",
        "--force",
    ];
    let out = common::signalled_once_begun(
        &dir,
        &args,
        libc::SIGTERM,
        |_, _| true,
        std::time::Duration::from_secs(5),
    );
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert_eq!(out.status.code(), Some(143), "{stdout}{stderr}");
    assert!(
        stderr.contains("s of the check: no verdict; nothing is written"),
        "{stderr}"
    );
    assert!(
        stdout.ends_with("; the check was stopped: nothing is written to c.yaml\n"),
        "{stdout}"
    );
    assert!(!stdout.contains("wrote"), "{stdout}");
    assert!(!dir.join("c.yaml").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--no-check` (issue 46 item 6): the timing is written without a closed-loop run, said to be
/// unchecked, with status 0 (it keeps every limit as played), no verdict and no trail; it is
/// the checked command's first timing (the circle follows at once under the default margin,
/// so the same file). A run's output asked for beside it is refused with status 2, and so is
/// a retime from Python (it returns the checked run).
#[test]
fn no_check_writes_the_timing_unchecked() {
    let dir = common::temp_dir("retime-no-check");
    let circle = repo_path("tests/fixtures/shape_circle_q.npy");
    let circle = circle.to_str().unwrap();
    let retime = |extra: &[&str]| {
        let mut args = vec!["retime", "--q-traj", circle, "--motors", "faze4"];
        args.extend_from_slice(extra);
        common::faze4(&dir, &args)
    };
    let run = retime(&["--out", "unchecked.yaml", "--no-check"]);
    assert_eq!(run.status.code(), Some(0), "{}{}", run.stdout, run.stderr);
    let last = run.stdout.lines().last().unwrap();
    assert_eq!(
        last,
        "not checked in the closed loop (--no-check): whether the loop follows it is not known (replay it to know); wrote unchecked.yaml",
        "{}",
        run.stdout
    );
    assert!(!run.stdout.contains("verdict"), "{}", run.stdout);
    assert!(!dir.join("faze4_trail.csv").exists());
    // checked, the binary's default trail is written (the check's last run)
    let checked = retime(&["--out", "checked.yaml", "--quiet"]);
    assert!(checked.status.success(), "{}", checked.stderr);
    assert!(dir.join("faze4_trail.csv").exists());
    assert_eq!(
        std::fs::read(dir.join("unchecked.yaml")).unwrap(),
        std::fs::read(dir.join("checked.yaml")).unwrap()
    );
    for output in [["--summary", "s.json"], ["--trail", "t.csv"]] {
        let refused = retime(&["--out", "x.yaml", "--no-check", output[0], output[1]]);
        assert_eq!(refused.status.code(), Some(2), "{output:?}: {}", refused.stderr);
        assert!(refused.stderr.contains("--no-check"), "{}", refused.stderr);
        assert!(!dir.join("x.yaml").exists());
    }
}

/// A grid too coarse for the path (the circle on 10 intervals): its speeds at one point cannot
/// reach the next point's. Said so, with the speeds and a finer `--grid`; not "at any path
/// speed", which the point's own limits contradict (issue 49: messages name the real cause).
#[test]
fn a_grid_too_coarse_is_named_not_a_path_nothing_follows() {
    let dir = common::temp_dir("retime_coarse_grid");
    let circle = common::repo_path("tests/fixtures/shape_circle_q.npy");
    let out = dir.join("c.yaml");
    let run = common::faze4(
        &dir,
        &[
            "retime",
            "--q-traj",
            circle.to_str().unwrap(),
            "--motors",
            "faze4",
            "--grid",
            "10",
            "--no-check",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(run.status.code(), Some(3), "{}", run.stderr);
    assert!(
        run.stderr.contains("cannot reach those the next grid point at s = ")
            && run.stderr.contains("a finer --grid may time it")
            && !run.stderr.contains("at any path speed"),
        "{}",
        run.stderr
    );
    assert!(!out.exists());
}

/// retime has no `--duration`: a `--dt` that the check cannot play the timing in, or that the
/// arm cannot be simulated at, is refused naming `--dt` (the check's and the start's scenarios
/// blamed `--duration`, a tiny `dt` the arm's masses); `--no-check` times it all the same.
#[test]
fn a_dt_retime_cannot_play_names_dt() {
    let dir = common::temp_dir("retime_dt");
    let circle = common::repo_path("tests/fixtures/shape_circle_q.npy");
    let out = dir.join("c.yaml");
    let args = |dt: &'static str| {
        vec![
            "retime".to_string(),
            "--q-traj".into(),
            circle.to_str().unwrap().into(),
            "--motors".into(),
            "faze4".into(),
            "--dt".into(),
            dt.into(),
            "--out".into(),
            out.to_str().unwrap().into(),
        ]
    };
    for (dt, words) in [
        ("10", "less than one step"),
        ("1e-12", "too short to simulate this arm"),
    ] {
        let args = args(dt);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        common::refuses(&dir, &args, &["--dt: ", words]);
    }
    let mut unchecked = args("10");
    unchecked.push("--no-check".into());
    let unchecked: Vec<&str> = unchecked.iter().map(String::as_str).collect();
    let run = common::faze4(&dir, &unchecked);
    assert_eq!(run.status.code(), Some(0), "{}", run.stderr);
    assert!(out.exists());
    std::fs::remove_file(&out).unwrap();
    // the same rule for a run
    common::refuses(
        &dir,
        &["wave", "--dt", "1e-12", "--duration", "1e-9"],
        &["--dt: 1e-12 s: too short to simulate this arm"],
    );
}
