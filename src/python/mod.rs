//! The Python module `faze4._faze4` (cargo feature `python`; `pyproject.toml` builds it with
//! maturin; `python/faze4/__init__.py` is the API on top). Thin by design:
//!
//! * the runs, sweeps and searches are the command line's, called as a library
//!   ([`crate::cli::call`]): the Python keywords become the words of the same subcommand, parsed
//!   by the binary's clap definitions, so options, defaults, checks, messages and summaries are
//!   the binary's;
//! * `Robot` holds the model the same words load (`--urdf`, `--motors`, …; `--payload-kg` and
//!   `--no-gravity` applied as a run applies them) and one `Data` workspace for the dynamics
//!   calls.
//!
//! A run releases the GIL and looks for signals at every look at its stop flag (every 1,024
//! steps); sweeps and searches run on a worker thread while the calling thread, the GIL
//! released, waits and looks for signals every [`SIGNAL_POLL`]. Either way Ctrl-C raises the
//! stop flag and the call raises `KeyboardInterrupt`. A panic on the worker is re-raised on the
//! caller, where PyO3 turns it into a Python exception.

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use numpy::{
    PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyReadonlyArray2, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::algo::{Data, crba, forward_dynamics, forward_kinematics, gravity, rnea};
use crate::cli::args::Command;
use crate::cli::{call, scenario};
use crate::model::Model;
use crate::sim::StopFlag;
use crate::sweep::{Found, Outcome, Row};

create_exception!(faze4, Error, PyValueError, "Bad input: the binary's one-line message.");

/// How often a waiting call looks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// `faze4.Error` with the line the binary prints after `faze4: error: ` (control characters
/// escaped as there).
fn error(message: impl std::fmt::Display) -> PyErr {
    Error::new_err(crate::error::escape_controls(&message.to_string()))
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
    words: Vec<String>,
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
    /// Loads the arm the option words describe (`--urdf F --motors faze4 …`, as a run takes
    /// them). `faze4.Robot.faze4()` and `faze4.Robot.from_urdf()` build the words.
    #[new]
    fn new(words: Vec<String>) -> PyResult<Self> {
        let mut argv = vec!["wave".to_string()];
        argv.extend(words.iter().cloned());
        let Command::Wave(args) = call::parse(&argv).map_err(error)? else {
            unreachable!("parsed as wave")
        };
        let run = &args.run;
        let robot = scenario::load_model(run).map_err(error)?;
        let effort = call::effort(run, &robot.model).map_err(error)?;
        let mut model = robot.model;
        let tool = scenario::tool_frame(&model, run.tool_link.as_deref()).map_err(error)?;
        if run.no_gravity {
            model.gravity = Default::default();
        }
        if run.payload_kg > 0.0 {
            model = model.with_point_mass(tool, run.payload_kg);
        }
        Ok(PyRobot {
            data: Mutex::new(Data::new(&model)),
            model,
            effort,
            words,
        })
    }

    /// The option words the robot was loaded with (every run of it starts from them).
    #[getter]
    fn _words(&self) -> Vec<String> {
        self.words.clone()
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
        Ok(PyArray1::from_slice(
            py,
            rnea(&self.model, &mut data, &q, &v, &a).as_slice(),
        ))
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
        let qdd = forward_dynamics(&self.model, &mut data, &q, &v, &tau).map_err(error)?;
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
        let frame = scenario::tool_frame(&self.model, Some(link)).map_err(|_| {
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

/// An N×dof float64 array's rows, checked as a `.npy` trajectory is (`label` names it).
fn frames(label: &str, q_traj: Option<PyReadonlyArray2<'_, f64>>) -> PyResult<Option<Vec<Vec<f64>>>> {
    q_traj
        .map(|a| crate::traj::npy::samples_from_array(std::path::Path::new(label), a.as_array()))
        .transpose()
        .map_err(error)
}

/// The summary as JSON text (the `--summary` file's content, compact).
fn summary_json(summary: &crate::sim::Summary) -> String {
    serde_json::to_string(summary).expect("a summary serialises")
}

/// A run (`words`: the subcommand and its options): (summary JSON, verdict line, t, q, q_cmd,
/// tool_xyz, warnings, the seconds [`call::run`] took: scenario, run and outputs, what the
/// binary does too; the rest of the call is the binding's, which tools/bench/python_api.py
/// measures).
#[pyfunction]
#[pyo3(signature = (words, q_traj=None))]
#[allow(clippy::type_complexity)]
fn _run<'py>(
    py: Python<'py>,
    words: Vec<String>,
    q_traj: Option<PyReadonlyArray2<'py, f64>>,
) -> PyResult<(
    String,
    String,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Vec<String>,
    f64,
)> {
    let command = call::parse(&words).map_err(error)?;
    let frames = frames("q_traj", q_traj)?;
    // the run stays on this thread, the GIL released; at every look at the stop flag (every
    // 1,024 steps) it takes the GIL back for a moment and runs Python's signal handlers
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
    let (finished, engine) = py.detach(|| {
        let started = Instant::now();
        (call::run(&command, frames, &stop), started.elapsed())
    });
    if let Some(interrupt) = caught.lock().unwrap_or_else(|p| p.into_inner()).take() {
        return Err(interrupt);
    }
    // a signal that came while the run was being built or its files written
    py.check_signals()?;
    let finished = finished.map_err(error)?;
    let trail = finished.trail;
    let rows = trail.rows();
    let table = |v: Vec<f64>, columns: usize| PyArray1::from_vec(py, v).reshape([rows, columns]);
    Ok((
        summary_json(&finished.summary),
        finished.summary.verdict.to_string(),
        PyArray1::from_vec(py, trail.t),
        table(trail.q, trail.dof)?,
        table(trail.q_cmd, trail.dof)?,
        table(trail.tool_xyz, 3)?,
        finished.warnings,
        engine.as_secs_f64(),
    ))
}

/// A row as (values, summary JSON or None, failure or None).
fn row_tuple(row: &Row) -> (Vec<f64>, Option<String>, Option<String>) {
    match &row.outcome {
        Outcome::Ran(summary) => (row.values.clone(), Some(summary_json(summary)), None),
        Outcome::Failed(reason) => (row.values.clone(), None, Some(reason.clone())),
    }
}

/// A sweep (`words`: `sweep --vary … -- COMMAND …`): its rows and warnings.
#[pyfunction]
#[pyo3(signature = (words, q_traj=None))]
#[allow(clippy::type_complexity)]
fn _sweep(
    py: Python<'_>,
    words: Vec<String>,
    q_traj: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<(Vec<(Vec<f64>, Option<String>, Option<String>)>, Vec<String>)> {
    let args = call::parse_sweep(&words).map_err(error)?;
    let frames = frames("q_traj", q_traj)?;
    let stop = StopFlag::new();
    let (rows, warnings) =
        interruptible(py, &stop, || crate::cli::sweep::rows(&args, frames, &stop))?.map_err(error)?;
    Ok((
        rows.iter().map(row_tuple).collect(),
        warnings.iter().map(ToString::to_string).collect(),
    ))
}

/// A search (`words`: `sweep --find NAME=LO:HI … -- COMMAND …`): (what was found, the
/// binary's line, the run that follows, the run that does not, warnings).
#[pyfunction]
#[pyo3(signature = (words, q_traj=None))]
#[allow(clippy::type_complexity)]
fn _find(
    py: Python<'_>,
    words: Vec<String>,
    q_traj: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<(
    &'static str,
    String,
    Option<(Vec<f64>, Option<String>, Option<String>)>,
    Option<(Vec<f64>, Option<String>, Option<String>)>,
    Vec<String>,
)> {
    let args = call::parse_sweep(&words).map_err(error)?;
    let frames = frames("q_traj", q_traj)?;
    let stop = StopFlag::new();
    let (found, line, warnings) =
        interruptible(py, &stop, || crate::cli::sweep::find_line(&args, frames, &stop))?.map_err(error)?;
    let (kind, follows, fails) = match &found {
        Found::Boundary { follows, fails } => ("boundary", Some(row_tuple(follows)), Some(row_tuple(fails))),
        Found::NoneFollows(row) => ("none_follows", None, Some(row_tuple(row))),
        Found::AllFollow(row) => ("all_follow", Some(row_tuple(row)), None),
    };
    Ok((
        kind,
        line,
        follows,
        fails,
        warnings.iter().map(ToString::to_string).collect(),
    ))
}

/// The options of a command as clap declares them: (long name, kind, repeated, required,
/// default, choices, help) each.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn _options(command: &str) -> PyResult<Vec<(String, &'static str, bool, bool, Option<String>, Vec<String>, String)>> {
    let options = call::options(command).ok_or_else(|| error(format!("no command '{command}'")))?;
    Ok(options
        .into_iter()
        .map(|o| {
            (
                o.long,
                o.kind.name(),
                o.repeated,
                o.required,
                o.default,
                o.choices,
                o.help,
            )
        })
        .collect())
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
    m.add_function(wrap_pyfunction!(_run, m)?)?;
    m.add_function(wrap_pyfunction!(_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(_find, m)?)?;
    m.add_function(wrap_pyfunction!(_options, m)?)?;
    m.add_function(wrap_pyfunction!(_panic, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
