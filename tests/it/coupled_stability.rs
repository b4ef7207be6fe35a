//! The tuning on coupled arms of our own making: with unlimited torque, the rule followed by
//! `stabilize` never diverges and still tracks; the rule alone does diverge on the same arms.

use crate::common;

use common::Rng;
use faze4::algo::{Data, crba};
use faze4::control::{Gains, Stability, auto_tune, stabilize};
use faze4::model::urdf::read_str;
use faze4::model::{Model, PackagePaths};
use faze4::sim::{Scenario, StopFlag, Summary, run};
use faze4::traj::{Trajectory, Wave};

/// The start pose's mass matrix and damping of `model` for `trajectory`.
fn start(model: &Model, trajectory: &Trajectory) -> (nalgebra::DMatrix<f64>, Vec<f64>) {
    let n = model.dof();
    let (mut q0, mut v0) = (vec![0.0; n], vec![0.0; n]);
    trajectory.eval(0.0, &mut q0, &mut v0);
    let mut data = Data::new(model);
    (crba(model, &mut data, &q0).clone(), model.damping().collect())
}

/// The rule's gains with unlimited torque, and whether `stabilize` follows them.
fn tuned(model: &Model, trajectory: &Trajectory, dt: f64, stabilized: bool) -> Gains {
    let (m, damping) = start(model, trajectory);
    let diagonal: Vec<f64> = m.diagonal().iter().copied().collect();
    let mut gains = auto_tune(&diagonal, &vec![f64::INFINITY; model.dof()], dt);
    if stabilized {
        stabilize(&mut gains, &m, &damping, dt);
    }
    gains
}

/// A wave of `amplitude` rad at ω = 2 rad/s, run for `duration` s at `dt` with `gains`.
fn wave_run(model: &Model, amplitude: f64, dt: f64, duration: f64, gains: Gains) -> Summary {
    let given = |k: &[f64]| k.iter().map(|&k| Some(k)).collect::<Vec<_>>();
    let scenario = Scenario::builder(model.clone(), wave(model, amplitude))
        .dt(dt)
        .duration(duration)
        .record_period(duration)
        .effort(gains.effort.clone())
        .kp(given(&gains.kp))
        .kd(given(&gains.kd))
        .build()
        .unwrap();
    run(&scenario, &mut [], &StopFlag::new()).unwrap()
}

fn wave(model: &Model, amplitude: f64) -> Trajectory {
    Trajectory::Wave(Wave {
        amplitude: vec![amplitude; model.dof()],
        omega: 2.0,
        center: vec![0.0; model.dof()],
    })
}

fn model(urdf: &str) -> Model {
    read_str(urdf, "test arm", None, &PackagePaths::default()).unwrap()
}

/// One link of a generated arm: a box-like body of `mass` kg whose centre is `com` from the
/// joint, moved by a joint of `kind` about/along `axis`, `offset` from its parent's frame.
struct LinkSpec {
    parent: Option<usize>,
    kind: &'static str,
    axis: [f64; 3],
    offset: [f64; 3],
    mass: f64,
    com: [f64; 3],
    inertia: f64,
}

/// A URDF of the given links (link i is `l{i}`, joint i `j{i}`); no limits, no effort.
fn urdf(name: &str, links: &[LinkSpec]) -> String {
    let mut s = format!("<?xml version=\"1.0\"?>\n<robot name=\"{name}\">\n<link name=\"world\"/>\n");
    let v = |x: [f64; 3]| format!("{} {} {}", x[0], x[1], x[2]);
    for (i, l) in links.iter().enumerate() {
        let parent = l.parent.map_or("world".to_string(), |p| format!("l{p}"));
        let limit = if l.kind == "prismatic" {
            "<limit lower=\"-1e3\" upper=\"1e3\" effort=\"0\" velocity=\"0\"/>"
        } else {
            ""
        };
        s += &format!(
            "<joint name=\"j{i}\" type=\"{}\"><parent link=\"{parent}\"/><child link=\"l{i}\"/>\
             <origin xyz=\"{}\" rpy=\"0 0 0\"/><axis xyz=\"{}\"/>{limit}</joint>\n\
             <link name=\"l{i}\"><inertial><origin xyz=\"{}\" rpy=\"0 0 0\"/><mass value=\"{}\"/>\
             <inertia ixx=\"{in}\" ixy=\"0\" ixz=\"0\" iyy=\"{in}\" iyz=\"0\" izz=\"{in}\"/></inertial></link>\n",
            l.kind,
            v(l.offset),
            v(l.axis),
            v(l.com),
            l.mass,
            in = l.inertia
        );
    }
    s + "</robot>\n"
}

