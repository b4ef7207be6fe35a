//! The step as a public API (`faze4::sim::step`): a scenario stepped by hand, stage by stage,
//! with the samples handed to a recorder as `run` hands them, gives `run`'s trail to the bit.

use faze4::config::{DriveMode, Motion, Motors, RunConfig, WaveConfig};
use faze4::control::FeedForward;
use faze4::output::Capture;
use faze4::session::Prepared;
use faze4::sim::{self, Recorder, Step, StopFlag};

/// A 0.3 s Faze4 wave without clearance, changed by `change`.
fn scenario(change: impl FnOnce(&mut RunConfig)) -> sim::Scenario {
    let mut config = RunConfig::new(Motion::Wave(WaveConfig::default()));
    config.duration = Some(0.3);
    config.record_period = 0.01;
    config.clearance.no_collisions = true;
    change(&mut config);
    Prepared::new(config, None).unwrap().scenario
}

/// The trail of `sc` stepped by hand: the five stages at each step, a sample at step 0, every
/// record period and the last step, as `run` takes them.
fn by_hand(sc: &sim::Scenario, period: f64) -> Capture {
    let mut capture = Capture::new(period);
    let every = sim::steps_per_record(period, sc.dt);
    let mut s = Step::new(sc);
    for k in 0..=sc.steps {
        let t = k as f64 * sc.dt;
        sim::dynamics(sc, &mut s);
        sim::command(sc, &mut s, t);
        sim::controller(sc, &mut s);
        sim::actuation(sc, &mut s, t);
        if k % every == 0 || k == sc.steps {
            capture.record(&sim::sample(sc, &mut s, k, t, &[])).unwrap();
        }
        if k < sc.steps {
            sim::integrate(sc, &mut s, t).unwrap();
        }
    }
    capture
}

fn run(sc: &sim::Scenario, period: f64) -> Capture {
    let mut capture = Capture::new(period);
    sim::run(sc, &mut [&mut capture], &StopFlag::new()).unwrap();
    capture
}

fn same_trail(sc: &sim::Scenario) {
    let (hand, looped) = (by_hand(sc, 0.01), run(sc, 0.01));
    assert_eq!(hand.rows(), 31);
    assert_eq!(hand.t, looped.t);
    assert_eq!(hand.q, looped.q, "{}", sc.command);
    assert_eq!(hand.q_cmd, looped.q_cmd);
    assert_eq!(hand.tool_xyz, looped.tool_xyz);
}

#[test]
fn a_wave_stepped_by_hand_is_runs_trail() {
    same_trail(&scenario(|c| c.arm.payload_kg = 0.5));
}

#[test]
fn with_the_commands_inverse_dynamics_fed_forward() {
    same_trail(&scenario(|c| c.control.ff = Some(FeedForward::Full)));
}

#[test]
fn with_motors_and_open_loop_steppers() {
    let sc = scenario(|c| {
        c.arm.motors = Some(Motors::Preset("faze4".into()));
        c.control.drive = DriveMode::Stepper;
    });
    assert!(sc.drives.iter().any(|d| d.stepper().is_some()));
    same_trail(&sc);
}

#[test]
fn step_is_the_five_stages() {
    let sc = scenario(|_| {});
    let (mut a, mut b) = (Step::new(&sc), Step::new(&sc));
    for k in 0..100 {
        let t = k as f64 * sc.dt;
        sim::step(&sc, &mut a, t).unwrap();
        sim::dynamics(&sc, &mut b);
        sim::command(&sc, &mut b, t);
        sim::controller(&sc, &mut b);
        sim::actuation(&sc, &mut b, t);
        sim::integrate(&sc, &mut b, t).unwrap();
    }
    assert_eq!(a.state.q, b.state.q);
    assert_eq!(a.state.v, b.state.v);
    assert_ne!(a.state.q, Step::new(&sc).state.q, "the arm moved");
}
