//! `faze4 sweep`: the command line of [`crate::sweep`]. A sweep point is a set of overrides
//! applied to the parsed options of the base command (after `--`); the model (and a replay's
//! frames, a shape's IK, the collision meshes) are read once and shared by every run.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clap::Parser;

use super::args::{Cli, Command, ReplayArgs, RunArgs, ShapeArgs, SweepArgs, SweepCommand, WaveArgs};
use super::{interrupted_status, print_stdout, scenario, stopped_by, warn};
use crate::atomic::{Inputs, Outputs, check_output_path};
use crate::error::{Error, Result};
use crate::geometry::{CollisionSet, Robot};
use crate::output::format::exact;
use crate::sim::scenario::load_collisions;
use crate::sim::{Scenario, ShapeRun, StopFlag, Warning};
use crate::sweep::{
    self, Axis, Format, Found, Grid, MAX_RUNS, Outcome, PartMeta, Row, Runner, Scale, Seek, Shard, TableWriter,
};
use crate::traj::{Trajectory, npy};

/// An option of the base command, if the command has it.
#[derive(Clone, Copy)]
enum Field {
    /// A real number.
    Number(fn(&mut Command) -> Option<&mut f64>),
    /// A count (whole values only).
    Count(fn(&mut Command) -> Option<&mut usize>),
}

impl Field {
    /// Sets the option of `command` to `x`; `Err` says why it cannot.
    fn set(self, command: &mut Command, x: f64) -> std::result::Result<(), &'static str> {
        const NOT_HERE: &str = "is not an option of this command";
        match self {
            Field::Number(field) => *field(command).ok_or(NOT_HERE)? = x,
            Field::Count(field) => {
                let slot = field(command).ok_or(NOT_HERE)?;
                self.accepts(x)?;
                *slot = x as usize;
            }
        }
        Ok(())
    }

    /// Whether `x` is a value of this kind of option (a count is whole, ≥ 0).
    fn accepts(self, x: f64) -> std::result::Result<(), &'static str> {
        match self {
            Field::Count(_) if x < 0.0 || x.fract() != 0.0 || x > u32::MAX as f64 => Err("takes whole numbers ≥ 0"),
            _ => Ok(()),
        }
    }
}

/// What a sweep NAME changes.
#[derive(Clone, Copy)]
enum Knob {
    /// An option of the base command.
    Option(Field),
    /// A multiplier of the built scenario.
    Scale(Scale),
}

/// The numeric options a sweep can vary, one line each.
const OPTIONS: &[(&str, Field)] = &[
    ("duration", Field::Number(|c| Some(duration(c)))),
    ("freq", Field::Number(|c| wave(c).map(|a| &mut a.freq))),
    ("amp-deg", Field::Number(|c| wave(c).map(|a| &mut a.amp_deg))),
    ("traj-period", Field::Number(|c| replay(c).map(|a| &mut a.traj_period))),
    ("shape-points", Field::Count(|c| shape(c).map(|a| &mut a.shape_points))),
    ("payload-kg", Field::Number(|c| Some(&mut run(c).payload_kg))),
    ("dt", Field::Number(|c| Some(&mut run(c).dt))),
    ("record-period", Field::Number(|c| Some(&mut run(c).record_period))),
    (
        "supply-voltage",
        Field::Number(|c| Some(run(c).supply_voltage.insert(0.0))),
    ),
    (
        "max-saturation-pct",
        Field::Number(|c| Some(&mut run(c).max_saturation_pct)),
    ),
    ("max-error", Field::Number(|c| Some(&mut run(c).max_error))),
    (
        "max-deviation-mm",
        Field::Number(|c| Some(&mut run(c).max_deviation_mm)),
    ),
];

fn knob(name: &str) -> Option<Knob> {
    (OPTIONS.iter().find(|(n, _)| *n == name).map(|(_, s)| Knob::Option(*s))).or_else(|| {
        Scale::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, s)| Knob::Scale(*s))
    })
}

fn known_names() -> String {
    let names: Vec<&str> = OPTIONS
        .iter()
        .map(|(n, _)| *n)
        .chain(Scale::ALL.iter().map(|(n, _)| *n))
        .collect();
    names.join(", ")
}

