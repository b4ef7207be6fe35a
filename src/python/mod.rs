//! The Python module `faze4._faze4` (cargo feature `python`; `pyproject.toml` builds it with
//! maturin; `python/faze4/__init__.py` is the API on top). Thin by design:
//!
//! * the keywords fill the library's own configuration ([`crate::config::RunConfig`]) field by
//!   field ([`crate::config::fields`]), each value converted by the field's kind (a value of
//!   another type is a `TypeError`); the runs, sweeps and searches are then the library's, as
//!   the binary's are, so defaults, checks, summaries are the binary's, and a message names
//!   options as keywords (`dt`) where the binary writes flags (`--dt`);
//! * `Robot` holds the model its keywords load (`robot`, `motors`, …; `payload_kg` and
//!   `no_gravity` applied as a run applies them) and one `Data` workspace for the dynamics
//!   calls.
//!
//! A run releases the GIL and looks for signals at every look at its stop flag (every 1,024
//! steps); sweeps and searches run on a worker thread while the calling thread, the GIL
//! released, waits and looks for signals every [`SIGNAL_POLL`]. Either way Ctrl-C raises the
//! stop flag and the call raises `KeyboardInterrupt`. A panic on the worker is re-raised on the
//! caller, where PyO3 turns it into a Python exception.

