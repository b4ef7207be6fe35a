//! The fuzz targets' code (`fuzz/fuzz_targets/`), kept in the library so that the regression
//! tests (`tests/it/fuzz_regressions.rs`) run exactly the same path on every stored input.
//!
//! Each entry point takes arbitrary bytes. Bad input must come back as an error; anything else
//! (a panic in faze4 or a dependency, a broken invariant, asserted here) is a bug.

use std::path::Path;

use crate::algo::{
    Data, State, bias, compute_all_terms, crba, discrete_step, forward_dynamics, forward_kinematics, frame_jacobian,
    frame_position, gravity, rnea,
};
use crate::atomic::Outputs;
use crate::error::{Error, Result};
use crate::geometry::mesh::{Mesh, parse_mesh};
use crate::geometry::{GeometryModel, Robot};
use crate::model::{FrameId, Model, PackagePaths};
use crate::traj::npy::{self, check_array_size};

/// The name the fuzzed URDF goes by in error messages.
pub const URDF_LABEL: &str = "fuzz.urdf";
/// The name the fuzzed `.npy` goes by in error messages.
pub const NPY_LABEL: &str = "fuzz.npy";

/// `urdf_model`: bytes → (if UTF-8) [`Robot::from_urdf_str`] → on success, every algorithm at q = 0
/// and at joint values taken from the bytes, one discrete step from a limit, forward
/// kinematics and Jacobians. `None` if the bytes are not UTF-8 (the CLI refuses those before
/// parsing).
///
/// Checks: a refused model gets a one-line error naming the file; an accepted one is
/// consistent (bodies root to tip, every number finite).
pub fn urdf_model(data: &[u8]) -> Option<Result<Robot>> {
    let text = std::str::from_utf8(data).ok()?;
    let result = Robot::from_urdf_str(text, URDF_LABEL, None, &PackagePaths::default());
    match &result {
        Ok(robot) => {
            check_model(&robot.model);
            check_geometry(&robot.model, &robot.geometry);
            exercise(&robot.model, data);
        }
        Err(e) => check_error(e, URDF_LABEL),
    }
    Some(result)
}

/// The names an `output_set` script writes to, in a directory holding a file `a`, a link `l` to
/// it, a dangling link `m`, a directory `d` and nothing else.
const OUTPUT_NAMES: [&str; 12] = [
    "a",
    "b",
    "c",
    "l",
    "m",
    "d",
    "d/",
    "./a",
    "d/x",
    "b/",
    "d/../b",
    "/dev/null",
];

/// `output_set`: bytes → a script of outputs written through one [`Outputs`] set, the command
/// line's output layer. Each byte pair names an output (`OUTPUT_NAMES`) and whether its writing
/// fails half-way; the last byte says whether the set is committed. Checks: a refused claim is
/// one line naming its option; a set that is not committed (a claim refused, a write failed,
/// abandoned) leaves the directory exactly as it was; a committed one leaves every output
/// holding its bytes (links followed, links kept) and no temporary.
pub fn output_set(data: &[u8]) -> Result<()> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static RUN: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "faze4-fuzz-outputs-{}-{}",
        std::process::id(),
        RUN.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("d")).expect("a fresh directory");
    std::fs::write(dir.join("a"), "old a").expect("a file");
    #[cfg(unix)]
    {
        let _ = std::os::unix::fs::symlink("a", dir.join("l"));
        let _ = std::os::unix::fs::symlink("n", dir.join("m"));
    }
    let before = snapshot(&dir);
    let result = write_outputs(&dir, data);
    let commit = data.last().is_some_and(|b| b % 2 == 0);
    let after = snapshot(&dir);
    match &result {
        Ok(written) if commit => {
            assert!(
                !after.keys().any(|n| n.ends_with(".tmp") || n.ends_with(".bak")),
                "temporary left: {after:?}"
            );
            for (name, bytes) in written {
                if !name.starts_with('/') {
                    assert_eq!(&std::fs::read(dir.join(name)).expect("written"), bytes, "{name}");
                }
            }
            for link in ["l", "m"] {
                assert!(after[link].starts_with("link"), "{link} replaced: {after:?}");
            }
        }
        _ => assert_eq!(before, after, "an uncommitted set changed the directory"),
    }
    let _ = std::fs::remove_dir_all(&dir);
    result.map(|_| ())
}