fn run(c: &mut Command) -> &mut RunArgs {
    match c {
        Command::Wave(a) => &mut a.run,
        Command::Replay(a) => &mut a.run,
        Command::Shape(a) => &mut a.run,
        Command::Sweep(_) => unreachable!("a sweep's base is a run command"),
    }
}

fn duration(c: &mut Command) -> &mut f64 {
    match c {
        Command::Wave(a) => &mut a.duration,
        Command::Replay(a) => &mut a.duration,
        Command::Shape(a) => &mut a.duration,
        Command::Sweep(_) => unreachable!("a sweep's base is a run command"),
    }
}

fn wave(c: &mut Command) -> Option<&mut WaveArgs> {
    match c {
        Command::Wave(a) => Some(a),
        _ => None,
    }
}

fn replay(c: &mut Command) -> Option<&mut ReplayArgs> {
    match c {
        Command::Replay(a) => Some(a),
        _ => None,
    }
}

fn shape(c: &mut Command) -> Option<&mut ShapeArgs> {
    match c {
        Command::Shape(a) => Some(a),
        _ => None,
    }
}

/// The base command with what it reads once: the model, a replay's frames, a shape's plan, the
/// collision set.
struct Base {
    command: Command,
    robot: Robot,
    /// The collision set every run measures its self-clearance with (`robot.geometry` keeps
    /// its collision elements only when there is one).
    collision_set: Option<Arc<CollisionSet>>,
    frames: Vec<Vec<f64>>,
    plan: Option<(Trajectory, ShapeRun)>,
    /// What reading the collision geometry found wrong (meshes not found), said once for the
    /// whole sweep.
    warnings: Vec<Warning>,
    /// The files the runs read, which the sweep's outputs may not replace.
    inputs: Inputs,
}

impl Base {
    /// Parses the words after `--` and reads the model (and a replay's frames unless `frames`
    /// gives them, and the shape's IK unless `replan`, when `shape-points` varies).
    fn load(words: &[String], replan: bool, frames: Option<Vec<Vec<f64>>>) -> Result<Base> {
        if words.is_empty() {
            return Err(Error::argument(
                "sweep",
                "no command to run: add -- wave|replay|shape and its options",
            ));
        }
        let argv = std::iter::once("faze4".to_string()).chain(words.iter().cloned());
        let command = Cli::try_parse_from(argv)
            .map_err(|e| {
                let text = e.to_string();
                let first = text
                    .lines()
                    .next()
                    .unwrap_or("")
                    .trim_start_matches("error: ")
                    .to_string();
                Error::argument(format!("sweep -- {}", words[0]), first)
            })?
            .command;
        let (mut robot, frames, plan) = match &command {
            Command::Wave(a) => (scenario::load_model(&a.run)?, Vec::new(), None),
            Command::Replay(a) => {
                let robot = scenario::load_model(&a.run)?;
                let frames = match frames {
                    Some(frames) => frames,
                    None => npy::read_samples(&a.q_traj)?,
                };
                (robot, frames, None)
            }
            Command::Shape(a) => {
                let robot = scenario::load_model(&a.run)?;
                let plan = match replan {
                    true => None,
                    false => Some(scenario::shape_plan(a, &robot.model)?),
                };
                (robot, Vec::new(), plan)
            }
            Command::Sweep(_) => return Err(Error::argument("sweep", "the command to sweep cannot be a sweep")),
        };
        let run = run_args(&command);
        if let Some(path) = run.summary.as_ref().filter(|p| !super::is_none(p)) {
            return Err(Error::argument(
                "--summary",
                format!(
                    "{}: a sweep writes its table with --out, not a summary per run",
                    path.display()
                ),
            ));
        }
        let save_q = matches!(&command, Command::Shape(a) if a.save_q.is_some());
        for (given, option) in [
            (run.html.is_some(), "--html"),
            (run.plot.is_some(), "--plot"),
            (run.plot_motors.is_some(), "--plot-motors"),
            (run.view || run.hold, "--view"),
            (save_q, "--save-q"),
        ] {
            if given {
                return Err(Error::argument(
                    option,
                    "is for single runs: a sweep's outputs are --out, --plot and --trails before the `--`",
                ));
            }
        }
        // the meshes are read once, not once per run, and a mesh not found is said once
        let collisions = scenario::collisions(run);
        let mut warnings = Vec::new();
        let inputs = super::inputs(&command, &robot.geometry);
        let (geometry, collision_set) = load_collisions(&robot.model, robot.geometry, collisions, &mut warnings)?;
        robot.geometry = geometry;
        Ok(Base {
            command,
            robot,
            collision_set,
            frames,
            plan,
            warnings,
            inputs,
        })
    }