use std::path::Path;
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use numpy::{
    PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use pyo3::types::{PyBool, PyDict, PyList, PyString, PyTuple};

use crate::algo::{Data, crba, forward_dynamics, forward_kinematics, gravity, rnea_checked};
use crate::choice::Choice;
use crate::config::fields::{self, Field, Kind, any_field};
use crate::config::object::{self, Keyword, Object, Reading, Refusal};
use crate::config::{self, Command, Motion, Replayed, RunConfig};
use crate::error::{Words, in_words};
use crate::model::Model;
use crate::output::Capture;
use crate::session::Prepared;
use crate::sim::{StopFlag, Warning};
use crate::sweep::{Family, Found, Grid, MAX_RUNS, Outcome, Row, Seek, Sharing};
use crate::traj::TimedTrajectory;
use crate::traj::npy::check_array_size;

create_exception!(faze4, Error, PyValueError, "Bad input: one line naming what is wrong.");
create_exception!(
    faze4,
    NothingFollows,
    Error,
    "No timing of a retime's path follows, or the path collides (the Python package raises it as Error, or as CannotFollow under strict)."
);

/// How often a waiting call looks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// `faze4.Error` with the library's line, the options it names as keywords (control
/// characters escaped as the binary does).
fn error(message: impl std::fmt::Display) -> PyErr {
    Error::new_err(crate::error::escape_controls(&keywords(&message.to_string())))
}

/// A dynamics algorithm's error with its argument names (`qd`, `qdd`) as `Robot`'s methods
/// call them (`v`, `a`).
fn dynamics_error(e: crate::error::Error) -> PyErr {
    let as_method = |name: &str| {
        match name {
            "qd" => "v",
            "qdd" => "a",
            other => other,
        }
        .to_string()
    };
    match e {
        crate::error::Error::InvalidArgument { option, message } => {
            let message = message.replace(&format!("|{option}|"), &format!("|{}|", as_method(&option)));
            error(format!("{}: {message}", as_method(&option)))
        }
        other => error(other),
    }
}

/// A library message with the options it names as Python keywords.
fn keywords(text: &str) -> String {
    in_words(text, Words::Keywords)
}

/// A Python value as the conversion reads it ([`object::Object`]), `depth` levels below the
/// keyword's own value; each value is admitted by `reading` first (its depth and count caps).
fn read(obj: &Bound<'_, PyAny>, depth: usize, reading: &mut Reading) -> PyResult<Object> {
    if let Err(limit) = reading.admit(depth) {
        return Ok(Object::Cut(limit));
    }
    if obj.is_none() {
        return Ok(Object::None);
    }
    if obj.is_instance_of::<PyBool>() || obj.get_type().name().is_ok_and(|n| n == "bool_") {
        return Ok(Object::Bool(obj.is_truthy()?));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Object::Str(s.to_string()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut entries = Vec::new();
        for (k, v) in d.iter() {
            let v = read(&v, depth + 1, reading)?;
            let cut = matches!(v, Object::Cut(_));
            entries.push((k.str()?.to_string(), v));
            if cut {
                break;
            }
        }
        return Ok(Object::Dict(entries));
    }
    if let Ok(array) = obj.cast::<PyUntypedArray>()
        && array.ndim() > 0
    {
        // a complex array is no array of numbers (its items would convert to float, below)
        if array.dtype().kind() == b'c' {
            return Ok(Object::Other(type_name(obj)?));
        }
        return Ok(Object::Array {
            shape: array.shape().to_vec(),
            items: read_items(obj.try_iter()?, depth, reading)?,
        });
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        return Ok(Object::List(read_items(obj.try_iter()?, depth, reading)?));
    }
    if let Ok(n) = obj.extract::<i128>() {
        return Ok(Object::Int(n));
    }
    // a complex number is not a real one: numpy's complex scalars convert to float, dropping
    // the imaginary part with only a warning
    let name = obj.get_type().name()?;
    let name = name.to_cow()?;
    if name.starts_with("complex") || name == "clongdouble" {
        return Ok(Object::Other(type_name(obj)?));
    }
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(Object::Float(x));
    }
    if let Ok(p) = obj.extract::<std::path::PathBuf>() {
        return Ok(Object::Path(p));
    }
    if reading.iterates(depth)
        && let Ok(iter) = obj.try_iter()
    {
        return Ok(Object::Iterable(read_items(iter, depth, reading)?));
    }
    Ok(Object::Other(obj.get_type().name()?.to_string()))
}

/// A value's type as messages name it, an array by its dtype too ("ndarray of complex128"):
/// its type alone names no fault.
fn type_name(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(match obj.cast::<PyUntypedArray>() {
        Ok(array) => format!("ndarray of {}", array.dtype()),
        Err(_) => obj.get_type().name()?.to_string(),
    })
}

/// The items of an iterable `depth` levels down, read until the first one [`Reading`] cuts.
fn read_items(iter: Bound<'_, pyo3::types::PyIterator>, depth: usize, reading: &mut Reading) -> PyResult<Vec<Object>> {
    let mut out = Vec::new();
    for item in iter {
        let item = read(&item?, depth + 1, reading)?;
        let cut = matches!(item, Object::Cut(_));
        out.push(item);
        if cut {
            break;
        }
    }
    Ok(out)
}

/// The configuration of `command` (`wave`, `replay`, `shape`, `retime`) with the keywords of
/// `options`, each read ([`read`]) and set by name ([`object::run_config`]).
fn run_config(command: &str, options: &Bound<'_, PyDict>) -> PyResult<RunConfig> {
    let mut keywords = Vec::with_capacity(options.len());
    for (key, obj) in options.iter() {
        let name: String = key.extract()?;
        let kind = any_field(&name).map_or(Kind::Flag, |f| f.kind);
        keywords.push(Keyword {
            type_name: type_name(&obj)?,
            value: read(&obj, 0, &mut Reading::new(kind))?,
            name,
        });
    }
    object::run_config(command, &keywords).map_err(|refusal| match refusal {
        Refusal::Type(line) => PyTypeError::new_err(line),
        Refusal::Value(e) => error(e),
    })
}

/// Warnings as Python's lines.
fn warning_lines(warnings: &[Warning]) -> Vec<String> {
    warnings.iter().map(|w| keywords(&w.to_string())).collect()
}

/// Runs `work` on a worker thread with the GIL released, looking for signals every
/// [`SIGNAL_POLL`]; a signal's exception (KeyboardInterrupt) raises `stop`, waits for the
/// worker to end, and is returned.
fn interruptible<T: Send>(py: Python<'_>, stop: &StopFlag, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    std::thread::scope(|s| {
        let (done_tx, done_rx) = mpsc::channel::<()>();
        let worker = s.spawn(move || {
            // sent when the worker ends, by return or by panic
            struct Done(mpsc::Sender<()>);
            impl Drop for Done {
                fn drop(&mut self) {
                    let _ = self.0.send(());
                }
            }
            let _done = Done(done_tx);
            work()
        });
        // the receiver is moved in and out of each wait (it is Send, not Sync)
        let mut done_rx = done_rx;
        loop {
            let (finished, rx) = py.detach(move || (done_rx.recv_timeout(SIGNAL_POLL).is_ok(), done_rx));
            done_rx = rx;
            if finished {
                break;
            }
            if let Err(interrupt) = py.check_signals() {
                stop.raise();
                py.detach(move || {
                    let _ = done_rx.recv();
                });
                let _ = worker.join();
                return Err(interrupt);
            }
        }
        match worker.join() {
            Ok(value) => Ok(value),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// A float64 vector of `n` finite values from `obj`: a 1-D numpy array of real numbers (any
/// strides), or a sequence of numbers. Anything else is an error naming `name`.
fn vector(obj: &Bound<'_, PyAny>, name: &str, n: usize) -> PyResult<Vec<f64>> {
    let values: Vec<f64> = if let Ok(array) = obj.cast::<PyArray1<f64>>() {
        let array = array.readonly();
        array.as_array().to_vec()
    } else if let Ok(array) = obj.cast::<PyUntypedArray>() {
        let kind = array.dtype().kind();
        if !matches!(kind, b'f' | b'i' | b'u') {
            return Err(PyTypeError::new_err(format!(
                "{name}: dtype {} is not a real number type (float64 expected)",
                array.dtype()
            )));
        }
        if array.ndim() != 1 {
            return Err(error(format!(
                "{name}: shape {:?}; expected ({n},), one value per joint",
                array.shape()
            )));
        }
        // an exact conversion (float32, integers), strides honoured
        let converted = array.call_method1("astype", ("float64",))?;
        let converted = converted.cast::<PyArray1<f64>>()?.readonly();
        converted.as_array().to_vec()
    } else {
        obj.extract::<Vec<f64>>().map_err(|_| {
            PyTypeError::new_err(format!(
                "{name}: expected a float64 array or a sequence of {n} numbers, got {}",
                obj.get_type().name().map(|s| s.to_string()).unwrap_or_default()
            ))
        })?
    };
    if values.len() != n {
        return Err(error(format!(
            "{name}: {} values; the model has {n} joints",
            values.len()
        )));
    }
    if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(error(format!("{name}: J{} is {v}: every value must be finite", i + 1)));
    }
    Ok(values)
}

/// An arm: its model as a run of the same options loads it, and a dynamics workspace.
#[pyclass(subclass, module = "faze4._faze4", name = "Robot")]
pub struct PyRobot {
    /// The model of the dynamics calls (payload and gravity as a run applies them).
    model: Model,
    data: Mutex<Data>,
    effort: Vec<f64>,
}

impl PyRobot {
    fn data(&self) -> std::sync::MutexGuard<'_, Data> {
        // a panic while it was held leaves no half-written state that matters: every call
        // writes what it reads
        self.data.lock().unwrap_or_else(|p| p.into_inner())
    }
}

#[pymethods]
impl PyRobot {
    /// Loads the arm the keywords describe (`robot`, `motors`, `payload_kg`, …, the options every
    /// run command shares). `faze4.Robot.faze4()` and `faze4.Robot.from_urdf()` call it.
    #[new]
    fn new(options: &Bound<'_, PyDict>) -> PyResult<Self> {
        let config = run_config("wave", options)?;
        let arm = config::load_arm(&config.arm).map_err(error)?;
        let model = &arm.robot.model;
        let effort = crate::sim::effort_limits(model, config.control.effort.as_deref(), arm.motors.as_deref());
        let model = crate::sim::simulated_model(model, arm.tool, config.arm.payload_kg, !config.arm.no_gravity);
        Ok(PyRobot {
            data: Mutex::new(Data::new(&model)),
            model,
            effort,
        })
    }

    /// Degrees of freedom (moving joints).
    #[getter]
    fn dof(&self) -> usize {
        self.model.dof()
    }

    /// The moving joints' names, in the order of q (depth-first from the root, as Drake).
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.model.joints.iter().map(|j| j.name.clone()).collect()
    }

    /// Every link's name (fixed ones included; `frame_pose` takes them).
    #[getter]
    fn link_names(&self) -> Vec<String> {
        self.model.frames.iter().map(|f| f.name.clone()).collect()
    }

    /// Torque (force) limits per joint as a run uses them, N·m or N; inf where unlimited.
    #[getter]
    fn effort<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.effort)
    }

    /// Lower position limits per joint (rad or m); -inf where unlimited.
    #[getter]
    fn lower<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v: Vec<f64> = self.model.joints.iter().map(|j| j.lower).collect();
        PyArray1::from_vec(py, v)
    }

    /// Upper position limits per joint (rad or m); inf where unlimited.
    #[getter]
    fn upper<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v: Vec<f64> = self.model.joints.iter().map(|j| j.upper).collect();
        PyArray1::from_vec(py, v)
    }

    /// M(q), the joint-space mass matrix (dof, dof) (CRBA; rotor inertias included).
    fn mass_matrix<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let n = self.model.dof();
        let q = vector(q, "q", n)?;
        let mut data = self.data();
        let m = crba(&self.model, &mut data, &q);
        // nalgebra is column-major, M symmetric: its storage read row-major is M too
        PyArray1::from_slice(py, m.as_slice()).reshape([n, n])
    }

    /// g(q), the generalized gravity forces (dof,).
    fn gravity<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = vector(q, "q", self.model.dof())?;
        let mut data = self.data();
        Ok(PyArray1::from_slice(py, gravity(&self.model, &mut data, &q).as_slice()))
    }

    /// τ = M(q) a + C(q, v) v + g(q), inverse dynamics by RNEA (dof,).
    fn rnea<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.model.dof();
        let (q, v, a) = (vector(q, "q", n)?, vector(v, "v", n)?, vector(a, "a", n)?);
        let mut data = self.data();
        let tau = rnea_checked(&self.model, &mut data, &q, &v, &a).map_err(dynamics_error)?;
        Ok(PyArray1::from_slice(py, tau.as_slice()))
    }

    /// a = M(q)⁻¹ (τ − D v − C(q, v) v − g(q)), forward dynamics (dof,), D the joint damping.
    fn aba<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.model.dof();
        let (q, v, tau) = (vector(q, "q", n)?, vector(v, "v", n)?, vector(tau, "tau", n)?);
        let mut data = self.data();
        let qdd = forward_dynamics(&self.model, &mut data, &q, &v, &tau).map_err(dynamics_error)?;
        Ok(PyArray1::from_slice(py, qdd.as_slice()))
    }

    /// The world pose of link `link` at q, a (4, 4) homogeneous transform (m).
    fn frame_pose<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        link: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = vector(q, "q", self.model.dof())?;
        let frame = config::tool_frame(&self.model, Some(link)).map_err(|_| {
            error(format!(
                "link: no link '{link}' in {} (links: {})",
                self.model.source,
                self.link_names().join(", ")
            ))
        })?;
        let mut data = self.data();
        forward_kinematics(&self.model, &mut data, &q);
        let pose = &data.frame_pose[frame.0];
        let mut t = [0.0; 16];
        for r in 0..3 {
            for c in 0..3 {
                t[4 * r + c] = pose.rot[(r, c)];
            }
            t[4 * r + 3] = pose.pos[r];
        }
        t[15] = 1.0;
        PyArray1::from_slice(py, &t).reshape([4, 4])
    }

    fn __repr__(&self) -> String {
        format!("faze4.Robot({}, {} joints)", self.model.source, self.model.dof())
    }
}

