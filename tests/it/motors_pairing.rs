//! A motors file, a preset and the per-joint overrides land on the joints they name: every
//! joint's torque limit and effective inertia (the summary's `effort` and
//! `effective_inertia`) against what the file's figures give, from a run without motors.
//! A file naming only some joints once put their ratios and rotors on other joints.

use crate::common;

use common::*;
use faze4::faze4::motors::{faze4 as faze4_preset, faze4_bom};
use serde_json::Value;

/// The Faze4's moving joints, J1..J6.
const JOINTS: [&str; 6] = ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"];

/// One DC motor entry: (ratio, efficiency, rotor inertia kg·m², stall torque N·m).
type Entry = (f64, f64, f64, f64);

/// Six distinct motors, J1..J6, so that a joint given another's figures is seen.
const SIX: [Entry; 6] = [
    (30.0, 0.9, 2e-5, 0.5),
    (40.0, 0.8, 3e-5, 0.6),
    (20.0, 0.85, 1.5e-5, 0.4),
    (12.0, 0.95, 4e-6, 0.3),
    (10.0, 0.7, 5e-6, 0.25),
    (20.0, 1.0, 1e-5, 0.1),
];

/// A `[[joint]]` entry, named or not.
fn toml_entry(name: Option<&str>, (ratio, eta, rotor, stall): Entry) -> String {
    let name = name.map_or(String::new(), |n| format!("name = \"{n}\"\n"));
    format!(
        "[[joint]]\n{name}gear_ratio = {ratio:?}\nefficiency = {eta:?}\nrotor_inertia = {rotor:?}\nkind = \"dc\"\nstall_torque = {stall:?}\nno_load_speed = 400.0\n\n"
    )
}

/// (effort, effective inertia) per joint of a 0.2 s Faze4 wave with `extra` options.
fn limits_and_inertia(dir: &std::path::Path, extra: &[&str]) -> (Vec<f64>, Vec<f64>) {
    let mut args = vec![
        "wave",
        "--duration",
        "0.2",
        "--no-collisions",
        "--trail",
        "none",
        "--summary",
        "s.json",
        "-q",
    ];
    args.extend_from_slice(extra);
    let run = faze4(dir, &args);
    assert!(run.status.code().is_some_and(|c| c == 0), "{args:?}: {}", run.stderr);
    let s: Value = summary(dir, "s.json");
    (vec_f64(&s["effort"]), vec_f64(&s["effective_inertia"]))
}

/// The run without motors: the Faze4's default limits and its bare effective inertias (its
/// URDF has no rotors).
fn bare(dir: &std::path::Path) -> (Vec<f64>, Vec<f64>) {
    limits_and_inertia(dir, &[])
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-300)
}

/// Every joint: the motor's limit r·η·stall and I + r²·I_rotor where `entries` gives one, the
/// bare run's figures where not.
fn check(label: &str, got: &(Vec<f64>, Vec<f64>), bare: &(Vec<f64>, Vec<f64>), entries: &[Option<Entry>; 6]) {
    for i in 0..6 {
        let (effort, inertia) = match entries[i] {
            Some((r, eta, rotor, stall)) => (r * eta * stall, bare.1[i] + r * r * rotor),
            None => (bare.0[i], bare.1[i]),
        };
        assert!(
            close(got.0[i], effort),
            "{label}: J{} limit {} N·m, expected {effort}",
            i + 1,
            got.0[i]
        );
        assert!(
            close(got.1[i], inertia),
            "{label}: J{} effective inertia {} kg·m², expected {inertia}",
            i + 1,
            got.1[i]
        );
    }
}

#[test]
fn a_file_naming_one_joint_changes_that_joint_alone() {
    let dir = temp_dir("pairing_one");
    let base = bare(&dir);
    std::fs::write(dir.join("j6.toml"), toml_entry(Some("hvataljka"), SIX[5])).unwrap();
    let got = limits_and_inertia(&dir, &["--motors", "j6.toml"]);
    check("J6 only", &got, &base, &[None, None, None, None, None, Some(SIX[5])]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_naming_every_joint_in_reverse_order_pairs_by_name() {
    let dir = temp_dir("pairing_reverse");
    let base = bare(&dir);
    let text: String = (0..6).rev().map(|i| toml_entry(Some(JOINTS[i]), SIX[i])).collect();
    std::fs::write(dir.join("reverse.toml"), text).unwrap();
    let got = limits_and_inertia(&dir, &["--motors", "reverse.toml"]);
    check("reverse order", &got, &base, &SIX.map(Some));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_without_names_pairs_in_order() {
    let dir = temp_dir("pairing_order");
    let base = bare(&dir);
    let text: String = SIX.iter().map(|&e| toml_entry(None, e)).collect();
    std::fs::write(dir.join("order.toml"), text).unwrap();
    let got = limits_and_inertia(&dir, &["--motors", "order.toml"]);
    check("by order", &got, &base, &SIX.map(Some));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--gear-ratio` over a preset changes the joints it gives, once: J6 at ratio 10 gets the
/// preset motor's limit at 10 and its rotor reflected through 10; every other joint keeps the
/// preset's figures.
#[test]
fn an_override_on_a_preset_changes_the_joints_it_gives() {
    let dir = temp_dir("pairing_override");
    let base = bare(&dir);
    let got = limits_and_inertia(
        &dir,
        &["--motors", "faze4", "--gear-ratio", "auto,auto,auto,auto,auto,10"],
    );
    for (i, m) in faze4_preset(None).iter().enumerate() {
        let m = m.as_ref().unwrap();
        let ratio = if i == 5 { 10.0 } else { m.gear_ratio.unwrap() };
        let rotor = m.rotor_inertia.unwrap();
        let (effort, inertia) = (m.motor.joint_limit(ratio), base.1[i] + ratio * ratio * rotor);
        assert!(close(got.0[i], effort), "J{} limit {} vs {effort}", i + 1, got.0[i]);
        assert!(close(got.1[i], inertia), "J{} inertia {} vs {inertia}", i + 1, got.1[i]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The `faze4-bom` preset: each joint gets its own motor's limit and rotor (J1's and J2's
/// rotors are not published: none), a joint without a motor the default limit and no rotor.
#[test]
fn the_bom_preset_lands_on_its_joints() {
    let dir = temp_dir("pairing_bom");
    let base = bare(&dir);
    let got = limits_and_inertia(&dir, &["--motors", "faze4-bom"]);
    for (i, m) in faze4_bom(None).iter().enumerate() {
        let (effort, inertia) = match m {
            Some(m) => {
                let ratio = m.gear_ratio.unwrap();
                let rotor = m.rotor_inertia.unwrap_or(0.0);
                (m.motor.joint_limit(ratio), base.1[i] + ratio * ratio * rotor)
            }
            None => (base.0[i], base.1[i]),
        };
        assert!(close(got.0[i], effort), "J{} limit {} vs {effort}", i + 1, got.0[i]);
        assert!(close(got.1[i], inertia), "J{} inertia {} vs {inertia}", i + 1, got.1[i]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