/// Claims and writes the outputs `data` names in `dir`; commits when its last byte is even.
/// The outputs written, with their bytes.
fn write_outputs(dir: &Path, data: &[u8]) -> Result<Vec<(String, Vec<u8>)>> {
    let files = Outputs::new();
    let mut written = Vec::new();
    for (k, pair) in data.chunks_exact(2).enumerate().take(8) {
        let name = OUTPUT_NAMES[pair[0] as usize % OUTPUT_NAMES.len()];
        let path = match name.starts_with('/') {
            true => std::path::PathBuf::from(name),
            false => dir.join(name),
        };
        let option = format!("--out{k}");
        if let Err(e) = files.claim(&path, &option) {
            let message = e.to_string();
            assert!(message.starts_with(&option) && !message.contains('\n'), "{message}");
            return Err(e);
        }
        let bytes = format!("output {k} of {}", pair[1]).into_bytes();
        let mut file = files.create(&path)?;
        std::io::Write::write_all(file.writer(), &bytes).map_err(|e| file.error(e))?;
        // an odd second byte: the writing fails half-way (the file is dropped uncommitted)
        if pair[1] % 2 == 1 {
            return Err(Error::argument(option, "failed half-way"));
        }
        file.commit()?;
        written.push((name.to_string(), bytes));
    }
    if data.last().is_some_and(|b| b % 2 == 0) {
        files.commit()?;
    }
    Ok(written)
}

/// Every entry of `dir` (one level below too): a file's bytes, a link's target, `dir`.
fn snapshot(dir: &Path) -> std::collections::BTreeMap<String, String> {
    let mut out = std::collections::BTreeMap::new();
    for sub in ["", "d"] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let name = path
                .strip_prefix(dir)
                .map_or(String::new(), |p| p.display().to_string());
            let what = match std::fs::symlink_metadata(&path) {
                Ok(m) if m.file_type().is_symlink() => format!("link {:?}", std::fs::read_link(&path).ok()),
                Ok(m) if m.is_dir() => "dir".to_string(),
                _ => format!("file {:?}", std::fs::read(&path).ok()),
            };
            out.insert(name, what);
        }
    }
    out
}

/// The name the fuzzed STL goes by in error messages.
pub const STL_LABEL: &str = "fuzz.stl";

/// `stl_mesh`: bytes → [`parse_mesh`] as an STL. Checks: see `check_mesh`.
pub fn stl_mesh(data: &[u8]) -> Result<Mesh> {
    check_mesh(parse_mesh(data, Path::new(STL_LABEL)), STL_LABEL)
}

/// The names the fuzzed mesh file goes by in `mesh_file`, which give its format.
pub const MESH_LABELS: [&str; 3] = ["fuzz.stl", "fuzz.dae", "fuzz.obj"];

/// `mesh_file`: the first byte picks the format (its value mod 3: STL, COLLADA, OBJ), the rest
/// is the file → [`parse_mesh`]. Checks: see `check_mesh`. `None` for no bytes.
pub fn mesh_file(data: &[u8]) -> Option<Result<Mesh>> {
    let (&first, bytes) = data.split_first()?;
    let label = MESH_LABELS[first as usize % 3];
    Some(check_mesh(parse_mesh(bytes, Path::new(label)), label))
}

/// An error is one line naming the file; an accepted mesh has at least one triangle, finite
/// vertices, distinct in-range indices in every triangle, and no two bit-identical vertices.
fn check_mesh(result: Result<Mesh>, label: &str) -> Result<Mesh> {
    match &result {
        Ok(mesh) => {
            assert!(!mesh.triangles.is_empty(), "a mesh without triangles accepted");
            assert!(
                mesh.vertices.iter().flatten().all(|c| c.is_finite()),
                "non-finite vertex accepted"
            );
            let n = mesh.vertices.len() as u32;
            for t in &mesh.triangles {
                assert!(t.iter().all(|&i| i < n), "index out of range: {t:?}");
                assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], "collapsed triangle {t:?}");
            }
            let mut keys: Vec<[u32; 3]> = (mesh.vertices.iter()).map(|p| p.map(|c| (c + 0.0).to_bits())).collect();
            keys.sort_unstable();
            keys.dedup();
            assert_eq!(keys.len(), mesh.vertices.len(), "vertices not welded");
        }
        Err(e) => check_error(e, label),
    }
    result
}