/// An N×dof float64 array's rows, checked as a `.npy` trajectory is (`label` names it), as
/// what a replay plays.
/// A time-stamped trajectory's arrays besides its positions: `t` (N,) in s, then `v` and `a`
/// (N, J) or `None`, and the joints' names (`None`: the model's joints in order).
type TimedArrays<'py> = (
    PyReadonlyArray1<'py, f64>,
    Option<PyReadonlyArray2<'py, f64>>,
    Option<PyReadonlyArray2<'py, f64>>,
    Option<Vec<String>>,
);

/// What a replay given as arrays plays: `q_traj` (N, dof) frames, or with `timed` a
/// time-stamped trajectory as a trajectory file gives one.
fn frames(q_traj: Option<PyReadonlyArray2<'_, f64>>, timed: Option<TimedArrays<'_>>) -> PyResult<Option<Replayed>> {
    let label = Path::new("q_traj");
    let Some(q) = q_traj else {
        return Ok(None);
    };
    // each array as a .npy of it would be capped, before a value is copied
    check_array_size(label, q.shape()).map_err(error)?;
    if let Some((t, v, a, _)) = &timed {
        check_array_size(Path::new("t"), t.shape()).map_err(error)?;
        for (name, array) in [("v", v), ("a", a)] {
            if let Some(array) = array {
                check_array_size(Path::new(name), array.shape()).map_err(error)?;
            }
        }
    }
    let replayed = match timed {
        None => crate::traj::npy::samples_from_array(label, q.as_array()).map(Replayed::Samples),
        Some((t, v, a, names)) => {
            let t = t.as_slice().map_err(|e| error(format!("t: {e}")))?;
            TimedTrajectory::from_arrays(
                names,
                t,
                q.as_array(),
                v.as_ref().map(|v| v.as_array()),
                a.as_ref().map(|a| a.as_array()),
                label,
            )
            .map(Replayed::Timed)
        }
    };
    replayed.map(Some).map_err(error)
}

