//! The command line: clap arguments → the library's configuration → the run with its outputs
//! ([`crate::session`]) → the lines and the exit status. The library names options as fields
//! (`` `dt` ``); every line printed here shows them as flags (`--dt`, [`flags`]).

pub mod args;
pub mod config;
pub mod options;
pub mod sweep;

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use self::args::{Cli, Command};
use crate::atomic::Outputs;
use crate::error::{Error, Result, Words, escape_controls, in_words};
use crate::session::{Prepared, divergence_line, report_text};
use crate::sim::{self, StopFlag};

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
            eprintln!("faze4: error: {}", escape_controls(&flags(&e.to_string())));
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

/// A library message with the options it names shown as the command line's flags.
pub fn flags(text: &str) -> String {
    in_words(text, Words::Flags)
}

fn execute(cli: &Cli) -> Result<ExitCode> {
    // the signal handlers go in before the model and its meshes load: a Ctrl-C (or SIGTERM)
    // while they load stops the run before its first step (exit 130, the files as a stopped
    // run writes them) instead of killing the process with nothing written
    let _ = StopFlag::ctrl_c();
    if let Command::Sweep(a) = &cli.command {
        return sweep::execute(a);
    }
    let prepared = Prepared::new(config::run_config(&cli.command)?, None)?;
    run_and_report(&prepared)
}

/// Prints `warnings` on stderr, one line each, options as flags; under `quiet`, only those that
/// change the result ([`crate::sim::Warning::changes_result`]).
fn warn(warnings: &[crate::sim::Warning], quiet: bool) {
    for warning in warnings.iter().filter(|w| !quiet || w.changes_result()) {
        eprintln!("faze4: {}", escape_controls(&flags(&warning.to_string())));
    }
}

/// Runs `prepared` with the outputs its configuration asks for. The last line says whether the
/// arm follows its command; the exit status says whether the run diverged (1), was stopped by a
/// signal (128 + its number: 130 Ctrl-C, 143 SIGTERM, 129 SIGHUP), or, with `--strict`, cannot
/// follow or collides (3).
///
/// Every file is written into one [`Outputs`] set and appears only once the run, every other
/// file and the lines on stdout are complete: an error anywhere leaves every file as it was.
fn run_and_report(prepared: &Prepared) -> Result<ExitCode> {
    let stop = StopFlag::ctrl_c();
    let files = Outputs::new();
    let config = &prepared.config;
    let finished = crate::session::run(prepared, &files, &mut [], &stop, |w| warn(w, config.outputs.quiet))?;
    let summary = &finished.summary;
    let mut stdout = report_text(&finished, config);
    // the answer, always the last line on stdout
    stdout.push_str(&format!("{}\n", summary.verdict));
    print_stdout(&stdout)?;
    files.commit()?;
    if let Some(d) = &summary.diverged {
        eprintln!("faze4: {}", flags(&divergence_line(&prepared.scenario, d)));
    }
    if let Some(t) = summary.interrupted_at_s {
        eprintln!(
            "faze4: {} at t = {t:.3} s; the outputs are complete up to there",
            stopped_by(&stop)
        );
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    let code = if summary.diverged.is_some() {
        ExitCode::from(EXIT_DIVERGED)
    } else if config.verdict.strict && !summary.verdict.follows {
        ExitCode::from(EXIT_CANNOT_FOLLOW)
    } else {
        ExitCode::SUCCESS
    };
    // the run's files are written: a signal now only ends the serving
    if let (Some(l), true) = (&finished.recorders.live, config.outputs.hold) {
        l.hold_until(|| stop.is_raised());
    }
    Ok(code)
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

/// Writes `text` on stdout. A failed write (a full disk) is an error; a closed pipe
/// (`faze4 … | head`) is not the run's failure.
fn print_stdout(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Error::Io {
            path: "stdout".into(),
            source: e,
        }),
        _ => Ok(()),
    }
}
