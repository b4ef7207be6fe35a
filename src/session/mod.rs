//! One run of a configuration with the outputs its options ask for, as both front ends (the
//! command line and Python) run it: every output opened (and its path checked) before the run,
//! the command's joint samples and the summary written, every file in one [`Outputs`] set that
//! the caller commits; and the lines a run prints (`[done]`, the verdict).

mod report;
mod retime;

use std::path::Path;

pub use report::{divergence_line, done_line, report_text};
pub use retime::{RetimeFinished, retime, retime_lines};

use crate::atomic::{Inputs, Outputs};
use crate::config::{Loaded, Motion, Replayed, RunConfig};
use crate::error::{Error, Result};
use crate::output::{PRINT_PERIOD, Terminal, TrailCsv};
use crate::sim::{self, Recorder, Scenario, StopFlag, Summary, Warning};
use crate::traj::{Trajectory, npy};
use crate::viz::{HtmlExport, LiveView, MotorPlot, PlotRecorder};

/// A configuration's run, ready: what was loaded, and its scenario.
pub struct Prepared {
    /// The configuration.
    pub config: RunConfig,
    /// The run.
    pub scenario: Scenario,
    /// Everything the user should know before the run, in the order it is said: the
    /// scenario's warnings, then what loading found (meshes not found).
    pub warnings: Vec<Warning>,
    /// The files loading read, which no output of the run may replace.
    pub inputs: Inputs,
}

impl Prepared {
    /// Loads `config` (what a replay plays given in memory, or read from its `q_traj`) and
    /// builds its scenario.
    pub fn new(config: RunConfig, replayed: Option<Replayed>) -> Result<Prepared> {
        let loaded = Loaded::load(&config, replayed)?;
        let scenario = loaded.scenario(&config)?;
        let mut warnings = scenario.warnings.clone();
        let inputs = loaded.inputs().clone();
        warnings.extend(loaded.warnings);
        Ok(Prepared {
            config,
            scenario,
            warnings,
            inputs,
        })
    }
}

/// What a run gives back: its summary, and the recorders it wrote (for the `[done]` line and
/// the live view's hold).
pub struct Finished {
    /// The summary (the `summary` file's JSON).
    pub summary: Summary,
    /// The run's recorders.
    pub recorders: Recorders,
}

/// Runs `prepared` with the outputs its configuration asks for (and `extra` recorders), into
/// `files` (the caller commits them): refuses an output that is one of its inputs, opens the
/// recorders, tells `warn` the warnings (once
/// every output is open: a bad output path is the only line), writes a shape's joint samples
/// (`save_q`), runs until the end or `stop`, and writes the summary file.
pub fn run(
    prepared: &Prepared,
    files: &Outputs,
    extra: &mut [&mut dyn Recorder],
    stop: &StopFlag,
    warn: impl FnOnce(&[Warning]),
) -> Result<Finished> {
    run_with(prepared, files, extra, stop, warn, |scenario, recorders| {
        sim::run(scenario, recorders, stop)
    })
}

/// [`run`] with the run made by `play` (given the scenario and every recorder): the run
/// itself, or one already made handed over from its tape ([`crate::sim::Tape::play`]).
fn run_with(
    prepared: &Prepared,
    files: &Outputs,
    extra: &mut [&mut dyn Recorder],
    stop: &StopFlag,
    warn: impl FnOnce(&[Warning]),
    play: impl FnOnce(&Scenario, &mut [&mut dyn Recorder]) -> Result<Summary>,
) -> Result<Finished> {
    let Prepared {
        config,
        scenario,
        warnings,
        inputs,
    } = prepared;
    let save_q = save_q(config);
    // the outputs' temporaries exist from here on: a signal must stop the run, not the process
    stop.watch();
    files.reading(inputs.clone())?;
    let mut recorders = Recorders::open(scenario, config, files)?;
    warn(warnings);
    if let (Some(path), Trajectory::Interpolated(samples)) = (save_q, &scenario.trajectory) {
        let rows: Vec<Vec<f64>> = (0..samples.rows()).map(|k| samples.row(k).to_vec()).collect();
        npy::write_samples_within(files, path, &rows)?;
    }
    let mut all = recorders.recorders();
    all.extend(extra.iter_mut().map(|r| &mut **r as &mut dyn Recorder));
    let summary = play(scenario, &mut all)?;
    if let Some(path) = &config.outputs.summary {
        write_summary(files, path, &summary)?;
    }
    Ok(Finished { summary, recorders })
}

/// An output file a run can write, as [`OUTPUT_FILES`] lists it for the places that treat
/// every output alike: its path claimed before the run ([`Recorders`]), its part of the
/// `[done]` line ([`done_line`]), whether `retime` plays its timing for it.
pub struct OutputFile {
    /// Its `RunConfig` field (`plot_motors`), as messages name it.
    pub field: &'static str,
    /// What the `[done]` line calls it (`motor plot -> PATH`).
    pub word: &'static str,
    /// Its path in a configuration, when it is asked for.
    pub path: fn(&RunConfig) -> Option<&Path>,
    /// What the `[done]` line adds after its path, from the run's recorders (the trail's rows).
    pub detail: fn(&Recorders) -> Option<String>,
    /// Whether it is made of a run's recorded samples (`retime` then plays the timing it
    /// writes).
    pub records: bool,
}

