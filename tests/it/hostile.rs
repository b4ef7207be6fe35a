//! No input can hurt the user (issue 35), through the real binary: an output never replaces an
//! input; every file read whole has a cap, checked before memory is taken, and streams are
//! read up to it; a mesh's claims are checked against what it holds; a model's size is capped;
//! mesh references stay in their package; names from a file cannot forge a line of output;
//! messages name the cause; a bag's messages are bounded as they are decoded; a signal stops a
//! parse; a full stderr or a closed stdout is no panic; an output path cannot forge a line; a
//! FIFO with no writer is not waited for for ever; YAML nesting and the values of text
//! trajectories are counted before they cost time or memory; a file's misspelled field, its
//! own span and its field names are said as the file has them (issue 49); an option both varied
//! and given, a plan's multi-DOF part, a dataset's paths and version, an unknown xacro argument,
//! a stream going back in time, a step angle no motor has (issue 49, fourth round). Each case checks the exit status,
//! the one line on stderr, and the directory before and after.

use crate::common;

use std::os::unix::fs::{PermissionsExt, symlink};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;

/// A directory holding the mesh test arm (`arm.urdf`, its meshes in the package `mesh_arms`
/// under `pkg/`), a motors file for its three joints and a replay for them.
fn arm_dir(name: &str) -> PathBuf {
    let dir = temp_dir(name);
    let meshes = dir.join("pkg/mesh_arms/meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    for entry in std::fs::read_dir(repo_path("tests/urdf/mesh_arms/meshes")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, meshes.join(path.file_name().unwrap())).unwrap();
    }
    std::fs::copy(repo_path("tests/urdf/mesh_arm_stl.urdf"), dir.join("arm.urdf")).unwrap();
    let motor = "[[joint]]\nkind = \"dc\"\nstall_torque = 0.25\nno_load_speed = 250.0\ngear_ratio = 100.0\n";
    std::fs::write(dir.join("motors.toml"), motor.repeat(3)).unwrap();
    faze4::traj::npy::write_samples(&dir.join("q.npy"), &[vec![0.0, 0.1, 0.2], vec![0.1, 0.2, 0.3]]).unwrap();
    dir
}

/// `faze4 wave` on the mesh arm, short and quiet, with `extra`.
fn arm_wave<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "wave",
        "--urdf",
        "arm.urdf",
        "--package-path",
        "pkg",
        "--duration",
        "0.2",
        "-q",
    ];
    args.extend_from_slice(extra);
    args
}

/// [`arm_wave`] not quiet: the banner and the line saying what was written are printed.
fn arm_wave_told<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    arm_wave(extra).into_iter().filter(|a| *a != "-q").collect()
}