/// Refuses an array of `shape` given as `name` whose float64 values are more than a `.npy`
/// trajectory may hold ([`check_array_size`]): Python asks before it converts one.
#[pyfunction]
fn _check_array(name: &str, shape: Vec<usize>) -> PyResult<()> {
    check_array_size(Path::new(name), &shape).map_err(error)
}

/// The summary as JSON text (the `--summary` file's content, compact).
fn summary_json(summary: &crate::sim::Summary) -> String {
    serde_json::to_string(summary).expect("a summary serialises")
}

/// A run of `command` with the keywords `options` (a replay's frames given as `q_traj`, or read
/// from its path): (summary JSON, verdict line, t, q, q_cmd, tool_xyz, warnings, the seconds
/// the library's load, run and outputs took: what the binary does too; the rest of the call is
/// the binding's, which tools/bench/python_api.py measures).
#[pyfunction]
#[pyo3(signature = (command, options, q_traj=None, timed=None))]
#[allow(clippy::type_complexity)]
fn _run<'py>(
    py: Python<'py>,
    command: &str,
    options: &Bound<'py, PyDict>,
    q_traj: Option<PyReadonlyArray2<'py, f64>>,
    timed: Option<TimedArrays<'py>>,
) -> PyResult<(
    String,
    String,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Vec<String>,
    f64,
    String,
    Option<String>,
)> {
    let config = run_config(command, options)?;
    let frames = frames(q_traj, timed)?;
    let (stop, caught) = signal_stop();
    let (finished, engine) = py.detach(|| {
        let started = Instant::now();
        let mut trail = Capture::new(config.record_period);
        let finished = Prepared::new(config, frames).and_then(|prepared| {
            let files = crate::atomic::Outputs::new();
            let mut warnings = Vec::new();
            let finished = crate::session::run(&prepared, &files, &mut [&mut trail], &stop, |w| {
                warnings = warning_lines(w)
            })?;
            files.commit()?;
            if let (Some(live), true) = (&finished.recorders.live, prepared.config.outputs.hold) {
                live.hold_until(|| stop.is_raised());
            }
            let printed = crate::session::report_text(&finished, &prepared.config);
            let diverged = (finished.summary.diverged.as_ref())
                .map(|d| keywords(&crate::session::divergence_line(&prepared.scenario, d)));
            Ok((finished.summary, warnings, printed, diverged))
        });
        (
            finished.map(|(summary, warnings, printed, diverged)| (summary, trail, warnings, printed, diverged)),
            started.elapsed(),
        )
    });
    interrupted(py, &caught)?;
    let (summary, trail, warnings, printed, diverged) = finished.map_err(error)?;
    let (t, q, q_cmd, tool_xyz) = trail_arrays(py, trail)?;
    Ok((
        summary_json(&summary),
        summary.verdict.to_string(),
        t,
        q,
        q_cmd,
        tool_xyz,
        warnings,
        engine.as_secs_f64(),
        printed,
        diverged,
    ))
}