/// A time-stamped trajectory format, one fuzz target each (`trajectory_yaml`, …): the three
/// text formats and MCAP as [`crate::traj::files::parse`] reads a file's bytes, and the two
/// bags MCAP's slot reaches only through their magic, from their own readers' entries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrajectoryFormat {
    /// `trajectory_yaml`: [`crate::traj::files::parse`] as YAML.
    Yaml,
    /// `trajectory_json`: [`crate::traj::files::parse`] as JSON.
    Json,
    /// `trajectory_csv`: [`crate::traj::files::parse`] as CSV.
    Csv,
    /// `trajectory_mcap`: [`crate::traj::files::parse`] as MCAP (which reads any bag its bytes
    /// say: a ROS 1 bag, a rosbag2 SQLite database, zstd).
    Mcap,
    /// `trajectory_db3`: a rosbag2 SQLite database from bytes
    /// ([`crate::traj::files::bag::db3::collect_bytes`]), read without touching the disk.
    Db3,
    /// `trajectory_ros1`: a ROS 1 bag from a slice ([`crate::traj::files::bag::ros1::collect`]).
    Ros1,
}

impl TrajectoryFormat {
    /// The name the fuzzed file goes by in error messages.
    pub fn label(self) -> &'static str {
        match self {
            TrajectoryFormat::Yaml => "fuzz.yaml",
            TrajectoryFormat::Json => "fuzz.json",
            TrajectoryFormat::Csv => "fuzz.csv",
            TrajectoryFormat::Mcap => "fuzz.mcap",
            TrajectoryFormat::Db3 => "fuzz.db3",
            TrajectoryFormat::Ros1 => "fuzz.bag",
        }
    }
}

/// `trajectory_yaml`, `trajectory_json`, `trajectory_csv`, `trajectory_mcap`, `trajectory_db3`,
/// `trajectory_ros1`: bytes → the file of `format` (the first message, the one topic), checked
/// as [`crate::traj::files::parse`] checks it. Checks: an error is one line naming the file
/// first; an accepted trajectory passes [`crate::traj::TimedTrajectory::check`] (at most
/// [`crate::input::MAX_MOVING_JOINTS`] joints, one point or more, times increasing from 0 or
/// later, every point as long as the names); a `.db3` read from bytes writes nothing (Linux:
/// the calling thread's write calls in `/proc/thread-self/io`, where a temporary file of
/// SQLite's, a journal or a WAL would show).
pub fn trajectory(format: TrajectoryFormat, bytes: &[u8]) -> Result<crate::traj::TimedTrajectory> {
    use crate::traj::files::bag::{Collected, db3, ros1};
    use crate::traj::files::{Format, Selection, parse};
    let label = format.label();
    let path = Path::new(label);
    let selection = Selection::default();
    let bag = |collect: &dyn Fn(&mut Collected) -> Result<()>| {
        let mut found = Collected::default();
        collect(&mut found)?;
        let read = found.trajectory(&selection, path)?.0;
        read.trajectory.check(path)?;
        Ok(read.trajectory)
    };
    let result = match format {
        TrajectoryFormat::Yaml => parse(bytes, Format::Yaml, &selection, path).map(|read| read.trajectory),
        TrajectoryFormat::Json => parse(bytes, Format::Json, &selection, path).map(|read| read.trajectory),
        TrajectoryFormat::Csv => parse(bytes, Format::Csv, &selection, path).map(|read| read.trajectory),
        TrajectoryFormat::Mcap => parse(bytes, Format::Mcap, &selection, path).map(|read| read.trajectory),
        TrajectoryFormat::Db3 => {
            let before = writes();
            let result = bag(&|found| db3::collect_bytes(bytes, found, path));
            assert_eq!(before, writes(), "a .db3 read from bytes wrote a file");
            result
        }
        TrajectoryFormat::Ros1 => bag(&|found| ros1::collect(&mut &bytes[..], found, path)),
    };
    match &result {
        Ok(t) => {
            if let Err(e) = t.check(path) {
                panic!("an accepted trajectory fails its check: {e}");
            }
            assert!(t.joint_names.len() <= crate::input::MAX_MOVING_JOINTS);
            assert!(!t.points.is_empty() && t.points[0].time_from_start >= 0.0);
            let n = t.joint_names.len();
            for (p, q) in t.points.iter().zip(&t.points[1..]) {
                assert!(p.time_from_start < q.time_from_start, "{p:?} {q:?}");
            }
            assert!(t.points.iter().all(|p| p.positions.len() == n));
        }
        Err(e) => check_error(e, label),
    }
    result
}

/// The calling thread's write system calls so far (`syscw` of `/proc/thread-self/io`, read in
/// one call); `None` where there is no such file.
fn writes() -> Option<u64> {
    use std::io::Read;
    let mut buf = [0u8; 512];
    let n = std::fs::File::open("/proc/thread-self/io").ok()?.read(&mut buf).ok()?;
    let io = std::str::from_utf8(&buf[..n]).ok()?;
    io.lines()
        .find_map(|line| line.strip_prefix("syscw:")?.trim().parse().ok())
}

