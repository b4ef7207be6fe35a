//! All or nothing (issue 26): a run or sweep that fails leaves every file as it was and no
//! temporary behind; two outputs naming one file are refused; SIGTERM and SIGHUP stop a run as
//! Ctrl-C does; inputs that would run away or overflow are refused before they start; every
//! message is one line that names its option. One test per class, each through the real binary,
//! each checking the exit status, the one line on stderr and the directory before and after.

use crate::common;

use std::os::unix::fs::symlink;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;

/// The names in `dir` that look like temporaries (`.NAME.PID.tmp`, `.NAME.PID.bak`).
fn temporaries(dir: &Path) -> Vec<String> {
    snapshot(dir)
        .into_keys()
        .filter(|n| n.ends_with(".tmp") || n.ends_with(".bak"))
        .collect()
}

const SHORT: [&str; 4] = ["--duration", "0.3", "--no-collisions", "-q"];

fn wave<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["wave"];
    args.extend_from_slice(&SHORT);
    args.extend_from_slice(extra);
    args
}

#[test]
fn a_failed_run_or_sweep_changes_no_file() {
    let dir = temp_dir("aon-failed");
    std::fs::write(dir.join("t.csv"), "old trail\n").unwrap();
    std::fs::write(dir.join("faze4_trail.csv"), "old default trail\n").unwrap();
    std::fs::write(dir.join("s.json"), "{}\n").unwrap();
    std::fs::create_dir(dir.join("d")).unwrap();
    std::fs::create_dir(dir.join("d.svg")).unwrap();
    std::fs::create_dir(dir.join("trails")).unwrap();
    std::fs::write(dir.join("trails/run_0000000.csv"), "old run\n").unwrap();
    // an output that fails only when written, after the run: a link to a full device
    symlink("/dev/full", dir.join("full.svg")).unwrap();
    symlink("/dev/full", dir.join("full.json")).unwrap();
    let cases: &[(Vec<&str>, &[&str])] = &[
        (wave(&["--summary", "/dev/full", "--trail", "t.csv"]), &["/dev/full"]),
        (wave(&["--summary", "/dev/full"]), &["/dev/full"]),
        (wave(&["--summary", "full.json", "--trail", "t.csv"]), &["full.json"]),
        (
            wave(&["--plot", "full.svg", "--trail", "t.csv", "--summary", "s.json"]),
            &["full.svg"],
        ),
        (
            wave(&["--html", "d", "--trail", "t.csv"]),
            &["--html", "is a directory"],
        ),
        (wave(&["--plot", "/dev/full", "--trail", "t.csv"]), &["--plot"]),
        (
            vec![
                "sweep",
                "--vary",
                "dt=1e-4,2e-4",
                "--out",
                "t.csv",
                "--plot",
                "d.svg",
                "-q",
                "--",
                "wave",
                "--duration",
                "0.2",
            ],
            &["--plot", "is a directory"],
        ),
        (
            vec![
                "sweep",
                "--vary",
                "dt=1e-4,2e-4",
                "--out",
                "t.csv",
                "--plot",
                "full.svg",
                "--trails",
                "trails",
                "-q",
                "--",
                "wave",
                "--duration",
                "0.2",
                "--no-collisions",
            ],
            &["full.svg"],
        ),
    ];
    for (args, parts) in cases {
        fails_leaving_all_as_was(&dir, args, parts);
    }
    // stdout on a full disk: the verdict is lost, so the run failed and wrote nothing
    for args in [
        wave(&["--trail", "t.csv", "--summary", "s.json"]),
        vec![
            "sweep",
            "--vary",
            "dt=1e-4",
            "--out",
            "t.csv",
            "-q",
            "--",
            "wave",
            "--duration",
            "0.2",
            "--no-collisions",
        ],
    ] {
        let before = snapshot(&dir);
        let out = Command::new(env!("CARGO_BIN_EXE_faze4"))
            .args(&args)
            .current_dir(&dir)
            .stdout(std::fs::File::create("/dev/full").unwrap())
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        check_refusal(
            &args,
            out.status.code(),
            &String::from_utf8_lossy(&out.stderr),
            &["stdout"],
        );
        assert_eq!(snapshot(&dir), before, "{args:?} changed the directory");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn two_outputs_naming_one_file_are_refused() {
    let dir = temp_dir("aon-same");
    std::fs::write(dir.join("x.json"), "keep\n").unwrap();
    symlink("x.json", dir.join("link.json")).unwrap();
    std::fs::create_dir(dir.join("sub")).unwrap();
    let cases: &[(Vec<&str>, &[&str])] = &[
        (
            wave(&["--summary", "x.json", "--trail", "x.json"]),
            &["--summary", "--trail", "x.json"],
        ),
        (wave(&["--trail", "x.html", "--html", "x.html"]), &["--html", "--trail"]),
        (
            wave(&["--trail", "none", "--html", "x.svg", "--plot", "x.svg"]),
            &["--plot", "--html"],
        ),
        (
            wave(&["--trail", "./x.json", "--summary", "sub/../x.json"]),
            &["--summary", "--trail"],
        ),
        (
            wave(&["--trail", "link.json", "--summary", "x.json"]),
            &["--summary", "--trail"],
        ),
        (
            vec![
                "shape",
                "--shape",
                "circle",
                "--duration",
                "0.3",
                "-q",
                "--save-q",
                "x.npy",
                "--trail",
                "x.npy",
            ],
            &["--save-q", "--trail"],
        ),
        (
            vec![
                "sweep", "--vary", "dt=1e-4", "--out", "x.csv", "--plot", "./x.csv", "--", "wave",
            ],
            &["--plot", "--out"],
        ),
    ];
    for (args, parts) in cases {
        fails_leaving_all_as_was(&dir, args, parts);
    }
    // a device may be named twice: both are written into it
    let run = faze4(&dir, &wave(&["--trail", "/dev/null", "--summary", "/dev/null"]));
    assert!(run.status.success(), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn outputs_are_written_through_links_and_a_trailing_slash_leaves_nothing() {
    let dir = temp_dir("aon-links");
    std::fs::write(dir.join("real.csv"), "old\n").unwrap();
    symlink("real.csv", dir.join("link.csv")).unwrap();
    symlink("new.json", dir.join("dangling.json")).unwrap();
    let run = faze4(&dir, &wave(&["--trail", "link.csv", "--summary", "dangling.json"]));
    assert!(run.status.success(), "{}", run.stderr);
    // the links stay links; the files they name hold the outputs
    assert_eq!(std::fs::read_link(dir.join("link.csv")).unwrap(), Path::new("real.csv"));
    assert_eq!(
        std::fs::read_link(dir.join("dangling.json")).unwrap(),
        Path::new("new.json")
    );
    let (header, rows) = read_csv(&dir.join("real.csv"));
    assert_eq!(header[0], "t");
    assert_eq!(rows.last().unwrap()[0], 0.3);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("new.json")).unwrap()).unwrap();
    assert_eq!(summary["steps"], 1500);
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));

    for (args, parts) in [
        (wave(&["--summary", "sub/"]), ["--summary", "sub/"]),
        (wave(&["--trail", "none", "--html", "sub/"]), ["--html", "sub/"]),
        (wave(&["--trail", "t.csv/"]), ["--trail", "t.csv/"]),
        (
            vec![
                "sweep",
                "--vary",
                "dt=1e-4",
                "--out",
                "sub.csv/",
                "--",
                "wave",
                "--duration",
                "0.2",
            ],
            ["--out", "sub.csv/"],
        ),
    ] {
        fails_leaving_all_as_was(&dir, &args, &parts);
    }
    // `none` writes nothing, for every output of a run
    let before = snapshot(&dir);
    let run = faze4(
        &dir,
        &wave(&[
            "--trail",
            "none",
            "--summary",
            "none",
            "--html",
            "none",
            "--plot",
            "none",
        ]),
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert_eq!(snapshot(&dir), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sigterm_and_sighup_stop_a_run_as_ctrl_c_does() {
    for (signal, status, name) in [(libc::SIGTERM, 143, "SIGTERM"), (libc::SIGHUP, 129, "SIGHUP")] {
        let dir = temp_dir(&format!("aon-{name}"));
        std::fs::write(dir.join("t.csv"), "old\n").unwrap();
        // 10 000 s of simulated time: the signal always comes first
        // sent once the trail's temporary exists: the run has begun
        let out = signalled_once_begun(
            &dir,
            &[
                "wave",
                "--duration",
                "10000",
                "--no-collisions",
                "-q",
                "--trail",
                "t.csv",
                "--summary",
                "s.json",
            ],
            signal,
            |dir, _| has_temporary(dir),
            Duration::from_millis(500),
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(status), "{name}: {stderr}");
        assert!(stderr.contains(&format!("stopped by {name} at t =")), "{stderr}");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
        let stopped = summary["interrupted_at_s"].as_f64().expect("interrupted_at_s");
        // the trail is whole up to the step the run stopped at
        let (_, rows) = read_csv(&dir.join("t.csv"));
        assert!((rows.last().unwrap()[0] - stopped).abs() < 1e-9, "{stopped}");
        assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
        std::fs::remove_dir_all(&dir).unwrap();
    }
    // a sweep: the table of the runs that finished, their trails, no temporary
    let dir = temp_dir("aon-sweep-term");
    std::fs::create_dir(dir.join("trails")).unwrap();
    let out = signalled_once_begun(
        &dir,
        &[
            "sweep",
            "--vary",
            "payload-kg=0:9.9999:0.0001",
            "--out",
            "t.csv",
            "--trails",
            "trails",
            "-q",
            "--",
            "wave",
            "--no-collisions",
            "--duration",
            "0.5",
        ],
        libc::SIGTERM,
        |dir, _| has_temporary(dir),
        Duration::from_millis(1500),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(143), "{stderr}");
    assert!(stderr.contains("stopped by SIGTERM after"), "{stderr}");
    let text = std::fs::read_to_string(dir.join("t.csv")).unwrap();
    let rows = text.lines().count() - 1;
    assert!(rows < 100_000, "{rows}");
    // one trail per row of the table, and none of a run the table does not hold
    assert_eq!(std::fs::read_dir(dir.join("trails")).unwrap().count(), rows);
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A URDF of `body` inside a robot element.
fn urdf(dir: &Path, name: &str, body: &str) -> String {
    std::fs::write(dir.join(name), format!("<robot name=\"r\">{body}</robot>")).unwrap();
    name.to_string()
}

const LINK: &str = r#"<inertial><origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="1.0"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>"#;

#[test]
fn runaway_and_overflowing_inputs_are_refused_before_they_start() {
    let dir = temp_dir("aon-runaway");
    let zero_dof = urdf(&dir, "still.urdf", r#"<link name="base"/>"#);
    let negative_effort = urdf(
        &dir,
        "effort.urdf",
        &format!(
            r#"<link name="base"/><joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
            <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="-5" velocity="1"/></joint>
            <link name="l1">{LINK}</link>"#
        ),
    );
    let gear = "--gear-ratio=1e160,auto,auto,auto,auto,auto";
    let rotor = "--rotor-inertia=1e-5,auto,auto,auto,auto,auto";
    let cases: &[(Vec<&str>, &[&str])] = &[
        // a 1e12-run sweep's half is still 5e11 runs
        (
            vec![
                "sweep",
                "--vary",
                "dt=1:1000000:1",
                "--vary",
                "freq=1:1000000:1",
                "--shard",
                "1/2",
                "--",
                "wave",
            ],
            &["--shard", "1/2", "500000000000"],
        ),
        // six ranges of 1e7 values: refused from their sizes, before any list is made
        (
            vec![
                "sweep",
                "--vary",
                "dt=0:0.5:1e-7",
                "--vary",
                "freq=0:0.5:1e-7",
                "--vary",
                "amp-deg=0:0.5:1e-7",
                "--vary",
                "payload-kg=0:0.5:1e-7",
                "--vary",
                "max-error=0:0.5:1e-7",
                "--vary",
                "kp-scale=0:0.5:1e-7",
                "--",
                "wave",
            ],
            &["--vary", "too many"],
        ),
        (
            vec!["sweep", "--jobs", "100000", "--vary", "dt=1e-4", "--", "wave"],
            &["--jobs", "1024"],
        ),
        (
            vec!["sweep", "--jobs", "-1", "--vary", "dt=1e-4", "--", "wave"],
            &["--jobs", "number of threads"],
        ),
        (
            vec!["sweep", "--shard", "-1/2", "--vary", "dt=1e-4", "--", "wave"],
            &["--shard", "K/N"],
        ),
        (
            wave(&["--trail", "none", "--payload-kg", "1e308"]),
            &["--payload-kg", "1e308", "overflow"],
        ),
        (
            wave(&["--trail", "none", rotor, gear]),
            &["'rotary_base'", "overflow", "--gear-ratio"],
        ),
        (
            vec![
                "wave",
                "--duration",
                "0.3",
                "--trail",
                "none",
                "--self-collisions",
                "--friction",
                "1e200",
            ],
            &["--friction", "1e200", "overflows"],
        ),
        (
            vec!["wave", "--trail", "none", "--duration", "1e300"],
            &["--duration", "more than the 10^12 steps"],
        ),
        (
            wave(&["--trail", "none", "--urdf", &zero_dof]),
            &["still.urdf", "no moving joint"],
        ),
        (
            wave(&["--trail", "none", "--urdf", &negative_effort]),
            &["effort.urdf", "'j1'", "effort=\"-5\""],
        ),
        (
            vec![
                "sweep",
                "--vary",
                "kp-scale=1e308",
                "--out",
                "t.csv",
                "--",
                "wave",
                "--duration",
                "0.2",
            ],
            &[],
        ),
    ];
    for (args, parts) in &cases[..cases.len() - 1] {
        fails_leaving_all_as_was(&dir, args, parts);
    }
    // a sweep's run whose scale overflows is a failed row, not a diverged one
    let run = faze4(&dir, &cases[cases.len() - 1].0);
    assert!(run.status.success(), "{}", run.stderr);
    let table = std::fs::read_to_string(dir.join("t.csv")).unwrap();
    assert!(table.contains("kp-scale: 1e308: too large to simulate"), "{table}");
    std::fs::remove_file(dir.join("t.csv")).unwrap();
    // --jobs is capped at the runs
    let run = faze4(
        &dir,
        &[
            "sweep",
            "--jobs",
            "64",
            "--vary",
            "dt=1e-4,2e-4",
            "--",
            "wave",
            "--duration",
            "0.2",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(run.stdout.contains("on 2 threads"), "{}", run.stdout);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn find_checks_its_bounds_as_the_option_would() {
    let dir = temp_dir("aon-find");
    let cases: &[(Vec<&str>, &[&str])] = &[
        (
            vec!["sweep", "--find", "payload-kg=-1:3", "--", "wave"],
            &["--find", "--payload-kg", "-1"],
        ),
        (
            vec!["sweep", "--find-min", "dt=-1e-4:1e-3", "--", "wave"],
            &["--find-min", "--dt", "-0.0001"],
        ),
        (
            vec!["sweep", "--find", "amp-deg=0:1000", "--", "wave"],
            &["--find", "amp-deg=1000", "beyond its limits"],
        ),
        (
            vec!["sweep", "--find", "payload-kg=0:3", "--resolution", "inf", "--", "wave"],
            &["--resolution", "inf", "> 0"],
        ),
    ];
    for (args, parts) in cases {
        fails_leaving_all_as_was(&dir, args, parts);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn messages_are_one_readable_line_naming_their_option() {
    let dir = temp_dir("aon-messages");
    // a joint name with a line break (NEL, which XML keeps): quoted and escaped, on one line
    let model = urdf(
        &dir,
        "names.urdf",
        &format!(
            r#"<link name="base"/><joint name="j&#x85;1" type="revolute"><parent link="base"/><child link="l1"/>
            <axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1"/></joint><link name="l1">{LINK}</link>"#
        ),
    );
    let run = faze4(
        &dir,
        &["wave", "--duration", "0.2", "--trail", "none", "--urdf", &model],
    );
    assert!(run.status.success(), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(lines[0].contains("no effort limit for 'j\\u{85}1'"), "{}", lines[0]);
    // a tiny resolution prints the digits that tell the two values apart, and no more
    let run = faze4(
        &dir,
        &[
            "sweep",
            "--find",
            "payload-kg=0:3",
            "--resolution",
            "1e-300",
            "-q",
            "--",
            "wave",
            "--duration",
            "0.1",
            "--no-collisions",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    let line = run.stdout.lines().last().unwrap();
    assert!(line.len() < 200, "{line}");
    if let Some(rest) = line.strip_prefix("largest payload-kg that follows: ") {
        let (follows, rest) = rest.split_once(" (at ").unwrap();
        let fails = rest.split_once(':').unwrap().0;
        assert_ne!(follows, fails, "{line}");
        assert!(follows.len() <= 20 && fails.len() <= 20, "{line}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