/// A run's stop flag for a run on the calling thread with the GIL released: at every look at
/// the flag (every 1,024 steps) it takes the GIL back for a moment and runs Python's signal
/// handlers; a signal's exception is kept in the second value ([`interrupted`]).
fn signal_stop() -> (StopFlag, Arc<Mutex<Option<PyErr>>>) {
    let caller = std::thread::current().id();
    let caught: Arc<Mutex<Option<PyErr>>> = Arc::default();
    let stop = {
        let caught = caught.clone();
        StopFlag::with_poll(move || {
            std::thread::current().id() == caller
                && Python::attach(|py| match py.check_signals() {
                    Ok(()) => false,
                    Err(e) => {
                        *caught.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
                        true
                    }
                })
        })
    };
    (stop, caught)
}

/// The exception of a signal that stopped the run ([`signal_stop`]), or of one that came while
/// the run was being built or its files written.
fn interrupted(py: Python<'_>, caught: &Mutex<Option<PyErr>>) -> PyResult<()> {
    if let Some(interrupt) = caught.lock().unwrap_or_else(|p| p.into_inner()).take() {
        return Err(interrupt);
    }
    py.check_signals()
}

/// The trail's rows as arrays: t (N,), q (N, dof), q_cmd (N, dof), tool_xyz (N, 3).
#[allow(clippy::type_complexity)]
fn trail_arrays(
    py: Python<'_>,
    trail: Capture,
) -> PyResult<(
    Bound<'_, PyArray1<f64>>,
    Bound<'_, PyArray2<f64>>,
    Bound<'_, PyArray2<f64>>,
    Bound<'_, PyArray2<f64>>,
)> {
    let rows = trail.rows();
    let table = |v: Vec<f64>, columns: usize| PyArray1::from_vec(py, v).reshape([rows, columns]);
    Ok((
        PyArray1::from_vec(py, trail.t),
        table(trail.q, trail.dof)?,
        table(trail.q_cmd, trail.dof)?,
        table(trail.tool_xyz, 3)?,
    ))
}