/// The name the fuzzed motors file goes by in error messages.
pub const MOTORS_LABEL: &str = "fuzz.toml";

/// `motors_file`: bytes → (if UTF-8) the motors file's parser
/// ([`crate::config::motors::file_motors`]) for the bundled Faze4 (six joints, `joint_1` …
/// `joint_6`). Checks: an error is one line, `` `motors`: fuzz.toml: … ``; accepted motors are one
/// per joint, each passing [`crate::control::Motor::check`], with ratios and rotors > 0 (a rotor
/// may be 0) where given. `None` if the bytes are not UTF-8.
pub fn motors_file(data: &[u8]) -> Option<Result<Vec<Option<crate::control::JointMotor>>>> {
    let text = std::str::from_utf8(data).ok()?;
    // the bundled model, parsed once: its URDF parse was most of an execution (about 70 a second)
    static MODEL: std::sync::OnceLock<Model> = std::sync::OnceLock::new();
    let model = MODEL.get_or_init(crate::faze4::model);
    let result = crate::config::motors::file_motors(text, Path::new(MOTORS_LABEL), model);
    match &result {
        Ok(motors) => {
            assert_eq!(motors.len(), model.dof());
            for m in motors.iter().flatten() {
                assert_eq!(m.motor.check(), Ok(()), "{m:?}");
                assert!(m.gear_ratio.is_none_or(|r| r.is_finite() && r > 0.0), "{m:?}");
                assert!(m.rotor_inertia.is_none_or(|r| r.is_finite() && r >= 0.0), "{m:?}");
                if let crate::control::Envelope::Stepper { curve } = &m.motor.envelope {
                    assert!(curve.len() >= 2 && curve[0][0] == 0.0, "{curve:?}");
                }
            }
        }
        Err(e) => {
            let message = e.to_string();
            assert!(message.starts_with("`motors`: fuzz.toml: "), "{message:?}");
            assert!(
                !message.contains(['\n', '\r']),
                "the error is not one line: {message:?}"
            );
        }
    }
    Some(result)
}

/// The names the fuzzed COLLADA and OBJ files go by.
pub const DAE_LABEL: &str = "fuzz.dae";
/// See [`DAE_LABEL`].
pub const OBJ_LABEL: &str = "fuzz.obj";

/// `dae_mesh`: bytes → [`parse_mesh`] as a COLLADA file (its claims checked first, then
/// mesh-loader). Checks: a mesh that reads is finite and its indices in range (as `stl_mesh`).
pub fn dae_mesh(data: &[u8]) -> Result<Mesh> {
    check_mesh(parse_mesh(data, Path::new(DAE_LABEL)), DAE_LABEL)
}

/// `obj_mesh`: bytes → [`parse_mesh`] as a Wavefront OBJ file (no `.mtl` read). Checks: a mesh
/// that reads is finite and its indices in range (as `stl_mesh`).
pub fn obj_mesh(data: &[u8]) -> Result<Mesh> {
    check_mesh(parse_mesh(data, Path::new(OBJ_LABEL)), OBJ_LABEL)
}

/// `npy_samples`: bytes → [`npy::parse_samples`]. Checks: an error is one line naming the
/// file; accepted samples are N ≥ 2 rows of the same non-zero width, all finite.
pub fn npy_samples(data: &[u8]) -> Result<Vec<Vec<f64>>> {
    let result = npy::parse_samples(data, Path::new(NPY_LABEL));
    match &result {
        Ok(rows) => {
            assert!(rows.len() >= 2, "{} rows accepted", rows.len());
            let width = rows[0].len();
            assert!(width > 0, "zero-width rows accepted");
            for row in rows {
                assert_eq!(row.len(), width, "ragged rows");
                assert!(row.iter().all(|v| v.is_finite()), "non-finite sample accepted: {row:?}");
            }
        }
        Err(e) => check_error(e, NPY_LABEL),
    }
    result
}

/// One line, naming the input first.
fn check_error(e: &Error, label: &str) {
    let message = e.to_string();
    assert!(
        message.starts_with(&format!("{label}: ")),
        "the error does not name the file first: {message:?}"
    );
    assert!(
        !message.contains(['\n', '\r']),
        "the error is not one line: {message:?}"
    );
}

