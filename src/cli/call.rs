//! The command line as a library call: the words of a command (what follows `faze4` on a
//! command line) → the binary's own parse, scenario, run and output files, with the trail kept
//! in memory. The Python binding (`src/python/`) turns its keywords into these words, so every
//! option of the command line is a keyword of the same name and default, and a run's summary
//! is the binary's for the same options; [`options`] describes them for its docstrings.

use std::any::TypeId;
use std::path::PathBuf;

use clap::{ArgAction, Args, CommandFactory, Parser};

use super::args::{Cli, Command, JointValues, RunArgs, SweepArgs};
use super::{is_none, run_into, scenario, usage_line};
use crate::atomic::Outputs;
use crate::error::{Error, Result};
use crate::output::Capture;
use crate::sim::{StopFlag, Summary};

/// `words` (e.g. `["wave", "--amp-deg", "25"]`) parsed by the binary's clap definitions; a
/// usage error is the one line the binary prints after `faze4: error: `.
pub fn parse(words: &[String]) -> std::result::Result<Command, String> {
    let argv = std::iter::once("faze4".to_string()).chain(words.iter().cloned());
    Cli::try_parse_from(argv)
        .map(|cli| cli.command)
        .map_err(|e| usage_line(&e))
}

/// What kind of value an option takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A flag: given or not.
    Flag,
    /// A real number.
    Number,
    /// A whole number.
    Count,
    /// A word or text.
    Text,
    /// A file or directory.
    Path,
    /// One value per joint, comma-separated (`auto` or empty keeps a joint's).
    PerJoint,
}

impl Kind {
    /// The kind's name: `flag`, `float`, `int`, `str`, `path`, `joints`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Flag => "flag",
            Kind::Number => "float",
            Kind::Count => "int",
            Kind::Text => "str",
            Kind::Path => "path",
            Kind::PerJoint => "joints",
        }
    }
}

/// An option of a command as its clap definition declares it.
#[derive(Clone, Debug, PartialEq)]
pub struct OptionInfo {
    /// The long name, without `--` (`amp-deg`).
    pub long: String,
    /// What it takes.
    pub kind: Kind,
    /// Whether it can be given more than once (`--package-path`).
    pub repeated: bool,
    /// Whether the command needs it.
    pub required: bool,
    /// Its default as the command line shows it (none: the option is off or computed).
    pub default: Option<String>,
    /// The values it accepts, when it names them.
    pub choices: Vec<String>,
    /// Its help text.
    pub help: String,
}

/// The options of `command` (`wave`, `replay`, `shape`, `sweep`, or `run`: those every run
/// command shares), in the order of `faze4 COMMAND --help`; `None` for another name.
pub fn options(command: &str) -> Option<Vec<OptionInfo>> {
    let cmd = match command {
        "run" => RunArgs::augment_args(clap::Command::new("run")),
        name => Cli::command().find_subcommand(name)?.clone(),
    };
    let info = cmd
        .get_arguments()
        .filter_map(|arg| {
            let long = arg.get_long()?.to_string();
            let id = arg.get_value_parser().type_id();
            let action = arg.get_action();
            let kind = if matches!(action, ArgAction::SetTrue) {
                Kind::Flag
            } else if id == TypeId::of::<f64>() {
                Kind::Number
            } else if id == TypeId::of::<usize>() || id == TypeId::of::<u16>() {
                Kind::Count
            } else if id == TypeId::of::<PathBuf>() {
                Kind::Path
            } else if id == TypeId::of::<JointValues>() {
                Kind::PerJoint
            } else {
                Kind::Text
            };
            let default = match kind {
                Kind::Flag => None,
                _ => arg
                    .get_default_values()
                    .first()
                    .map(|d| d.to_string_lossy().into_owned()),
            };
            Some(OptionInfo {
                long,
                kind,
                repeated: matches!(action, ArgAction::Append),
                required: arg.is_required_set(),
                default,
                choices: match kind {
                    Kind::Flag => Vec::new(),
                    _ => arg
                        .get_possible_values()
                        .iter()
                        .map(|v| v.get_name().to_string())
                        .collect(),
                },
                help: arg.get_help().map(|h| h.to_string()).unwrap_or_default(),
            })
        })
        .collect();
    Some(info)
}

/// What a run gives back: its summary, its trail in memory, the warnings it had.
#[derive(Clone, Debug)]
pub struct Finished {
    /// The summary (`--summary`'s JSON).
    pub summary: Summary,
    /// The trail's rows.
    pub trail: Capture,
    /// The scenario's warnings, one line each.
    pub warnings: Vec<String>,
}

/// Runs `command` (`wave`, `replay` or `shape`) as the binary does: the same scenario, the
/// output files its options ask for, the summary file; `frames` are a replay's joint positions
/// given in memory instead of read from `--q-traj` (which then only names them in messages).
/// The run stops at `stop`. Nothing is printed unless `--quiet` is off.
pub fn run(command: &Command, frames: Option<Vec<Vec<f64>>>, stop: &StopFlag) -> Result<Finished> {
    let (scenario, run, save_q) = match command {
        Command::Wave(a) => (scenario::wave(a)?, &a.run, None),
        Command::Replay(a) => match frames {
            Some(frames) => (
                scenario::replay_with(a, scenario::load_model(&a.run)?, &frames, None)?,
                &a.run,
                None,
            ),
            None => (scenario::replay(a)?, &a.run, None),
        },
        Command::Shape(a) => (scenario::shape(a)?, &a.run, a.save_q.as_deref()),
        Command::Sweep(_) => {
            return Err(Error::argument("sweep", "is a sweep of runs, not a run"));
        }
    };
    let mut trail = Capture::new(run.record_period);
    let files = Outputs::new();
    files.reading(super::inputs(command, &scenario.geometry))?;
    let save_q = save_q.filter(|p| !is_none(p));
    let (summary, recorders) = run_into(&scenario, run, save_q, &files, &mut [&mut trail], stop)?;
    files.commit()?;
    if let (Some(live), true) = (&recorders.live, run.hold) {
        live.hold_until(|| stop.is_raised());
    }
    Ok(Finished {
        summary,
        trail,
        warnings: scenario.warnings.iter().map(ToString::to_string).collect(),
    })
}

/// `words` parsed as `faze4 sweep …` (the sweep's options, `--`, the base command).
pub fn parse_sweep(words: &[String]) -> std::result::Result<SweepArgs, String> {
    match parse(words)? {
        Command::Sweep(args) => Ok(args),
        _ => Err("not a sweep".to_string()),
    }
}

/// A run command's effort limits as a run of `run` uses them (N·m or N; infinite where the
/// model has none): `--effort`, else the motors' (`--motors`), else the model's own.
pub fn effort(run: &RunArgs, model: &crate::model::Model) -> Result<Vec<f64>> {
    scenario::effort_limits(model, run)
}