    /// The scenario of one point: `knobs[i]` set to `values[i]`.
    fn build(&self, knobs: &[Knob], values: &[f64]) -> Result<Scenario> {
        let mut command = self.command.clone();
        let mut scales = Vec::new();
        for (knob, &x) in knobs.iter().zip(values) {
            match knob {
                Knob::Option(field) => field.set(&mut command, x).map_err(|e| Error::argument("--vary", e))?,
                Knob::Scale(scale) => scales.push((*scale, x)),
            }
        }
        // the collision set is Base's, loaded once
        let (robot, set) = (self.robot.clone(), self.collision_set.clone());
        let mut scenario = match &command {
            Command::Wave(a) => scenario::wave_with(a, robot, set)?,
            Command::Replay(a) => scenario::replay_with(a, robot, &self.frames, set)?,
            Command::Shape(a) => {
                let plan = match &self.plan {
                    Some(plan) => plan.clone(),
                    None => scenario::shape_plan(a, &robot.model)?,
                };
                scenario::shape_with(a, robot, plan, set)?
            }
            Command::Sweep(_) => unreachable!("refused by Base::load"),
        };
        for (scale, x) in scales {
            scale.apply(&mut scenario, x)?;
        }
        Ok(scenario)
    }
}

fn command_name(c: &Command) -> &'static str {
    match c {
        Command::Wave(_) => "wave",
        Command::Replay(_) => "replay",
        Command::Shape(_) => "shape",
        Command::Sweep(_) => "sweep",
    }
}

fn run_args(c: &Command) -> &RunArgs {
    match c {
        Command::Wave(a) => &a.run,
        Command::Replay(a) => &a.run,
        Command::Shape(a) => &a.run,
        Command::Sweep(_) => unreachable!("a sweep's base is a run command"),
    }
}

/// Checks every axis against the base command: a known numeric NAME, every value settable.
fn knobs(base: &Command, axes: &[Axis]) -> Result<Vec<Knob>> {
    axes.iter()
        .map(|axis| {
            let knob = knob(&axis.name).ok_or_else(|| {
                Error::argument(
                    "--vary",
                    format!(
                        "'{}' is not a numeric option a sweep can vary ({})",
                        axis.name,
                        known_names()
                    ),
                )
            })?;
            if let Knob::Option(field) = knob {
                let bad = |e| Error::argument("--vary", format!("{} {e} (faze4 {})", axis.name, command_name(base)));
                field.set(&mut base.clone(), axis.values[0]).map_err(bad)?;
                axis.values.iter().try_for_each(|&x| field.accepts(x)).map_err(bad)?;
            }
            Ok(knob)
        })
        .collect()
}

/// `faze4 sweep …`: exit 0 when it ran (rows may say the arm cannot follow), 130 when
/// interrupted; bad input is an `Err` (exit 2).
pub fn execute(args: &SweepArgs) -> Result<ExitCode> {
    if let Some(SweepCommand::Merge(m)) = &args.merge {
        check_output_path(&m.out, "--out")?;
        let parts: Vec<&Path> = m.tables.iter().map(PathBuf::as_path).collect();
        let merged = sweep::merge(&parts, &m.out, m.allow_partial)?;
        let line = match &merged.absent {
            None => format!("{} runs", merged.rows),
            Some(absent) => format!("{} of {} runs (absent: {absent})", merged.rows, merged.total),
        };
        print_stdout(&format!(
            "[done] {line} from {} tables -> {}\n",
            parts.len(),
            m.out.display()
        ))?;
        return Ok(ExitCode::SUCCESS);
    }
    match (&args.find, &args.find_min) {
        (Some(spec), _) => find(args, spec, Seek::Largest),
        (None, Some(spec)) => find(args, spec, Seek::Smallest),
        (None, None) => table(args),
    }
}