/// The builder's promises: bodies numbered root to tip, one body per moving joint, each driven
/// by a coordinate (its own, or a mimic leader's), unit axes, positive masses, and no number
/// that is not finite (limits may be infinite, not NaN).
fn check_model(model: &Model) {
    let (n, nb) = (model.dof(), model.num_bodies());
    assert!(n <= nb);
    assert_eq!(model.parent.len(), nb);
    assert_eq!(model.tree_pose.len(), nb);
    assert_eq!(model.s.len(), nb);
    assert_eq!(model.inertia.len(), nb);
    assert!(!model.frames.is_empty(), "a model without frames");
    for i in 0..n {
        let joint = &model.joints[i];
        assert!((joint.axis.norm() - 1.0).abs() < 1e-9, "axis {:?}", joint.axis);
        assert!(!joint.lower.is_nan() && !joint.upper.is_nan() && joint.lower <= joint.upper);
        assert!(joint.damping.is_finite() && joint.damping >= 0.0);
        assert!(joint.effort.is_none_or(|e| e > 0.0));
    }
    for i in 0..nb {
        if let Some(p) = model.parent[i] {
            assert!(p < i, "body {i} has parent {p}");
        }
        let body = &model.bodies[i];
        assert!(body.coordinate < n && body.multiplier.is_finite() && body.offset.is_finite());
        assert!(body.follower || (body.multiplier == 1.0 && body.offset == 0.0));
        assert!((body.axis.norm() - 1.0).abs() < 1e-9, "axis {:?}", body.axis);
        let inertia = &model.inertia[i];
        assert!(
            inertia.is_finite() && inertia.mass > 0.0,
            "body {i} ({}): inertia {inertia:?}",
            body.joint
        );
        assert!(
            model.tree_pose[i].is_finite() && model.s[i].is_finite(),
            "joint {}: placement {:?}",
            body.joint,
            model.tree_pose[i]
        );
    }
    for frame in &model.frames {
        assert!(frame.body.is_none_or(|b| b.0 < nb));
        assert!(
            frame.placement.is_finite(),
            "frame {}: {:?}",
            frame.name,
            frame.placement
        );
    }
}

/// Every shape sits on a frame of its own link, at a finite placement.
fn check_geometry(model: &Model, geometry: &GeometryModel) {
    for g in geometry.visuals.iter().chain(&geometry.collisions) {
        assert_eq!(model.frame(g.frame).name, g.link);
        assert!(g.placement.is_finite(), "{}: {:?}", g.link, g.placement);
    }
}

/// Runs every algorithm; results may be non-finite for extreme models, but nothing may panic.
fn exercise(model: &Model, data: &[u8]) {
    let n = model.dof();
    let mut d = Data::new(model);
    let zero = vec![0.0; n];
    compute_all_terms(model, &mut d, &zero, &zero);

    // Joint values from the input: small angles from single bytes, and raw 8-byte floats
    // (any value, NaN and ±∞ included).
    let small: Vec<f64> = (0..n).map(|i| byte(data, i, 0) as f64 / 16.0 - 8.0).collect();
    let raw: Vec<f64> = (0..n)
        .map(|i| f64::from_le_bytes(std::array::from_fn(|k| byte(data, 8 * i + k, 1))))
        .collect();
    let velocity: Vec<f64> = (0..n).map(|i| byte(data, i, 2) as f64 - 128.0).collect();
    for q in [&small, &raw] {
        compute_all_terms(model, &mut d, q, &velocity);
        crba(model, &mut d, q);
        rnea(model, &mut d, q, &velocity, &small);
        gravity(model, &mut d, q);
        bias(model, &mut d, q, &velocity);
        let _ = forward_dynamics(model, &mut d, q, &velocity, &small);
        forward_kinematics(model, &mut d, q);
        for frame in 0..model.frames.len() {
            frame_jacobian(model, &mut d, FrameId(frame));
            let _ = frame_position(model, q, FrameId(frame));
        }
    }

    // One step from each joint's upper limit (or the small angle) moving fast outwards, so
    // that the limit solve runs.
    let q: Vec<f64> = (0..n)
        .map(|i| match model.joints[i].upper {
            u if u.is_finite() => u,
            _ => small[i],
        })
        .collect();
    let v: Vec<f64> = velocity.iter().map(|v| v.abs() + 1.0).collect();
    let tau: Vec<f64> = (0..n).map(|i| (byte(data, i, 3) as f64 - 128.0) * 10.0).collect();
    let _ = discrete_step(model, &mut d, &mut State::at(&q, &v, &tau, 2e-4));
    let _ = model.default_tool_frame();
}

