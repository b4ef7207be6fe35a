//! The command line: clap arguments → a validated scenario → the run → its outputs.

pub mod args;
pub mod call;
pub mod motors;
pub mod scenario;
pub mod sweep;

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use clap::Parser;

use self::args::{Cli, Command, RunArgs};
use crate::atomic::{Inputs, Outputs};
use crate::error::{Error, Result, escape_controls, escape_lines, quoted};
use crate::geometry::GeometryModel;
use crate::output::format::number;
use crate::output::{PRINT_PERIOD, Terminal, TrailCsv};
use crate::sim::scenario::positive;
use crate::sim::{self, Recorder, Scenario, StopFlag, Summary};
use crate::traj::{Trajectory, npy};
use crate::viz::{HtmlExport, LiveView, MotorPlot, PlotRecorder};

/// Exit status of a run that diverged.
pub const EXIT_DIVERGED: u8 = 1;
/// Exit status of bad input (arguments, files, models).
pub const EXIT_INPUT: u8 = 2;
/// Exit status of a run whose verdict is "cannot follow" or "collides", under `--strict`.
pub const EXIT_CANNOT_FOLLOW: u8 = 3;
/// Exit status of a run stopped by Ctrl-C (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Parses the process arguments, runs, and reports. The whole program.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    match execute(&cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("faze4: error: {}", escape_controls(&e.to_string()));
            ExitCode::from(EXIT_INPUT)
        }
    }
}

/// clap's help and version print as usual; its usage errors become one line on stderr.
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind::*;
    if matches!(
        e.kind(),
        DisplayHelp | DisplayVersion | DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::from(e.exit_code() as u8);
    }
    eprintln!("faze4: error: {}", usage_line(&e));
    ExitCode::from(EXIT_INPUT)
}

/// A clap usage error as the one line the binary prints after `faze4: error: `: clap's first
/// paragraph, and its closest match for a mistyped subcommand, option or value.
pub fn usage_line(e: &clap::Error) -> String {
    // clap's first paragraph (the error and its indented details) joined into one line
    let text = e.to_string();
    let first: Vec<&str> = text.lines().map(str::trim).take_while(|l| !l.is_empty()).collect();
    let first = first.join(" ");
    let first = first.trim_start_matches("error: ");
    // a mistyped subcommand, option or value: clap's closest match
    use clap::error::{ContextKind, ContextValue};
    let suggestion = [
        ContextKind::SuggestedSubcommand,
        ContextKind::SuggestedArg,
        ContextKind::SuggestedValue,
    ]
    .into_iter()
    .find_map(|kind| match e.get(kind) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        Some(ContextValue::Strings(v)) if !v.is_empty() => Some(v.join("' or '")),
        _ => None,
    });
    match suggestion {
        Some(s) => format!("{first}; did you mean '{s}'? (faze4 --help lists the options)"),
        None => format!("{first} (faze4 --help lists the options)"),
    }
}

fn execute(cli: &Cli) -> Result<ExitCode> {
    // the signal handlers go in before the model and its meshes load: a Ctrl-C (or SIGTERM)
    // while they load stops the run before its first step (exit 130, the files as a stopped
    // run writes them) instead of killing the process with nothing written
    let _ = StopFlag::ctrl_c();
    let (scenario, run, save_q) = match &cli.command {
        Command::Wave(a) => (scenario::wave(a)?, &a.run, None),
        Command::Replay(a) => (scenario::replay(a)?, &a.run, None),
        Command::Shape(a) => (scenario::shape(a)?, &a.run, a.save_q.as_deref()),
        Command::Sweep(a) => return sweep::execute(a),
    };
    run_and_report(&scenario, run, save_q, inputs(&cli.command, &scenario.geometry))
}

/// The files a run of `command` reads, which none of its outputs may replace: `--urdf`, the
/// meshes of `geometry`, a `--motors` file, `--q-traj`.
fn inputs(command: &Command, geometry: &GeometryModel) -> Inputs {
    let mut inputs = Inputs::new();
    let run = match command {
        Command::Wave(a) => &a.run,
        Command::Replay(a) => {
            inputs.add(&a.q_traj, "--q-traj");
            &a.run
        }
        Command::Shape(a) => &a.run,
        Command::Sweep(_) => return inputs,
    };
    if let Some(urdf) = &run.urdf {
        inputs.add(urdf, "--urdf");
    }
    if let Some(file) = run.motors.as_deref().filter(|m| m.ends_with(".toml")) {
        inputs.add(Path::new(file), "--motors");
    }
    for (link, path) in geometry.mesh_files() {
        inputs.add(path, format!("the mesh of link {}", quoted(link)));
    }
    inputs
}

/// Prints `warnings` on stderr, one line each; under `quiet`, only those that change the
/// result ([`crate::sim::Warning::changes_result`]).
fn warn(warnings: &[crate::sim::Warning], quiet: bool) {
    for warning in warnings.iter().filter(|w| !quiet || w.changes_result()) {
        eprintln!("faze4: {}", escape_controls(&warning.to_string()));
    }
}

