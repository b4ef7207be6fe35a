//! The real `faze4` binary: outputs, their contracts, and its answers to bad input.

use crate::common;

use std::path::Path;

use common::*;

/// Writes a .npy by hand (any dtype string, order and shape), as other tools might.
fn write_npy(path: &Path, descr: &str, fortran: bool, shape: &[usize], data: &[u8]) {
    let shape_text = match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")
        ),
    };
    let mut header = format!(
        "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape_text}, }}",
        if fortran { "True" } else { "False" }
    );
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    bytes.extend(data);
    std::fs::write(path, bytes).unwrap();
}

fn f64_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A gentle N×6 trajectory around the wave start, row-major.
fn trajectory(n: usize) -> Vec<f64> {
    (0..n)
        .flat_map(|k| (0..6).map(move |i| 0.3 * ((k as f64) * 0.2 + i as f64).sin()))
        .collect()
}

#[test]
fn wave_writes_the_trail_and_summary_contracts() {
    let dir = temp_dir("contract");
    let run = faze4(&dir, &["wave", "--duration", "1", "--summary", "s.json"]);
    assert!(run.status.success(), "{}", run.stderr);
    // trail: default name, header, t = 0 and the last step, one row per 0.02 s
    let (header, rows) = read_csv(&dir.join("faze4_trail.csv"));
    assert_eq!(header, ["t", "x", "y", "z", "q1", "q2", "q3", "q4", "q5", "q6"]);
    assert_eq!(rows.len(), 51);
    assert_eq!(rows[0][0], 0.0);
    assert_eq!(rows[50][0], 1.0);
    // summary: exactly the contract's keys
    let s = summary(&dir, "s.json");
    let mut keys: Vec<&str> = s.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "clearance",
            "clearance_wall_time_s",
            "diverged",
            "dof",
            "dt",
            "dynamics_wall_time_s",
            "effective_inertia",
            "effort",
            "feed_forward",
            "format",
            "joints",
            "kd",
            "kp",
            "mapped",
            "max_speed",
            "max_tracking_error_rad",
            "meshes",
            "robot",
            "robot_source",
            "saturation_pct",
            "stability",
            "steps",
            "tool_choice",
            "tool_link",
            "tool_range_m",
            "velocity_limit",
            "velocity_limit_pct",
            "verdict",
            "wall_time_s"
        ]
    );
    assert_eq!(s["steps"], 5000);
    // the loop's own time is part of its whole, the clearance's too
    let wall = s["wall_time_s"].as_f64().unwrap();
    assert!(
        (0.0..=wall).contains(&s["dynamics_wall_time_s"].as_f64().unwrap()),
        "{s}"
    );
    assert!(
        (0.0..=wall).contains(&s["clearance_wall_time_s"].as_f64().unwrap()),
        "{s}"
    );
    assert_eq!(s["feed_forward"], "gravity");
    assert!(s["diverged"].is_null());
    // the printed banner and summary
    for part in [
        "6 dof",
        "5 kHz",
        "kp",
        "kd",
        "eff. inertia",
        "start pose",
        "t=  0.50s",
        "[summary]",
        "tool range",
        "self-clearance (meshes, tolerance 1.00 mm): ",
    ] {
        assert!(run.stdout.contains(part), "stdout lacks {part:?}:\n{}", run.stdout);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn debug_adds_torque_error_velocity_and_gravity() {
    let dir = temp_dir("debug");
    let run = faze4(&dir, &["wave", "--duration", "0.5", "--debug", "--trail", "t.csv"]);
    assert!(run.status.success(), "{}", run.stderr);
    let (header, rows) = read_csv(&dir.join("t.csv"));
    assert_eq!(header.len(), 4 + 6 * 5);
    assert!(header.contains(&"tau6".to_string()) && header.contains(&"g2".to_string()));
    // g2 at t = 0 is the J2 gravity torque of the start pose: a few N·m, within J2's limit
    let g2 = rows[0][header.iter().position(|h| h == "g2").unwrap()];
    assert!(g2.abs() > 1.0 && g2.abs() < 8.5, "g2 = {g2}");
    assert!(run.stdout.contains("g(q) (N·m)"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn payload_raises_the_shoulder_load() {
    let dir = temp_dir("payload");
    let light = faze4(
        &dir,
        &["wave", "--duration", "0.2", "--trail", "none", "--summary", "a.json"],
    );
    let heavy = faze4(
        &dir,
        &[
            "wave",
            "--duration",
            "0.2",
            "--trail",
            "none",
            "--payload-kg",
            "0.5",
            "--summary",
            "b.json",
        ],
    );
    assert!(light.status.success() && heavy.status.success());
    let (a, b) = (summary(&dir, "a.json"), summary(&dir, "b.json"));
    let (ia, ib) = (vec_f64(&a["effective_inertia"]), vec_f64(&b["effective_inertia"]));
    assert!(ib[1] > ia[1] * 1.1, "J2 inertia {} → {}", ia[1], ib[1]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn replay_reads_float32_and_fortran_order() {
    let dir = temp_dir("npy");
    let n = 20;
    let rows = trajectory(n);
    write_npy(&dir.join("c64.npy"), "<f8", false, &[n, 6], &f64_bytes(&rows));
    // the same values, float32 in Fortran (column-major) order
    let mut col_major = Vec::new();
    for i in 0..6 {
        for k in 0..n {
            col_major.extend((rows[k * 6 + i] as f32).to_le_bytes());
        }
    }
    write_npy(&dir.join("f32.npy"), "<f4", true, &[n, 6], &col_major);
    for f in ["c64.npy", "f32.npy"] {
        let run = faze4(
            &dir,
            &[
                "replay",
                "--q-traj",
                f,
                "--duration",
                "1",
                "--trail",
                &format!("{f}.csv"),
            ],
        );
        assert!(run.status.success(), "{f}: {}", run.stderr);
    }
    let (_, a) = read_csv(&dir.join("c64.npy.csv"));
    let (_, b) = read_csv(&dir.join("f32.npy.csv"));
    // the start state is frame 0: equal to float32 rounding
    assert!(max_abs_diff(&a[0][4..], &rows[..6]) == 0.0);
    assert!(max_abs_diff(&b[0][4..], &rows[..6]) < 1e-7);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_trajectories_are_refused_with_what_was_found() {
    let dir = temp_dir("bad-npy");
    let write =
        |name: &str, descr: &str, shape: &[usize], data: &[u8]| write_npy(&dir.join(name), descr, false, shape, data);
    write("one.npy", "<f8", &[1, 6], &f64_bytes(&trajectory(1)));
    write("cols.npy", "<f8", &[10, 5], &f64_bytes(&trajectory(10)[..50]));
    write("int.npy", "<i8", &[10, 6], &[0u8; 480]);
    write("flat.npy", "<f8", &[60], &f64_bytes(&trajectory(10)));
    let mut nan = trajectory(10);
    nan[33] = f64::NAN;
    write("nan.npy", "<f8", &[10, 6], &f64_bytes(&nan));
    let mut inf = trajectory(10);
    inf[7] = f64::INFINITY;
    write("inf.npy", "<f8", &[10, 6], &f64_bytes(&inf));
    let mut far = trajectory(10);
    far[4 * 6 + 1] = 2.5; // J2 limit is ±2.094 rad
    write("limit.npy", "<f8", &[10, 6], &f64_bytes(&far));
    std::fs::write(dir.join("junk.npy"), b"not an npy file at all").unwrap();
    write("short.npy", "<f8", &[10, 6], &f64_bytes(&trajectory(5)));

    fn replay(f: &str) -> Vec<&str> {
        vec!["replay", "--q-traj", f]
    }
    refuses(
        &dir,
        &replay("one.npy"),
        &["one.npy", "at least 2 frames", "shape [1, 6]"],
    );
    refuses(&dir, &replay("cols.npy"), &["cols.npy", "5 columns", "6 joints"]);
    refuses(&dir, &replay("int.npy"), &["int.npy", "float64 or float32", "<i8"]);
    refuses(&dir, &replay("flat.npy"), &["flat.npy", "2-D", "shape [60]"]);
    refuses(&dir, &replay("nan.npy"), &["nan.npy", "frame 5, joint 4", "NaN"]);
    refuses(&dir, &replay("inf.npy"), &["inf.npy", "frame 1, joint 2", "inf"]);
    refuses(
        &dir,
        &replay("limit.npy"),
        &["limit.npy", "frame 4", "J2 (nadlaktica)", "2.5", "limits"],
    );
    refuses(&dir, &replay("junk.npy"), &["junk.npy", "not a NumPy .npy file"]);
    refuses(&dir, &replay("short.npy"), &["short.npy", "cannot read"]);
    refuses(&dir, &replay("missing.npy"), &["missing.npy", "No such file"]);
    refuses(
        &dir,
        &["replay", "--q-traj", "limit.npy", "--traj-period", "0"],
        &["--traj-period", "must be > 0"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_arguments_are_refused_naming_the_option() {
    let dir = temp_dir("bad-args");
    refuses(&dir, &["wave", "--dt", "0"], &["--dt", "must be > 0"]);
    refuses(&dir, &["wave", "--dt", "-1e-4"], &["--dt", "must be > 0"]);
    refuses(&dir, &["wave", "--duration", "0"], &["--duration", "must be > 0"]);
    refuses(
        &dir,
        &["wave", "--duration", "NaN"],
        &["--duration", "not a finite number"],
    );
    refuses(&dir, &["wave", "--freq", "inf"], &["--freq", "not a finite number"]);
    refuses(
        &dir,
        &["wave", "--effort", "1,2,3"],
        &["--effort", "3 values", "6 joints"],
    );
    refuses(&dir, &["wave", "--kp", "1,2,3,4,5,6,7"], &["--kp", "7 values"]);
    refuses(&dir, &["wave", "--kd", "1,2,x,4,5,6"], &["--kd", "'x' is not a number"]);
    refuses(
        &dir,
        &["wave", "--effort", "1,2,3,4,5,-6"],
        &["--effort", "J6", "must be > 0"],
    );
    refuses(
        &dir,
        &["wave", "--amp-deg", "150"],
        &["--amp-deg", "J2 (nadlaktica)", "limits"],
    );
    refuses(
        &dir,
        &["wave", "--tool-link", "pen"],
        &["--tool-link", "no link 'pen'", "tool_link"],
    );
    refuses(&dir, &["wave", "--payload-kg", "-1"], &["--payload-kg", "≥ 0"]);
    refuses(
        &dir,
        &["wave", "--duration", "1e-5"],
        &["--duration", "shorter than one step"],
    );
    refuses(&dir, &["wave", "--urdf", "nope.urdf"], &["nope.urdf", "No such file"]);
    std::fs::write(dir.join("bad.urdf"), "<robot name='x'><link name='a'/><joint name='j' type='revolute'><parent link='a'/><child link='b'/></joint></robot>").unwrap();
    refuses(
        &dir,
        &["wave", "--urdf", "bad.urdf"],
        &["bad.urdf", "joint 'j'", "child link 'b' does not exist"],
    );
    std::fs::remove_file(dir.join("bad.urdf")).unwrap();
    // clap's own usage errors: also status 2, no panic
    let run = faze4(&dir, &["wave", "--no-such-option"]);
    assert_eq!(run.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_diverging_run_stops_at_once_and_says_so() {
    let dir = temp_dir("diverge");
    // J6 with kp = 40000 (b = Δt²·kp/I ≈ 248) and no effective torque limit
    let run = faze4(
        &dir,
        &[
            "wave",
            "--kp",
            "auto,auto,auto,auto,auto,40000",
            "--effort",
            "7.9,8.5,4.7,3.7,3.5,1e9",
            "--summary",
            "s.json",
        ],
    );
    assert_eq!(run.status.code(), Some(1), "{}", run.stderr);
    let line = run
        .stderr
        .lines()
        .find(|l| l.contains("diverged"))
        .expect("a 'diverged' line");
    for part in ["J6 ('hvataljka')", "t = ", "b = Δt²·kp/I", "248", "spectral radius"] {
        assert!(line.contains(part), "{line:?} lacks {part:?}");
    }
    // the given gains were flagged before the run
    let warning = run
        .stderr
        .lines()
        .position(|l| l.contains("warning") && l.contains("spectral radius"));
    let diverged = run.stderr.lines().position(|l| l.contains("diverged"));
    assert!(warning.is_some_and(|w| Some(w) < diverged), "{}", run.stderr);

    let s = summary(&dir, "s.json");
    assert_eq!(s["diverged"]["joint"], 6);
    assert!(s["diverged"]["t"].as_f64().unwrap() < 0.01, "stopped at once");
    assert!((vec_f64(&s["diverged"]["stiffness_b"])[5] - 248.0).abs() < 1.0);
    assert!(s["stability"]["spectral_radius"].as_f64().unwrap() >= 1.0);
    assert_eq!(s["stability"]["scaled"], false);
    // the trail is kept, complete up to the divergence
    let (_, rows) = read_csv(&dir.join("faze4_trail.csv"));
    assert!(!rows.is_empty() && rows.iter().flatten().all(|x| x.is_finite()));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn progress_bar_shows_on_a_terminal_only() {
    let dir = temp_dir("progress");
    let exe = env!("CARGO_BIN_EXE_faze4");
    // a run of a few seconds: under a pseudo-terminal (util-linux `script`) the bar appears…
    let command = format!("{exe} wave --duration 300 --trail none --no-collisions");
    let tty = std::process::Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .current_dir(&dir)
        .output()
        .expect("util-linux `script` runs the binary under a pseudo-terminal");
    assert!(tty.status.success());
    let text = String::from_utf8_lossy(&tty.stdout);
    assert!(
        text.contains("%  t = ") && text.contains("s left"),
        "no progress bar on a terminal"
    );
    // …and with stderr a pipe, it does not
    let piped = faze4(
        &dir,
        &["wave", "--duration", "300", "--trail", "none", "--no-collisions"],
    );
    assert!(piped.status.success());
    assert!(
        piped.stderr.is_empty(),
        "stderr should be empty, got {:?}",
        &piped.stderr[..piped.stderr.len().min(200)]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn ctrl_c_ends_the_run_with_complete_files() {
    let dir = temp_dir("ctrl-c");
    // once the trail's temporary exists the run has begun
    let out = signalled_once_begun(
        &dir,
        &["wave", "--duration", "36000", "--trail", "t.csv", "--summary", "s.json"],
        libc::SIGINT,
        |dir, _| has_temporary(dir),
        std::time::Duration::from_millis(500),
    );
    assert_eq!(out.status.code(), Some(130), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("interrupted at t = "));
    // both files complete: every trail row whole, the summary valid JSON that says where it stopped
    let (header, rows) = read_csv(&dir.join("t.csv"));
    assert!(rows.len() > 10 && rows.iter().all(|r| r.len() == header.len()));
    let s = summary(&dir, "s.json");
    let t = s["interrupted_at_s"].as_f64().unwrap();
    assert!(t > 0.0 && t < 36000.0);
    assert!(
        (rows.last().unwrap()[0] - t).abs() < 1e-9,
        "the trail ends where the run stopped"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Broken copies of the bundled arm, each given to every run command: one line naming the file,
/// the element and what is wrong.
#[test]
fn bad_urdfs_are_refused_naming_file_element_and_fault() {
    let dir = temp_dir("bad-urdf");
    let good = std::fs::read_to_string(repo_path("urdf/faze4_arm.urdf")).unwrap();
    let lakat_mass = r#"<mass value="1.2726491805247"/>"#;
    let variants: [(&str, String, &[&str]); 9] = [
        ("truncated", good[..good.len() / 2].to_string(), &["malformed URDF"]),
        (
            "malformed",
            good.replace("<link name=\"lakat\">", "<link name=\"lakat\""),
            &["malformed URDF"],
        ),
        (
            "missing-link",
            good.replace("<child link=\"saka\"/>", "<child link=\"wrist\"/>"),
            &["joint 'saka'", "child link 'wrist' does not exist"],
        ),
        (
            "loop",
            good.replace(
                "</robot>",
                r#"<joint name="back" type="fixed"><parent link="saka"/><child link="lakat"/></joint></robot>"#,
            ),
            &["joint 'back'", "loop"],
        ),
        (
            "negative-mass",
            good.replace(lakat_mass, r#"<mass value="-1.27"/>"#),
            &["link 'lakat' <inertial>", "negative"],
        ),
        (
            "zero-mass",
            good.replace(lakat_mass, r#"<mass value="0"/>"#),
            &["link 'lakat'", "mass"],
        ),
        (
            "triangle",
            good.replace("izz=\"0.00512549454697952\"", "izz=\"0.0512549454697952\""),
            &["link 'lakat' <inertial>", "triangle inequality"],
        ),
        (
            "nan",
            good.replace("<origin xyz=\"0.32 0 0\"", "<origin xyz=\"0.32 NaN 0\""),
            &["joint 'lakat'", "origin", "non-finite"],
        ),
        ("empty", String::new(), &["empty"]),
    ];
    for (name, text, parts) in variants {
        assert_ne!(text, good, "test setup: {name} changed nothing");
        let file = format!("{name}.urdf");
        std::fs::write(dir.join(&file), text).unwrap();
        let mut expected = vec![file.as_str()];
        expected.extend_from_slice(parts);
        for command in [vec!["wave"], vec!["shape", "--shape", "circle"]] {
            let mut args = command.clone();
            args.extend(["--urdf", &file, "--summary", "s.json"]);
            refuses(&dir, &args, &expected);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `faze4 shape` writes the joint samples `faze4 replay` plays, and refuses bad shape input.
#[test]
fn shape_saves_samples_replay_plays_and_refuses_bad_input() {
    let dir = temp_dir("shape");
    let run = faze4(
        &dir,
        &[
            "shape",
            "--shape",
            "circle",
            "--shape-points",
            "60",
            "--duration",
            "1",
            "--save-q",
            "q.npy",
            "--summary",
            "s.json",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(run.stdout.contains("path deviation (mm)") && run.stdout.contains("joint samples -> q.npy"));
    let s = summary(&dir, "s.json");
    assert!(s["path_deviation_mm"]["max"].as_f64().unwrap() > 0.0);
    assert!(s["ik_max_residual_m"].as_f64().unwrap() < 1e-6);
    let q = faze4::traj::npy::read_samples(&dir.join("q.npy")).unwrap();
    assert_eq!((q.len(), q[0].len()), (60, 6));
    let replay = faze4(
        &dir,
        &["replay", "--q-traj", "q.npy", "--duration", "1", "--trail", "none"],
    );
    assert!(replay.status.success(), "{}", replay.stderr);
    for f in ["q.npy", "s.json", "faze4_trail.csv"] {
        std::fs::remove_file(dir.join(f)).unwrap();
    }

    refuses(
        &dir,
        &["shape", "--shape", "star"],
        &["invalid value 'star'", "--shape"],
    );
    refuses(&dir, &["shape"], &["--shape"]);
    refuses(
        &dir,
        &["shape", "--shape", "tri", "--shape-points", "0"],
        &["--shape-points", "at least 3"],
    );
    refuses(
        &dir,
        &["shape", "--shape", "tri", "--shape-points", "-5"],
        &["--shape-points"],
    );
    refuses(
        &dir,
        &["shape", "--shape", "tri", "--duration", "0"],
        &["--duration", "must be > 0"],
    );
    // the base cannot reach the board: the first sample is named with its target and distance
    refuses(
        &dir,
        &[
            "shape",
            "--shape",
            "circle",
            "--tool-link",
            "rotary_base",
            "--save-q",
            "q.npy",
        ],
        &[
            "IK sample 0 of 240",
            "(0.240000, -0.480000, 0.550000)",
            "rotary_base",
            "closest distance",
        ],
    );
    refuses(
        &dir,
        &["shape", "--shape", "sine", "--save-q", "no/such/dir/q.npy"],
        &["no/such/dir/q.npy"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The visual outputs' bad input: a port in use, an unwritable HTML or plot path, a plot
/// format that is not SVG or PNG. All refused before the run, nothing written.
#[test]
fn bad_view_options_are_refused_before_the_run() {
    let dir = temp_dir("bad-view");
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    refuses(
        &dir,
        &["wave", "--view", "--port", &port, "--summary", "s.json"],
        &["--port", &port, "already in use"],
    );
    refuses(
        &dir,
        &["shape", "--shape", "tri", "--hold", "--port", &port],
        &["--port", "already in use"],
    );
    refuses(&dir, &["wave", "--port", "70000"], &["--port", "70000"]);
    refuses(
        &dir,
        &["wave", "--html", "no/such/dir/a.html"],
        &["--html", "no/such/dir"],
    );
    refuses(
        &dir,
        &["wave", "--plot", "no/such/dir/a.svg"],
        &["--plot", "no/such/dir"],
    );
    refuses(&dir, &["wave", "--plot", "a.pdf"], &["--plot", "a.pdf", ".svg or .png"]);
    drop(taken);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--html`, `--plot` and `--html none` from the real binary (the browser tests open them).
#[test]
fn html_and_plot_are_written_whole() {
    let dir = temp_dir("html-plot");
    let run = faze4(
        &dir,
        &[
            "shape",
            "--shape",
            "tri",
            "--duration",
            "2",
            "--html",
            "t.html",
            "--plot",
            "t.svg",
            "--trail",
            "none",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(run.stdout.contains("html -> t.html") && run.stdout.contains("plot -> t.svg"));
    let html = std::fs::read_to_string(dir.join("t.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "nothing fetched from the network"
    );
    let svg = std::fs::read_to_string(dir.join("t.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("reference path"));
    let none = faze4(
        &dir,
        &["wave", "--duration", "0.1", "--html", "none", "--trail", "none"],
    );
    assert!(none.status.success(), "{}", none.stderr);
    let files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(files.len(), 2, "--html none writes nothing: {files:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Under `--hold` the verdict stays the last line a terminal shows (stdout and stderr on one
/// pipe, as a terminal has them): the line saying the view is served comes before the result
/// lines, nothing after the verdict while the view is served, nor once Ctrl-C ends the serving.
#[test]
fn the_verdict_is_the_last_line_under_hold() {
    use std::io::BufRead;
    let dir = temp_dir("hold-last-line");
    let (reader, writer) = std::io::pipe().unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args([
            "wave",
            "--duration",
            "0.2",
            "--hold",
            "--port",
            "0",
            "--no-collisions",
            "--trail",
            "none",
        ])
        .current_dir(&dir)
        .stdout(writer.try_clone().unwrap())
        .stderr(writer)
        .spawn()
        .expect("run faze4");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(reader).lines() {
            tx.send(line.unwrap()).unwrap();
        }
    });
    let timeout = std::time::Duration::from_secs(60);
    let mut lines = Vec::new();
    while !lines.last().is_some_and(|l: &String| l.starts_with("verdict: ")) {
        lines.push(rx.recv_timeout(timeout).expect("a verdict line"));
    }
    // served: nothing more comes while it holds
    let later = rx.recv_timeout(std::time::Duration::from_millis(800));
    assert!(later.is_err(), "a line after the verdict while holding: {later:?}");
    assert!(child.try_wait().unwrap().is_none(), "the view should still be served");
    send(child.id(), libc::SIGINT);
    let status = child.wait().unwrap();
    lines.extend(rx.iter());
    assert_eq!(status.code(), Some(0), "{lines:#?}");
    assert!(lines.last().unwrap().starts_with("verdict: follows"), "{lines:#?}");
    let serving =
        (lines.iter()).position(|l| l.starts_with("viz: serving http://127.0.0.1:") && l.ends_with("until Ctrl-C"));
    assert!(
        serving.is_some_and(|k| k < lines.len() - 1),
        "the serving line before the verdict: {lines:#?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The self-clearance line's bound on the true minimum: a pair apart gets `(true minimum ≥ …
/// mm)`, never below zero; an intersecting pair (the exact meshes' 0.00 mm, the hulls' negative
/// signed distance) reads `(intersecting)`, not a negative bound.
#[test]
fn an_intersecting_pair_reads_intersecting_not_a_negative_bound() {
    let dir = temp_dir("clearance-bound");
    let line = |args: &[&str]| {
        let run = faze4(&dir, &[args, &["--duration", "1", "--trail", "none"]].concat());
        assert!(run.status.success(), "{args:?}: {}", run.stderr);
        let line = (run.stdout.lines())
            .find(|l| l.starts_with("self-clearance ("))
            .unwrap_or_else(|| panic!("{args:?}: no self-clearance line in {}", run.stdout))
            .to_string();
        assert!(!line.contains("≥ -"), "a negative bound: {line}");
        line
    };
    let apart = line(&["wave"]);
    assert!(
        apart.contains(" s (true minimum ≥ ") && !apart.contains("intersecting"),
        "{apart}"
    );
    // the payload folds the arm into itself: the exact meshes cross (0.00 mm)
    let meshes = line(&["shape", "--shape", "circle", "--payload-kg", "5"]);
    assert!(
        meshes.contains(" 0.00 mm at t = ") && meshes.contains(" s (intersecting) · intersecting: "),
        "{meshes}"
    );
    // the hulls overlap from the start (a negative signed distance)
    let hulls = line(&["shape", "--shape", "circle", "--collision-geometry", "hull"]);
    assert!(
        hulls.contains(" -3.") && hulls.contains(" s (intersecting) · intersecting: "),
        "{hulls}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `faze4 completions bash` is a script bash loads, and it completes the options the run
/// commands declare; `faze4 man` is a roff page naming every command; an unknown shell is
/// refused naming the ones there are.
#[test]
fn completions_and_man_page() {
    let dir = temp_dir("completions");
    let script = faze4(&dir, &["completions", "bash"]);
    assert!(script.status.success(), "{}", script.stderr);
    std::fs::write(dir.join("faze4.bash"), &script.stdout).unwrap();
    // bash's completion as a user's shell runs it: the words typed so far, then the function
    // with the command, the word being completed and the one before it
    let complete = |words: &str| {
        let out = std::process::Command::new("bash")
            .arg("-c")
            .arg(format!(
                "source ./faze4.bash; COMP_WORDS=({words}); COMP_CWORD=$((${{#COMP_WORDS[@]}} - 1)); \
                 COMP_LINE=\"${{COMP_WORDS[*]}}\"; COMP_POINT=${{#COMP_LINE}}; _faze4 faze4 \"${{COMP_WORDS[COMP_CWORD]}}\" \"${{COMP_WORDS[COMP_CWORD-1]}}\"; printf '%s\\n' \"${{COMPREPLY[@]}}\""
            ))
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    let commands = complete("faze4 ''");
    for command in ["wave", "replay", "shape", "retime", "sweep", "completions", "man"] {
        assert!(
            commands.lines().any(|l| l == command),
            "{command} not completed: {commands}"
        );
    }
    let options = complete("faze4 shape --pay");
    assert_eq!(options.trim(), "--payload-kg", "{options}");
    let shapes = complete("faze4 shape --shape ''");
    assert_eq!(shapes.split_whitespace().collect::<Vec<_>>(), ["sine", "circle", "tri"]);
    for shell in ["zsh", "fish", "elvish", "powershell"] {
        let run = faze4(&dir, &["completions", shell]);
        assert!(
            run.status.success() && run.stdout.contains("payload-kg"),
            "{shell}: {}",
            run.stderr
        );
    }
    let empty = temp_dir("completions-refused");
    refuses(&empty, &["completions", "tcsh"], &["tcsh", "bash", "zsh"]);
    std::fs::remove_dir_all(&empty).unwrap();

    let man = faze4(&dir, &["man"]);
    assert!(man.status.success(), "{}", man.stderr);
    assert!(
        man.stdout.starts_with(".ie") || man.stdout.contains(".TH faze4 1"),
        "{}",
        &man.stdout[..200]
    );
    for command in ["wave", "replay", "shape", "retime", "sweep"] {
        assert!(
            man.stdout.contains(&format!("faze4\\-{command}")),
            "the man page does not name {command}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A file given without its flag gets a hint naming the flag; the line stays one line.
#[test]
fn a_path_without_its_flag_names_the_flag() {
    let dir = temp_dir("path-hint");
    refuses(
        &dir,
        &["replay", "circle.npy"],
        &["'circle.npy'", "did you mean '--q-traj circle.npy'"],
    );
    refuses(
        &dir,
        &["retime", "plan.yaml", "--out", "t.yaml"],
        &["did you mean '--q-traj plan.yaml'"],
    );
    refuses(&dir, &["wave", "arm.urdf"], &["did you mean '--robot arm.urdf'"]);
    refuses(
        &dir,
        &["wave", "ur.urdf.xacro"],
        &["did you mean '--robot ur.urdf.xacro'"],
    );
    refuses(
        &dir,
        &["shape", "--shape", "circle", "motors.toml"],
        &["did you mean '--motors motors.toml'"],
    );
    // a word that is no path, or a path no flag of the command reads, gets no guess
    let run = faze4(&dir, &["wave", "circle.npy"]);
    assert_eq!(run.status.code(), Some(2));
    assert!(!run.stderr.contains("did you mean"), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `faze4 list motors|drives|robots` prints every preset, drive and robot format from where
/// each is defined: a preset's sources and a row per joint with its motor's ratio, torque and
/// speed as the library gives them; each drive's word and sentence; each format `--robot`
/// reads. An unknown list is refused naming the choices.
#[test]
fn list_prints_presets_drives_and_robots_from_their_definitions() {
    use faze4::choice::Choice;
    let dir = temp_dir("list");
    let motors = faze4(&dir, &["list", "motors"]);
    assert!(motors.status.success(), "{}", motors.stderr);
    let lines: Vec<&str> = motors.stdout.lines().collect();
    for preset in faze4::config::PRESET_SETS {
        let at = (lines
            .iter()
            .position(|l| *l == format!("{}: {}", preset.name, preset.sources)))
        .unwrap_or_else(|| panic!("{}'s line in {}", preset.name, motors.stdout));
        let set = (preset.motors)(None);
        for (k, m) in set.iter().enumerate() {
            let m = m.as_ref().unwrap();
            let ratio = m.gear_ratio.unwrap();
            let row = lines[at + 1 + k];
            let joint = if preset.every_joint {
                "every joint".to_string()
            } else {
                format!("J{}", k + 1)
            };
            assert!(
                row.starts_with(&format!("  {joint:<11} {} · ratio {ratio} · ", m.motor.label)),
                "{row}"
            );
            let torque = format!("up to {:.2} N·m", m.motor.joint_limit(ratio));
            let speed = format!("torque to {:.2} rad/s", m.motor.envelope.top_speed() / ratio);
            assert!(row.contains(&torque) && row.contains(&speed), "{row}");
        }
    }
    // the faze4 preset's J2: 0.45 N·m / √2 at 2.0 A (its rated current) through 27:1
    let j2 = lines
        .iter()
        .find(|l| l.starts_with("  J2          17HS16-2004S1, 2.0 A, 24 V"))
        .unwrap();
    assert!(
        j2.contains(&format!("up to {:.2} N·m", 0.45 / 2f64.sqrt() * 27.0)),
        "{j2}"
    );
    let drives = faze4(&dir, &["list", "drives"]);
    assert!(drives.status.success(), "{}", drives.stderr);
    assert_eq!(drives.stdout.lines().count(), faze4::config::DriveMode::WORDS.len());
    for (drive, line) in faze4::config::DriveMode::VALUES.iter().zip(drives.stdout.lines()) {
        assert_eq!(line, format!("{:<8} {}", drive.word(), drive.about()));
    }
    let robots = faze4(&dir, &["list", "robots"]);
    assert!(robots.status.success(), "{}", robots.stderr);
    assert!(
        robots
            .stdout
            .starts_with("faze4 (the default, built in: urdf/faze4_arm.urdf): 6 joints")
    );
    for format in faze4::model::RobotFormat::ALL {
        let line = format!("  {:<6} {}", format.name(), format.told_by());
        assert!(robots.stdout.lines().any(|l| l == line), "{line}: {}", robots.stdout);
    }
    let wrong = faze4(&dir, &["list", "servos"]);
    assert_eq!(wrong.status.code(), Some(2));
    assert!(
        wrong.stderr.contains("robots") && wrong.stderr.contains("motors"),
        "{}",
        wrong.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
