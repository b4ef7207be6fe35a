//! Every input a fuzzer broke faze4 with (`tests/fuzz_regressions/<target>/`, bytes as found)
//! and every fuzz seed (`fuzz/seeds/<target>/`) goes through the fuzz target's own code
//! (`faze4::fuzzing`): no panic, no broken invariant, and for the regressions the error that
//! the fix gives. See the README's "Reliability" section.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use faze4::fuzzing::{self, TrajectoryFormat};

/// What each stored regression input must give: a fragment of its error message, or `None`
/// for "accepted". Every file under tests/fuzz_regressions/ needs an entry.
const EXPECTED: &[(&str, &str, Option<&str>)] = &[
    // mesh_file in CI's smoke run: a malformed COLLADA file made mesh-loader 0.1.13 panic
    // (collada/iter.rs:73); the panic is caught and is the file's one-line error
    (
        "mesh_file",
        "collada_panic_in_mesh_loader",
        Some("the mesh reader (mesh-loader) failed on this file"),
    ),
    // The first seed of extreme values: its axis (1e-300, 0, 1e300) has an infinite norm and
    // was normalised to zero; its 1e300 kg link at 1e10 m gave an infinite body inertia.
    (
        "urdf_model",
        "extreme-values-seed",
        Some("link 'h' <inertial>: mass, centre of mass and inertia overflow"),
    ),
    // (hand-made) each of those alone: a huge axis is a direction like any other ...
    ("urdf_model", "huge-axis", None),
    // ... and offsets that add up to infinity are refused, naming the joint
    (
        "urdf_model",
        "placement-overflow",
        Some("joint 'g' <origin>: places link 'd' beyond the range"),
    ),
    // ndarray-npy's header parse error quoted the header over several lines
    ("npy_samples", "multi-line-header-error", Some("not a NumPy .npy file")),
    // a 2.9 GB header length in a 148-byte file: ndarray-npy allocated it before reading
    ("npy_samples", "oom-header-length", Some("truncated: the header claims")),
    // (hand-made) the same for the data: 10^15 rows claimed, 6 values there
    (
        "npy_samples",
        "huge-shape",
        Some("it needs 48000000000000000 bytes, the file has 48"),
    ),
    // nested brackets in the header: ndarray-npy's literal parser took over 10 s on 128 bytes
    ("npy_samples", "slow-nested-header", Some("its brackets nest 13 deep")),
    // RustyXML (inside urdf-rs) panics with "No namespace prefix bound": caught as before, but
    // the panic message and backtrace went to stderr; as found, and minimised by cargo fuzz tmin
    (
        "urdf_model",
        "xml-namespace-panic",
        Some("urdf-rs panicked: No namespace prefix bound"),
    ),
    (
        "urdf_model",
        "xml-namespace-panic-min",
        Some("urdf-rs panicked: No namespace prefix bound"),
    ),
    // trajectory_file (the four formats behind a first byte, split into a target per format
    // since; these inputs are stored without that byte) in CI's smoke run: an MCAP header record claiming a 4 GB profile string;
    // the mcap crate's decoding reserved it (an out-of-memory under libFuzzer). The header is
    // not decoded any more, and the reader stops at the first record over the length cap.
    (
        "trajectory_mcap",
        "oom-mcap-header-string",
        Some("not a readable MCAP file: record with opcode 13 length exceeds limit"),
    ),
    // trajectory_file in CI's smoke run (a 10 s timeout): a 5 kB MCAP whose second record
    // claims 250 MB; the linear reader was given a buffer of the claimed length at once, so
    // the process allocated and cleared 254 MB (24 s under the sanitizer); now read a piece
    // at a time (bag/mcap.rs `READ_PIECE`): 10 MB, the same refusal
    (
        "trajectory_mcap",
        "slow-mcap-record-claim",
        Some("not a readable MCAP file: MCAP file ended in the middle of a record"),
    ),
    // trajectory_file, fuzzing: a record inside an uncompressed chunk claims more than the
    // chunk has left; the mcap crate's reader subtracted it from what was left (an underflow:
    // a panic in a debug build, records read past the chunk in a release one). Each chunk is
    // now read whole (this one is cut short) and checked before the reader walks it ...
    (
        "trajectory_mcap",
        "panic-mcap-chunk-record-underflow",
        Some("not a readable MCAP file: MCAP file ended in the middle of a record"),
    ),
    // ... (hand-made) and a whole chunk whose record claims 1000 bytes of its 20 is refused
    (
        "trajectory_mcap",
        "chunk-record-past-its-chunk",
        Some("not a readable MCAP file: a record inside a chunk claims 1000 bytes where the chunk has 20 left"),
    ),
    // motors_file, fuzzing: a joint name holding a carriage return was put in the message as it
    // was (the front ends escape a message, but the library's own message must be one line);
    // the names a motors file gives are quoted and escaped now
    (
        "motors_file",
        "joint-name-with-carriage-return",
        Some("joint 1 names 'rotya\\r_base', not a moving joint of"),
    ),
    // python_conversion's first campaign, at its 15th input: a keyword that is no option is
    // named first as it was given (the target's check wanted an option's name there)
    (
        "python_conversion",
        "unknown-keyword-named-first",
        Some("`m$otor`: is not an option of shape"),
    ),
    // python_conversion's campaign: an empty array (0 rows) may claim 2³² columns; the target
    // made a name for each (out of memory in the target itself, not in faze4)
    (
        "python_conversion",
        "empty-array-of-2-32-columns",
        Some("q_traj: 1953459480 columns; a model has at most 256"),
    ),
    // python_conversion's campaign: a keyword holding backticks around an option's name is
    // shown with that name reworded, so the check cannot find it as given
    (
        "python_conversion",
        "keyword-holding-backticks",
        Some("is not an option of replay"),
    ),
];

