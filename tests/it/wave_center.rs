//! `faze4 wave --center`: waving about a pose other than zero, through the real binary.

use crate::common;

use common::*;

/// The rotor arm with J2's range moved off zero, like a Panda's elbow: its zero pose is outside.
fn offset_arm(dir: &std::path::Path) -> &'static str {
    let text = std::fs::read_to_string(repo_path("tests/urdf/rotor_arm.urdf")).unwrap();
    let moved = text.replace(
        "<limit lower=\"-2\" upper=\"2\" effort=\"15\"",
        "<limit lower=\"0.5\" upper=\"2.5\" effort=\"15\"",
    );
    assert_ne!(moved, text);
    std::fs::write(dir.join("offset.urdf"), moved).unwrap();
    "offset.urdf"
}

#[test]
fn an_arm_whose_zero_is_outside_its_limits_waves_about_mid() {
    let dir = temp_dir("center-mid");
    let urdf = offset_arm(&dir);
    // J3 is prismatic: 10° in radians as metres too (without --amp-m, a quarter of its range)
    let wave = [
        "wave",
        "--urdf",
        urdf,
        "--duration",
        "0.5",
        "--amp-deg",
        "10",
        "--amp-m",
        "0.17453292519943295",
    ];
    let with = |extra: &[&'static str]| -> Vec<&str> { wave.iter().copied().chain(extra.iter().copied()).collect() };
    // about zero: refused, naming the joint
    refuses(&dir, &with(&[]), &["--amp-deg", "J2 (pitch)"]);
    // about the middle of each range: J1 (-3, 3) → 0, J2 (0.5, 2.5) → 1.5, J3 → 0, J4 (continuous) → 0
    let run = faze4(&dir, &with(&["--center", "mid", "--trail", "t.csv"]));
    assert!(run.status.success(), "{}", run.stderr);
    let (_, rows) = read_csv(&dir.join("t.csv"));
    let amplitude = 10f64.to_radians();
    let center = [0.0, 1.5, 0.0, 0.0];
    for (i, c) in center.iter().enumerate() {
        let expected = c + amplitude * (i as f64 * std::f64::consts::FRAC_PI_3).sin();
        assert!(
            (rows[0][4 + i] - expected).abs() < 1e-12,
            "q{} starts at {}",
            i + 1,
            rows[0][4 + i]
        );
        // and stays near it: the loop tracks the centred wave
        for row in &rows {
            assert!(
                (row[4 + i] - c).abs() <= amplitude + 1e-3,
                "q{} = {}",
                i + 1,
                row[4 + i]
            );
        }
    }
    // an explicit centre: the same run
    let run = faze4(&dir, &with(&["--center", "0,1.5,0,0", "--trail", "u.csv"]));
    assert!(run.status.success(), "{}", run.stderr);
    assert_eq!(read_csv(&dir.join("u.csv")).1, rows);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_centres_are_refused_naming_the_joint() {
    let dir = temp_dir("center-bad");
    let urdf = offset_arm(&dir);
    let wave = ["wave", "--urdf", urdf, "--duration", "0.1"];
    let with = |extra: &[&'static str]| -> Vec<&str> { wave.iter().copied().chain(extra.iter().copied()).collect() };
    refuses(
        &dir,
        &with(&["--center", "0,0,0,0"]),
        &["--center", "J2 (pitch)", "outside its limits"],
    );
    refuses(
        &dir,
        &with(&["--center", "0,1.5,0"]),
        &["--center", "3 values", "4 joints"],
    );
    refuses(&dir, &with(&["--center", "0,1.5,x,0"]), &["--center", "J3", "'x'"]);
    // the amplitude about a legal centre still may not cross a limit
    refuses(
        &dir,
        &with(&["--center", "0,0.6,0,0", "--amp-deg", "20", "--freq", "50"]),
        &["--amp-deg", "J2 (pitch)"],
    );
    // the bundled Faze4's default run is unchanged by an explicit zero centre
    let plain = faze4(&dir, &["wave", "--duration", "0.2", "--trail", "a.csv"]);
    let zero = faze4(
        &dir,
        &[
            "wave",
            "--duration",
            "0.2",
            "--trail",
            "b.csv",
            "--center",
            "0,0,0,0,0,0",
        ],
    );
    assert!(plain.status.success() && zero.status.success());
    assert_eq!(read_csv(&dir.join("a.csv")), read_csv(&dir.join("b.csv")));
    std::fs::remove_dir_all(&dir).unwrap();
}