/// A serial chain of `n` revolute-continuous links about alternating axes, 5 cm apart.
fn chain(n: usize) -> String {
    let links: Vec<LinkSpec> = (0..n)
        .map(|i| LinkSpec {
            parent: i.checked_sub(1),
            kind: "continuous",
            axis: [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]][i % 3],
            offset: if i == 0 { [0.0; 3] } else { [0.0, 0.0, 0.05] },
            mass: 0.2,
            com: [0.0, 0.0, 0.025],
            inertia: 1e-4,
        })
        .collect();
    urdf(&format!("chain{n}"), &links)
}

/// A 7-dof arm in the usual yaw-pitch-pitch-yaw-pitch-yaw-pitch layout, heavy near the base
/// and light at the wrist.
fn seven_dof() -> String {
    let z = [0.0, 0.0, 1.0];
    let y = [0.0, 1.0, 0.0];
    let axes = [z, y, z, y, z, y, z];
    let lengths = [0.3, 0.0, 0.4, 0.0, 0.35, 0.0, 0.1];
    let masses = [4.0, 3.5, 2.5, 2.0, 1.2, 0.6, 0.2];
    let links: Vec<LinkSpec> = (0..7usize)
        .map(|i| LinkSpec {
            parent: i.checked_sub(1),
            kind: "continuous",
            axis: axes[i],
            offset: [0.0, 0.0, if i == 0 { 0.0 } else { lengths[i - 1] }],
            mass: masses[i],
            com: [0.0, 0.0, lengths[i] / 2.0],
            inertia: masses[i] * 1e-3,
        })
        .collect();
    urdf("seven_dof", &links)
}

/// A random tree of 2..=12 joints: any earlier link as parent, oblique axes, some prismatic,
/// masses over four decades.
fn random_tree(rng: &mut Rng) -> String {
    let n = 2 + (rng.next_u64() % 11) as usize;
    let links: Vec<LinkSpec> = (0..n)
        .map(|i| {
            let axis = rng.vector(3, -1.0, 1.0);
            let norm = axis.iter().map(|a| a * a).sum::<f64>().sqrt().max(1e-3);
            LinkSpec {
                parent: (i > 0).then(|| (rng.next_u64() % i as u64) as usize),
                kind: if rng.uniform(0.0, 1.0) < 0.2 {
                    "prismatic"
                } else {
                    "continuous"
                },
                axis: [axis[0] / norm, axis[1] / norm, axis[2] / norm],
                offset: [rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(0.0, 0.3)],
                mass: 10f64.powf(rng.uniform(-2.0, 2.0)),
                com: [rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2)],
                inertia: 10f64.powf(rng.uniform(-5.0, -1.0)),
            }
        })
        .collect();
    urdf("random_tree", &links)
}

/// The tuned arm holds ρ < 1 and tracks a 0.1 rad wave within `tolerance` (rad or m);
/// returns the stability figures.
fn assert_tracks(model: &Model, dt: f64, duration: f64, tolerance: f64) -> Stability {
    let gains = tuned(model, &wave(model, 0.1), dt, true);
    let stability = gains.stability.expect("stabilize records the figures");
    assert!(stability.spectral_radius < 1.0, "{}: {stability:?}", model.name);
    let summary = wave_run(model, 0.1, dt, duration, gains);
    assert!(summary.diverged.is_none(), "{}: {:?}", model.name, summary.diverged);
    let worst = summary.max_tracking_error_rad.iter().copied().fold(0.0, f64::max);
    println!(
        "{}: {} dof, Δt {dt}: {stability:?}, tracking error {worst:.2e}",
        model.name,
        model.dof()
    );
    assert!(
        worst < tolerance,
        "{}: tracking error {worst} ≥ {tolerance}",
        model.name
    );
    stability
}

#[test]
fn the_coupled_two_link_arm_diverges_on_the_rule_alone_and_not_after_stabilize() {
    let text = std::fs::read_to_string(common::repo_path("tests/urdf/coupled_two_link.urdf")).unwrap();
    let model = model(&text);
    let dt = 2e-4;
    let rule = tuned(&model, &wave(&model, 0.1), dt, false);
    let (m, damping) = start(&model, &wave(&model, 0.1));
    let before = Stability::assess(&m, &damping, &rule.kp, &rule.kd, dt);
    assert!(before.b_max > 1.0 && before.spectral_radius > 1.0, "{before:?}");
    assert!(wave_run(&model, 0.1, dt, 0.2, rule).diverged.is_some());
    let after = assert_tracks(&model, dt, 1.0, 2e-3);
    assert!(
        after.scaled && after.b_max <= 0.4 + 1e-12 && after.b_kd <= 0.5 + 1e-12,
        "{after:?}"
    );
}