/// Every output file a run can write, in the order their paths are claimed (two options
/// naming one file: the later one is refused) and the `[done]` line names them. Each is opened
/// by [`Recorders`] (a recorder of the run), or written by [`run`] (the joint samples, the
/// summary).
pub const OUTPUT_FILES: [OutputFile; 6] = [
    OutputFile {
        field: "trail",
        word: "trail",
        path: |c| c.outputs.trail.as_deref(),
        detail: |r| r.trail.as_ref().map(|t| format!(" ({} rows)", t.rows())),
        records: true,
    },
    OutputFile {
        field: "summary",
        word: "summary",
        path: |c| c.outputs.summary.as_deref(),
        detail: |_| None,
        records: false,
    },
    OutputFile {
        field: "save_q",
        word: "joint samples",
        path: save_q,
        detail: |_| None,
        records: false,
    },
    OutputFile {
        field: "html",
        word: "html",
        path: |c| c.outputs.html.as_deref(),
        detail: |_| None,
        records: true,
    },
    OutputFile {
        field: "plot",
        word: "plot",
        path: |c| c.outputs.plot.as_deref(),
        detail: |_| None,
        records: true,
    },
    OutputFile {
        field: "plot_motors",
        word: "motor plot",
        path: |c| c.outputs.plot_motors.as_deref(),
        detail: |_| None,
        records: true,
    },
];

/// A shape's `save_q`.
fn save_q(config: &RunConfig) -> Option<&Path> {
    match &config.motion {
        Motion::Shape(s) => s.save_q.as_deref(),
        _ => None,
    }
}

/// Writes the summary JSON to `path`, a file of `files`.
pub fn write_summary(files: &Outputs, path: &Path, summary: &Summary) -> Result<()> {
    let mut json = serde_json::to_vec_pretty(summary).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    })?;
    json.push(b'\n');
    files.write(path, &json)
}

/// The recorders a run writes to, opened (and every output path and the port checked) before
/// it starts.
pub struct Recorders {
    terminal: Option<Terminal>,
    trail: Option<TrailCsv>,
    html: Option<HtmlExport>,
    plot: Option<PlotRecorder>,
    motor_plot: Option<MotorPlot>,
    /// The live view, when the run is shown live.
    pub live: Option<LiveView>,
}

impl Recorders {
    /// Whether a recorder `config` asks for reads each sample's intersections (the 3D views:
    /// the HTML export, the live view; [`Recorder::reads_intersections`]).
    fn read_intersections(config: &RunConfig) -> bool {
        let out = &config.outputs;
        out.html.is_some() || out.view || out.hold
    }

    /// Claims every output path in `files` (two options naming one file are refused) and
    /// opens the recorders, their files in `files`.
    fn open(scenario: &Scenario, config: &RunConfig, files: &Outputs) -> Result<Recorders> {
        let out = &config.outputs;
        if out.plot_motors.is_some() && scenario.motors.is_none() {
            return Err(Error::option("plot_motors", "draws the motors: add `motors`"));
        }
        if out.sizing && scenario.motors.is_none() {
            return Err(Error::option("sizing", "sizes the motors: add `motors`"));
        }
        for output in &OUTPUT_FILES {
            if let Some(path) = (output.path)(config) {
                files.claim(path, &format!("`{}`", output.field))?;
            }
        }
        let print_period = out
            .print_period
            .unwrap_or_else(|| default_print_period(scenario.steps as f64 * scenario.dt));
        let period = config.record_period;
        let live = match out.view || out.hold {
            true => Some(LiveView::start(out.port)?.with_period(period)),
            false => None,
        };
        let html = match &out.html {
            Some(path) => Some(HtmlExport::new(path)?.with_period(period).within(files)),
            None => None,
        };
        let plot = match &out.plot {
            Some(path) => Some(PlotRecorder::new(path)?.with_period(period).within(files)),
            None => None,
        };
        let motor_plot = match &out.plot_motors {
            Some(path) => Some(MotorPlot::new(path)?.within(files)),
            None => None,
        };
        let trail = match &out.trail {
            Some(path) => Some(TrailCsv::within(files, path, period, out.debug)?),
            None => None,
        };
        Ok(Recorders {
            terminal: (!out.quiet).then(|| Terminal::new(out.debug, print_period, out.words)),
            trail,
            html,
            plot,
            motor_plot,
            live,
        })
    }

    fn recorders(&mut self) -> Vec<&mut dyn Recorder> {
        let mut recorders: Vec<&mut dyn Recorder> = Vec::new();
        if let Some(t) = self.terminal.as_mut() {
            recorders.push(t);
        }
        if let Some(t) = self.trail.as_mut() {
            recorders.push(t);
        }
        if let Some(h) = self.html.as_mut() {
            recorders.push(h);
        }
        if let Some(p) = self.plot.as_mut() {
            recorders.push(p);
        }
        if let Some(p) = self.motor_plot.as_mut() {
            recorders.push(p);
        }
        if let Some(l) = self.live.as_mut() {
            recorders.push(l);
        }
        recorders
    }
}

/// Progress lines every 0.5 s of simulated time, or, for runs longer than 20 s, at the first
/// of 1, 2, 5, 10, 20, 50… seconds that keeps them to at most 40.
fn default_print_period(duration: f64) -> f64 {
    const MOST_LINES: f64 = 40.0;
    if duration <= PRINT_PERIOD * MOST_LINES {
        return PRINT_PERIOD;
    }
    let wanted = duration / MOST_LINES;
    let mut decade = 1.0;
    loop {
        for step in [1.0, 2.0, 5.0] {
            if step * decade >= wanted {
                return step * decade;
            }
        }
        decade *= 10.0;
    }
}