fn table(args: &SweepArgs) -> Result<ExitCode> {
    if args.vary.is_empty() {
        return Err(Error::argument(
            "--vary",
            "nothing to vary: give --vary NAME=LO:HI:STEP (or --find NAME=LO:HI)",
        ));
    }
    if args.resolution.is_some() {
        return Err(Error::argument("--resolution", "is for --find and --find-min"));
    }
    // before any temporary exists: a signal from here on stops the sweep cleanly
    let stop = StopFlag::ctrl_c();
    let shard = args.shard.as_deref().map(str::parse::<Shard>).transpose()?;
    let (grid, indices) = Grid::parse(&args.vary, shard, MAX_RUNS)?;
    let total = grid.len().expect("sized by Grid::parse");
    let files = Outputs::new();
    for (path, option) in [(&args.out, "--out"), (&args.plot, "--plot")] {
        if let Some(path) = path {
            files.claim(path, option)?;
        }
    }
    let format = match &args.out {
        Some(path) => Some(Format::of(path, "--out")?),
        None => None,
    };
    let plot = match &args.plot {
        Some(path) => Some(crate::viz::SweepPlot::new(path, &grid)?.within(&files)),
        None => None,
    };
    check_trails(args.trails.as_deref())?;
    let (base, knobs) = load_for(&grid, &args.base, None)?;
    files.reading(base.inputs.clone())?;
    warn(&base.warnings, args.quiet);
    let axes: Vec<String> = grid.axes.iter().map(|a| a.name.clone()).collect();

    let build = |values: &[f64]| base.build(&knobs, values);
    let progress = Progress::new(indices.len(), args.quiet);
    let on_done = || progress.tick();
    let mut runner = Runner::new(&build, threads(args.jobs, indices.len()))?.with_progress(&on_done);
    if let Some(dir) = &args.trails {
        runner = runner.with_trails(dir, &files);
    }
    let mut table = match (&args.out, format) {
        (Some(path), Some(format)) => Some(TableWriter::within(&files, path, format)?),
        _ => None,
    };
    let mut plot = plot;
    let started = Instant::now();
    let (mut cannot, mut failed) = (0, 0);
    let ran = runner.sweep(&grid, indices.clone(), &stop, |row| {
        cannot += usize::from(!row.follows());
        failed += usize::from(matches!(row.outcome, sweep::Outcome::Failed(_)));
        if let Some(t) = table.as_mut() {
            t.push(&axes, &row)?;
        }
        if let Some(p) = plot.as_mut() {
            p.add(&row);
        }
        if table.is_none() && !args.quiet {
            progress.clear();
            print_stdout(&format!("{}\n", row_line(&axes, &row)))?;
        }
        Ok(())
    })?;
    let wall = started.elapsed().as_secs_f64();
    progress.clear();
    let mut written = Vec::new();
    if let (Some(mut t), Some(path)) = (table, &args.out) {
        if !t.has_columns() {
            // no run of this part ran (none, or all failed): the sweep's columns all the same
            if let Some(row) = probe(&base, &knobs, &grid, total) {
                t.set_columns(sweep::cells(&axes, &row).into_iter().map(|(name, _)| name).collect())?;
            }
        }
        // a part of a sweep says what it is beside it (docs/sweep.md)
        let mut part = shard.map(|s| {
            let held = indices.start..indices.start + ran;
            PartMeta::new(&args.base, &grid, total, Some(s), held)
        });
        t.finish(part.as_mut())?;
        written.push(format!("table -> {}", path.display()));
    }
    if let (Some(p), Some(path)) = (plot, &args.plot) {
        p.finish()?;
        written.push(format!("plot -> {}", path.display()));
    }
    if let Some(dir) = &args.trails {
        written.push(format!("trails -> {}", dir.display()));
    }
    let part = match shard {
        Some(s) => format!(
            " (part {}/{} of {total}: runs {}..{})",
            s.k, s.n, indices.start, indices.end
        ),
        None => String::new(),
    };
    written.insert(
        0,
        format!(
            "{ran} runs{part}, {} follow, {cannot} cannot follow ({failed} failed to run), in {wall:.3} s on {} threads ({:.1} runs/s)",
            ran - cannot,
            runner.threads(),
            ran as f64 / wall.max(1e-9)
        ),
    );
    print_stdout(&format!("[done] {}\n", written.join(" · ")))?;
    files.commit()?;
    if ran < indices.len() {
        eprintln!(
            "faze4: {} after {ran} of {} runs; the outputs hold those",
            stopped_by(&stop),
            indices.len()
        );
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    // a signal during the final writes: the outputs are whole, but the status says it came
    if stop.signal().is_some() {
        eprintln!(
            "faze4: {} after the last run; the outputs are complete",
            stopped_by(&stop)
        );
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    Ok(ExitCode::SUCCESS)
}

/// The base command (`words`, with a replay's `frames` when given) and the knobs of `grid`'s
/// axes, checked against it.
fn load_for(grid: &Grid, words: &[String], frames: Option<Vec<Vec<f64>>>) -> Result<(Base, Vec<Knob>)> {
    let replan = grid.axes.iter().any(|a| a.name == "shape-points");
    let base = Base::load(words, replan, frames)?;
    let knobs = knobs(&base.command, &grid.axes)?;
    Ok((base, knobs))
}

/// A sweep's rows as a library call (the Python binding's `faze4.sweep`): the runs of
/// `args.vary`'s grid on `args.base` (a replay's `frames` given, or read from its `--q-traj`),
/// in index order, each run stopping at `stop`; with the base's warnings. A raised `stop`
/// ends the sweep early (fewer rows than runs).
pub fn rows(args: &SweepArgs, frames: Option<Vec<Vec<f64>>>, stop: &StopFlag) -> Result<(Vec<Row>, Vec<Warning>)> {
    for (given, name) in [
        (args.out.is_some(), "--out"),
        (args.plot.is_some(), "--plot"),
        (args.shard.is_some(), "--shard"),
        (args.trails.is_some(), "--trails"),
        (args.find.is_some() || args.find_min.is_some(), "--find"),
    ] {
        if given {
            return Err(Error::argument(name, "is not for a sweep's rows in memory"));
        }
    }
    let (grid, indices) = Grid::parse(&args.vary, None, MAX_RUNS)?;
    let (base, knobs) = load_for(&grid, &args.base, frames)?;
    let build = |values: &[f64]| base.build(&knobs, values);
    let runner = Runner::new(&build, threads(args.jobs, indices.len()))?.with_stop(stop);
    let mut rows = Vec::with_capacity(indices.len());
    runner.sweep(&grid, indices, stop, |row| {
        rows.push(row);
        Ok(())
    })?;
    Ok((rows, base.warnings))
}

/// The threads of a sweep of `runs` runs: `jobs` (0: one per core), never more than the runs.
fn threads(jobs: usize, runs: usize) -> usize {
    let jobs = match jobs {
        0 => std::thread::available_parallelism().map_or(1, usize::from),
        n => n,
    };
    jobs.min(runs).max(1)
}

/// Most runs [`probe`] tries to build.
const PROBES: usize = 100;

/// A row with the sweep's columns, for a part none of whose runs ran: the first of the sweep's
/// first [`PROBES`] runs that builds, run for one step (the columns depend on the model and the
/// base command, not on the values; the same for every part). `None` when none builds: the
/// table then has the base columns only.
fn probe(base: &Base, knobs: &[Knob], grid: &Grid, total: usize) -> Option<Row> {
    (0..total.min(PROBES)).find_map(|index| {
        let values = grid.point(index);
        let mut scenario = base.build(knobs, &values).ok()?;
        scenario.steps = scenario.steps.min(1);
        let summary = crate::sim::run(&scenario, &mut [], &StopFlag::new()).ok()?;
        Some(Row {
            index,
            values,
            outcome: Outcome::Ran(Box::new(summary)),
        })
    })
}

/// A run for people: `payload-kg=0.5 dt=0.0002: follows` or `…: cannot follow — reasons`.
fn row_line(axes: &[String], row: &Row) -> String {
    let values: Vec<String> = (axes.iter().zip(&row.values))
        .map(|(n, &v)| format!("{n}={}", exact(v)))
        .collect();
    let answer = match row.follows() {
        true => "follows".to_string(),
        false => format!("cannot follow — {}", row.reasons()),
    };
    format!("{}: {answer}", values.join(" "))
}

fn check_trails(dir: Option<&Path>) -> Result<()> {
    match dir {
        Some(dir) if !dir.is_dir() => Err(Error::argument(
            "--trails",
            format!("{} is not a directory", dir.display()),
        )),
        _ => Ok(()),
    }
}

/// `--find NAME=LO:HI` (or `--find-min`).
fn find(args: &SweepArgs, spec: &str, seek: Seek) -> Result<ExitCode> {
    let (_, line, _) = search(args, spec, seek, None, &StopFlag::new(), |w| warn(w, args.quiet))?;
    print_stdout(&format!("{line}\n"))?;
    Ok(ExitCode::SUCCESS)
}

/// What `--find` (or `--find-min`, as `args` asks) finds, and the line the binary prints for
/// it, as a library call (the Python binding's `faze4.find`); a replay's `frames` given or read
/// from its `--q-traj`; each run stops at `stop`.
pub fn find_line(
    args: &SweepArgs,
    frames: Option<Vec<Vec<f64>>>,
    stop: &StopFlag,
) -> Result<(Found, String, Vec<Warning>)> {
    match (&args.find, &args.find_min) {
        (Some(spec), _) => search(args, spec, Seek::Largest, frames, stop, |_| ()),
        (None, Some(spec)) => search(args, spec, Seek::Smallest, frames, stop, |_| ()),
        (None, None) => Err(Error::argument("--find", "no NAME=LO:HI to find")),
    }
}

/// The search of `--find`/`--find-min` `spec` and its answer line; `warn` is told the base's
/// warnings once it is loaded, before the runs.
fn search(
    args: &SweepArgs,
    spec: &str,
    seek: Seek,
    frames: Option<Vec<Vec<f64>>>,
    stop: &StopFlag,
    warn: impl Fn(&[Warning]),
) -> Result<(Found, String, Vec<Warning>)> {
    let option = match seek {
        Seek::Largest => "--find",
        Seek::Smallest => "--find-min",
    };
    for (given, name) in [
        (args.out.is_some(), "--out"),
        (args.plot.is_some(), "--plot"),
        (args.shard.is_some(), "--shard"),
        (args.trails.is_some(), "--trails"),
    ] {
        if given {
            return Err(Error::argument(name, format!("is for tables, not {option}")));
        }
    }
    let (name, range) = spec
        .split_once('=')
        .ok_or_else(|| Error::argument(option, format!("'{spec}' is not NAME=LO:HI")))?;
    let bounds: Vec<f64> = range
        .split(':')
        .map(|x| x.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| Error::argument(option, format!("'{spec}' is not NAME=LO:HI with numbers")))?;
    let [lo, hi] = bounds[..] else {
        return Err(Error::argument(option, format!("'{spec}' is not NAME=LO:HI")));
    };
    if hi <= lo {
        return Err(Error::argument(
            option,
            format!("{spec}: empty range ({} ≤ {})", exact(hi), exact(lo)),
        ));
    }
    let resolution = args.resolution.unwrap_or((hi - lo) / 100.0);
    if !resolution.is_finite() || resolution <= 0.0 {
        return Err(Error::argument(
            "--resolution",
            format!(
                "{}: give a finite width > 0 (default: 1 % of the range)",
                exact(resolution)
            ),
        ));
    }
    let name = name.trim().trim_start_matches("--");
    let axis = Axis {
        name: name.to_string(),
        values: vec![lo, hi],
    };
    let replan = name == "shape-points";
    let base = Base::load(&args.base, replan, frames)?;
    let knobs = knobs(&base.command, std::slice::from_ref(&axis)).map_err(|e| match e {
        Error::InvalidArgument { message, .. } => Error::argument(option, message),
        other => other,
    })?;
    warn(&base.warnings);
    if let [Knob::Option(Field::Count(_))] = knobs[..] {
        return Err(Error::argument(
            option,
            format!("{name} takes whole numbers: list them with --vary {name}=v1,v2,…"),
        ));
    }
    // each end is a value the option takes, as the command would check it
    for x in [lo, hi] {
        base.build(&knobs, &[x]).map_err(|e| {
            let e = crate::error::one_line(&e.to_string());
            Error::argument(option, format!("{name}={}: {e}", exact(x)))
        })?;
    }
    let build = |values: &[f64]| base.build(&knobs, values);
    let runner = Runner::new(&build, args.jobs)?.with_stop(stop);
    let (lo_text, hi_text) = (exact(lo), exact(hi));
    let found = sweep::find(&runner, lo, hi, resolution, seek);
    let line = match &found {
        Found::Boundary { follows, fails } => {
            let which = match seek {
                Seek::Largest => "largest",
                Seek::Smallest => "smallest",
            };
            // the values run, each as its shortest round-trip decimal: rerunning either with
            // the option gives the same row
            let (follows_at, fails_at) = (exact(follows.values[0]), exact(fails.values[0]));
            format!(
                "{which} {name} that follows: {follows_at} (at {fails_at}: {})",
                fails.reasons()
            )
        }
        Found::NoneFollows(row) => {
            if let sweep::Outcome::Failed(reason) = &row.outcome {
                return Err(Error::argument(
                    option,
                    format!("the run at {name}={} could not run: {reason}", exact(row.values[0])),
                ));
            }
            format!(
                "no {name} in [{lo_text}, {hi_text}] follows: already at {}: {}",
                exact(row.values[0]),
                row.reasons()
            )
        }
        Found::AllFollow(row) => {
            let (end, widen) = match seek {
                Seek::Largest => ("largest", "raise HI"),
                Seek::Smallest => ("smallest", "lower LO"),
            };
            format!(
                "every {name} in [{lo_text}, {hi_text}] follows, {} too: the {end} that follows is beyond the range ({widen})",
                exact(row.values[0])
            )
        }
    };
    Ok((found, line, base.warnings))
}

/// The sweep's progress bar on stderr, when stderr is a terminal: redrawn at most every 0.1 s
/// from whichever thread finishes a run.
struct Progress {
    total: usize,
    done: AtomicUsize,
    started: Instant,
    drawn: Option<Mutex<Option<Instant>>>,
}

const REDRAW: Duration = Duration::from_millis(100);

impl Progress {
    fn new(total: usize, quiet: bool) -> Progress {
        Progress {
            total,
            done: AtomicUsize::new(0),
            started: Instant::now(),
            drawn: (!quiet && std::io::stderr().is_terminal()).then(|| Mutex::new(None)),
        }
    }

    fn tick(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let Some(drawn) = &self.drawn else { return };
        let Ok(mut drawn) = drawn.try_lock() else { return };
        if drawn.is_some_and(|t| t.elapsed() < REDRAW) && done < self.total {
            return;
        }
        const WIDTH: usize = 30;
        let filled = WIDTH * done / self.total.max(1);
        let _ = write!(
            std::io::stderr().lock(),
            "\r\x1b[2K[{}{}] {done}/{} runs · {:.1} s",
            "#".repeat(filled),
            " ".repeat(WIDTH - filled),
            self.total,
            self.started.elapsed().as_secs_f64()
        );
        *drawn = Some(Instant::now());
    }

    /// Erases the bar (before a line is printed, and at the end).
    fn clear(&self) {
        if let Some(Ok(mut drawn)) = self.drawn.as_ref().map(Mutex::lock)
            && drawn.take().is_some()
        {
            let _ = write!(std::io::stderr().lock(), "\r\x1b[2K");
        }
    }
}