#[test]
fn a_seven_dof_arm_tracks_at_5_and_1_khz() {
    let model = model(&seven_dof());
    assert_eq!(model.dof(), 7);
    assert_tracks(&model, 2e-4, 1.0, 2e-3);
    assert_tracks(&model, 1e-3, 1.0, 2e-3);
}

#[test]
fn a_200_link_chain_does_not_diverge() {
    let model = model(&chain(200));
    let dt = 2e-4;
    let rule = tuned(&model, &wave(&model, 0.1), dt, false);
    assert!(
        wave_run(&model, 0.1, dt, 0.02, rule).diverged.is_some(),
        "the rule alone diverges"
    );
    // one scale for every gain: the chain's stiffest mode sets it (the rule alone has b_max in
    // the 1e5s), which leaves its slowest modes barely damped (ρ within 1e-9 of 1). It stays
    // stable, but follows the wave only loosely: within the wave's amplitude, not closely.
    assert_tracks(&model, dt, 0.1, 0.1);
}

/// Property: on random trees with unlimited torque the tuned loop has ρ < 1, never diverges
/// and tracks a 0.1 rad wave within a tenth of its amplitude, at 5 kHz and at 1 kHz.
#[test]
fn random_trees_never_diverge() {
    let mut rng = Rng::new(0x5eed_c0de);
    for case in 0..24 {
        let model = model(&random_tree(&mut rng));
        let dt = if case % 2 == 0 { 2e-4 } else { 1e-3 };
        assert_tracks(&model, dt, 0.5, 1e-2);
    }
}

/// Through the real binary: the tuned chain runs, and given gains that make it diverge are
/// warned about before the run; the divergence stays one short line that names the stiffest
/// joints and counts the rest.
#[test]
fn the_binary_keeps_a_200_joint_divergence_to_one_line() {
    let dir = common::temp_dir("chain200");
    std::fs::write(dir.join("chain.urdf"), chain(200)).unwrap();
    let tuned = common::faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            "chain.urdf",
            "--duration",
            "0.002",
            "--summary",
            "s.json",
        ],
    );
    assert!(tuned.status.success(), "{}", tuned.stderr);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
    assert_eq!(summary["stability"]["scaled"], true);
    assert!(summary["stability"]["spectral_radius"].as_f64().unwrap() < 1.0);
    assert!(tuned.stdout.contains("gains scaled down"), "{}", tuned.stdout);

    let kp = vec!["1e9"; 200].join(",");
    let run = common::faze4(
        &dir,
        &["wave", "--urdf", "chain.urdf", "--duration", "0.01", "--kp", &kp],
    );
    assert_eq!(run.status.code(), Some(1), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().filter(|l| l.contains("diverged")).collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(lines[0].len() < 400, "{}", lines[0]);
    assert!(lines[0].contains("and 197 more"), "{}", lines[0]);
    assert!(run.stderr.contains("warning"), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The Faze4 within its torque limits: the coupled figures sit at the rule's own caps
/// (b_max 0.401, b_kd 0.502 at 5 kHz, 0.525 at 1 kHz), so its gains are never scaled.
#[test]
fn the_faze4_gains_do_not_move() {
    use faze4::faze4::EFFORT as FAZE4_EFFORT;
    let model = faze4::faze4::model();
    for (dt, b_kd) in [(2e-4, 0.502), (1e-3, 0.525)] {
        let trajectory = Trajectory::Wave(Wave {
            amplitude: vec![25f64.to_radians(); 6],
            omega: 0.5,
            center: vec![0.0; 6],
        });
        let (m, damping) = start(&model, &trajectory);
        let diagonal: Vec<f64> = m.diagonal().iter().copied().collect();
        let rule = auto_tune(&diagonal, &FAZE4_EFFORT, dt);
        let mut gains = rule.clone();
        let s = stabilize(&mut gains, &m, &damping, dt);
        assert!(!s.scaled && s.is_stable(), "{s:?}");
        assert_eq!((gains.kp, gains.kd), (rule.kp, rule.kd));
        assert!(
            (s.b_max - 0.401).abs() < 1.5e-3 && (s.b_kd - b_kd).abs() < 1.5e-3,
            "Δt {dt}: {s:?}"
        );
    }
}
