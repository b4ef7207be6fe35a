//! The command line: clap arguments → a validated scenario → the run → its outputs.

pub mod args;
pub mod scenario;

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use clap::Parser;

use self::args::{Cli, Command, RunArgs};
use crate::error::{Error, Result};
use crate::output::atomic::write_atomically;
use crate::output::format::number;
use crate::output::{Recorder, Terminal, TrailCsv};
use crate::sim::{self, Scenario, StopFlag, Summary};
use crate::traj::{Trajectory, npy};
use crate::viz::{HtmlExport, LiveView, PlotRecorder};

/// Exit status of a run that diverged.
pub const EXIT_DIVERGED: u8 = 1;
/// Exit status of bad input (arguments, files, models).
pub const EXIT_INPUT: u8 = 2;
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
            eprintln!("faze4: error: {e}");
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
    // clap's first paragraph (the error and its indented details) joined into one line
    let text = e.to_string();
    let first: Vec<&str> = text.lines().map(str::trim).take_while(|l| !l.is_empty()).collect();
    let first = first.join(" ");
    let first = first.trim_start_matches("error: ");
    eprintln!("faze4: error: {first} (faze4 --help lists the options)");
    ExitCode::from(EXIT_INPUT)
}

fn execute(cli: &Cli) -> Result<ExitCode> {
    let (scenario, run, save_q) = match &cli.command {
        Command::Wave(a) => (scenario::wave(a)?, &a.run, None),
        Command::Replay(a) => (scenario::replay(a)?, &a.run, None),
        Command::Shape(a) => (scenario::shape(a)?, &a.run, a.save_q.as_deref()),
    };
    run_and_report(&scenario, run, save_q)
}

/// Runs `scenario` with the outputs `run` asks for (and, with `save_q`, first writes the
/// command's joint samples there); the exit status says whether it diverged.
fn run_and_report(scenario: &Scenario, run: &RunArgs, save_q: Option<&Path>) -> Result<ExitCode> {
    let stop = StopFlag::ctrl_c();
    let outputs = Outputs::open(run)?;
    if let (Some(path), Trajectory::Interpolated(samples)) = (save_q, &scenario.trajectory) {
        let rows: Vec<Vec<f64>> = (0..samples.rows()).map(|k| samples.row(k).to_vec()).collect();
        npy::write_samples(path, &rows)?;
    }
    let Outputs {
        mut terminal,
        mut trail,
        mut html,
        mut plot,
        mut live,
    } = outputs;
    let mut recorders: Vec<&mut dyn Recorder> = vec![&mut terminal];
    if let Some(t) = trail.as_mut() {
        recorders.push(t);
    }
    if let Some(h) = html.as_mut() {
        recorders.push(h);
    }
    if let Some(p) = plot.as_mut() {
        recorders.push(p);
    }
    if let Some(l) = live.as_mut() {
        recorders.push(l);
    }
    let summary = sim::run(scenario, &mut recorders, &stop)?;
    if let Some(path) = &run.summary {
        write_summary(path, &summary)?;
    }
    let mut written = Vec::new();
    if let Some(t) = &trail {
        written.push(format!("trail -> {} ({} rows)", run.trail.display(), t.rows()));
    }
    if let Some(path) = &run.summary {
        written.push(format!("summary -> {}", path.display()));
    }
    if let Some(path) = save_q {
        written.push(format!("joint samples -> {}", path.display()));
    }
    if let Some(h) = &html {
        written.push(format!("html -> {}", h.path().display()));
    }
    if let Some(p) = &plot {
        written.push(format!("plot -> {}", p.path().display()));
    }
    report_files(scenario, &summary, written);
    if let Some(t) = summary.interrupted_at_s {
        eprintln!("faze4: interrupted at t = {t:.3} s; the outputs are complete up to there");
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    let code = match &summary.diverged {
        None => ExitCode::SUCCESS,
        Some(d) => {
            let joint = &scenario.model.joints[d.joint - 1];
            eprintln!(
                "faze4: diverged at t = {:.4} s on joint J{} ({}): {}; above ~0.5 the discrete loop is unstable (lower --dt or --kp); the outputs keep the steps before it",
                d.t,
                d.joint,
                joint.name,
                stiffest_joints(scenario, &d.stiffness_b)
            );
            ExitCode::from(EXIT_DIVERGED)
        }
    };
    // the run's files are written: Ctrl-C now only ends the serving
    if let (Some(l), true) = (&live, run.hold) {
        l.hold_until(|| stop.is_raised());
    }
    Ok(code)
}

/// The recorders a run writes to, opened (and their paths and port checked) before it starts.
struct Outputs {
    terminal: Terminal,
    trail: Option<TrailCsv>,
    html: Option<HtmlExport>,
    plot: Option<PlotRecorder>,
    live: Option<LiveView>,
}

impl Outputs {
    fn open(run: &RunArgs) -> Result<Outputs> {
        let live = match run.view || run.hold {
            true => Some(LiveView::start(run.port)?.with_period(run.record_period)),
            false => None,
        };
        let html = match run.html.as_deref().filter(|p| !is_none(p)) {
            Some(path) => Some(HtmlExport::new(path)?.with_period(run.record_period)),
            None => None,
        };
        let plot = match run.plot.as_deref() {
            Some(path) => Some(PlotRecorder::new(path)?.with_period(run.record_period)),
            None => None,
        };
        let trail = match is_none(&run.trail) {
            true => None,
            false => Some(TrailCsv::create(&run.trail, run.record_period, run.debug)?),
        };
        Ok(Outputs {
            terminal: Terminal::new(run.debug),
            trail,
            html,
            plot,
            live,
        })
    }
}

fn report_files(scenario: &Scenario, summary: &Summary, mut written: Vec<String>) {
    let per_step = summary.wall_time_s / scenario.steps.max(1) as f64;
    written.push(format!(
        "{} steps in {:.3} s ({:.2} µs/step)",
        scenario.steps,
        summary.wall_time_s,
        per_step * 1e6
    ));
    // a closed stdout (`faze4 … | head`) is not the run's failure
    let _ = writeln!(std::io::stdout().lock(), "[done] {}", written.join(" · "));
}

/// Writes the summary JSON (whole or not at all).
pub fn write_summary(path: &Path, summary: &Summary) -> Result<()> {
    let mut json = serde_json::to_vec_pretty(summary).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    })?;
    json.push(b'\n');
    write_atomically(path, &json)
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
        .map(|&i| format!("J{} ({}) {}", i + 1, scenario.model.joints[i].name, number(b[i], 0)))
        .collect();
    let more = if b.len() > STIFFEST_NAMED {
        format!(" and {} more", b.len() - STIFFEST_NAMED)
    } else {
        String::new()
    };
    let coupled = match &scenario.gains.stability {
        Some(s) => format!(
            "b_max = {}, spectral radius {}; ",
            number(s.b_max, 0),
            number(s.spectral_radius, 0)
        ),
        None => String::new(),
    };
    format!("{coupled}b = Δt²·kp/I largest at {}{more}", named.join(", "))
}