/// A retime timing as arrays: t (M,), q, qd, qdd (M, J each), and the J joints' names.
type TimingArrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Vec<String>,
);

fn timing_arrays<'py>(py: Python<'py>, timing: &TimedTrajectory) -> PyResult<TimingArrays<'py>> {
    let (m, j) = (timing.points.len(), timing.joint_names.len());
    let column = |pick: fn(&crate::traj::TrajectoryPoint) -> &Vec<f64>| {
        let flat: Vec<f64> = timing.points.iter().flat_map(|p| pick(p).iter().copied()).collect();
        PyArray1::from_vec(py, flat).reshape([m, j])
    };
    Ok((
        PyArray1::from_vec(py, timing.points.iter().map(|p| p.time_from_start).collect()),
        column(|p| &p.positions)?,
        column(|p| &p.velocities)?,
        column(|p| &p.accelerations)?,
        timing.joint_names.clone(),
    ))
}

/// A retime of the path `q_traj` (frames given as an array, or read from the path the
/// keywords' `q_traj` names) with the keywords `options`: (the checked timing's run as
/// [`_run`] gives it, with the lines the binary prints before its verdict; the timing's
/// arrays; its duration; the input's own duration, if any). The trail is the check's last run,
/// taped ([`crate::sim::Tape`]); `no_check` is refused (there is no run to return).
#[pyfunction]
#[pyo3(signature = (options, q_traj=None))]
#[allow(clippy::type_complexity)]
fn _retime<'py>(
    py: Python<'py>,
    options: &Bound<'py, PyDict>,
    q_traj: Option<PyReadonlyArray2<'py, f64>>,
) -> PyResult<(
    (
        String,
        String,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Vec<String>,
        f64,
        String,
    ),
    TimingArrays<'py>,
    f64,
    Option<f64>,
)> {
    let config = run_config("retime", options)?;
    let frames = frames(q_traj, None)?;
    let (stop, caught) = signal_stop();
    let (finished, engine) = py.detach(|| {
        let started = Instant::now();
        let mut trail = Capture::new(config.record_period);
        let files = crate::atomic::Outputs::new();
        let mut warnings = Vec::new();
        let finished = crate::session::retime(&config, frames, &files, &mut [&mut trail], &stop, |w| {
            warnings = warning_lines(w)
        })
        .and_then(|finished| {
            // a check a signal ended early writes nothing, as on the command line
            if finished.summary.as_ref().is_none_or(|s| s.interrupted_at_s.is_none()) {
                files.commit()?;
            }
            let out = match &config.motion {
                Motion::Retime(r) => r.out.as_deref(),
                _ => None,
            };
            let printed = keywords(&crate::session::retime_lines(&finished, out));
            Ok((finished, printed))
        });
        (
            finished.map(|(f, printed)| (f, trail, warnings, printed)),
            started.elapsed(),
        )
    });
    interrupted(py, &caught)?;
    let (finished, trail, warnings, printed) = finished.map_err(|e| match e {
        crate::Error::NothingFollows { .. } | crate::Error::PathCollides { .. } => {
            NothingFollows::new_err(crate::error::escape_controls(&keywords(&e.to_string())))
        }
        e => error(e),
    })?;
    // a trail is captured, so `no_check` was refused: the summary is the checked run's
    let summary = finished.summary.as_ref().expect("a retime with a trail is checked");
    let (t, q, q_cmd, tool_xyz) = trail_arrays(py, trail)?;
    Ok((
        (
            summary_json(summary),
            summary.verdict.to_string(),
            t,
            q,
            q_cmd,
            tool_xyz,
            warnings,
            engine.as_secs_f64(),
            printed,
        ),
        timing_arrays(py, &finished.retimed.trajectory)?,
        finished.retimed.profile.duration(),
        finished.own_duration,
    ))
}

