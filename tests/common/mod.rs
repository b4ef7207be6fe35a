//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use faze4::algo::{Data, rnea};
use faze4::control::JointMotor;
use faze4::model::{Model, PackagePaths};
use faze4::retime::{PathSpline, Profile};
use serde_json::Value;

/// The repository root.
pub fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A path under the repository root.
pub fn repo_path(rel: &str) -> PathBuf {
    repo().join(rel)
}

/// The official Faze4 description (URDF and meshes): the repository's copy,
/// `assets/faze4_description`, or wherever `$FAZE4_DESCRIPTION` points.
pub fn shared_description() -> PathBuf {
    match std::env::var_os("FAZE4_DESCRIPTION") {
        Some(dir) => PathBuf::from(dir),
        None => repo_path("assets/faze4_description"),
    }
}

/// Loads a URDF from a repository-relative path.
pub fn load(rel: &str) -> Model {
    Model::from_urdf_file(&repo_path(rel), &PackagePaths::default()).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Reads a JSON fixture from tests/fixtures.
pub fn fixture(name: &str) -> Value {
    let path = repo_path(&format!("tests/fixtures/{name}"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

pub fn vec_f64(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

pub fn mat_f64(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().expect("array").iter().map(vec_f64).collect()
}

/// A small seeded generator (SplitMix64) for reproducible random states.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
    pub fn vector(&mut self, n: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.uniform(lo, hi)).collect()
    }
    /// A random configuration inside each joint's limits (±π for unlimited joints).
    pub fn configuration(&mut self, model: &Model) -> Vec<f64> {
        model
            .joints
            .iter()
            .map(|j| {
                let lo = if j.lower.is_finite() {
                    j.lower
                } else {
                    -std::f64::consts::PI
                };
                let hi = if j.upper.is_finite() {
                    j.upper
                } else {
                    std::f64::consts::PI
                };
                self.uniform(lo, hi)
            })
            .collect()
    }
}

/// max |a − b| over two equally long slices.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// max |x| over a slice.
pub fn max_abs(a: &[f64]) -> f64 {
    a.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

/// A fresh empty directory for one test's output files, named after the test file that asks
/// (`tests/it/` is one process: two files may use the same `name`).
#[track_caller]
pub fn temp_dir(name: &str) -> PathBuf {
    let file = Path::new(std::panic::Location::caller().file());
    let module = file.file_stem().unwrap_or_default().to_string_lossy();
    let dir = std::env::temp_dir().join(format!("faze4-test-{}-{module}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The result of running the real `faze4` binary.
pub struct Run {
    pub status: std::process::ExitStatus,
    pub stdout: String,
    pub stderr: String,
}

/// Runs the `faze4` binary with `args` in directory `dir`.
pub fn faze4(dir: &Path, args: &[&str]) -> Run {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(args)
        .current_dir(dir)
        // a panic would print a backtrace: the one-line error checks would see it
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("run faze4");
    Run {
        status: out.status,
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// A CSV file as its header and rows of numbers.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines.next().expect("header").split(',').map(str::to_string).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("number")).collect())
        .collect();
    (header, rows)
}

/// The JSON file `name` a run wrote into `dir` (its `--summary`).
pub fn summary(dir: &Path, name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap()
}

/// The trail a run wrote to `dir/trail.csv`, its header checked against the oracle fixture's
/// `trail.columns`.
pub fn fixture_trail(dir: &Path, fixture: &Value) -> Vec<Vec<f64>> {
    let (header, rows) = read_csv(&dir.join("trail.csv"));
    let columns: Vec<&str> = (fixture["trail"]["columns"].as_array().unwrap().iter())
        .map(|c| c.as_str().unwrap())
        .collect();
    assert_eq!(header, columns);
    rows
}

/// Sends SIGINT (what Ctrl-C sends) to process `pid`.
pub fn interrupt(pid: u32) {
    send(pid, libc::SIGINT);
}

/// Sends `signal` to process `pid`.
pub fn send(pid: u32, signal: libc::c_int) {
    // SAFETY: kill(2) only reads its arguments
    let sent = unsafe { libc::kill(pid as libc::pid_t, signal) };
    assert_eq!(sent, 0, "kill({signal}) failed: {}", std::io::Error::last_os_error());
}

/// Runs the `faze4` binary with `args` in `dir`, sends it `signal` once the run has begun —
/// once `begun` says so, given `dir` and the standard output so far (looked at every 20 ms, for
/// at most 60 s) — and `after` more, and waits for it: its exit status and both outputs. A
/// signal before the run begins ends the process with nothing written (issue 49), so a fixed
/// delay from the start fails on a loaded machine.
pub fn signalled_once_begun(
    dir: &Path,
    args: &[&str],
    signal: libc::c_int,
    begun: impl Fn(&Path, &str) -> bool,
    after: std::time::Duration,
) -> std::process::Output {
    use std::io::Read;
    use std::sync::{Arc, Mutex};
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run faze4");
    let printed = Arc::new(Mutex::new(Vec::new()));
    let (mut out, mut err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let reader = {
        let printed = Arc::clone(&printed);
        std::thread::spawn(move || {
            let mut buffer = [0u8; 4096];
            while let Ok(n @ 1..) = out.read(&mut buffer) {
                printed.lock().unwrap().extend_from_slice(&buffer[..n]);
            }
        })
    };
    let stderr = std::thread::spawn(move || {
        let mut text = Vec::new();
        let _ = err.read_to_end(&mut text);
        text
    });
    let start = std::time::Instant::now();
    while start.elapsed().as_secs() < 60 && !begun(dir, &String::from_utf8_lossy(&printed.lock().unwrap())) {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(after);
    send(child.id(), signal);
    let status = child.wait().expect("faze4 ends");
    reader.join().unwrap();
    let stdout = std::mem::take(&mut *printed.lock().unwrap());
    std::process::Output {
        status,
        stdout,
        stderr: stderr.join().unwrap(),
    }
}

/// Whether `dir` holds an output's temporary (`NAME.tmp`): a run's outputs are open, so it has
/// begun.
pub fn has_temporary(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries
            .flatten()
            .any(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
    })
}

/// Runs `args`, expects bad-input failure (status 2), one line on stderr containing `parts`,
/// and no output file left behind.
pub fn refuses(dir: &Path, args: &[&str], parts: &[&str]) {
    let run = faze4(dir, args);
    assert_eq!(
        run.status.code(),
        Some(2),
        "{args:?} should fail with status 2: {}",
        run.stderr
    );
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: one line on stderr, got:\n{}", run.stderr);
    assert!(lines[0].starts_with("faze4: error: "), "{}", lines[0]);
    for p in parts {
        assert!(lines[0].contains(p), "{args:?}: {:?} should mention {p:?}", lines[0]);
    }
    assert!(!run.stderr.contains("panicked"));
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.ends_with(".npy") && !n.ends_with(".urdf"))
        .collect();
    assert!(left.is_empty(), "{args:?} left files behind: {left:?}");
}

/// Everything in `dir`, recursively: each entry's relative path and what it is (a file's bytes,
/// a link's target, a directory, a device or FIFO).
pub fn snapshot(dir: &Path) -> std::collections::BTreeMap<String, String> {
    fn walk(root: &Path, dir: &Path, out: &mut std::collections::BTreeMap<String, String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.strip_prefix(root).unwrap().display().to_string();
            let meta = std::fs::symlink_metadata(&path).unwrap();
            let what = if meta.file_type().is_symlink() {
                format!("link -> {}", std::fs::read_link(&path).unwrap().display())
            } else if meta.is_dir() {
                walk(root, &path, out);
                "dir".to_string()
            } else if meta.is_file() {
                format!("file {:?}", std::fs::read(&path).unwrap())
            } else {
                "special".to_string()
            };
            out.insert(name, what);
        }
    }
    let mut out = std::collections::BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Runs `args` in `dir` and expects bad input: status 2, one line on stderr (`faze4: error:`)
/// containing each of `parts`, and `dir` exactly as it was (no file changed, none added).
pub fn fails_leaving_all_as_was(dir: &Path, args: &[&str], parts: &[&str]) {
    let before = snapshot(dir);
    let run = faze4(dir, args);
    check_refusal(args, run.status.code(), &run.stderr, parts);
    assert_eq!(snapshot(dir), before, "{args:?} changed the directory");
}

pub fn check_refusal(args: &[&str], code: Option<i32>, stderr: &str, parts: &[&str]) {
    assert_eq!(code, Some(2), "{args:?} should fail with status 2: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: one line on stderr, got:\n{stderr}");
    assert!(lines[0].starts_with("faze4: error: "), "{}", lines[0]);
    for p in parts {
        assert!(lines[0].contains(p), "{args:?}: {:?} should mention {p:?}", lines[0]);
    }
}

/// The most `profile` asks of a motor at the grid points: the largest share |τ| / |bound| over
/// joints and points, where τ is the inverse dynamics at (s_i, ṡ_i, s̈ on the interval from
/// s_i; reflected rotor inertia included) plus the joint's damping d·q̇, and the bound the
/// motor's envelope on τ's side at the joint's speed there. Returns (share, joint, grid point, motor speed rad/s).
pub fn most_asked(
    model: &Model,
    motors: &[Option<JointMotor>],
    path: &PathSpline,
    profile: &Profile,
) -> (f64, usize, usize, f64) {
    let n = model.dof();
    let mut data = Data::new(model);
    let (mut q, mut dq, mut ddq) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut most = (0.0, 0, 0, 0.0);
    for (i, &u) in profile.sdd.iter().enumerate() {
        let x = profile.x[i];
        path.eval(profile.s[i], &mut q, &mut dq, &mut ddq);
        let qd: Vec<f64> = dq.iter().map(|d| d * x.sqrt()).collect();
        let qdd: Vec<f64> = (ddq.iter().zip(&dq)).map(|(dd, d)| dd * x + d * u).collect();
        let tau = rnea(model, &mut data, &q, &qd, &qdd).as_slice().to_vec();
        for (j, m) in motors.iter().enumerate() {
            let m = m.as_ref().unwrap();
            let ratio = m.gear_ratio.unwrap();
            let (lo, hi) = m.motor.joint_bounds(ratio, qd[j]);
            let needed = tau[j] + model.joints[j].damping * qd[j];
            let share = match needed >= 0.0 {
                true => needed / hi,
                false => needed / lo,
            };
            if share > most.0 {
                most = (share, j, i, ratio * qd[j].abs());
            }
        }
    }
    most
}

/// The Faze4's circle as a path: the 240 joint samples `faze4 shape --shape circle --save-q`
/// wrote (tests/fixtures/shape_circle_q.npy).
pub fn circle_path() -> PathSpline {
    let points = faze4::traj::npy::read_samples(&repo_path("tests/fixtures/shape_circle_q.npy")).unwrap();
    PathSpline::through(&points).unwrap()
}

/// `n` points of a curved path inside `model`'s limits (a fixed pseudo-random walk from the
/// middle of each joint's range, each point within the middle 30 %).
pub fn curved(model: &Model, n: usize, seed: u64) -> PathSpline {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let points: Vec<Vec<f64>> = (0..n)
        .map(|_| {
            (model.joints.iter())
                .map(|j| {
                    let (lo, hi) = (j.lower.max(-3.0), j.upper.min(3.0));
                    let mid = 0.5 * (lo + hi);
                    mid + 0.3 * (next() - 0.5) * (hi - lo)
                })
                .collect()
        })
        .collect();
    PathSpline::through(&points).unwrap()
}

/// Samples per interval of the written trajectory (`most_asked_as_played`).
pub const SAMPLES: usize = 20;

/// The most the played trajectory asks of a limit: the largest of |q̇|/v̄ and τ/bound over
/// joints and samples, τ the inverse dynamics plus damping, bound the torque limit (and the
/// motor's envelope at the joint's speed) times 1 − margin. Returns (share, joint, time,
/// "speed" or "torque").
pub fn most_asked_as_played(
    scenario: &faze4::sim::Scenario,
    trajectory: &faze4::traj::TimedTrajectory,
) -> (f64, usize, f64, &'static str) {
    let model = &scenario.model;
    let (played, _) = faze4::retime::command(model, trajectory).unwrap();
    let n = model.dof();
    let keep = 1.0 - faze4::retime::DEFAULT_MARGIN;
    let mut data = Data::new(model);
    let (mut q, mut v, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut most = (0.0, 0, 0.0, "");
    let times: Vec<f64> = trajectory.points.iter().map(|p| p.time_from_start).collect();
    for w in times.windows(2) {
        for k in 0..=SAMPLES {
            let t = w[0] + (w[1] - w[0]) * k as f64 / SAMPLES as f64;
            played.eval_with_acceleration(t, &mut q, &mut v, &mut a);
            let tau = rnea(model, &mut data, &q, &v, &a).as_slice().to_vec();
            for j in 0..n {
                let effort = scenario.controller.gains.effort[j];
                let (mut lo, mut hi) = (-effort, effort);
                if let Some(Some(m)) = scenario.motors.as_ref().map(|m| &m[j]) {
                    let (mlo, mhi) = m.joint_bounds(model.joints[j].gear_ratio, v[j]);
                    (lo, hi) = (lo.max(mlo), hi.min(mhi));
                }
                let needed = tau[j] + model.joints[j].damping * v[j];
                let torque = match needed >= 0.0 {
                    true => needed / (keep * hi),
                    false => needed / (keep * lo),
                };
                let speed = v[j].abs() / scenario.speed_limit[j];
                for (share, what) in [(torque, "torque"), (speed, "speed")] {
                    if share > most.0 {
                        most = (share, j, t, what);
                    }
                }
            }
        }
    }
    most
}
