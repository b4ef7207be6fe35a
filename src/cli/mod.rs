//! The command line: clap arguments (built from the library's declared options) → the
//! library's configuration → the run with its outputs ([`faze4::session`]) → the lines and the
//! exit status. The library names options as fields (`` `dt` ``); every line printed here shows
//! them as flags (`--dt`, [`flags`]).

pub mod args;
pub mod config;
pub mod list;
pub mod sweep;

use std::io::Write;
use std::process::ExitCode;

use clap::{CommandFactory, Parser};

use self::args::{Cli, Command};
use faze4::atomic::Outputs;
use faze4::error::{Error, Result, Words, escape_lines, in_words, to_stderr};
use faze4::output::for_people;
use faze4::session::{Prepared, divergence_line, report_text};
use faze4::sim::{self, StopFlag};

/// Exit status of a run that diverged.
pub const EXIT_DIVERGED: u8 = 1;
/// Exit status of bad input (arguments, files, models).
pub const EXIT_INPUT: u8 = 2;
/// Exit status of a run whose verdict is "cannot follow" or "collides", under `--strict`, and
/// of `retime` whenever its checked timing does not follow or no timing follows.
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
        // stdout closed under it (`| head`): the pipe's status, as SIGPIPE would have ended it
        Ok(_) if StopFlag::ctrl_c().signal() == Some(sim::SIGPIPE) => ExitCode::from(sim::exit_status(sim::SIGPIPE)),
        Ok(code) => code,
        Err(e) => failed(&e),
    }
}