fn inputs(target: &str) -> Vec<(PathBuf, bool)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for (dir, is_regression) in [("tests/fuzz_regressions", true), ("fuzz/seeds", false)] {
        let Ok(entries) = std::fs::read_dir(root.join(dir).join(target)) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            if path.is_file() {
                files.push((path, is_regression));
            }
        }
    }
    files.sort();
    files
}

/// Runs `run` on every input of `target`, collecting every failure before failing.
fn check_all(target: &str, run: impl Fn(&[u8]) -> Option<Result<(), String>>) {
    let files = inputs(target);
    assert!(!files.is_empty(), "no inputs for {target}");
    let mut failures = Vec::new();
    for (path, is_regression) in &files {
        let name = path.file_name().unwrap().to_str().unwrap();
        let bytes = std::fs::read(path).unwrap();
        let outcome = match catch_unwind(AssertUnwindSafe(|| run(&bytes))) {
            Ok(outcome) => outcome,
            Err(_) => {
                failures.push(format!("{}: panicked", path.display()));
                continue;
            }
        };
        if !is_regression {
            continue;
        }
        let expected = EXPECTED.iter().find(|(t, n, _)| *t == target && *n == name);
        let Some((_, _, expected)) = expected else {
            failures.push(format!("{}: no entry in EXPECTED", path.display()));
            continue;
        };
        match (expected, outcome) {
            (None, Some(Ok(()))) => {}
            (Some(fragment), Some(Err(message))) if message.contains(fragment) => {}
            (expected, got) => failures.push(format!("{}: expected {expected:?}, got {got:?}", path.display())),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn urdf_model_inputs() {
    check_all("urdf_model", |bytes| {
        fuzzing::urdf_model(bytes).map(|r| r.map(|_| ()).map_err(|e| e.to_string()))
    });
}

#[test]
fn npy_samples_inputs() {
    check_all("npy_samples", |bytes| {
        Some(fuzzing::npy_samples(bytes).map(|_| ()).map_err(|e| e.to_string()))
    });
}

#[test]
fn stl_mesh_inputs() {
    check_all("stl_mesh", |bytes| {
        Some(fuzzing::stl_mesh(bytes).map(|_| ()).map_err(|e| e.to_string()))
    });
}

#[test]
fn output_set_inputs() {
    check_all("output_set", |bytes| {
        Some(fuzzing::output_set(bytes).map_err(|e| e.to_string()))
    });
}

#[test]
fn mesh_file_inputs() {
    check_all("mesh_file", |bytes| {
        fuzzing::mesh_file(bytes).map(|r| r.map(|_| ()).map_err(|e| e.to_string()))
    });
}

#[test]
fn dae_mesh_inputs() {
    check_all("dae_mesh", |bytes| {
        Some(fuzzing::dae_mesh(bytes).map(|_| ()).map_err(|e| e.to_string()))
    });
}

#[test]
fn obj_mesh_inputs() {
    check_all("obj_mesh", |bytes| {
        Some(fuzzing::obj_mesh(bytes).map(|_| ()).map_err(|e| e.to_string()))
    });
}

/// One trajectory format's target on `bytes`, as `check_all` takes it.
fn trajectory(format: TrajectoryFormat, bytes: &[u8]) -> Option<Result<(), String>> {
    Some(
        fuzzing::trajectory(format, bytes)
            .map(|_| ())
            .map_err(|e| e.to_string()),
    )
}

#[test]
fn trajectory_yaml_inputs() {
    check_all("trajectory_yaml", |bytes| trajectory(TrajectoryFormat::Yaml, bytes));
}

#[test]
fn trajectory_json_inputs() {
    check_all("trajectory_json", |bytes| trajectory(TrajectoryFormat::Json, bytes));
}

#[test]
fn trajectory_csv_inputs() {
    check_all("trajectory_csv", |bytes| trajectory(TrajectoryFormat::Csv, bytes));
}

#[test]
fn trajectory_mcap_inputs() {
    check_all("trajectory_mcap", |bytes| trajectory(TrajectoryFormat::Mcap, bytes));
}

#[test]
fn trajectory_db3_inputs() {
    check_all("trajectory_db3", |bytes| trajectory(TrajectoryFormat::Db3, bytes));
}

#[test]
fn trajectory_ros1_inputs() {
    check_all("trajectory_ros1", |bytes| trajectory(TrajectoryFormat::Ros1, bytes));
}

#[test]
fn motors_file_inputs() {
    check_all("motors_file", |bytes| {
        fuzzing::motors_file(bytes).map(|r| r.map(|_| ()).map_err(|e| e.to_string()))
    });
}

#[test]
fn python_conversion_inputs() {
    check_all("python_conversion", fuzzing::python_conversion);
}

/// What a COLLADA file claims is checked before mesh-loader allocates or recurses (issue 35):
/// an 834-byte file claiming 4 billion triangles asked for 48 GB, 100,000 nested `<node>`s
/// overflowed the stack; an OBJ reference is said as written. Generated rather than stored.
#[test]
fn mesh_claims_are_refused_before_the_parser() {
    let seed =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds/dae_mesh/box.dae")).unwrap();
    let at = seed.find("<triangles").unwrap();
    let count = at + seed[at..].find("count=\"").unwrap() + 7;
    let end = count + seed[count..].find('"').unwrap();
    let bomb = format!("{}4000000000{}", &seed[..count], &seed[end..]);
    let e = fuzzing::dae_mesh(bomb.as_bytes()).unwrap_err().to_string();
    assert!(e.contains("<triangles> claims 12000000000 indices"), "{e}");
    let n = 100_000;
    let deep = format!(
        "<COLLADA><library_visual_scenes><visual_scene>{}{}</visual_scene></library_visual_scenes></COLLADA>",
        "<node>".repeat(n),
        "</node>".repeat(n)
    );
    let e = fuzzing::dae_mesh(deep.as_bytes()).unwrap_err().to_string();
    assert!(e.contains("elements nest more than 256 deep"), "{e}");
    let e = fuzzing::obj_mesh(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -99999\n")
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "fuzz.obj: OBJ line 4: a face refers to vertex -99999, with 3 vertices before it"
    );
}

/// Deep nesting overflowed the stack inside urdf-rs (an abort, not a panic): 4,000 levels
/// under the fuzzer (AddressSanitizer), 20,000 in the CLI. Generated rather than stored.
#[test]
fn deep_nesting_is_refused_before_the_parser() {
    let n = 100_000;
    let text = format!(
        "<robot name=\"r\"><link name=\"x\">{}{}</link></robot>",
        "<a>".repeat(n),
        "</a>".repeat(n)
    );
    let error = fuzzing::urdf_model(text.as_bytes()).unwrap().unwrap_err().to_string();
    assert!(error.contains("elements nest more than 100 deep"), "{error}");
}

/// A panic inside urdf-rs is one line from the CLI, backtraces on or not.
#[test]
fn urdf_parser_panic_is_one_quiet_line_from_the_cli() {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions/urdf_model/xml-namespace-panic-min");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(["wave", "--trail", "none", "--urdf"])
        .arg(&input)
        .env("RUST_BACKTRACE", "1")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("faze4: error: ") && stderr.contains("urdf-rs panicked: No namespace prefix bound"),
        "{stderr}"
    );
}

#[test]
fn every_expectation_has_its_input() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (target, name, _) in EXPECTED {
        let path = root.join("tests/fuzz_regressions").join(target).join(name);
        assert!(path.is_file(), "{} is missing", path.display());
    }
}

/// The bag targets' seeds are real bags that read (the SQLite ones vacuumed to 512-byte pages):
/// the fuzzer starts from accepted inputs, and a `.db3` read from bytes passes the target's
/// check that it wrote nothing.
#[test]
fn the_bag_seeds_read() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (target, format) in [
        ("trajectory_db3", TrajectoryFormat::Db3),
        ("trajectory_ros1", TrajectoryFormat::Ros1),
    ] {
        for (path, _) in inputs(target) {
            let bytes = std::fs::read(&path).unwrap();
            let read = fuzzing::trajectory(format, &bytes);
            assert!(read.is_ok(), "{}: {read:?}", path.strip_prefix(root).unwrap().display());
        }
    }
}