/// Byte `i` of the input, cycled, shifted by `salt` so that the derived vectors differ.
fn byte(data: &[u8], i: usize, salt: usize) -> u8 {
    match data.len() {
        0 => 0,
        len => data[(i.wrapping_mul(7).wrapping_add(salt * 13)) % len],
    }
}

/// `python_conversion`: the Python binding's conversions without Python. The first byte picks
/// what: even, keyword values (a command, then up to 8 keywords, each an option's name and a
/// tree of [`Object`]s up to 40 levels deep: dicts, lists, numpy arrays, numbers, strings, paths,
/// iterables, values the reader cut) → [`crate::config::object::run_config`], what the binding
/// calls with the trees it reads; odd, the arrays a replay takes (`q_traj`, and `t`, `v`, `a`,
/// joint names), their claimed shapes first checked as the binding checks them, then
/// [`npy::samples_from_array`] or [`crate::traj::TimedTrajectory::from_arrays`].
///
/// Checks: a type error is one line naming its keyword first; any other error is one line once
/// escaped as Python shows it, naming an option (or `command`) first; motors given as a dict
/// resolve on the bundled Faze4 to motors that pass their check, or to a one-line error;
/// accepted frames are 2 rows or more, finite; an accepted timed trajectory passes its check.
/// `None` for no bytes.
pub fn python_conversion(data: &[u8]) -> Option<std::result::Result<(), String>> {
    let (&first, rest) = data.split_first()?;
    let mut bytes = Bytes { data: rest, at: 0 };
    Some(match first % 2 {
        0 => keywords(&mut bytes),
        _ => arrays(&mut bytes).map_err(|e| e.to_string()),
    })
}

use crate::config::object::{Keyword, Limit, Object};

/// The fuzz input read a piece at a time; past its end, zeros.
struct Bytes<'a> {
    data: &'a [u8],
    at: usize,
}

impl Bytes<'_> {
    fn byte(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }

    fn eight(&mut self) -> [u8; 8] {
        std::array::from_fn(|_| self.byte())
    }

    fn done(&self) -> bool {
        self.at >= self.data.len()
    }

    /// A word from `words` or, when the first byte is a multiple of 4 (`4n`), the `n` bytes
    /// that follow (up to 63) as (lossy) UTF-8.
    fn text(&mut self, words: &[&str]) -> String {
        let b = self.byte();
        match b % 4 {
            0 => {
                let n = (b / 4) as usize;
                let raw: Vec<u8> = (0..n).map(|_| self.byte()).collect();
                String::from_utf8_lossy(&raw).into_owned()
            }
            _ => words[b as usize / 4 % words.len()].to_string(),
        }
    }
}

/// The words a fuzzed string or key is most often: motors-dict keys and values, presets,
/// choices, per-joint texts.
const WORDS: &[&str] = &[
    "joint",
    "kind",
    "stepper",
    "dc",
    "servo",
    "curve",
    "stall_torque",
    "no_load_speed",
    "peak_torque",
    "continuous_torque",
    "gear_ratio",
    "rotor_inertia",
    "efficiency",
    "name",
    "label",
    "step_angle",
    "detent_torque",
    "microsteps",
    "joint_1",
    "joint_2",
    "joint_6",
    "faze4",
    "nema17",
    "a.toml",
    "1,2,3,4,5,6",
    "0.5",
    "mid",
    "none",
    "",
    "x\ny",
    "1e400",
    "-1",
];

/// An option's name as a keyword: a byte under 255 picks one of every field's names and old
/// names, and one that is none; 255 is followed by a text ([`Bytes::text`], so that a seed can
/// spell its keywords).
fn keyword_name(bytes: &mut Bytes) -> String {
    let names: Vec<&str> = (crate::config::fields::FIELDS.iter())
        .flat_map(|f| std::iter::once(f.name).chain(f.aliases.iter().copied()))
        .chain(["colour"])
        .collect();
    match bytes.byte() {
        255 => bytes.text(&names),
        b => names[b as usize % names.len()].to_string(),
    }
}

/// Deepest tree built: past [`crate::config::object::MAX_NESTING`].
const MAX_FUZZ_DEPTH: usize = 40;