/// The end of a command that failed: its error on stderr, status 2; but an output written into
/// a pipe whose reader left (`--trail /dev/stdout | head`, help into `| head`) ends quietly
/// with the pipe's status, as SIGPIPE would have ended it (the other outputs are not written:
/// an output failed).
fn failed(e: &Error) -> ExitCode {
    match e {
        Error::Io { source, .. } | Error::Output { source, .. } if source.kind() == std::io::ErrorKind::BrokenPipe => {
            ExitCode::from(sim::exit_status(sim::SIGPIPE))
        }
        e => {
            to_stderr(&format!("faze4: error: {}", flags(&e.to_string())));
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
        // help and version go to stdout: a failed write there fails the command as any
        // output's does ([`failed`]), where a failed write on stderr leaves clap's status
        return match e.print() {
            Err(source) if !e.use_stderr() => failed(&Error::Io {
                path: "stdout".into(),
                source,
            }),
            _ => ExitCode::from(e.exit_code() as u8),
        };
    }
    to_stderr(&format!("faze4: error: {}", usage_line(&e)));
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
    match suggestion.or_else(|| path_hint(e)) {
        Some(s) => format!("{first}; did you mean '{s}'? (faze4 --help lists the options)"),
        None => format!("{first} (faze4 --help lists the options)"),
    }
}

/// A file given without its flag (`faze4 replay circle.npy`): the flag it is most likely for,
/// with the word (`--q-traj circle.npy`). A robot file by its extension (`--robot`), a motors file
/// (`--motors`), else the trajectory of a command that reads one (`replay`, `retime`).
fn path_hint(e: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    let (ErrorKind::UnknownArgument, Some(ContextValue::String(word))) = (e.kind(), e.get(ContextKind::InvalidArg))
    else {
        return None;
    };
    if word.starts_with('-') || !(word.contains('.') || word.contains('/')) {
        return None;
    }
    let usage = e.get(ContextKind::Usage).map(|u| u.to_string()).unwrap_or_default();
    let lower = word.to_lowercase();
    let flag = if [".urdf", ".xacro", ".xml"].iter().any(|ext| lower.ends_with(ext)) {
        "--robot"
    } else if lower.ends_with(".toml") {
        "--motors"
    } else if usage.contains("faze4 replay") || usage.contains("faze4 retime") {
        "--q-traj"
    } else {
        return None;
    };
    Some(format!("{flag} {word}"))
}

/// A library message with the options it names shown as the command line's flags.
pub fn flags(text: &str) -> String {
    in_words(text, Words::Flags)
}

/// `faze4 completions SHELL`, `faze4 man` and `faze4 list`: what `write` writes, on stdout as
/// it is (made whole first: clap_complete panics on a failed write).
fn shell_file(write: impl FnOnce(&mut Vec<u8>) -> std::io::Result<()>) -> Result<ExitCode> {
    let mut bytes = Vec::new();
    write(&mut bytes).map_err(|source| Error::Io {
        path: "stdout".into(),
        source,
    })?;
    write_stdout(&bytes)?;
    Ok(ExitCode::SUCCESS)
}

fn execute(cli: &Cli) -> Result<ExitCode> {
    // the signal handlers go in first: until a run or its outputs begin, a Ctrl-C (or SIGTERM)
    // ends the process at once with one line (a parse, a load, a retime look at no flag)
    let _ = StopFlag::ctrl_c();
    match &cli.command {
        Command::Sweep(a) => return sweep::execute(a),
        Command::Completions { shell } => {
            return shell_file(|out| {
                clap_complete::generate(*shell, &mut Cli::command(), "faze4", out);
                Ok(())
            });
        }
        Command::Man => return shell_file(|out| clap_mangen::Man::new(Cli::command()).render(out)),
        Command::List { what } => return shell_file(|out| out.write_all(list::text(*what).as_bytes())),
        _ => {}
    }
    let config = config::run_config(&cli.command, true)?;
    if let faze4::config::Motion::Retime(_) = &config.motion {
        return retime_and_report(&config);
    }
    let prepared = Prepared::new(config, None)?;
    run_and_report(&prepared)
}

/// `faze4 retime`: the timing, its lines and the check's verdict last. The exit status is 0
/// only when the checked timing follows: 1 diverged, 128 + a signal's number, else 3 when the
/// check's verdict is not "follows" (the verdict names why: collides, loses steps, tracking
/// error, saturates), with or without `--strict`, the timing then written only under
/// `--force`; a path that no timing follows, or whose poses collide (refused before it is
/// timed), is the reason on stderr, status 3 (nothing is written).
/// Under `--no-check` there is no verdict: status 0 when the timing keeps every limit as a
/// controller plays it (it is then written, unchecked, and says so), else 3.
fn retime_and_report(config: &faze4::config::RunConfig) -> Result<ExitCode> {
    let stop = StopFlag::ctrl_c();
    let files = Outputs::new();
    let quiet = config.outputs.quiet;
    let finished = match faze4::session::retime(config, None, &files, &mut [], &stop, |w| warn(w, quiet)) {
        Err(e @ (Error::NothingFollows { .. } | Error::PathCollides { .. })) => {
            to_stderr(&format!("faze4: {}", flags(&e.to_string())));
            return Ok(ExitCode::from(EXIT_CANNOT_FOLLOW));
        }
        other => other?,
    };
    let out = match &config.motion {
        faze4::config::Motion::Retime(r) => r.out.as_deref(),
        _ => None,
    };
    let mut stdout = String::new();
    if !quiet {
        stdout = flags(&faze4::session::retime_lines(&finished, out));
    }
    // unchecked (`--no-check`): no verdict; the answer is a timing that keeps every limit as played
    let Some(summary) = &finished.summary else {
        print_stdout(&stdout)?;
        files.commit()?;
        if stop.signal().is_some() {
            tell_stop(&stop, "after the timing; its outputs are complete");
            return Ok(ExitCode::from(interrupted_status(&stop)));
        }
        return Ok(ExitCode::from(match finished.follows() {
            true => 0,
            false => EXIT_CANNOT_FOLLOW,
        }));
    };
    // a stopped check has no verdict: it did not play the whole timing
    if let Some(t) = summary.interrupted_at_s {
        print_stdout(&stdout)?;
        tell_stop(
            &stop,
            &format!("at t = {t:.3} s of the check: no verdict; nothing is written"),
        );
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    stdout.push_str(&format!("{}\n", summary.verdict));
    print_stdout(&stdout)?;
    files.commit()?;
    // a signal (or a closed stdout) after the check: the outputs are whole, the status says it
    if stop.signal().is_some() {
        tell_stop(&stop, "after the check; its outputs are complete");
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    // retime's answer is a timing that follows: anything else is status 3, `--strict` or not
    let code = exit_code(summary, true);
    if let (Some(l), true) = (
        finished.replayed.as_ref().and_then(|r| r.recorders.live.as_ref()),
        config.outputs.hold,
    ) {
        l.hold_until(|| stop.is_raised());
    }
    Ok(code)
}

/// Prints `warnings` on stderr, one line each, options as flags; under `quiet`, only those that
/// change the result ([`faze4::sim::Warning::changes_result`]).
fn warn(warnings: &[faze4::sim::Warning], quiet: bool) {
    for warning in warnings.iter().filter(|w| !quiet || w.changes_result()) {
        to_stderr(&format!("faze4: {}", flags(&warning.to_string())));
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
    let finished = faze4::session::run(prepared, &files, &mut [], &stop, |w| warn(w, config.outputs.quiet))?;
    let summary = &finished.summary;
    let mut stdout = report_text(&finished, config);
    // the answer, always the last line on stdout; a run stopped early has none (it did not run
    // the rest of its command)
    if summary.interrupted_at_s.is_none() {
        stdout.push_str(&format!("{}\n", summary.verdict));
    }
    // --hold: the line saying the view stays up comes before the verdict, which stays the last
    // line a terminal shows while the view is served and after Ctrl-C ends it
    let hold = (finished.recorders.live.as_ref()).filter(|_| config.outputs.hold && summary.interrupted_at_s.is_none());
    if let Some(l) = hold {
        to_stderr(&l.hold_line());
    }
    // what ended the run early, on stderr before the result lines: the verdict stays last
    if let Some(d) = &summary.diverged {
        to_stderr(&format!("faze4: {}", flags(&divergence_line(&prepared.scenario, d))));
    }
    if let Some(t) = summary.interrupted_at_s {
        let of = for_people(prepared.scenario.steps as f64 * prepared.scenario.dt);
        tell_stop(
            &stop,
            &format!("at t = {t:.3} s of {of} s: no verdict; the outputs are complete up to there"),
        );
    }
    print_stdout(&stdout)?;
    files.commit()?;
    if summary.interrupted_at_s.is_some() {
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    // a signal during the final writes: the outputs are whole, but the status says it came
    if stop.signal().is_some() {
        tell_stop(&stop, "after the run; its outputs are complete");
        return Ok(ExitCode::from(interrupted_status(&stop)));
    }
    let code = exit_code(summary, config.verdict.strict);
    // the run's files are written: a signal now only ends the serving
    if let Some(l) = hold {
        l.serve_until(|| stop.is_raised());
    }
    Ok(code)
}

/// The exit status of a run that ended: 1 diverged, 3 not followed under `strict`, else 0.
fn exit_code(summary: &sim::Summary, strict: bool) -> ExitCode {
    if summary.diverged.is_some() {
        ExitCode::from(EXIT_DIVERGED)
    } else if strict && !summary.verdict.follows {
        ExitCode::from(EXIT_CANNOT_FOLLOW)
    } else {
        ExitCode::SUCCESS
    }
}

/// The exit status of a run or sweep `stop` ended: 128 + the signal's number.
fn interrupted_status(stop: &StopFlag) -> u8 {
    stop.signal().map_or(EXIT_INTERRUPTED, sim::exit_status)
}

/// Says on stderr that `stop` ended the run (`faze4: stopped by SIGTERM {what}`); a closed
/// stdout ends it quietly, as SIGPIPE ends other programs.
fn tell_stop(stop: &StopFlag, what: &str) {
    if stop.signal() != Some(sim::SIGPIPE) {
        to_stderr(&format!("faze4: {} {what}", stopped_by(stop)));
    }
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
/// breaks (the lines' own parts, paths and names, are escaped where each line is made:
/// [`faze4::error::shown_path`]). A failed write (a full disk) is an error; a closed pipe
/// (`faze4 … | head`) raises the stop flag as SIGPIPE ([`sim::stdout_closed`]): the command
/// ends quietly with SIGPIPE's status.
fn print_stdout(text: &str) -> Result<()> {
    write_stdout(escape_lines(text).as_bytes())
}

/// `bytes` on stdout as they are; a failure as [`print_stdout`] says.
fn write_stdout(bytes: &[u8]) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            sim::stdout_closed();
            Ok(())
        }
        Err(e) => Err(Error::Io {
            path: "stdout".into(),
            source: e,
        }),
        Ok(()) => Ok(()),
    }
}