/// A row as (values, summary JSON or None, failure or None).
fn row_tuple(row: &Row) -> (Vec<f64>, Option<String>, Option<String>) {
    match &row.outcome {
        Outcome::Ran(summary) => (row.values.clone(), Some(summary_json(summary)), None),
        Outcome::Failed(reason) => (row.values.clone(), None, Some(keywords(reason))),
    }
}

/// Whether a sweep's runs share their commanded path's clearance (`own_clearance`: each its own).
fn sharing(own_clearance: bool) -> Sharing {
    match own_clearance {
        true => Sharing::Own,
        false => Sharing::Shared,
    }
}

/// A sweep of `command` with the keywords `options`, over the grid of `vary` (`NAME=v1,v2,…` or
/// `NAME=LO:HI:STEP` each) on `jobs` threads: its rows and warnings.
#[pyfunction]
#[pyo3(signature = (command, options, given, vary, jobs, own_clearance, q_traj=None, timed=None))]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn _sweep(
    py: Python<'_>,
    command: &str,
    options: &Bound<'_, PyDict>,
    given: Vec<String>,
    vary: Vec<String>,
    jobs: usize,
    own_clearance: bool,
    q_traj: Option<PyReadonlyArray2<'_, f64>>,
    timed: Option<TimedArrays<'_>>,
) -> PyResult<(Vec<(Vec<f64>, Option<String>, Option<String>)>, Vec<String>)> {
    let config = run_config(command, options)?;
    let frames = frames(q_traj, timed)?;
    let stop = StopFlag::new();
    let (rows, warnings) = interruptible(py, &stop, || {
        let (grid, indices) = Grid::parse(&vary, None, MAX_RUNS)?;
        let varied: Vec<&str> = grid.axes.iter().map(|a| a.name.as_str()).collect();
        let given: Vec<&str> = given.iter().map(String::as_str).collect();
        crate::sweep::refuse_given_and_varied(&varied, config.motion.command(), &given, "vary")?;
        let names: Vec<(&str, &[f64])> = (grid.axes.iter())
            .map(|a| (a.name.as_str(), a.values.as_slice()))
            .collect();
        let family = Family::load(config, frames, &names, sharing(own_clearance))?;
        let rows = family.rows(&grid, indices, jobs, &stop)?;
        Ok::<_, crate::Error>((rows, warning_lines(family.warnings())))
    })?
    .map_err(error)?;
    Ok((rows.iter().map(row_tuple).collect(), warnings))
}

/// A search of `command` with the keywords `options` for the largest (`smallest`: smallest)
/// value of `name` in [`lo`, `hi`] that follows: (what was found, the line, the run that
/// follows, the run that does not, warnings).
#[pyfunction]
#[pyo3(signature = (command, options, given, name, lo, hi, resolution, smallest, jobs, own_clearance, q_traj=None, timed=None))]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn _find(
    py: Python<'_>,
    command: &str,
    options: &Bound<'_, PyDict>,
    given: Vec<String>,
    name: &str,
    lo: f64,
    hi: f64,
    resolution: Option<f64>,
    smallest: bool,
    jobs: usize,
    own_clearance: bool,
    q_traj: Option<PyReadonlyArray2<'_, f64>>,
    timed: Option<TimedArrays<'_>>,
) -> PyResult<(
    &'static str,
    String,
    Option<(Vec<f64>, Option<String>, Option<String>)>,
    Option<(Vec<f64>, Option<String>, Option<String>)>,
    Vec<String>,
)> {
    let config = run_config(command, options)?;
    let frames = frames(q_traj, timed)?;
    let stop = StopFlag::new();
    let seek = if smallest { Seek::Smallest } else { Seek::Largest };
    let option = if smallest { "find_min" } else { "find" };
    let given: Vec<&str> = given.iter().map(String::as_str).collect();
    crate::sweep::refuse_given_and_varied(&[name], config.motion.command(), &given, option).map_err(error)?;
    let warnings = Mutex::new(Vec::new());
    let searched = interruptible(py, &stop, || {
        crate::sweep::search(
            config,
            frames,
            sharing(own_clearance),
            name,
            lo,
            hi,
            resolution,
            seek,
            jobs,
            &stop,
            |w| *warnings.lock().unwrap_or_else(|p| p.into_inner()) = warning_lines(w),
        )
    })?
    .map_err(error)?;
    let (kind, follows, fails) = match &searched.found {
        Found::Boundary { follows, fails } => ("boundary", Some(row_tuple(follows)), Some(row_tuple(fails))),
        Found::NoneFollows(row) => ("none_follows", None, Some(row_tuple(row))),
        Found::AllFollow(row) => ("all_follow", Some(row_tuple(row)), None),
    };
    let warnings = warnings.into_inner().unwrap_or_else(|p| p.into_inner());
    Ok((kind, keywords(&searched.line), follows, fails, warnings))
}