/// A tree of Python values from the bytes, `depth` deep.
fn object(bytes: &mut Bytes, depth: usize) -> Object {
    if depth >= MAX_FUZZ_DEPTH || bytes.done() {
        return Object::None;
    }
    let b = bytes.byte();
    let count = |bytes: &mut Bytes| bytes.byte() as usize % 8;
    match b % 16 {
        0 => Object::None,
        1 => Object::Bool(b & 16 != 0),
        2 => Object::Int((b as i128 >> 4) - 4),
        3 => Object::Int(i64::from_le_bytes(bytes.eight()) as i128 * if b & 16 != 0 { 1 << 64 } else { 1 }),
        4 => Object::Float(f64::from_le_bytes(bytes.eight())),
        5 => Object::Float((b >> 4) as f64 / 4.0),
        6 | 7 => Object::Str(bytes.text(WORDS)),
        8 => Object::Path(bytes.text(WORDS).into()),
        9 | 10 => {
            let n = count(bytes);
            Object::Dict((0..n).map(|_| (bytes.text(WORDS), object(bytes, depth + 1))).collect())
        }
        11 | 12 => {
            let n = count(bytes);
            Object::List((0..n).map(|_| object(bytes, depth + 1)).collect())
        }
        13 => {
            let dims = 1 + bytes.byte() as usize % 3;
            let shape: Vec<usize> = (0..dims).map(|_| bytes.byte() as usize % 4).collect();
            array(bytes, &shape)
        }
        14 => {
            let n = count(bytes);
            Object::Iterable((0..n).map(|_| object(bytes, depth + 1)).collect())
        }
        _ => match b >> 4 {
            0 => Object::Cut(Limit::Depth),
            1 => Object::Cut(Limit::Count),
            _ => Object::Other("object".into()),
        },
    }
}

/// A numpy array of `shape` (at least one dimension) as the binding reads it: its items along
/// the first axis, floats or arrays.
fn array(bytes: &mut Bytes, shape: &[usize]) -> Object {
    let items = (0..shape[0])
        .map(|_| match shape.len() {
            1 => Object::Float((bytes.byte() as f64 - 128.0) / 8.0),
            _ => array(bytes, &shape[1..]),
        })
        .collect();
    Object::Array {
        shape: shape.to_vec(),
        items,
    }
}

/// The Python type's name of a value, as the binding gives it with a keyword.
fn python_type(object: &Object) -> String {
    match object {
        Object::None => "NoneType",
        Object::Bool(_) => "bool",
        Object::Int(_) => "int",
        Object::Float(_) => "float",
        Object::Str(_) => "str",
        Object::Path(_) => "PosixPath",
        Object::Dict(_) => "dict",
        Object::List(_) => "list",
        Object::Array { .. } => "ndarray",
        Object::Iterable(_) => "generator",
        Object::Other(name) => name,
        Object::Cut(_) => "list",
    }
    .to_string()
}

/// The keywords half of [`python_conversion`].
fn keywords(bytes: &mut Bytes) -> std::result::Result<(), String> {
    use crate::config::object::{Refusal, run_config};
    const COMMANDS: [&str; 5] = ["wave", "replay", "shape", "retime", "walk"];
    let command = COMMANDS[bytes.byte() as usize % COMMANDS.len()];
    let mut given = Vec::new();
    while given.len() < 8 && !bytes.done() {
        let name = keyword_name(bytes);
        let value = object(bytes, 0);
        given.push(Keyword {
            name,
            type_name: python_type(&value),
            value,
        });
    }
    match run_config(command, &given) {
        Ok(config) => check_motors(&config),
        Err(Refusal::Type(line)) => {
            assert!(
                given.iter().any(|k| line.starts_with(&format!("{}: ", k.name))),
                "a type error names no keyword: {line:?}"
            );
            assert!(!line.contains(['\n', '\r']), "{line:?}");
            Err(line)
        }
        Err(Refusal::Value(e)) => Err(check_keyword_error(&e, &given)),
    }
}

/// A library error as Python shows it: one line, options named as keywords, an option (or
/// `command`, or a keyword of `given` that is no option, as it was given) first.
fn check_keyword_error(e: &Error, given: &[Keyword]) -> String {
    let line = crate::error::escape_controls(&crate::error::in_words(&e.to_string(), crate::error::Words::Keywords));
    assert!(!line.contains(['\n', '\r']), "not one line: {line:?}");
    let first = line.split([':', ' ']).next().unwrap_or_default();
    // a keyword as given may hold ':' or ' ' itself
    let named = |name: &str| {
        first == name
            || [format!("`{name}`:"), format!("`{name}` ")]
                .iter()
                .any(|n| line.starts_with(n.as_str()))
    };
    assert!(
        named("command")
            || crate::config::fields::any_field(first).is_some()
            || given.iter().any(|k| named(&crate::error::escape_controls(&k.name)))
            // a keyword holding a backtick is shown with the options it quotes reworded
            // (`error::in_words`): it cannot be matched as given
            || given.iter().any(|k| k.name.contains('`')),
        "the error does not name an option first: {line:?}"
    );
    line
}

