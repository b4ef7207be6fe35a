//! The command line, as clap sees it. A run command's arguments are the options the library
//! declares for it ([`faze4::config::fields::FIELDS`]: the flag is the field's name with
//! dashes, its help, value name, default, choices and relations the declaration's), built by
//! [`Declared`]; the binary adds only its own conventions ([`DEFAULT_TRAIL`], `retime`'s
//! required `--out`). [`super::config`] fills a configuration from what clap parsed. `sweep`'s
//! own arguments are the binary's alone.

use std::path::PathBuf;

use clap::builder::PossibleValuesParser;
use clap::{Arg, ArgAction, ArgMatches, Args, FromArgMatches, Parser, Subcommand, value_parser};
use faze4::choice::Choice;
use faze4::config::Command as Run;
use faze4::config::fields::{self, Field, Kind, parse_per_joint};
use faze4::error::Words;

/// faze4: can the motors of a real arm follow this trajectory? A fast, exact dynamics
/// simulator of the Faze4 six-axis arm (or any URDF arm) under a 5 kHz digital PD controller.
#[derive(Debug, Parser)]
#[command(name = "faze4", version, about, long_about = None)]
pub struct Cli {
    /// What to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The experiments.
#[derive(Clone, Debug, Subcommand)]
pub enum Command {
    /// Every joint follows A·sin(ω t + i·π/3) (docs/model.md).
    Wave(Declared<{ Run::Wave as usize }>),
    /// Replay a joint trajectory: time-stamped (.yaml, .json, .mcap, .csv; played once as ros2_control plays it), or an N×dof .npy repeating every --traj-period.
    Replay(Declared<{ Run::Replay as usize }>),
    /// Draw a sine, circle or triangle on the board: exact IK, then the samples as a loop (docs/model.md).
    Shape(Declared<{ Run::Shape as usize }>),
    /// The fastest timing of a path that the motors follow (TOPP-RA on the motors' torque–speed envelopes, checked in the closed loop; docs/retime.md): the path is --q-traj's points (times ignored), the timing goes to --out (replay plays it); --plot draws the phase plane.
    Retime(Declared<{ Run::Retime as usize }>),
    /// Many runs at once: vary options over a grid (--vary), or find the largest value that
    /// still follows (--find); after `--`, the command to run: sweep --vary payload-kg=0:2:0.5 -- shape --shape circle.
    Sweep(SweepArgs),
    /// Print the shell completion script for SHELL on stdout: `faze4 completions bash > ~/.local/share/bash-completion/completions/faze4`.
    Completions {
        /// The shell.
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// Print the manual page (roff) on stdout: `faze4 man > faze4.1 && man ./faze4.1`.
    Man,
    /// List what --robot, --motors and --drive take, with each one's figures and sources: `faze4 list motors`.
    List {
        /// What to list.
        #[arg(value_enum)]
        what: super::list::Listed,
    },
}

impl Command {
    /// A run command and what clap parsed of it (`None` for `sweep`).
    pub fn run(&self) -> Option<(Run, &ArgMatches)> {
        match self {
            Command::Wave(d) => Some(d.parts()),
            Command::Replay(d) => Some(d.parts()),
            Command::Shape(d) => Some(d.parts()),
            Command::Retime(d) => Some(d.parts()),
            Command::Sweep(_) | Command::Completions { .. } | Command::Man | Command::List { .. } => None,
        }
    }
}

/// The trail file a run writes when `--trail` is not given: the command line's own default
/// (the library writes no file it is not asked for).
pub const DEFAULT_TRAIL: &str = "faze4_trail.csv";

/// The arguments of run command `C` (`Run::VALUES[C]`): every option the library declares for
/// it, kept as clap parsed them.
#[derive(Clone, Debug)]
pub struct Declared<const C: usize>(ArgMatches);

impl<const C: usize> Declared<C> {
    /// The command.
    const RUN: Run = Run::VALUES[C];

