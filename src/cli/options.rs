//! The options of each command as clap declares them (long name, kind, default, choices,
//! help): for the Python binding's docstrings and signatures, whose keywords are the same
//! fields ([`crate::config::fields`]) with underscores.

use std::any::TypeId;
use std::path::PathBuf;

use clap::{ArgAction, Args, CommandFactory};

use super::args::{Cli, JointValues, RunArgs};

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

/// The options of `command` (`wave`, `replay`, `shape`, `retime`, `sweep`, or `run`: those every run
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::fields::{self, Kind as FieldKind};
    use crate::config::{Motion, ReplayConfig, RetimeConfig, ShapeConfig, WaveConfig};
    use crate::traj::shape::Shape;

    /// Every option clap declares for a run command is a field of the configuration of the same
    /// name and kind, and every field of that command is an option: the command line and Python
    /// name the same options.
    #[test]
    fn the_command_line_and_the_configuration_have_the_same_options() {
        for motion in [
            Motion::Wave(WaveConfig::default()),
            Motion::Replay(ReplayConfig::new("q.npy")),
            Motion::Shape(ShapeConfig::new(Shape::Circle)),
            Motion::Retime(RetimeConfig::new("q.npy")),
        ] {
            let clap: Vec<OptionInfo> = options(motion.name()).unwrap();
            let mut names: Vec<String> = clap.iter().map(|o| o.long.replace('-', "_")).collect();
            let mut declared: Vec<&str> = fields::names(&motion);
            names.sort();
            declared.sort();
            assert_eq!(names, declared, "{}", motion.name());
            for option in &clap {
                let field = fields::field(&option.long.replace('-', "_")).unwrap();
                let agrees = match field.kind {
                    FieldKind::Flag => option.kind == Kind::Flag,
                    FieldKind::Number => option.kind == Kind::Number,
                    FieldKind::Count => option.kind == Kind::Count,
                    FieldKind::Path | FieldKind::Paths => option.kind == Kind::Path,
                    FieldKind::PerJoint | FieldKind::Numbers => option.kind == Kind::PerJoint,
                    FieldKind::Text
                    | FieldKind::Texts
                    | FieldKind::Choice(_)
                    | FieldKind::Center
                    | FieldKind::Motors => option.kind == Kind::Text,
                };
                assert!(
                    agrees,
                    "{}: clap {:?}, field {:?}",
                    option.long, option.kind, field.kind
                );
                if let FieldKind::Choice(words) = field.kind {
                    assert_eq!(option.choices, words, "{}", option.long);
                }
            }
        }
    }

    /// `--vary`'s help names every option a sweep varies, and nothing else.
    #[test]
    fn varys_help_names_what_a_sweep_varies() {
        let sweep = options("sweep").unwrap();
        let help = &sweep.iter().find(|o| o.long == "vary").unwrap().help;
        let listed: String = (help.split_once("NAME is").unwrap().1.chars())
            .map(|c| if c.is_ascii_lowercase() || c == '-' { c } else { ' ' })
            .collect();
        let known = crate::sweep::known_names();
        let mut known: Vec<&str> = known.split(", ").collect();
        let mut named: Vec<&str> = (listed.split_whitespace())
            .filter(|w| w.contains('-') || crate::config::fields::field(w).is_some())
            .filter(|w| *w != "a" && !w.starts_with('-'))
            .collect();
        known.sort();
        named.sort();
        named.dedup();
        assert_eq!(named, known);
    }
}