/// Runs `scenario` with the outputs `run` asks for (and, with `save_q`, first writes the
/// command's joint samples there). The last line says whether the arm follows its command; the
/// exit status says whether the run diverged (1), was stopped by a signal (128 + its number:
/// 130 Ctrl-C, 143 SIGTERM, 129 SIGHUP), or, with `--strict`, cannot follow or collides (3).
///
/// Every file is written into one [`Outputs`] set and appears only once the run, every other
/// file and the lines on stdout are complete: an error anywhere leaves every file as it was.
fn run_and_report(scenario: &Scenario, run: &RunArgs, save_q: Option<&Path>, inputs: Inputs) -> Result<ExitCode> {
    let stop = StopFlag::ctrl_c();
    let files = Outputs::new();
    files.reading(inputs)?;
    let save_q = save_q.filter(|p| !is_none(p));
    let (summary, recorders) = run_into(scenario, run, save_q, &files, &mut [], &stop)?;
    let mut stdout = String::new();
    if !run.quiet {
        stdout = report_files(&recorders, run, save_q, &summary);
    }
    // the answer, always the last line on stdout
    stdout.push_str(&format!("{}\n", summary.verdict));
    print_stdout(&stdout)?;
    files.commit()?;
    if let Some(d) = &summary.diverged {
        let joint = scenario.model.joint(d.joint);
        eprintln!(
            "faze4: diverged at t = {:.4} s on joint {} ({}): {} (the tuning rule keeps b ≤ 0.4: lower --dt or --kp); the outputs keep the steps before it",
            d.t,
            d.joint,
            quoted(&joint.name),
            stiffest_joints(scenario, &d.stiffness_b)
        );
    }
    if let Some(t) = summary.interrupted_at_s {
        eprintln!(
            "faze4: {} at t = {t:.3} s; the outputs are complete up to there",
            stopped_by(&stop)
        );
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    // a signal during the final writes: the outputs are whole, but the status says it came
    if stop.signal().is_some() {
        eprintln!("faze4: {} after the run; its outputs are complete", stopped_by(&stop));
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    let code = if summary.diverged.is_some() {
        ExitCode::from(EXIT_DIVERGED)
    } else if run.strict && !summary.verdict.follows {
        ExitCode::from(EXIT_CANNOT_FOLLOW)
    } else {
        ExitCode::SUCCESS
    };
    // the run's files are written: a signal now only ends the serving
    if let (Some(l), true) = (&recorders.live, run.hold) {
        l.hold_until(|| stop.is_raised());
    }
    Ok(code)
}

/// The part of a run every caller shares (the binary, [`call::run`]): opens the recorders
/// `run` asks for in `files`, says the scenario's warnings (unless quiet), writes `save_q`,
/// runs with those recorders and `extra`, and writes the summary file, all into `files` (the
/// caller commits them). The recorders are returned for the report and the live view's hold.
fn run_into(
    scenario: &Scenario,
    run: &RunArgs,
    save_q: Option<&Path>,
    files: &Outputs,
    extra: &mut [&mut dyn Recorder],
    stop: &StopFlag,
) -> Result<(Summary, Recorders)> {
    let mut recorders = Recorders::open(scenario, run, save_q, files)?;
    warn(&scenario.warnings, run.quiet);
    if let (Some(path), Trajectory::Interpolated(samples)) = (save_q, &scenario.trajectory) {
        let rows: Vec<Vec<f64>> = (0..samples.rows()).map(|k| samples.row(k).to_vec()).collect();
        npy::write_samples_within(files, path, &rows)?;
    }
    let mut all = recorders.recorders();
    all.extend(extra.iter_mut().map(|r| &mut **r as &mut dyn Recorder));
    let summary = sim::run(scenario, &mut all, stop)?;
    if let Some(path) = summary_path(run) {
        write_summary(files, path, &summary)?;
    }
    Ok((summary, recorders))
}

/// The exit status of a run or sweep `stop` ended: 128 + the signal's number.
fn interrupted_status(stop: &StopFlag) -> u8 {
    stop.signal().map_or(EXIT_INTERRUPTED, sim::exit_status)
}

/// What stopped a run, for its message: "interrupted" (Ctrl-C), "stopped by SIGTERM"…
fn stopped_by(stop: &StopFlag) -> &'static str {
    match stop.signal() {
        Some(15) => "stopped by SIGTERM",
        Some(1) => "stopped by SIGHUP",
        _ => "interrupted",
    }
}

/// Writes `text` on stdout, its control and bidirectional characters escaped but its line
/// breaks. A failed write (a full disk) is an error; a closed pipe
/// (`faze4 … | head`) is not the run's failure.
fn print_stdout(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    // paths and names as they are shown: no control or bidirectional character (escape_lines)
    match out.write_all(escape_lines(text).as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Error::Io {
            path: "stdout".into(),
            source: e,
        }),
        _ => Ok(()),
    }
}

/// `--summary`, unless absent or `none`.
fn summary_path(run: &RunArgs) -> Option<&Path> {
    run.summary.as_deref().filter(|p| !is_none(p))
}