    fn parts(&self) -> (Run, &ArgMatches) {
        (Self::RUN, &self.0)
    }
}

impl<const C: usize> FromArgMatches for Declared<C> {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        Ok(Declared(matches.clone()))
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        self.0 = matches.clone();
        Ok(())
    }
}

impl<const C: usize> Args for Declared<C> {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        cmd.args(fields::of(Self::RUN).map(|f| own_conventions(Self::RUN, f, arg(f))))
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

/// `arg` with the command line's own conventions for `field` of `run`: a trail unless told
/// otherwise (or retime told `--no-check`), and retime's timing written somewhere (the library
/// writes neither unless asked).
fn own_conventions(run: Run, field: &Field, arg: Arg) -> Arg {
    match (run, field.name) {
        // retime unchecked plays no run: no trail
        (Run::Retime, "trail") => arg.default_value(DEFAULT_TRAIL).default_value_if(
            "no_check",
            clap::builder::ArgPredicate::Equals("true".into()),
            None,
        ),
        (_, "trail") => arg.default_value(DEFAULT_TRAIL),
        (Run::Retime, "out") => arg.required(true),
        _ => arg,
    }
}

/// The argument of a declared option: `--payload-kg <M>`, its help with the options it names as
/// flags, its parser by kind.
fn arg(field: &'static Field) -> Arg {
    let help = field.help_in(Words::Flags);
    let mut arg = Arg::new(field.name)
        .long(field.name.replace('_', "-"))
        // clap's derive drops a help's final full stop; so does the declaration's here
        .help(help.strip_suffix('.').unwrap_or(&help).to_string())
        .required(field.required)
        .conflicts_with_all(field.conflicts.iter().copied());
    for needed in field.requires {
        arg = arg.requires(*needed);
    }
    if let Some(letter) = field.short {
        arg = arg.short(letter);
    }
    for alias in field.aliases {
        arg = arg.visible_alias(alias.replace('_', "-"));
    }
    if let Some(default) = field.default.shown() {
        arg = arg.default_value(default);
    }
    if field.kind == Kind::Flag {
        return arg.action(ArgAction::SetTrue);
    }
    arg = arg.value_name(field.value_name.map_or_else(|| field.name.to_uppercase(), String::from));
    let numeric = matches!(
        field.kind,
        Kind::Number | Kind::Count | Kind::PerJoint | Kind::Numbers | Kind::Center
    );
    arg = arg.allow_hyphen_values(numeric);
    match field.kind {
        Kind::Number => arg.value_parser(value_parser!(f64)),
        Kind::Count => match field.most {
            Some(most) => arg.value_parser(value_parser!(u64).range(..=most)),
            None => arg.value_parser(value_parser!(u64)),
        },
        Kind::Choice(words) => arg.value_parser(PossibleValuesParser::new(words)),
        Kind::Path => arg.value_parser(value_parser!(PathBuf)),
        Kind::Paths => arg.value_parser(value_parser!(PathBuf)).action(ArgAction::Append),
        Kind::Texts => arg.action(ArgAction::Append),
        Kind::PerJoint | Kind::Numbers => arg.value_parser(parse_joint_values),
        Kind::Flag | Kind::Text | Kind::Center | Kind::Motors => arg,
    }
}

/// A comma-separated value per joint; `auto` leaves a joint's value alone
/// ([`faze4::config::fields::parse_per_joint`]).
#[derive(Clone, Debug, PartialEq)]
pub struct JointValues(pub Vec<Option<f64>>);

fn parse_joint_values(text: &str) -> Result<JointValues, String> {
    parse_per_joint(text).map(JointValues)
}

/// `--vary`'s help: the numeric options a sweep varies and the multipliers, from the library.
fn vary_help() -> String {
    let options: Vec<String> = (faze4::sweep::varied_fields().iter())
        .map(|n| n.replace('_', "-"))
        .collect();
    let scales: Vec<&str> = faze4::sweep::Scale::ALL.iter().map(|(n, _)| *n).collect();
    format!(
        "An option and its values: a range LO:HI:STEP (HI included) or a list v1,v2,… (repeatable: the runs are the \
         product). NAME is a numeric option of the command ({}) or a multiplier of the tuned or given values: {}",
        options.join(", "),
        scales.join(", ")
    )
}

/// `faze4 sweep`.
#[derive(Clone, Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct SweepArgs {
    /// Join the tables of a sweep's parts (--shard K/N).
    #[command(subcommand)]
    pub merge: Option<SweepCommand>,
    // its help: vary_help, from the library's options
    #[arg(long, value_name = "NAME=LO:HI:STEP", allow_hyphen_values = true, help = vary_help())]
    pub vary: Vec<String>,
    /// Find the largest value of NAME in [LO, HI] at which the arm still follows (bisection).
    #[arg(long, value_name = "NAME=LO:HI", allow_hyphen_values = true, conflicts_with_all = ["vary", "find_min"])]
    pub find: Option<String>,
    /// Find the smallest value of NAME in [LO, HI] at which the arm follows.
    #[arg(
        long = "find-min",
        value_name = "NAME=LO:HI",
        allow_hyphen_values = true,
        conflicts_with = "vary"
    )]
    pub find_min: Option<String>,
    /// How close --find gets (default: 1 % of the range).
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub resolution: Option<f64>,
    /// Threads (default: one per core; never more than the runs).
    #[arg(long, short, default_value_t = 0, value_name = "N", allow_hyphen_values = true, value_parser = jobs)]
    pub jobs: usize,
    /// The table, one row per run: .csv or .json (default: one line per run on stdout).
    #[arg(long, value_name = "F.csv|F.json")]
    pub out: Option<PathBuf>,
    /// Each figure against the varied option, or heatmaps for two, as .svg or .png.
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    /// Write each run's trail CSV into this directory (run_0000000.csv, …).
    #[arg(long, value_name = "DIR")]
    pub trails: Option<PathBuf>,
    /// Run only part K of N of the sweep (deterministic; `faze4 sweep merge` joins the tables).
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Each run computes its own self-clearance, as alone. By default, when the varied options
    /// keep the commanded path (payload-kg, supply-voltage, friction, the thresholds, the
    /// multipliers), the path's clearance is computed once and each run's derived from it:
    /// within --clearance-tolerance of its own, with the same intersections (docs/clearance.md,
    /// "Sweeps").
    #[arg(long)]
    pub own_clearance: bool,
    /// No progress bar and no per-run lines.
    #[arg(long, short)]
    pub quiet: bool,
    /// The base command and its options, after `--`: wave|replay|shape ….
    #[arg(last = true, value_name = "COMMAND")]
    pub base: Vec<String>,
}