#[test]
fn an_output_never_replaces_an_input() {
    let dir = arm_dir("hostile-inputs");
    // other names for the URDF: a link, a hard link (as outputs need .svg / .csv names)
    symlink("arm.urdf", dir.join("urdf.svg")).unwrap();
    std::fs::hard_link(dir.join("arm.urdf"), dir.join("hard.csv")).unwrap();
    symlink("arm.urdf", dir.join("urdf.csv")).unwrap();
    let mesh = "pkg/mesh_arms/meshes/base.stl";
    let cases: &[(Vec<&str>, &[&str])] = &[
        (
            arm_wave(&["--trail", "arm.urdf"]),
            &["--trail", "arm.urdf is the --robot input"],
        ),
        (
            arm_wave(&["--summary", mesh]),
            &["--summary", "is the mesh of link 'base'"],
        ),
        (
            arm_wave(&["--motors", "motors.toml", "--html", "motors.toml"]),
            &["--html", "the --motors input"],
        ),
        (
            arm_wave(&["--plot", "urdf.svg"]),
            &["--plot", "urdf.svg is the --robot input (arm.urdf)"],
        ),
        (
            arm_wave(&["--trail", "hard.csv"]),
            &["--trail", "hard.csv is the --robot input"],
        ),
        (
            vec![
                "replay",
                "--urdf",
                "arm.urdf",
                "--package-path",
                "pkg",
                "--q-traj",
                "q.npy",
                "--duration",
                "0.2",
                "-q",
                "--trail",
                "q.npy",
            ],
            &["--trail", "the --q-traj input"],
        ),
        (
            vec![
                "sweep",
                "--vary",
                "dt=1e-4,2e-4",
                "-q",
                "--out",
                "urdf.csv",
                "--",
                "wave",
                "--urdf",
                "arm.urdf",
                "--package-path",
                "pkg",
                "--duration",
                "0.1",
            ],
            &["--out", "urdf.csv is the --robot input"],
        ),
    ];
    for (args, parts) in cases {
        fails_leaving_all_as_was(&dir, args, parts);
    }
    // retime's path is an input too: its timing, summary or figure replaced it, exit 0
    std::fs::write(dir.join("path.csv"), "t,j1,j2,j3\n0,0,0,0\n1,0.3,0.2,0.1\n2,0,0,0\n").unwrap();
    let retime = |extra: &[&'static str]| {
        let base = [
            "retime",
            "--urdf",
            "arm.urdf",
            "--package-path",
            "pkg",
            "--q-traj",
            "path.csv",
            "-q",
        ];
        [&base[..], extra].concat()
    };
    for (extra, field) in [
        (&["--out", "path.csv"][..], "--out"),
        (&["--out", "t.yaml", "--summary", "path.csv"][..], "--summary"),
        (&["--out", "t.yaml", "--plot", "path.csv"][..], "--plot"),
    ] {
        fails_leaving_all_as_was(&dir, &retime(extra), &[field, "path.csv is the --q-traj input"]);
    }
    // the parts of a merge and their metadata
    two_parts(&dir);
    let merge = |out: &'static str| vec!["sweep", "merge", "p1.csv", "p2.csv", "--out", out];
    fails_leaving_all_as_was(&dir, &merge("p1.csv"), &["--out", "p1.csv is a part being merged"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_replaced_file_keeps_its_mode_and_a_255_byte_name_is_written() {
    let dir = arm_dir("hostile-manners");
    std::fs::write(dir.join("t.csv"), "old\n").unwrap();
    std::fs::set_permissions(dir.join("t.csv"), std::fs::Permissions::from_mode(0o600)).unwrap();
    // the longest name Linux takes: its temporary (.NAME.PID.tmp) must still fit
    let long = format!("{}.json", "s".repeat(250));
    let run = faze4(&dir, &arm_wave(&["--trail", "t.csv", "--summary", &long]));
    assert!(run.status.success(), "{}", run.stderr);
    let mode = std::fs::metadata(dir.join("t.csv")).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o600, "the trail's mode {mode:o}");
    assert!(std::fs::read_to_string(dir.join("t.csv")).unwrap().starts_with("t,"));
    assert!(summary(&dir, &long)["verdict"].is_object());
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The names in `dir` that look like temporaries.
fn temporaries(dir: &Path) -> Vec<String> {
    snapshot(dir)
        .into_keys()
        .filter(|n| n.ends_with(".tmp") || n.ends_with(".bak"))
        .collect()
}

/// A SIGTERM that comes once the run is over, while its files are written (here the summary,
/// a FIFO nobody reads yet), does not end in status 0: the files are completed and the status
/// is 143.
#[test]
fn sigterm_during_the_final_writes_is_not_success() {
    let dir = arm_dir("hostile-sigterm");
    let fifo = dir.join("s.json");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let child = Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(arm_wave(&["--summary", "s.json", "--trail", "t.csv"]))
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // the run (0.2 s of a 3-joint arm) is over long before this; the summary waits for a reader
    std::thread::sleep(Duration::from_secs(3));
    send(child.id(), libc::SIGTERM);
    std::thread::sleep(Duration::from_millis(200));
    let summary = std::fs::read_to_string(&fifo).unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(143), "{stderr}");
    assert!(
        stderr.contains("stopped by SIGTERM after the run; its outputs are complete"),
        "{stderr}"
    );
    assert!(summary.contains("\"verdict\""), "{summary}");
    assert!(std::fs::read_to_string(dir.join("t.csv")).unwrap().starts_with("t,"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn files_read_whole_are_capped_and_streams_read_up_to_the_cap() {
    let dir = arm_dir("hostile-caps");
    // a sparse 2 GiB file takes no disk; it lives outside the directory compared before and after
    let big = temp_dir("hostile-caps-big").join("big.npy");
    std::fs::File::create(&big).unwrap().set_len(2 << 30).unwrap();
    let big = big.display().to_string();
    std::fs::write(dir.join("huge.toml"), vec![b'#'; 2 << 20]).unwrap();
    let far = [vec![1e308, 0.0, 0.0], vec![0.0; 3]];
    faze4::traj::npy::write_samples(&dir.join("far.npy"), &far).unwrap();
    symlink("/dev/zero", dir.join("zero.toml")).unwrap();
    symlink("/dev/zero", dir.join("zero.npy")).unwrap();
    let replay = |q: &'static str| -> Vec<&'static str> {
        vec![
            "replay",
            "--urdf",
            "arm.urdf",
            "--package-path",
            "pkg",
            "--q-traj",
            q,
            "--duration",
            "0.1",
            "-q",
        ]
    };
    let big_replay: Vec<&str> = replay("X")
        .into_iter()
        .map(|w| if w == "X" { big.as_str() } else { w })
        .collect();
    let cases: Vec<(Vec<&str>, &[&str])> = vec![
        (
            replay("zero.npy"),
            &["zero.npy: a stream of more than the 256 MiB an .npy trajectory may hold"],
        ),
        // a stream of no format faze4 reads, and no extension: refused from its first bytes
        (
            replay("/dev/zero"),
            &["/dev/zero: not a trajectory faze4 reads", "it starts with \\x00\\x00"],
        ),
        (
            big_replay,
            &["big.npy: 2 GiB (2147483648 bytes), more than the 256 MiB"],
        ),
        (
            arm_wave(&["--motors", "huge.toml"]),
            &[
                "--motors",
                "huge.toml: 2 MiB",
                "more than the 1 MiB a motors file may hold",
            ],
        ),
        (
            arm_wave(&["--motors", "zero.toml"]),
            &["--motors", "zero.toml: a stream of more than the 1 MiB"],
        ),
        (
            vec!["wave", "--urdf", "/dev/zero", "-q"],
            &["/dev/zero: a stream of more than the 16 MiB a URDF may hold"],
        ),
        // a value of 1e308 is said in its shortest digits, not 309 of them
        (
            replay("far.npy"),
            &["far.npy: frame 0: joint J1 (j1) is commanded to 1e308 rad, beyond its limits [-3, 3]"],
        ),
    ];
    for (args, parts) in &cases {
        fails_leaving_all_as_was(&dir, args, parts);
    }
    // a stream that is shorter than its cap is read: a replay through a FIFO
    let fifo = dir.join("fifo.npy");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let bytes = std::fs::read(dir.join("q.npy")).unwrap();
    let writer = std::thread::spawn(move || std::fs::write(fifo, bytes).unwrap());
    let run = faze4(&dir, &replay("fifo.npy"));
    writer.join().unwrap();
    assert!(run.status.success(), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(Path::new(&big).parent().unwrap()).unwrap();
}

/// The two parts `p1.csv` and `p2.csv` (with their `.meta`) of a small sweep, in `dir`.
fn two_parts(dir: &Path) {
    for k in 1..=2 {
        let (part, shard) = (format!("p{k}.csv"), format!("{k}/2"));
        let run = faze4(
            dir,
            &[
                "sweep",
                "--vary",
                "dt=1e-4,2e-4",
                "-q",
                "--shard",
                &shard,
                "--out",
                &part,
                "--",
                "wave",
                "--duration",
                "0.05",
                "--no-collisions",
            ],
        );
        assert!(run.status.success(), "{}", run.stderr);
    }
}

#[test]
fn a_merge_reads_only_regular_parts_and_metadata() {
    let dir = temp_dir("hostile-merge");
    two_parts(&dir);
    std::fs::rename(dir.join("p2.csv.meta"), dir.join("kept.meta")).unwrap();
    symlink("/dev/zero", dir.join("p2.csv.meta")).unwrap();
    let merge = ["sweep", "merge", "p1.csv", "p2.csv", "--out", "all.csv"];
    fails_leaving_all_as_was(
        &dir,
        &merge,
        &["p2.csv.meta: is a character device, not a sweep part's metadata"],
    );
    std::fs::remove_file(dir.join("p2.csv.meta")).unwrap();
    std::fs::rename(dir.join("kept.meta"), dir.join("p2.csv.meta")).unwrap();
    std::fs::rename(dir.join("p2.csv"), dir.join("kept.csv")).unwrap();
    assert!(
        Command::new("mkfifo")
            .arg(dir.join("p2.csv"))
            .status()
            .unwrap()
            .success()
    );
    fails_leaving_all_as_was(&dir, &merge, &["p2.csv: is a FIFO, not a sweep part's table"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A chain of `n` links of the joint kind `kind`.
fn chain(n: usize, kind: &str) -> String {
    let inertial = r#"<inertial><mass value="0.01"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>"#;
    let mut text = format!("<robot name=\"chain\"><link name=\"l0\">{inertial}</link>\n");
    for i in 1..n {
        text += &format!(
            "<joint name=\"j{i}\" type=\"{kind}\"><parent link=\"l{}\"/><child link=\"l{i}\"/><origin xyz=\"0 0 0.01\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" upper=\"3\" effort=\"30\" velocity=\"3\"/></joint><link name=\"l{i}\">{inertial}</link>\n",
            i - 1
        );
    }
    text + "</robot>\n"
}

#[test]
fn models_beyond_their_caps_are_refused_clearly() {
    let dir = temp_dir("hostile-model-caps");
    std::fs::write(dir.join("links.urdf"), chain(10_000, "fixed")).unwrap();
    std::fs::write(dir.join("chain.urdf"), chain(1_000, "revolute")).unwrap();
    let start = std::time::Instant::now();
    fails_leaving_all_as_was(
        &dir,
        &["wave", "--urdf", "links.urdf", "-q"],
        &["links.urdf: <robot>: has 10000 <link> elements, more than the 4096 faze4 reads"],
    );
    fails_leaving_all_as_was(
        &dir,
        &["wave", "--urdf", "chain.urdf", "-q"],
        &["chain.urdf: robot 'chain': has 999 moving joints, more than the 256 faze4 simulates"],
    );
    // refused from their size, not after building them (a 1,000-link chain ran 107 s)
    assert!(start.elapsed() < Duration::from_secs(20), "{:?}", start.elapsed());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A short quiet wave of `m.urdf` (a [`mesh_arm`]) writing no trail.
const MESH_ARM_WAVE: [&str; 8] = [
    "wave",
    "--urdf",
    "m.urdf",
    "--duration",
    "0.05",
    "-q",
    "--trail",
    "none",
];

/// A three-link arm whose links' visual and collision geometry is `mesh` (scaled by `scale`).
fn mesh_arm(mesh: &str, scale: &str) -> String {
    let inertial =
        r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;
    let geometry = format!("<geometry><mesh filename=\"{mesh}\" scale=\"{scale}\"/></geometry>");
    let link = |name: &str| {
        format!("<link name=\"{name}\">{inertial}<visual>{geometry}</visual><collision>{geometry}</collision></link>")
    };
    let joint = |name: &str, parent: &str, child: &str| {
        format!(
            "<joint name=\"{name}\" type=\"revolute\"><parent link=\"{parent}\"/><child link=\"{child}\"/><origin xyz=\"0 0 0.5\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" upper=\"3\" effort=\"30\" velocity=\"3\"/></joint>"
        )
    };
    format!(
        "<robot name=\"r\">{}{}{}{}{}</robot>\n",
        link("base"),
        joint("j1", "base", "a"),
        link("a"),
        joint("j2", "a", "b"),
        link("b")
    )
}

/// A binary STL of `triangles` whose header says `claimed`.
fn stl(triangles: u32, claimed: u32) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend(claimed.to_le_bytes());
    for t in 0..triangles {
        let z = t as f32 * 0.01;
        bytes.extend([0u8; 12]);
        for p in [[0.0, 0.0, z], [0.1, 0.0, z], [0.0, 0.1, z + 0.05]] {
            for c in p {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

#[test]
fn mesh_files_are_checked_against_what_they_claim() {
    let dir = temp_dir("hostile-meshes");
    let seed = std::fs::read_to_string(repo_path("fuzz/seeds/dae_mesh/box.dae")).unwrap();
    let at = seed.find("<triangles").unwrap();
    let count = at + seed[at..].find("count=\"").unwrap() + 7;
    let end = count + seed[count..].find('"').unwrap();
    std::fs::write(
        dir.join("bomb.dae"),
        format!("{}4000000000{}", &seed[..count], &seed[end..]),
    )
    .unwrap();
    let n = 100_000;
    let deep = format!(
        "<COLLADA><library_visual_scenes><visual_scene>{}{}</visual_scene></library_visual_scenes></COLLADA>",
        "<node>".repeat(n),
        "</node>".repeat(n)
    );
    std::fs::write(dir.join("deep.dae"), deep).unwrap();
    std::fs::write(dir.join("short.stl"), stl(12, 17)).unwrap();
    let mut two = stl(12, 12);
    two.extend_from_slice(&stl(12, 12)[84..]);
    std::fs::write(dir.join("two.stl"), two).unwrap();
    std::fs::write(dir.join("good.stl"), stl(12, 12)).unwrap();
    std::fs::write(dir.join("far.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -99999\n").unwrap();
    std::fs::write(dir.join("notes.txt"), "hello\n").unwrap();
    std::fs::create_dir(dir.join("folder.stl")).unwrap();
    assert!(
        Command::new("mkfifo")
            .arg(dir.join("pipe.stl"))
            .status()
            .unwrap()
            .success()
    );
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "bomb.dae",
            "1 1 1",
            &[
                "bomb.dae: COLLADA line",
                "<triangles> claims 12000000000 indices",
                "its <p> holds 36",
            ],
        ),
        (
            "deep.dae",
            "1 1 1",
            &["deep.dae: COLLADA: elements nest more than 256 deep"],
        ),
        (
            "short.stl",
            "1 1 1",
            &["short.stl: binary STL: its header says 17 triangles (934 bytes), the file has 684 bytes"],
        ),
        (
            "two.stl",
            "1 1 1",
            &[
                "two.stl: binary STL: its header says 12 triangles",
                "1284 bytes (24 triangles' worth)",
            ],
        ),
        (
            "far.obj",
            "1 1 1",
            &["far.obj: OBJ line 4: a face refers to vertex -99999, with 3 vertices before it"],
        ),
        (
            "notes.txt",
            "1 1 1",
            &[
                "notes.txt: not a mesh faze4 reads",
                "its contents are neither STL nor COLLADA",
            ],
        ),
        ("folder.stl", "1 1 1", &["folder.stl: is a directory, not a mesh file"]),
        ("pipe.stl", "1 1 1", &["pipe.stl: is a FIFO, not a mesh file"]),
        (
            "good.stl",
            "1e308 1e308 1e308",
            &[
                "good.stl: <mesh scale=\"1e308 1e308 1e308\">",
                "too large to compute its hull with",
            ],
        ),
    ];
    for (mesh, scale, parts) in cases {
        std::fs::write(dir.join("m.urdf"), mesh_arm(mesh, scale)).unwrap();
        fails_leaving_all_as_was(&dir, &MESH_ARM_WAVE, parts);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn mesh_references_stay_in_their_package() {
    let dir = arm_dir("hostile-package");
    let meshes = dir.join("pkg/mesh_arms/meshes");
    symlink(dir.join("arm.urdf"), meshes.join("out.stl")).unwrap();
    let urdf = std::fs::read_to_string(dir.join("arm.urdf")).unwrap();
    let cases: &[(&str, &[&str])] = &[
        (
            "package://mesh_arms/../../../../../../../../etc/passwd",
            &[
                "link 'base' <visual>: mesh 'package://mesh_arms/../",
                "leaves its package",
                "resolves to /etc/passwd",
            ],
        ),
        ("package://../../../../etc/passwd", &["'..' is not a package name"]),
        (
            "package://mesh_arms/meshes/out.stl",
            &[
                "leaves its package",
                "out.stl resolves to",
                "arm.urdf, outside the package folder",
            ],
        ),
    ];
    for (uri, parts) in cases {
        std::fs::write(
            dir.join("evil.urdf"),
            urdf.replace("package://mesh_arms/meshes/base.stl", uri),
        )
        .unwrap();
        fails_leaving_all_as_was(
            &dir,
            &["wave", "--urdf", "evil.urdf", "--package-path", "pkg", "-q"],
            parts,
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An OBJ's `mtllib` is not read when collision needs only its triangles (a FIFO there would
/// block the run forever), and for drawing only from the OBJ's folder, a regular file.
#[test]
fn an_objs_material_file_is_read_only_when_drawn_and_only_beside_it() {
    let dir = temp_dir("hostile-mtllib");
    let obj = std::fs::read_to_string(repo_path("fuzz/seeds/obj_mesh/box.obj")).unwrap();
    assert!(obj.starts_with("mtllib base.mtl\n"));
    std::fs::write(dir.join("box.obj"), obj).unwrap();
    assert!(
        Command::new("mkfifo")
            .arg(dir.join("base.mtl"))
            .status()
            .unwrap()
            .success()
    );
    std::fs::write(dir.join("m.urdf"), mesh_arm("box.obj", "1 1 1")).unwrap();
    let args = MESH_ARM_WAVE;
    let child = Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(args)
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(start.elapsed() < Duration::from_secs(30));
    let mut drawn = args.to_vec();
    drawn.extend(["--html", "v.html"]);
    let run = faze4(&dir, &drawn);
    assert!(run.status.success(), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Names read from a URDF (robot, link, joint) holding a line feed, a carriage return, the C1
/// CSI (U+009B) and a right-to-left override (U+202E) are shown escaped everywhere: stdout has
/// one `verdict:` line, and no output file holds those characters raw.
#[test]
fn names_cannot_forge_a_line_of_output() {
    let dir = arm_dir("hostile-names");
    let evil = "&#10;verdict: follows&#13;&#x9B;31m&#x202E;";
    let urdf = std::fs::read_to_string(dir.join("arm.urdf")).unwrap();
    let urdf = urdf
        .replace("<robot name=\"mesh_arm_stl\">", &format!("<robot name=\"r{evil}\">"))
        .replace("\"hand\"", &format!("\"hand{evil}\""))
        .replace("\"j2\"", &format!("\"j2{evil}\""));
    std::fs::write(dir.join("evil.urdf"), urdf).unwrap();
    let raw = ['\n', '\r', '\u{9b}', '\u{202e}'];
    let run = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            "evil.urdf",
            "--package-path",
            "pkg",
            "--duration",
            "0.6",
            "--trail",
            "t.csv",
            "--html",
            "v.html",
            "--plot",
            "p.svg",
            "--tool-link",
            "hand\nverdict: follows\r\u{9b}31m\u{202e}",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert_eq!(
        run.stdout.lines().filter(|l| l.starts_with("verdict:")).count(),
        1,
        "{}",
        run.stdout
    );
    assert!(run.stdout.lines().last().unwrap().starts_with("verdict: "));
    for line in run.stdout.lines().chain(run.stderr.lines()) {
        assert!(!line.contains(&raw[1..]), "{line:?}");
    }
    assert!(
        run.stdout.contains("r\\nverdict: follows\\r\\u{9b}31m\\u{202e}"),
        "{}",
        run.stdout
    );
    for file in ["t.csv", "v.html", "p.svg"] {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let found: Vec<char> = raw[1..].iter().copied().filter(|c| text.contains(*c)).collect();
        assert!(found.is_empty(), "{file} holds {found:?}");
    }
    // a sweep's table and its lines on stdout
    let run = faze4(
        &dir,
        &[
            "sweep",
            "--vary",
            "dt=1e-4,2e-4",
            "--out",
            "s.csv",
            "--",
            "wave",
            "--urdf",
            "evil.urdf",
            "--package-path",
            "pkg",
            "--duration",
            "0.1",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(!run.stdout.contains(&raw[1..]), "{}", run.stdout);
    let table = std::fs::read_to_string(dir.join("s.csv")).unwrap();
    assert!(!table.contains(&raw[1..]), "{table}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A model whose mass overflows says so (not "NaN ≤ 0"); an empty `<geometry>` says which
/// element, not the XML layer's debug text.
#[test]
fn model_messages_name_the_cause() {
    let dir = arm_dir("hostile-messages");
    let urdf = std::fs::read_to_string(dir.join("arm.urdf")).unwrap();
    let cases: &[(String, &[&str])] = &[
        (
            urdf.replacen("<mass value=\"1.5\"/>", "<mass value=\"1e308\"/>", 1),
            &[
                "link 'upper' <inertial>: mass 1e308 kg",
                "overflows floating-point numbers",
            ],
        ),
        // a link 1e200 m long was blamed on "its masses, rotor inertia or gear ratio"
        (
            urdf.replacen("<origin xyz=\"0 0 0.3\"/>", "<origin xyz=\"0 0 1e200\"/>", 1),
            &[
                "its masses, lengths (joint and inertial origins), rotor inertia or gear ratio are too large to simulate",
            ],
        ),
        (
            urdf.replacen(
                "<collision><geometry><mesh filename=\"package://mesh_arms/meshes/upper.stl\"/></geometry></collision>",
                "<collision><geometry></geometry></collision>",
                1,
            ),
            &["link 'upper' <collision>: <geometry> is empty: give it a <box>, <cylinder>, <sphere> or <mesh>"],
        ),
    ];
    for (text, parts) in cases {
        assert_ne!(*text, urdf);
        std::fs::write(dir.join("bad.urdf"), text).unwrap();
        fails_leaving_all_as_was(
            &dir,
            &["wave", "--urdf", "bad.urdf", "--package-path", "pkg", "-q"],
            parts,
        );
        let run = faze4(&dir, &["wave", "--urdf", "bad.urdf", "--package-path", "pkg", "-q"]);
        assert!(
            !run.stderr.contains("NaN") && !run.stderr.contains("XmlEvent"),
            "{}",
            run.stderr
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An MCAP record: its opcode, its length (u64 LE), its body.
fn mcap_record(op: u8, body: &[u8]) -> Vec<u8> {
    let mut r = vec![op];
    r.extend((body.len() as u64).to_le_bytes());
    r.extend(body);
    r
}

/// An MCAP string: its length (u32 LE), its bytes.
fn mcap_string(s: &str) -> Vec<u8> {
    let mut r = (s.len() as u32).to_le_bytes().to_vec();
    r.extend(s.as_bytes());
    r
}

/// A rosbag2-like MCAP file with a `JointState` channel whose data section is `data` (records),
/// as the MCAP specification lays it out (https://mcap.dev/spec).
fn mcap_file(data: &[u8]) -> Vec<u8> {
    mcap_bag("sensor_msgs/msg/JointState", data)
}

/// A rosbag2-like MCAP file with one channel (1, on `/joint_states`) of type `kind` whose data
/// section is `data` (records).
fn mcap_bag(kind: &str, data: &[u8]) -> Vec<u8> {
    mcap_channels(&[kind], data)
}

/// A rosbag2-like MCAP file whose channels, all on `/joint_states`, have the types `kinds`
/// (channel and schema k + 1 the k-th), its data section `data` (records).
fn mcap_channels(kinds: &[&str], data: &[u8]) -> Vec<u8> {
    const MAGIC: &[u8] = b"\x89MCAP0\r\n";
    let mut f = MAGIC.to_vec();
    f.extend(mcap_record(
        0x01,
        &[mcap_string("ros2"), mcap_string("hostile")].concat(),
    ));
    for (k, kind) in kinds.iter().enumerate() {
        let id = (k as u16 + 1).to_le_bytes();
        let mut schema = id.to_vec();
        schema.extend(mcap_string(kind));
        schema.extend(mcap_string("ros2msg"));
        schema.extend(0u32.to_le_bytes());
        f.extend(mcap_record(0x03, &schema));
        let mut channel = [id, id].concat();
        channel.extend(mcap_string("/joint_states"));
        channel.extend(mcap_string("cdr"));
        channel.extend(0u32.to_le_bytes());
        f.extend(mcap_record(0x04, &channel));
    }
    f.extend(data);
    f.extend(mcap_record(0x0F, &0u32.to_le_bytes()));
    f.extend(mcap_record(
        0x02,
        &[0u64.to_le_bytes().as_slice(), &0u64.to_le_bytes(), &0u32.to_le_bytes()].concat(),
    ));
    f.extend(MAGIC);
    f
}

/// A zstd-compressed chunk holding `records` (one raw block of a zstd frame, RFC 8878), its
/// header claiming they are `uncompressed_size` bytes.
fn zstd_chunk(records: &[u8], uncompressed_size: u64) -> Vec<u8> {
    let mut frame = vec![0x28, 0xB5, 0x2F, 0xFD, 0x00, 0x10]; // magic, no size, 64 KiB window
    frame.extend(&(1 | (records.len() as u32) << 3).to_le_bytes()[..3]); // last, raw block
    frame.extend(records);
    let mut chunk = [0u64.to_le_bytes(), 0u64.to_le_bytes(), uncompressed_size.to_le_bytes()].concat();
    chunk.extend(0u32.to_le_bytes()); // no CRC
    chunk.extend(mcap_string("zstd"));
    chunk.extend((frame.len() as u64).to_le_bytes());
    chunk.extend(frame);
    mcap_record(0x06, &chunk)
}

/// A message record's head claiming `len` bytes of body, and a few of them.
fn message_claiming(len: u64) -> Vec<u8> {
    let mut r = vec![0x05];
    r.extend(len.to_le_bytes());
    r.extend(1u16.to_le_bytes()); // channel
    r.extend([0; 20]); // sequence, log and publish times
    r
}

#[test]
fn trajectory_files_are_capped_and_checked_before_they_are_built() {
    let dir = arm_dir("hostile-trajectories");
    let csv = "t,j1,j2,j3\n0,0,0.1,0.2\n1,0.1,0.2,0.3\n";
    std::fs::write(dir.join("t.csv"), csv).unwrap();
    symlink("/dev/zero", dir.join("zero.yaml")).unwrap();
    symlink("/dev/zero", dir.join("zero.mcap")).unwrap();
    // a sparse 1 GiB file takes no disk; it lives outside the directory compared before and after
    let big = temp_dir("hostile-trajectories-big").join("big.json");
    std::fs::File::create(&big).unwrap().set_len(1 << 30).unwrap();
    let big = big.display().to_string();
    let header: Vec<String> = (0..2000).map(|k| format!("j{k}")).collect();
    std::fs::write(dir.join("wide.csv"), format!("t,{}\n", header.join(","))).unwrap();
    let names: Vec<String> = (0..300).map(|k| format!("\"j{k}\"")).collect();
    let point = |t: f64| {
        format!(
            "{{\"positions\": [{}], \"time_from_start\": {t}}}",
            vec!["0"; 300].join(",")
        )
    };
    let many = format!(
        "{{\"joint_names\": [{}], \"points\": [{}, {}]}}",
        names.join(","),
        point(0.0),
        point(1.0)
    );
    std::fs::write(dir.join("many.json"), many).unwrap();
    // "billion laughs": nine levels of nine aliases, 387 million strings once expanded
    let mut laughs = String::from("a0: &a0 [\"lol\"]\n");
    for k in 1..10 {
        laughs += &format!("a{k}: &a{k} [{}]\n", vec![format!("*a{}", k - 1); 9].join(","));
    }
    laughs += "joint_names: *a9\n";
    std::fs::write(dir.join("laughs.yaml"), laughs).unwrap();
    // a compressed chunk whose message claims 1 TiB; a message outside chunks claiming 1 EiB
    let inside = zstd_chunk(&message_claiming(1 << 40), 1 << 40);
    std::fs::write(dir.join("inside.mcap"), mcap_file(&inside)).unwrap();
    std::fs::write(dir.join("outside.mcap"), mcap_file(&message_claiming(1 << 60))).unwrap();
    let replay = |q: &str| -> Vec<String> {
        [
            "replay",
            "--urdf",
            "arm.urdf",
            "--package-path",
            "pkg",
            "--q-traj",
            q,
            "--duration",
            "0.1",
            "-q",
        ]
        .map(String::from)
        .to_vec()
    };
    let cases: Vec<(Vec<String>, &[&str])> = vec![
        (
            replay("zero.yaml"),
            &["zero.yaml: a stream of more than the 16 MiB a YAML trajectory may hold"],
        ),
        (
            replay("zero.mcap"),
            &[
                "zero.mcap: not a bag (MCAP, rosbag2 SQLite, ROS 1 or one of them compressed with zstd): it starts with \\x00\\x00",
            ],
        ),
        (
            replay(&big),
            &["big.json: 1 GiB (1073741824 bytes), more than the 64 MiB"],
        ),
        (
            replay("wide.csv"),
            &["wide.csv: its header has 2001 columns; a model has at most 256 moving joints"],
        ),
        (replay("many.json"), &["many.json: names 300 joints"]),
        (
            replay("laughs.yaml"),
            &["laughs.yaml: document 1 is not YAML: repetition limit exceeded"],
        ),
        (replay("inside.mcap"), &["inside.mcap: not a readable MCAP file"]),
        (replay("outside.mcap"), &["outside.mcap: not a readable MCAP file"]),
        // the trajectory file is an input: no output replaces it
        (
            [replay("t.csv"), vec!["--trail".into(), "t.csv".into()]].concat(),
            &["--trail", "t.csv is the --q-traj input"],
        ),
    ];
    for (args, parts) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        fails_leaving_all_as_was(&dir, &args, parts);
    }
    // the readable file replays
    let run = faze4(&dir, &replay("t.csv").iter().map(String::as_str).collect::<Vec<_>>());
    assert!(run.status.success(), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(Path::new(&big).parent().unwrap()).unwrap();
}

#[test]
fn options_beyond_what_a_run_can_do_name_their_cause() {
    let dir = arm_dir("hostile-options");
    let cases: Vec<(Vec<&str>, &[&str])> = vec![
        (
            vec!["shape", "--shape", "circle", "--shape-points", "100000000", "-q"],
            &["--shape-points: 100000000 samples: at most 100000"],
        ),
        (
            vec!["shape", "--shape", "circle", "--shape-points", "4294967297", "-q"],
            &["--shape-points: 4294967297 samples: at most 100000"],
        ),
        // a grid of a billion intervals aborted on a 48 GB allocation
        (
            vec![
                "retime",
                "--urdf",
                "arm.urdf",
                "--package-path",
                "pkg",
                "--q-traj",
                "q.npy",
                "--out",
                "t.yaml",
                "--grid",
                "1000000000",
                "-q",
            ],
            &["--grid: 1000000000 intervals: at most 100000"],
        ),
        (
            vec!["wave", "--freq", "1e308", "-q"],
            &["--freq: 1e308 rad/s turns the wave more than half a period per step of --dt 0.0002 s"],
        ),
        (
            vec!["wave", "--dt", "1e-320", "-q"],
            &["--duration: 8 s at --dt 1e-320 s is more than the 10^12 steps a run may take"],
        ),
        (
            vec!["wave", "--amp-deg", "1e308", "-q"],
            &[
                "commanded to 1.5114994701951815e306 rad at t = 0 s",
                "(amplitude 1e308 deg)",
            ],
        ),
        (
            vec![
                "replay",
                "--urdf",
                "arm.urdf",
                "--package-path",
                "pkg",
                "--q-traj",
                "q.npy",
                "--traj-period",
                "1e-320",
                "-q",
            ],
            &["--traj-period: 1e-320 s is shorter than one step of --dt 0.0002 s"],
        ),
        // a sweep writes its runs' trails with --trails DIR: one --trail file would be dropped
        (
            vec![
                "sweep",
                "--vary",
                "dt=1e-4,2e-4",
                "-q",
                "--out",
                "s.csv",
                "--",
                "wave",
                "--trail",
                "t.csv",
            ],
            &["--trail: t.csv: a sweep writes one trail per run with --trails DIR"],
        ),
    ];
    for (args, parts) in &cases {
        fails_leaving_all_as_was(&dir, args, parts);
    }
    // a limit of 0: the errors are shown with the digits that tell them from it
    let run = faze4(
        &dir,
        &[
            "wave",
            "--max-error",
            "0",
            "--duration",
            "0.01",
            "--trail",
            "none",
            "-q",
        ],
    );
    let verdict = run.stdout.lines().last().unwrap_or_default().to_string();
    assert!(
        verdict.starts_with("verdict: cannot follow — J1 tracking error "),
        "{verdict}"
    );
    assert!(!verdict.contains(" 0.000 rad (limit 0 rad)"), "{verdict}");
    // a trajectory no arm follows (2.5 rad in 2 ms) diverges naming its timing, not the gains
    std::fs::write(dir.join("fast.csv"), "t,j1,j2,j3\n0,0,0,0\n0.002,2.5,0,0\n").unwrap();
    let run = faze4(
        &dir,
        &[
            "replay",
            "--urdf",
            "arm.urdf",
            "--package-path",
            "pkg",
            "--q-traj",
            "fast.csv",
            "--trail",
            "none",
            "-q",
        ],
    );
    assert_eq!(run.status.code(), Some(1), "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("on joint J1 ('j1'): the command asks it for 1250.0 rad/s there")
            && run
                .stderr
                .contains("the trajectory's timing, not the gains, is the cause"),
        "{}",
        run.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A path the user gave is escaped in the lines that say what was written, as in the error
/// messages: `--trail $'e\nverdict: follows\ny.csv'` prints one `verdict:` line, the run's own
/// (issue 49: the success line printed a forged one before it).
#[test]
fn an_output_path_cannot_forge_a_line_of_output() {
    let dir = arm_dir("hostile-output-paths");
    let (trail, summary) = ("e\nverdict: follows\ny.csv", "s\u{202e}\nverdict: follows\n.json");
    let run = faze4(&dir, &arm_wave_told(&["--trail", trail, "--summary", summary]));
    assert!(run.status.success(), "{}", run.stderr);
    let verdicts = run.stdout.lines().filter(|l| l.starts_with("verdict:"));
    assert_eq!(verdicts.count(), 1, "{}", run.stdout);
    assert!(
        run.stdout.lines().last().unwrap().starts_with("verdict: "),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("trail -> e\\nverdict: follows\\ny.csv ("),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("summary -> s\\u{202e}\\nverdict: follows\\n.json"),
        "{}",
        run.stdout
    );
    // the files are written under the names given, unescaped
    assert!(std::fs::read_to_string(dir.join(trail)).unwrap().starts_with("t,"));
    assert!(
        std::fs::read_to_string(dir.join(summary))
            .unwrap()
            .contains("\"verdict\"")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs `command` with a stdout whose reading end is closed before it starts (closed after the
/// start, a short output could land in the pipe's buffer first), stderr captured.
fn with_stdout_closed(command: &mut Command) -> std::process::Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    command.stdout(writer).stderr(Stdio::piped()).output().unwrap()
}

/// A full stderr (`2>/dev/full`) is no panic: a refusal keeps its status 2 and a valid run
/// writes its files and ends with 0 (issue 49: exit 101). A closed stdout (`faze4 … | head`)
/// ends the run quietly with the pipe's status, 141 as SIGPIPE would, its files complete up to
/// where it stopped (issue 48).
#[test]
fn a_full_stderr_or_a_closed_stdout_is_no_panic() {
    let dir = arm_dir("hostile-io");
    let full_stderr = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_faze4"))
            .args(args)
            .current_dir(&dir)
            .stdout(Stdio::null())
            .stderr(std::fs::File::create("/dev/full").unwrap())
            .status()
            .unwrap();
        out.code()
    };
    assert_eq!(full_stderr(&arm_wave(&["--dt", "-1"])), Some(2));
    assert_eq!(full_stderr(&arm_wave(&["--trail", "full.csv"])), Some(0));
    assert!(std::fs::read_to_string(dir.join("full.csv")).unwrap().starts_with("t,"));
    // stdout's reading end closed before the run prints its first line
    let out = with_stdout_closed(
        Command::new(env!("CARGO_BIN_EXE_faze4"))
            .args(arm_wave_told(&["--trail", "closed.csv"]))
            .current_dir(&dir),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "{stderr}");
    assert_eq!(stderr, "", "a closed stdout ends the run quietly");
    assert!(
        std::fs::read_to_string(dir.join("closed.csv"))
            .unwrap()
            .starts_with("t,")
    );
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An output named `/dev/stdout` or `/dev/stderr` goes down a pipe as into a terminal (it was
/// refused, "No such file or directory": the link `/proc/self/fd/1` names `pipe:[…]`, which no
/// path reaches); a pipe whose reader left ends the run quietly with SIGPIPE's status, 141 (it
/// was "--trail: /dev/stdout: Broken pipe", status 2).
#[test]
fn outputs_into_a_pipe_through_dev_stdout() {
    let dir = arm_dir("hostile-dev-stdout");
    let out = Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(arm_wave(&["--trail", "none", "--summary", "/dev/stdout"]))
        .current_dir(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json = &stdout[stdout.find('{').unwrap()..=stdout.rfind('}').unwrap()];
    let summary: serde_json::Value = serde_json::from_str(json).unwrap_or_else(|e| panic!("{e}: {stdout}"));
    assert!(summary["verdict"].is_object(), "{summary}");
    let out = Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(arm_wave(&["--trail", "/dev/stderr"]))
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("t,"));
    // the reading end closed before the trail's first row
    let out = with_stdout_closed(
        Command::new(env!("CARGO_BIN_EXE_faze4"))
            .args(arm_wave(&["--trail", "/dev/stdout"]).iter().map(|a| match *a {
                "0.2" => "5",
                a => a,
            }))
            .current_dir(&dir),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "{stderr}");
    assert_eq!(stderr, "", "a closed pipe ends the run quietly");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// What the binary prints on stdout without a run (help, version, completions, the manual,
/// the lists) meets a full or closed stdout as a run does: a full one (`>/dev/full`) is an
/// error, status 2 (help said nothing and ended with 0; `completions` panicked, 101); a closed
/// one ends quietly with SIGPIPE's status, 141.
#[test]
fn help_and_shell_files_on_a_full_or_closed_stdout() {
    for args in [
        &["--help"][..],
        &["wave", "--help"],
        &["--version"],
        &["completions", "bash"],
        &["completions", "zsh"],
        &["man"],
        &["list", "motors"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_faze4"))
            .args(args)
            .stdout(std::fs::File::create("/dev/full").unwrap())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(
            stderr.trim_end(),
            "faze4: error: stdout: No space left on device (os error 28)",
            "{args:?}"
        );
        let out = with_stdout_closed(Command::new(env!("CARGO_BIN_EXE_faze4")).args(args));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(141), "{args:?}: {stderr}");
        assert_eq!(stderr, "", "{args:?}: a closed stdout ends quietly");
    }
}

/// A signal while an input is read ends the process at once, with one line and the signal's
/// status, nothing written (issue 49: SIGTERM waited for the parse to end, a minute for a
/// hostile YAML). The input here is a FIFO whose writer holds it open without ending it, so
/// the parse would wait for as long as the writer does (20 s).
#[test]
fn a_signal_stops_a_parse_at_once() {
    use std::io::Write;
    let dir = arm_dir("hostile-parse-signal");
    for (signal, status, said) in [
        (
            libc::SIGTERM,
            143,
            "faze4: stopped by SIGTERM before the run began; nothing is written",
        ),
        (
            libc::SIGINT,
            130,
            "faze4: interrupted before the run began; nothing is written",
        ),
    ] {
        let fifo = dir.join("q.yaml");
        assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let before = snapshot(&dir);
        let child = Command::new(env!("CARGO_BIN_EXE_faze4"))
            .args([
                "replay",
                "--urdf",
                "arm.urdf",
                "--package-path",
                "pkg",
                "--q-traj",
                "q.yaml",
            ])
            .args(["--trail", "t.csv", "--summary", "s.json", "-q"])
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // opening for writing waits until faze4 opens the FIFO to read it
        let mut writer = std::fs::OpenOptions::new().write(true).open(&fifo).unwrap();
        writer.write_all(b"joint_names: [j1, j2, j3]\npoints:\n").unwrap();
        let holder = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_secs(20));
            drop(writer);
        });
        std::thread::sleep(Duration::from_millis(300));
        let sent = std::time::Instant::now();
        send(child.id(), signal);
        let out = child.wait_with_output().unwrap();
        assert!(sent.elapsed() < Duration::from_secs(5), "{:?}", sent.elapsed());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(status), "{stderr}");
        assert_eq!(stderr.trim_end(), said);
        assert_eq!(snapshot(&dir), before);
        std::fs::remove_file(&fifo).unwrap();
        drop(holder);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A FIFO that no process opens for writing is refused after 10 s, naming it, where `open()`
/// waited for ever (issue 49).
#[test]
fn a_fifo_nobody_writes_is_refused_in_time() {
    let dir = arm_dir("hostile-fifo");
    assert!(
        Command::new("mkfifo")
            .arg(dir.join("q.csv"))
            .status()
            .unwrap()
            .success()
    );
    let args = [
        "replay",
        "--urdf",
        "arm.urdf",
        "--package-path",
        "pkg",
        "--q-traj",
        "q.csv",
        "-q",
    ];
    let before = snapshot(&dir);
    let started = std::time::Instant::now();
    let run = faze4(&dir, &args);
    let parts = ["q.csv", "a FIFO that no process opened for writing within 10 s"];
    check_refusal(&args, run.status.code(), &run.stderr, &parts);
    assert_eq!(snapshot(&dir), before);
    assert!(started.elapsed() < Duration::from_secs(30), "{:?}", started.elapsed());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs the `faze4` binary with `args` in `dir`: what it printed, and its peak resident memory
/// (MiB: the kernel's `ru_maxrss` of that child alone, by `wait4`).
// the child is reaped by wait4, which reads its resource usage too (clippy sees no wait())
#[allow(clippy::zombie_processes)]
fn faze4_peak(dir: &Path, args: &[&str]) -> (Run, f64) {
    use std::io::Read;
    use std::os::unix::process::ExitStatusExt;
    let mut child = Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = child.stdout.take().unwrap();
    let printed = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = out.read_to_string(&mut text);
        text
    });
    let mut stderr = String::new();
    let _ = child.stderr.take().unwrap().read_to_string(&mut stderr);
    let stdout = printed.join().unwrap();
    let (mut status, mut usage) = (0, unsafe { std::mem::zeroed::<libc::rusage>() });
    // SAFETY: wait4 writes the status and resource usage of this test's own child
    let waited = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(waited, child.id() as libc::pid_t);
    let run = Run {
        status: std::process::ExitStatus::from_raw(status),
        stdout,
        stderr,
    };
    (run, usage.ru_maxrss as f64 / 1024.0)
}

/// The bytes `write` writes, compressed with zstd as they come (a few hundred MB of them take
/// no memory here).
fn zstd_stream(write: impl FnOnce(&mut dyn std::io::Write)) -> Vec<u8> {
    let mut encoder = zstd::stream::Encoder::new(Vec::new(), 3).unwrap();
    write(&mut encoder);
    encoder.finish().unwrap()
}

/// A CDR header (encapsulation little-endian) and a ROS Header of stamp 0 and frame `""`.
fn cdr_head(out: &mut dyn std::io::Write) {
    out.write_all(&[0, 1, 0, 0]).unwrap();
    out.write_all(&[0; 8]).unwrap(); // stamp
    out.write_all(&[1, 0, 0, 0, 0, 0, 0, 0]).unwrap(); // frame_id "": length 1, NUL, padding
}

/// A JointState's CDR naming `names` one-letter joints with no values.
fn cdr_state(names: usize, out: &mut dyn std::io::Write) {
    cdr_head(out);
    out.write_all(&(names as u32).to_le_bytes()).unwrap();
    let name = [2, 0, 0, 0, b'a', 0, 0, 0]; // "a": length 2 with its NUL, padding to 4
    for _ in 0..names {
        out.write_all(&name).unwrap();
    }
    out.write_all(&[0; 12]).unwrap(); // position, velocity, effort: empty
}

/// A JointTrajectory's CDR of one joint and `points` empty points.
fn cdr_trajectory(points: usize, out: &mut dyn std::io::Write) {
    cdr_head(out);
    out.write_all(&[1, 0, 0, 0, 2, 0, 0, 0, b'a', 0, 0, 0]).unwrap(); // joint_names ["a"]
    out.write_all(&(points as u32).to_le_bytes()).unwrap();
    for _ in 0..points {
        out.write_all(&[0; 24]).unwrap(); // four empty lists, time_from_start 0
    }
}

/// An MCAP message record on channel 1 at `log_time` holding `data`.
fn mcap_message(log_time: u64, data: &[u8]) -> Vec<u8> {
    mcap_message_on(1, log_time, data)
}

/// An MCAP message record on channel `channel` at `log_time` holding `data`.
fn mcap_message_on(channel: u16, log_time: u64, data: &[u8]) -> Vec<u8> {
    let mut body = channel.to_le_bytes().to_vec();
    body.extend(0u32.to_le_bytes()); // sequence
    body.extend(log_time.to_le_bytes());
    body.extend(log_time.to_le_bytes());
    body.extend(data);
    mcap_record(0x05, &body)
}

/// Bags whose messages are small compressed and huge decoded (the counts of a list, the number
/// of messages) are refused as their counts pass the caps, not after decoding them: the
/// process stays within a few hundred MB where it took 1 to 4 GB (issue 49).
#[test]
fn bag_messages_are_bounded_once_decoded() {
    let dir = temp_dir("hostile-decoded");
    // one JointState of 30 million one-letter names: 240 MB in CDR, 23 kB with zstd
    // (rosbag2's compression per message), under the 256 MiB kept
    let names = zstd_stream(|w| cdr_state(30_000_000, w));
    std::fs::write(dir.join("names.mcap"), mcap_file(&mcap_message(0, &names))).unwrap();
    // a JointTrajectory of 10 million empty points: 240 MB in CDR
    let points = zstd_stream(|w| cdr_trajectory(10_000_000, w));
    let kind = "trajectory_msgs/msg/JointTrajectory";
    std::fs::write(dir.join("points.mcap"), mcap_bag(kind, &mcap_message(0, &points))).unwrap();
    // 120,000 JointStates of 250 names each: 240 MB in CDR, 2.1 GB once decoded
    let state = zstd_stream(|w| cdr_state(250, w));
    let states: Vec<u8> = (0..120_000u64).flat_map(|k| mcap_message(k, &state)).collect();
    std::fs::write(dir.join("states.mcap"), mcap_file(&states)).unwrap();
    let replay = |q: &'static str| vec!["replay", "--q-traj", q, "-q"];
    for (args, parts, most_mib) in [
        (
            replay("names.mcap"),
            &["more than 256 joint names in one list"][..],
            450.0,
        ),
        (replay("points.mcap"), &["more than 1000000 points in one list"], 600.0),
        (
            replay("states.mcap"),
            &["topic /joint_states's messages take more than 256 MiB once decoded, at message"],
            750.0,
        ),
    ] {
        let (run, peak) = faze4_peak(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, parts);
        assert!(peak < most_mib, "{args:?} peaked at {peak:.0} MiB");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// One topic name recorded with two types is two streams, not one: a bag whose `/joint_states`
/// carries both `JointState` and `JointTrajectory` messages is refused naming both types, with
/// or without `--topic` (issue 49: their messages were merged into one list).
#[test]
fn one_topic_name_with_two_types_is_refused() {
    let dir = temp_dir("hostile-two-types");
    let (mut state, mut trajectory) = (Vec::new(), Vec::new());
    cdr_state(1, &mut state);
    cdr_trajectory(2, &mut trajectory);
    let kinds = ["sensor_msgs/msg/JointState", "trajectory_msgs/msg/JointTrajectory"];
    let data = [mcap_message_on(1, 0, &state), mcap_message_on(2, 1, &trajectory)].concat();
    std::fs::write(dir.join("two.mcap"), mcap_channels(&kinds, &data)).unwrap();
    let parts = [
        "two.mcap",
        "topic /joint_states is recorded with 2 types or encodings",
        "sensor_msgs/msg/JointState in cdr (1 message)",
        "trajectory_msgs/msg/JointTrajectory in cdr (1 message)",
    ];
    let named = ["replay", "--q-traj", "two.mcap", "--topic", "/joint_states"];
    for args in [&named[..3], &named] {
        let args = [args, &["-q"]].concat();
        let run = faze4(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &parts);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A CSV column given twice is refused naming it and both places (the last one won, unsaid);
/// a row is named by its line in the file, comments and blank lines counted (issue 49: the
/// count skipped them).
#[test]
fn csv_columns_are_given_once_and_rows_named_by_their_line() {
    let dir = temp_dir("hostile-csv");
    let twice = "t,j1,j2,j1.velocity,j2.velocity,j1.velocity\n0,0,0,0,0,0\n1,0,0,0,0,0\n";
    std::fs::write(dir.join("twice.csv"), twice).unwrap();
    std::fs::write(dir.join("lines.csv"), "# by hand\nt,j1,j2\n\n# next\n0,0,0\n1,0,x\n").unwrap();
    for (file, said) in [
        ("twice.csv", "column 'j1.velocity' is given twice (columns 4 and 6)"),
        ("lines.csv", "line 6, column 'j2': 'x' is not a number"),
    ] {
        let args = ["replay", "--q-traj", file, "-q"];
        let run = faze4(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &[file, said]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A YAML trajectory nested deeper than 64 collections is refused before libyaml parses it,
/// flow or block, even inside the ignored `header` (issue 49: 100,000 nested `[` in 200 kB took
/// 59 s, libyaml's time growing as the square of the depth).
#[test]
fn yaml_nesting_is_refused_before_it_is_parsed() {
    let dir = temp_dir("hostile-yaml-nesting");
    let deep = 100_000;
    let flow = format!("header: {}{}\njoint_names: [a]\n", "[".repeat(deep), "]".repeat(deep));
    std::fs::write(dir.join("flow.yaml"), flow).unwrap();
    std::fs::write(dir.join("block.yaml"), format!("header:\n  {}a\n", "- ".repeat(deep))).unwrap();
    // 64 deep is read (and found to be no trajectory): the limit counts what it says
    let shallow = format!("header: {}{}\n", "[".repeat(63), "]".repeat(63));
    std::fs::write(dir.join("shallow.yaml"), shallow).unwrap();
    for (file, said) in [
        (
            "flow.yaml",
            "flow.yaml: line 1, column 264: collections nested more than 64 deep",
        ),
        (
            "block.yaml",
            "block.yaml: line 2, column 129: collections nested more than 64 deep",
        ),
        (
            "shallow.yaml",
            "shallow.yaml: document 1 is a message faze4 does not know (its fields: 'header')",
        ),
    ] {
        let args = ["replay", "--q-traj", file, "-q"];
        let run = faze4(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &[said]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A YAML or JSON trajectory's values are counted as its tree is built (4 Mi at most), YAML
/// aliases counted where they repeat; a CSV's rows as they are read (1 million at most): a file
/// cannot take more memory than a stated multiple of its cap (issue 49: a 15 MB YAML list of
/// names took 1.43 GB). Each process's peak (`ru_maxrss`) is checked.
#[test]
fn text_trajectories_are_bounded_as_they_are_built() {
    let dir = temp_dir("hostile-text-amplification");
    // 24 kB of YAML: 6,000 aliases of a 1,000-name list, 6 million names once repeated
    let names = format!("names: &n [{}]\n", vec!["a"; 1000].join(","));
    let aliases = format!("{names}joint_names: [{}]\n", vec!["*n"; 6000].join(","));
    std::fs::write(dir.join("aliases.yaml"), aliases).unwrap();
    // 8.4 MB of YAML: 4.2 million one-letter names, counted by the scanner before libyaml lists
    // an event for each (15.6 MB of them peaked at 1.43 GB)
    std::fs::write(
        dir.join("flow.yaml"),
        format!("joint_names: [{}]\n", vec!["a"; 4_200_000].join(",")),
    )
    .unwrap();
    // 10 MB of JSON: 5 million one-digit values
    std::fs::write(
        dir.join("values.json"),
        format!("[[{}]]", vec!["0"; 5_000_000].join(",")),
    )
    .unwrap();
    // 1,000,001 rows of 4 bytes
    std::fs::write(dir.join("rows.csv"), format!("t,a\n{}", "0,0\n".repeat(1_000_001))).unwrap();
    for (file, said, most_mib) in [
        (
            "aliases.yaml",
            "aliases.yaml: document 1: more than 4194304 values",
            600.0,
        ),
        ("flow.yaml", "flow.yaml: line 1: more than 4194304 values", 250.0),
        ("values.json", "values.json: more than 4194304 values", 450.0),
        ("rows.csv", "line 1000002: more than 1000000 rows", 350.0),
    ] {
        let args = ["replay", "--q-traj", file, "-q"];
        let (run, peak) = faze4_peak(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &[file, said]);
        assert!(peak < most_mib, "{file} peaked at {peak:.0} MiB");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A point's field the message type does not have is refused naming it as the file spells it,
/// with the field it likely meant (issue 49: `velocites` was dropped unsaid, the points played
/// linear instead of cubic); so is a JointState's, and a key given twice.
#[test]
fn unknown_fields_of_a_trajectory_file_are_refused_naming_them() {
    let dir = temp_dir("hostile-unknown-fields");
    let point = |field: &str, t: u32| {
        format!("{{positions: [0, 0, 0, 0, 0, 0], {field}: [0, 0, 0, 0, 0, 0], time_from_start: {{sec: {t}}}}}")
    };
    let names = "joint_names: [joint1, joint2, joint3, joint4, joint5, joint6]";
    let yaml = |field: &str| format!("{names}\npoints: [{}, {}]\n", point(field, 0), point(field, 1));
    std::fs::write(dir.join("velocites.yaml"), yaml("velocites")).unwrap();
    std::fs::write(dir.join("velocitys.yaml"), yaml("velocitys")).unwrap();
    std::fs::write(dir.join("speeds.yaml"), yaml("speeds")).unwrap();
    let json = r#"{"joint_names": ["joint1"], "point": [{"positions": [0]}]}"#;
    std::fs::write(dir.join("point.json"), json).unwrap();
    let state = "header: {stamp: {sec: 1}}\nname: [joint1]\nposition: [0]\nvelocities: [0]\n";
    std::fs::write(dir.join("state.yaml"), state).unwrap();
    // a key given twice: JSON's last one won, unsaid
    let twice = r#"{"joint_names": ["joint1"], "points": [{"positions": [0]}], "points": []}"#;
    std::fs::write(dir.join("twice.json"), twice).unwrap();
    std::fs::write(dir.join("twice.yaml"), "{joint_names: [a], joint_names: [b]}\n").unwrap();
    for (file, said) in [
        (
            "velocites.yaml",
            "document 1, point 0 has a field 'velocites' a trajectory_msgs/msg/JointTrajectoryPoint does not have: did you mean 'velocities'?",
        ),
        (
            "velocitys.yaml",
            "has a field 'velocitys' a trajectory_msgs/msg/JointTrajectoryPoint does not have: did you mean 'velocities'?",
        ),
        (
            "speeds.yaml",
            "has a field 'speeds' a trajectory_msgs/msg/JointTrajectoryPoint does not have (its fields: positions, velocities",
        ),
        (
            "point.json",
            "the message has a field 'point' a trajectory_msgs/msg/JointTrajectory does not have: did you mean 'points'?",
        ),
        (
            "state.yaml",
            "document 1 has a field 'velocities' a sensor_msgs/msg/JointState does not have: did you mean 'velocity'?",
        ),
        ("twice.json", "twice.json: not JSON: the key 'points' is given twice"),
        (
            "twice.yaml",
            "twice.yaml: document 1 is not YAML: the key 'joint_names' is given twice",
        ),
    ] {
        let args = ["replay", "--q-traj", file, "-q"];
        let run = faze4(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &[said]);
        assert!(!run.stderr.contains("--"), "{}", run.stderr);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A file's own times are the file's: a span no run can take names the file and its span, not
/// `--duration`, which was not given; a file's field names are shown as the file spells them,
/// not as flags; a UTF-8 byte order mark before a YAML, JSON or CSV file is no part of it
/// (issue 49).
#[test]
fn messages_name_the_file_and_its_own_words() {
    let dir = temp_dir("hostile-own-words");
    // the bundled Faze4's joints
    let names = r#""joint_names": ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"]"#;
    let at = |time: &str| format!(r#"{{"positions": [0, 0, 0, 0, 0, 0.1], "time_from_start": {time}}}"#);
    let two = |time: &str| format!(r#"{{{names}, "points": [{}, {}]}}"#, at("0"), at(time));
    std::fs::write(dir.join("short.json"), two("1e-12")).unwrap();
    std::fs::write(dir.join("long.json"), two(r#"{"sec": 2147483647}"#)).unwrap();
    let state = |sec: u64| format!("header: {{stamp: {{sec: {sec}}}}}\nname: [rotary_base]\nposition: [0]\n---\n");
    std::fs::write(dir.join("stamps.yaml"), format!("{}{}", state(1), state((1 << 31) - 1))).unwrap();
    std::fs::write(dir.join("m.toml"), "[[joint]]\nkind = \"dc\"\ncolour = \"red\"\n").unwrap();
    for (args, said) in [
        (
            vec!["replay", "--q-traj", "short.json"],
            "short.json: its points end 1e-12 s after it starts, shorter than one step of --dt (0.0002 s): give --duration",
        ),
        (
            vec!["replay", "--q-traj", "long.json"],
            "long.json: its points end 2147483647 s after it starts, more than the 10^12 steps of --dt",
        ),
        (
            vec!["replay", "--q-traj", "stamps.yaml"],
            "stamps.yaml: its points end 2147483646 s after it starts",
        ),
        (
            vec!["wave", "--motors", "m.toml"],
            "m.toml: unknown field 'colour', expected one of",
        ),
    ] {
        let args = [&args[..], &["-q"]].concat();
        let run = faze4(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &[said]);
        assert!(!run.stderr.contains("--gear-ratio"), "{}", run.stderr);
    }
    // a byte order mark, as Windows editors write one
    let bom = "\u{feff}";
    std::fs::write(
        dir.join("bom.yaml"),
        format!("{bom}{{{names}, \"points\": [{}, {}]}}\n", at("0"), at("0.1")),
    )
    .unwrap();
    std::fs::write(dir.join("bom.json"), format!("{bom}{}", two("0.1"))).unwrap();
    std::fs::write(
        dir.join("bom.csv"),
        format!("{bom}t,rotary_base,nadlaktica,lakat,podlaktica,saka,hvataljka\n0,0,0,0,0,0,0\n0.1,0,0,0,0,0,0.1\n"),
    )
    .unwrap();
    for file in ["bom.yaml", "bom.json", "bom.csv"] {
        let run = faze4(&dir, &["replay", "--q-traj", file, "--no-collisions", "-q"]);
        assert!(run.status.success(), "{file}: {}", run.stderr);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An option a sweep varies and the command after `--` gives too: the sweep set it at each run
/// and the given value was dropped unsaid (`--vary dt=… -- wave --dt 0.0001` ran at the varied
/// steps). Refused naming both; a multiplier of given values (`kp-scale` with `--kp`) is not
/// such a case (issue 49, fourth round).
#[test]
fn an_option_varied_and_given_to_the_command_is_refused_not_dropped() {
    let dir = temp_dir("hostile-varied-given");
    let base = ["--", "wave", "--duration", "0.01", "--no-collisions"];
    for (sweep, given, said) in [
        (
            ["--vary", "dt=0.001,0.002"],
            ["--dt", "0.0001"],
            "--vary: 'dt' is varied and also given to the command (--dt): the sweep sets it at each run, so that value would be dropped",
        ),
        (
            ["--find-min", "payload-kg=0:2"],
            ["--payload-kg", "1"],
            "--find-min: 'payload-kg' is varied and also given to the command (--payload-kg)",
        ),
        (
            ["--find", "payload_kg=0:2"],
            ["--payload-kg", "1"],
            "--find: 'payload_kg' is varied and also given to the command (--payload-kg)",
        ),
    ] {
        let args = [&["sweep"][..], &sweep, &base, &given].concat();
        let run = faze4(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &[said]);
    }
    let args = [
        &["sweep", "-q", "--vary", "kp-scale=1,2"][..],
        &base,
        &["--kp", "auto,auto,auto,auto,auto,30"],
    ]
    .concat();
    let run = faze4(&dir, &args);
    assert!(run.status.success(), "{}", run.stderr);
    assert!(run.stdout.starts_with("[done] 2 runs, 2 follow"), "{}", run.stdout);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A MoveIt `RobotTrajectory` whose `multi_dof_joint_trajectory` moves a mobile base beside the
/// arm's joints: its poses were left out unsaid and the arm played on a fixed base. Now a
/// warning names the document and the joints, said under `-q` too; an empty multi-DOF part (as
/// MoveIt fills it for an arm) says nothing. A figure from a file far beyond a joint's limits
/// is printed as short as it reads back, not in 309 digits (issue 49, fourth round).
#[test]
fn a_plans_multi_dof_part_is_said_and_a_huge_position_printed_short() {
    let dir = temp_dir("hostile-multi-dof");
    let names = r#""joint_names": ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"]"#;
    let at = |q: &str, time: &str| format!(r#"{{"positions": [0, 0, 0, 0, 0, {q}], "time_from_start": {time}}}"#);
    let arm = format!(r#"{{{names}, "points": [{}, {}]}}"#, at("0", "0"), at("0.1", "0.1"));
    let base = |points: &str| format!(r#"{{"joint_names": ["virtual_joint"], "points": [{points}]}}"#);
    let pose = r#"{"transforms": [{"translation": {"x": 1, "y": 0, "z": 0}, "rotation": {"x": 0, "y": 0, "z": 0, "w": 1}}], "time_from_start": 0}"#;
    let plan = |multi: &str| format!(r#"{{"joint_trajectory": {arm}, "multi_dof_joint_trajectory": {multi}}}"#);
    std::fs::write(dir.join("base.json"), plan(&base(&[pose, pose].join(", ")))).unwrap();
    std::fs::write(dir.join("arm.json"), plan(&base(""))).unwrap();
    let run = faze4(&dir, &["replay", "--q-traj", "base.json", "--no-collisions", "-q"]);
    assert!(run.status.success(), "{}", run.stderr);
    assert_eq!(
        run.stderr.trim(),
        "faze4: warning: base.json: the message's multi_dof_joint_trajectory moves 'virtual_joint' over 2 points (poses of frames: a mobile base, a floating joint): left out, the arm played fixed to the world as its model is"
    );
    let run = faze4(&dir, &["replay", "--q-traj", "arm.json", "--no-collisions", "-q"]);
    assert!(run.status.success() && run.stderr.is_empty(), "{}", run.stderr);
    std::fs::write(
        dir.join("far.json"),
        format!(r#"{{{names}, "points": [{}, {}]}}"#, at("0", "0"), at("1e308", "0.1")),
    )
    .unwrap();
    let args = ["replay", "--q-traj", "far.json", "-q"];
    let run = faze4(&dir, &args);
    check_refusal(
        &args,
        run.status.code(),
        &run.stderr,
        &[
            "far.json: point 1: joint J6 (hvataljka) is commanded to 1e308 rad, beyond its limits [-3.141592653589793, 3.141592653589793]",
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// One point, one number: a misspelled field in a file's second point was "point 2" while its
/// NaN, its time or its limits were "point 1" (every other message counts points from 0, as
/// `points[1]`). Both now say "point 1" (issue 49, fourth round).
#[test]
fn a_files_points_are_counted_alike_in_every_message() {
    let dir = temp_dir("hostile-point-numbers");
    let names = "joint_names: [rotary_base, nadlaktica, lakat, podlaktica, saka, hvataljka]";
    let point = |q: &str, extra: &str, t: u32| {
        format!("{{positions: [0, 0, 0, 0, 0, {q}],{extra} time_from_start: {{sec: {t}}}}}")
    };
    let file = |second: String| format!("{names}\npoints: [{}, {second}]\n", point("0", "", 0));
    std::fs::write(
        dir.join("field.yaml"),
        file(point("0", " velocites: [0, 0, 0, 0, 0, 0],", 1)),
    )
    .unwrap();
    std::fs::write(dir.join("nan.yaml"), file(point(".nan", "", 1))).unwrap();
    std::fs::write(dir.join("far.yaml"), file(point("9", "", 1))).unwrap();
    for (file, said) in [
        ("field.yaml", "field.yaml: document 1, point 1 has a field 'velocites'"),
        ("nan.yaml", "nan.yaml: point 1: positions of joint 'hvataljka' is NaN"),
        (
            "far.yaml",
            "far.yaml: point 1: joint J6 (hvataljka) is commanded to 9 rad",
        ),
    ] {
        let args = ["replay", "--q-traj", file, "-q"];
        let run = faze4(&dir, &args);
        check_refusal(&args, run.status.code(), &run.stderr, &[said]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A LeRobot v2.1 dataset's copy in `dir/name` whose `meta/info.json` is changed by `edit`.
fn lerobot_v21(dir: &Path, name: &str, edit: impl FnOnce(&mut serde_json::Value)) {
    let from = repo_path("tests/fixtures/trajectories/lerobot/so101_v21");
    let data = dir.join(name).join("data/chunk-000");
    std::fs::create_dir_all(&data).unwrap();
    std::fs::create_dir_all(dir.join(name).join("meta")).unwrap();
    let episode = "data/chunk-000/episode_000000.parquet";
    std::fs::copy(from.join(episode), dir.join(name).join(episode)).unwrap();
    let mut info: serde_json::Value =
        serde_json::from_slice(&std::fs::read(from.join("meta/info.json")).unwrap()).unwrap();
    edit(&mut info);
    std::fs::write(dir.join(name).join("meta/info.json"), info.to_string()).unwrap();
}

/// A LeRobot dataset's `meta/info.json` says where its data is and what layout it has:
/// a `data_path` of `/etc/passwd` or `../../…` was opened and read as Parquet (a downloaded
/// dataset could make faze4 read any file), and a `codebase_version` of v1.6 or v9.9 was read
/// as v3.0 (a v1 dataset "without data/chunk-*/file-*.parquet"; a v9.9 one silently). Both are
/// refused naming the field as `info.json` spells it (issue 49, fourth round).
#[test]
fn a_lerobot_datasets_info_stays_inside_it_and_names_a_version_it_cannot_read() {
    let dir = temp_dir("hostile-lerobot-info");
    std::fs::copy(
        repo_path("tests/urdf/example_robot_data/so101.urdf"),
        dir.join("so101.urdf"),
    )
    .unwrap();
    lerobot_v21(&dir, "ok", |_| {});
    lerobot_v21(&dir, "abs", |i| i["data_path"] = "/etc/passwd".into());
    lerobot_v21(&dir, "up", |i| {
        i["data_path"] = "../ok/data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet".into()
    });
    lerobot_v21(&dir, "v1", |i| i["codebase_version"] = "v1.6".into());
    lerobot_v21(&dir, "v9", |i| i["codebase_version"] = "v9.9".into());
    let run = |name: &'static str| {
        let args = [
            "replay",
            "--robot",
            "so101.urdf",
            "--q-traj",
            name,
            "--units",
            "deg",
            "--no-collisions",
            "-q",
        ];
        (args, faze4(&dir, &args))
    };
    let (_, ok) = run("ok");
    assert!(ok.status.success(), "{}", ok.stderr);
    for (name, said) in [
        (
            "abs",
            "abs/meta/info.json: data_path '/etc/passwd' gives '/etc/passwd', outside the dataset's folder",
        ),
        (
            "up",
            "up/meta/info.json: data_path '../ok/data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet' gives '../ok/data/chunk-000/episode_000000.parquet', outside the dataset's folder",
        ),
        (
            "v1",
            "v1/meta/info.json: codebase_version 'v1.6': faze4 reads LeRobot datasets v2.x and v3.x",
        ),
        (
            "v9",
            "v9/meta/info.json: codebase_version 'v9.9': faze4 reads LeRobot datasets v2.x and v3.x",
        ),
    ] {
        let (args, refused) = run(name);
        check_refusal(&args, refused.status.code(), &refused.stderr, &[said]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `--xacro-arg` the file neither declares nor reads was dropped unsaid: a misspelled
/// `ur_tpye:=ur10e` built the default arm and its verdict. Refused naming it and the arguments
/// the file knows (declared by `<xacro:arg>` or read by `$(arg)`) (issue 49, fourth round).
#[test]
fn a_xacro_argument_the_file_does_not_know_is_refused() {
    let dir = temp_dir("hostile-xacro-arg");
    let xacro = r#"<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="length" default="0.3"/>
  <link name="base"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0 0 $(arg length)"/>
    <axis xyz="0 0 $(arg axis_z)"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>
"#;
    std::fs::write(dir.join("arm.urdf.xacro"), xacro).unwrap();
    let wave = |args: &[&'static str]| {
        let args = [
            &[
                "wave",
                "--robot",
                "arm.urdf.xacro",
                "--duration",
                "0.01",
                "--no-collisions",
                "-q",
            ][..],
            args,
        ]
        .concat();
        (faze4(&dir, &args), args)
    };
    // declared, and read without a declaration: both known
    let (run, _) = wave(&["--xacro-arg", "length:=0.2", "--xacro-arg", "axis_z:=1"]);
    assert!(run.status.success(), "{}", run.stderr);
    let (run, args) = wave(&["--xacro-arg", "lenght:=0.2", "--xacro-arg", "axis_z:=1"]);
    check_refusal(
        &args,
        run.status.code(),
        &run.stderr,
        &[
            "--xacro-arg: lenght: arm.urdf.xacro neither declares nor reads an argument 'lenght' (it knows 'axis_z', 'length')",
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A recorded JointState stream whose stamps go back (a bag played in a loop: the motion
/// twice, the second from the start again) was sorted by stamp unsaid, the two passes
/// interleaved into one motion. A joint's own messages going back is refused naming the two
/// messages; publishers of different joints still interleave as they arrive (issue 49, fourth
/// round).
#[test]
fn a_joint_state_stream_going_back_in_time_is_refused_not_sorted() {
    let dir = temp_dir("hostile-stamps-back");
    let arm = "[rotary_base, nadlaktica, lakat, podlaktica, saka]";
    let state = |ms: u64, names: &str, q: f64| {
        let n = names.matches(',').count() + 1;
        let q = vec![format!("{q}"); n].join(", ");
        format!(
            "header: {{stamp: {{sec: {}, nanosec: {}}}}}\nname: {names}\nposition: [{q}]\n---\n",
            ms / 1000,
            ms % 1000 * 1_000_000
        )
    };
    // two passes of 0 → 0.1 rad over 0.5 s
    let looped: String = (0..2)
        .flat_map(|_| (0..6).map(|k| state(1000 + 100 * k, arm, 0.02 * k as f64)))
        .collect();
    std::fs::write(dir.join("looped.yaml"), looped).unwrap();
    // the gripper's driver publishes apart, its stamps a little behind the arm's
    let mut merged = String::new();
    for k in 0..6 {
        merged += &state(1000 + 100 * k, arm, 0.02 * k as f64);
        merged += &state(1000 + 100 * k - 30, "[hvataljka]", 0.01 * k as f64);
    }
    std::fs::write(dir.join("publishers.yaml"), merged).unwrap();
    let args = ["replay", "--q-traj", "looped.yaml", "--no-collisions", "-q"];
    let run = faze4(&dir, &args);
    check_refusal(
        &args,
        run.status.code(),
        &run.stderr,
        &[
            "looped.yaml: JointState message 7: joint 'rotary_base' at 1 s, before the 1.5 s of JointState message 6: its messages go back in time",
        ],
    );
    let run = faze4(
        &dir,
        &["replay", "--q-traj", "publishers.yaml", "--no-collisions", "-q"],
    );
    assert!(run.status.success(), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A motors file's stepper with a step angle of 1e-300° (9e301 rotor teeth) ran, warning
/// that its rotor "rings at" a 150-digit figure and advising `--dt 2e-153`, which `--dt`
/// refuses. A step angle below 0.1° (900 teeth; the finest hybrid steppers have 250) is
/// refused, printed as short as it reads back (issue 49, fourth round).
#[test]
fn a_stepper_step_angle_no_motor_has_is_refused() {
    let dir = temp_dir("hostile-step-angle");
    let motor = |angle: &str| {
        format!(
            "[[joint]]\nname = \"rotary_base\"\nkind = \"stepper\"\ncurve = [[0, 1], [10, 0]]\nstep_angle = {angle}\n"
        )
    };
    std::fs::write(dir.join("tiny.toml"), motor("1e-300")).unwrap();
    std::fs::write(dir.join("fine.toml"), motor("0.36")).unwrap();
    let args = [
        "wave",
        "--motors",
        "tiny.toml",
        "--drive",
        "stepper",
        "--duration",
        "0.01",
        "--no-collisions",
        "-q",
    ];
    let run = faze4(&dir, &args);
    check_refusal(
        &args,
        run.status.code(),
        &run.stderr,
        &["tiny.toml: J1 (rotary_base): step_angle 1e-300 must be in [0.1, 90] degrees"],
    );
    let run = faze4(
        &dir,
        &[
            "wave",
            "--motors",
            "fine.toml",
            "--drive",
            "stepper",
            "--duration",
            "0.01",
            "--no-collisions",
            "-q",
        ],
    );
    assert!(
        run.status.code() != Some(2) && !run.stderr.contains("error"),
        "{}",
        run.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