/// The recorders a run writes to, opened (and every output path and the port checked) before
/// it starts.
struct Recorders {
    terminal: Option<Terminal>,
    trail: Option<TrailCsv>,
    html: Option<HtmlExport>,
    plot: Option<PlotRecorder>,
    motor_plot: Option<MotorPlot>,
    live: Option<LiveView>,
}

impl Recorders {
    /// Claims every output path in `files` (two options naming one file are refused) and
    /// opens the recorders, their files in `files`.
    fn open(scenario: &Scenario, run: &RunArgs, save_q: Option<&Path>, files: &Outputs) -> Result<Recorders> {
        let trail = Some(run.trail.as_path()).filter(|p| !is_none(p));
        let html = run.html.as_deref().filter(|p| !is_none(p));
        let plot = run.plot.as_deref().filter(|p| !is_none(p));
        let motor_plot = run.plot_motors.as_deref().filter(|p| !is_none(p));
        if motor_plot.is_some() && scenario.motors.is_none() {
            return Err(Error::argument("--plot-motors", "draws the motors: add --motors"));
        }
        for (path, option) in [
            (trail, "--trail"),
            (summary_path(run), "--summary"),
            (save_q, "--save-q"),
            (html, "--html"),
            (plot, "--plot"),
            (motor_plot, "--plot-motors"),
        ] {
            if let Some(path) = path {
                files.claim(path, option)?;
            }
        }
        let print_period = match run.print_period {
            Some(p) => {
                positive("--print-period", p)?;
                p
            }
            None => default_print_period(scenario.steps as f64 * scenario.dt),
        };
        let live = match run.view || run.hold {
            true => Some(LiveView::start(run.port)?.with_period(run.record_period)),
            false => None,
        };
        let html = match html {
            Some(path) => Some(HtmlExport::new(path)?.with_period(run.record_period).within(files)),
            None => None,
        };
        let plot = match plot {
            Some(path) => Some(PlotRecorder::new(path)?.with_period(run.record_period).within(files)),
            None => None,
        };
        let motor_plot = match motor_plot {
            Some(path) => Some(MotorPlot::new(path)?.within(files)),
            None => None,
        };
        let trail = match trail {
            Some(path) => Some(TrailCsv::within(files, path, run.record_period, run.debug)?),
            None => None,
        };
        Ok(Recorders {
            terminal: (!run.quiet).then(|| Terminal::new(run.debug, print_period)),
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

/// The `[done]` line: the files written and the run's speed.
fn report_files(outputs: &Recorders, run: &RunArgs, save_q: Option<&Path>, summary: &Summary) -> String {
    let mut written = Vec::new();
    if let Some(t) = &outputs.trail {
        written.push(format!("trail -> {} ({} rows)", run.trail.display(), t.rows()));
    }
    if let Some(path) = summary_path(run) {
        written.push(format!("summary -> {}", path.display()));
    }
    if let Some(path) = save_q {
        written.push(format!("joint samples -> {}", path.display()));
    }
    if let Some(h) = &outputs.html {
        written.push(format!("html -> {}", h.path().display()));
    }
    if let Some(p) = &outputs.plot {
        written.push(format!("plot -> {}", p.path().display()));
    }
    if let Some(path) = run.plot_motors.as_deref().filter(|_| outputs.motor_plot.is_some()) {
        written.push(format!("motor plot -> {}", path.display()));
    }
    let per_step = summary.wall_time_s / summary.steps.max(1) as f64;
    let clearance = match summary.clearance_wall_time_s {
        Some(s) => format!("; self-clearance {s:.3} s of it"),
        None => String::new(),
    };
    written.push(format!(
        "{} steps in {:.3} s ({:.2} µs/step{clearance})",
        summary.steps,
        summary.wall_time_s,
        per_step * 1e6
    ));
    format!("[done] {}\n", written.join(" · "))
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

/// Whether an output path means "do not write it".
fn is_none(path: &Path) -> bool {
    path.as_os_str() == "none"
}

/// How many of the stiffest joints a divergence message names.
const STIFFEST_NAMED: usize = 3;

/// The divergence message's account of the gains, one line on any arm: the coupled figures,
/// then b = Δt²·kp/I of the [`STIFFEST_NAMED`] largest joints (all of them on a small arm).
fn stiffest_joints(scenario: &Scenario, b: &[f64]) -> String {
    let mut order: Vec<usize> = (0..b.len()).collect();
    order.sort_by(|&x, &y| b[y].total_cmp(&b[x]));
    let named: Vec<String> = order
        .iter()
        .take(STIFFEST_NAMED)
        .map(|&i| {
            format!(
                "J{} ({}) {}",
                i + 1,
                quoted(&scenario.model.joints[i].name),
                number(b[i], 0)
            )
        })
        .collect();
    let more = if b.len() > STIFFEST_NAMED {
        format!(" and {} more", b.len() - STIFFEST_NAMED)
    } else {
        String::new()
    };
    let coupled = match &scenario.controller.gains.stability {
        Some(s) => format!(
            "b_max = {}, spectral radius {}; ",
            number(s.b_max, 0),
            number(s.spectral_radius, 0)
        ),
        None => String::new(),
    };
    format!("{coupled}b = Δt²·kp/I largest at {}{more}", named.join(", "))
}