/// Motors given as a dict, resolved on the bundled Faze4 as a run would.
fn check_motors(config: &crate::config::RunConfig) -> std::result::Result<(), String> {
    use crate::config::Motors;
    let Some(motors @ Motors::Entries(_)) = &config.arm.motors else {
        return Ok(());
    };
    static MODEL: std::sync::OnceLock<Model> = std::sync::OnceLock::new();
    let model = MODEL.get_or_init(crate::faze4::model);
    match crate::config::motors::resolve(Some(motors), config.arm.supply_voltage, model) {
        Ok(set) => {
            let set = set.expect("motors given");
            assert_eq!(set.len(), model.dof());
            for m in set.iter().flatten() {
                assert_eq!(m.motor.check(), Ok(()), "{m:?}");
            }
            Ok(())
        }
        Err(e) => Err(check_keyword_error(&e, &[])),
    }
}

/// The arrays half of [`python_conversion`]: shapes claimed up to 2³² per axis are checked as
/// the binding checks them; arrays of up to 4,096 values are then built and converted.
fn arrays(bytes: &mut Bytes) -> Result<()> {
    use ndarray::Array2;
    let claim = |bytes: &mut Bytes| match bytes.byte() {
        b if b < 250 => b as usize % 12,
        _ => u32::from_le_bytes(std::array::from_fn(|_| bytes.byte())) as usize,
    };
    let (rows, columns) = (claim(bytes), claim(bytes));
    let q_traj = Path::new("q_traj");
    check_array_size(q_traj, &[rows, columns])?;
    let table = |bytes: &mut Bytes, rows: usize, columns: usize| -> Result<Array2<f64>> {
        if rows * columns > 4096 {
            return Err(Error::argument("q_traj", "too large to build in the fuzz target"));
        }
        let values = (0..rows * columns)
            .map(|_| match bytes.byte() {
                255 => f64::from_le_bytes(bytes.eight()),
                b => b as f64 / 16.0,
            })
            .collect();
        Ok(Array2::from_shape_vec((rows, columns), values).expect("the shape's values"))
    };
    let q = table(bytes, rows, columns)?;
    let timed = bytes.byte();
    if timed.is_multiple_of(2) {
        let frames = npy::samples_from_array(q_traj, q.view());
        match &frames {
            Ok(rows) => {
                assert!(
                    rows.len() >= 2
                        && rows
                            .iter()
                            .all(|r| r.len() == columns && r.iter().all(|v| v.is_finite()))
                );
            }
            Err(e) => check_error(e, "q_traj"),
        }
        return frames.map(|_| ());
    }
    let t_len = claim(bytes);
    check_array_size(Path::new("t"), &[t_len])?;
    let t = table(bytes, 1, t_len.min(4096))?.into_raw_vec_and_offset().0;
    let other = |bytes: &mut Bytes, name: &str| -> Result<Option<Array2<f64>>> {
        match bytes.byte() % 3 {
            0 => Ok(None),
            1 => Ok(Some(table(bytes, rows, columns)?)),
            _ => {
                let (r, c) = (claim(bytes), claim(bytes));
                check_array_size(Path::new(name), &[r, c])?;
                Ok(Some(table(bytes, r, c)?))
            }
        }
    };
    let v = other(bytes, "v")?;
    let a = other(bytes, "a")?;
    let names = match bytes.byte() % 3 {
        0 => None,
        // one name a column, as a caller would give them; an empty array may claim 2³² columns,
        // and a list past the joints' cap (256) is as good as a longer one
        1 => Some((0..columns.min(300)).map(|j| format!("j{j}")).collect()),
        _ => Some((0..bytes.byte() % 8).map(|_| bytes.text(WORDS)).collect()),
    };
    let result = crate::traj::TimedTrajectory::from_arrays(
        names,
        &t,
        q.view(),
        v.as_ref().map(|v| v.view()),
        a.as_ref().map(|a| a.view()),
        q_traj,
    );
    match &result {
        Ok(trajectory) => {
            if let Err(e) = trajectory.check(q_traj) {
                panic!("accepted arrays fail the trajectory's check: {e}");
            }
        }
        Err(e) => check_error(e, "q_traj"),
    }
    result.map(|_| ())
}