/// Most threads `--jobs` takes.
pub const MAX_JOBS: usize = 1024;

/// `--jobs N`: a whole number of threads, 0 (one per core) to [`MAX_JOBS`].
fn jobs(text: &str) -> Result<usize, String> {
    let most = MAX_JOBS;
    match text.trim().parse::<usize>() {
        Ok(n) if n <= most => Ok(n),
        Ok(_) => Err(format!("at most {most} threads")),
        Err(_) => Err(format!(
            "a number of threads is a whole number from 0 (one per core) to {most}"
        )),
    }
}

/// `faze4 sweep merge`.
#[derive(Clone, Debug, Subcommand)]
pub enum SweepCommand {
    /// Join the tables of a sweep's parts into one, ordered by run; refuses a set that is not
    /// the whole sweep (a part missing, twice, partial, truncated or of another sweep).
    Merge(MergeArgs),
}

/// `faze4 sweep merge a.csv b.csv … --out all.csv`.
#[derive(Clone, Debug, Args)]
pub struct MergeArgs {
    /// The parts' tables (.csv or .json, each with its .meta beside it).
    #[arg(required = true, value_name = "F.csv|F.json")]
    pub tables: Vec<PathBuf>,
    /// The joined table, .csv or .json.
    #[arg(long, required = true, value_name = "F.csv|F.json")]
    pub out: PathBuf,
    /// Merge the parts there are, even if runs are missing or a part is partial (the output
    /// says which runs are absent).
    #[arg(long = "allow-partial")]
    pub allow_partial: bool,
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use clap::CommandFactory;
    use faze4::config::fields::Value;
    use faze4::config::{Motion, RunConfig};

    use super::*;

