//! `faze4 sweep`: the command line of [`faze4::sweep`]. The base command (after `--`) is parsed
//! into a configuration; a sweep point sets the varied fields of it (or scales the built
//! scenario); the model (and a replay's frames, a shape's plan, the collision meshes) are read
//! once and shared by every run ([`Family`]).

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use clap::Parser;

use super::args::{Cli, SweepArgs, SweepCommand};
use super::{flags, interrupted_status, print_stdout, tell_stop, usage_line, warn};
use faze4::atomic::{Outputs, check_output_path};
use faze4::config::RunConfig;
use faze4::error::{Error, Result, shown_path};
use faze4::output::format::exact;
use faze4::sim::StopFlag;
use faze4::sweep::{
    self, Family, Format, Grid, MAX_RUNS, Outcome, PartMeta, Row, Runner, Seek, Shard, Sharing, TableWriter, threads,
};

/// Whether the runs share their commanded path's clearance (`--own-clearance`: not).
fn sharing(args: &SweepArgs) -> Sharing {
    match args.own_clearance {
        true => Sharing::Own,
        false => Sharing::Shared,
    }
}

/// The base command's words (after `--`) as a run configuration, refused when they give an
/// option the sweep varies (`varied`, for `option`: `vary`, `find`), whose value the sweep would
/// drop.
fn base_config(words: &[String], varied: &[&str], option: &str) -> Result<RunConfig> {
    if words.is_empty() {
        return Err(Error::argument(
            "sweep",
            "no command to run: add -- wave|replay|shape and its options",
        ));
    }
    let argv = std::iter::once("faze4".to_string()).chain(words.iter().cloned());
    let command = Cli::try_parse_from(argv)
        .map_err(|e| Error::argument(format!("sweep -- {}", words[0]), usage_line(&e)))?
        .command;
    match command {
        super::args::Command::Sweep(_) => {
            return Err(Error::argument("sweep", "the command to sweep cannot be a sweep"));
        }
        super::args::Command::Retime(_)
        | super::args::Command::Completions { .. }
        | super::args::Command::Man
        | super::args::Command::List { .. } => {
            return Err(Error::argument(
                "sweep",
                "the command to sweep is a run (wave, replay, shape)",
            ));
        }
        _ => {}
    }
    // the base takes none of the command line's own defaults: its runs' trails are --trails
    let config = super::config::run_config(&command, false)?;
    let given = super::config::given_fields(&command);
    sweep::refuse_given_and_varied(varied, config.motion.command(), &given, option)?;
    Ok(config)
}

/// A failed run's reason with the options it names as flags.
fn in_flags(mut row: Row) -> Row {
    if let Outcome::Failed(reason) = &row.outcome {
        row.outcome = Outcome::Failed(flags(reason));
    }
    row
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
            shown_path(&m.out)
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
        Some(path) => Some(faze4::viz::SweepPlot::new(path, &grid)?.within(&files)),
        None => None,
    };
    check_trails(args.trails.as_deref())?;
    let names: Vec<(&str, &[f64])> = (grid.axes.iter())
        .map(|a| (a.name.as_str(), a.values.as_slice()))
        .collect();
    let varied: Vec<&str> = names.iter().map(|(n, _)| *n).collect();
    let family = Family::load(base_config(&args.base, &varied, "vary")?, None, &names, sharing(args))?;
    // the outputs' temporaries and the runs begin: a signal now stops the sweep cleanly
    stop.watch();
    files.reading(family.inputs().clone())?;
    warn(family.warnings(), args.quiet);
    let axes: Vec<String> = grid.axes.iter().map(|a| a.name.clone()).collect();

    let build = |values: &[f64]| family.build(values);
    let progress = Progress::new(indices.len(), args.quiet);
    let on_done = || progress.tick();
    let mut runner = Runner::new(&build, threads(args.jobs, indices.len()))?
        .with_progress(&on_done)
        .with_stop(&stop);
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
        let row = in_flags(row);
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
            if let Some(row) = family.probe(&grid, total) {
                t.set_columns(sweep::cells(&axes, &row).into_iter().map(|(name, _)| name).collect())?;
            }
        }
        // a part of a sweep says what it is beside it (docs/sweep.md)
        let mut part = shard.map(|s| {
            let held = indices.start..indices.start + ran;
            PartMeta::new(&args.base, &grid, total, Some(s), held)
        });
        t.finish(part.as_mut())?;
        written.push(format!("table -> {}", shown_path(path)));
    }
    if let (Some(p), Some(path)) = (plot, &args.plot) {
        p.finish()?;
        written.push(format!("plot -> {}", shown_path(path)));
    }
    if let Some(dir) = &args.trails {
        written.push(format!("trails -> {}", shown_path(dir)));
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
        tell_stop(
            &stop,
            &format!("after {ran} of {} runs; the outputs hold those", indices.len()),
        );
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    // a signal during the final writes: the outputs are whole, but the status says it came
    if stop.signal().is_some() {
        tell_stop(&stop, "after the last run; the outputs are complete");
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    Ok(ExitCode::SUCCESS)
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
    let name = name.trim().trim_start_matches("--");
    let searched = sweep::search(
        base_config(
            &args.base,
            &[name],
            option.trim_start_matches("--").replace('-', "_").as_str(),
        )?,
        None,
        sharing(args),
        name,
        lo,
        hi,
        args.resolution,
        seek,
        args.jobs,
        &StopFlag::new(),
        |w| warn(w, args.quiet),
    )?;
    print_stdout(&format!("{}\n", flags(&searched.line)))?;
    Ok(ExitCode::SUCCESS)
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