/// A kind as Python's docstrings name it: `flag`, `float`, `int`, `str`, `path`, `joints`.
fn kind_word(kind: Kind) -> &'static str {
    match kind {
        Kind::Flag => "flag",
        Kind::Number => "float",
        Kind::Count => "int",
        Kind::Text | Kind::Texts | Kind::Choice(_) | Kind::Center | Kind::Motors => "str",
        Kind::Path | Kind::Paths => "path",
        Kind::PerJoint | Kind::Numbers => "joints",
    }
}

/// One option as the package's `faze4.Option` takes it.
type OptionTuple = (
    &'static str,
    &'static str,
    bool,
    bool,
    Option<String>,
    Vec<&'static str>,
    String,
);

/// The options of `command` (`wave`, `replay`, `shape`, `retime`; `run`: those every command
/// shares) as the library declares them ([`config::fields::FIELDS`]): (name, kind, repeated,
/// required, default, choices, help with the options it names as keywords) each.
#[pyfunction]
fn _options(command: &str) -> PyResult<Vec<OptionTuple>> {
    let declared: Vec<&Field> = match command {
        "run" => fields::shared().collect(),
        name => match Command::from_word(name) {
            Some(c) => fields::of(c).collect(),
            None => return Err(error(format!("no command '{command}'"))),
        },
    };
    Ok(declared
        .into_iter()
        .map(|f| {
            let choices = match f.kind {
                Kind::Choice(words) => words.to_vec(),
                _ => Vec::new(),
            };
            (
                f.name,
                kind_word(f.kind),
                matches!(f.kind, Kind::Paths | Kind::Texts),
                f.required,
                f.default.shown(),
                choices,
                f.help_in(crate::error::Words::Keywords),
            )
        })
        .collect())
}

/// The options' old names, each with its option's name (`urdf`, `robot`): the keywords still
/// read ([`Field::aliases`]).
#[pyfunction]
fn _old_names() -> Vec<(&'static str, &'static str)> {
    (fields::FIELDS.iter())
        .flat_map(|f| f.aliases.iter().map(move |&old| (old, f.name)))
        .collect()
}

/// The names a sweep varies, as keywords: the numeric options (`payload_kg`, …), then the
/// multipliers (`kp_scale`, …).
#[pyfunction]
fn _varied() -> (Vec<&'static str>, Vec<String>) {
    let scales = crate::sweep::Scale::ALL.iter().map(|(n, _)| n.replace('-', "_"));
    (crate::sweep::varied_fields(), scales.collect())
}

/// A panic on purpose, for the test that a panic does not take the interpreter down.
#[pyfunction]
fn _panic(on_worker: bool, py: Python<'_>) -> PyResult<()> {
    match on_worker {
        true => interruptible(py, &StopFlag::new(), || panic!("faze4: a test panic on the worker")),
        false => panic!("faze4: a test panic"),
    }
}

#[pymodule]
fn _faze4(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRobot>()?;
    m.add("Error", m.py().get_type::<Error>())?;
    m.add("_NothingFollows", m.py().get_type::<NothingFollows>())?;
    m.add_function(wrap_pyfunction!(_run, m)?)?;
    m.add_function(wrap_pyfunction!(_retime, m)?)?;
    m.add_function(wrap_pyfunction!(_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(_find, m)?)?;
    m.add_function(wrap_pyfunction!(_options, m)?)?;
    m.add_function(wrap_pyfunction!(_varied, m)?)?;
    m.add_function(wrap_pyfunction!(_old_names, m)?)?;
    m.add_function(wrap_pyfunction!(_panic, m)?)?;
    m.add_function(wrap_pyfunction!(_check_array, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