    fn config(words: &[&str], own_defaults: bool) -> faze4::Result<RunConfig> {
        let cli = Cli::try_parse_from(std::iter::once("faze4").chain(words.iter().copied())).unwrap();
        super::super::config::run_config(&cli.command, own_defaults)
    }

    #[test]
    fn the_command_line_is_well_formed() {
        Cli::command().debug_assert();
        for (i, run) in Run::VALUES.iter().enumerate() {
            assert_eq!(*run as usize, i, "Declared<C> indexes Run::VALUES by discriminant");
        }
    }

    /// Each run command's flags are its declared options, dashed, and nothing else.
    #[test]
    fn every_declared_option_is_a_flag_of_its_commands() {
        let cli = Cli::command();
        for run in Run::VALUES {
            let sub = cli.find_subcommand(run.name()).unwrap();
            let flags: Vec<String> = (sub.get_arguments())
                .filter_map(|a| a.get_long().map(String::from))
                .filter(|l| l != "help")
                .collect();
            let declared: Vec<String> = fields::of(*run).map(|f| f.name.replace('_', "-")).collect();
            assert_eq!(flags, declared, "{}", run.name());
        }
    }

    /// The command line sets what the same names and values set through the library (as
    /// Python's keywords do), and nothing it was not given, but its own trail file.
    #[test]
    fn the_command_line_sets_the_declared_options_by_name() {
        let line = "wave --dt 0.001 --kp auto,2 --center mid --ff full --package-path a --package-path b -q \
                    --port 8000 --shape-points 3";
        let words: Vec<&str> = line.split_whitespace().collect();
        let all = Cli::try_parse_from(std::iter::once("faze4").chain(words.iter().copied()));
        assert!(all.is_err(), "--shape-points is not a wave option");
        let given = config(&words[..words.len() - 2], true).unwrap();
        let mut expected = RunConfig::new(Run::Wave.motion());
        expected.outputs.words = Words::Flags;
        for (name, value) in [
            ("dt", Value::Number(0.001)),
            ("kp", Value::PerJoint(vec![None, Some(2.0)])),
            ("center", Value::Text("mid".into())),
            ("ff", Value::Text("full".into())),
            ("package_path", Value::Paths(vec!["a".into(), "b".into()])),
            ("quiet", Value::Flag(true)),
            ("port", Value::Count(8000)),
            ("trail", Value::Text(DEFAULT_TRAIL.into())),
        ] {
            expected.set(name, value).unwrap();
        }
        assert_eq!(given, expected);
        // a sweep's base takes no trail unless given (then Family::load refuses it)
        let base = config(&["shape", "--shape", "tri"], false).unwrap();
        assert!(matches!(&base.motion, Motion::Shape(s) if s.shape.name() == "tri"));
        assert_eq!(base.outputs.trail, None);
        let none = config(&["wave", "--trail", "none", "--html", "none"], true).unwrap();
        assert_eq!((none.outputs.trail, none.outputs.html), (None, None));
        let retime = config(&["retime", "--q-traj", "p.csv", "--out", "t.yaml"], true).unwrap();
        assert!(matches!(&retime.motion, Motion::Retime(r) if r.out == Some(PathBuf::from("t.yaml"))));
        let no_out = Cli::try_parse_from(["faze4", "retime", "--q-traj", "p.csv"]);
        assert!(no_out.is_err(), "the command line's retime needs --out");
    }

    /// `--vary`'s help names every option a sweep varies, and nothing else.
    #[test]
    fn varys_help_names_what_a_sweep_varies() {
        let help = vary_help();
        let listed: String = (help.split_once("NAME is").unwrap().1.chars())
            .map(|c| if c.is_ascii_lowercase() || c == '-' { c } else { ' ' })
            .collect();
        let known = faze4::sweep::known_names();
        let mut known: Vec<&str> = known.split(", ").collect();
        let mut named: Vec<&str> = (listed.split_whitespace())
            .filter(|w| w.contains('-') || fields::any_field(w).is_some())
            .filter(|w| *w != "a" && !w.starts_with('-'))
            .collect();
        known.sort();
        named.sort();
        named.dedup();
        assert_eq!(named, known);
    }
}
