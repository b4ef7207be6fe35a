//! What clap parsed → the library's [`RunConfig`]: every declared option the command line gave
//! is set by name ([`RunConfig::set`]), which parses and checks it (each error naming the
//! field, which [`super::main`] shows as its flag); the others keep the library's defaults.

use clap::ArgMatches;
use clap::parser::ValueSource;
use faze4::config::RunConfig;
use faze4::config::fields::{self, Field, Kind, Value};
use faze4::error::{Error, Result, Words};

use super::args::{Command, JointValues};

/// The configuration of a run command (`wave`, `replay`, `shape`, `retime`). With
/// `own_defaults`, the command line's own defaults (the trail file) count as given; a sweep's
/// base command takes none (its runs' trails are `--trails DIR`).
pub fn run_config(command: &Command, own_defaults: bool) -> Result<RunConfig> {
    let (run, matches) = command
        .run()
        .ok_or_else(|| Error::argument("sweep", "is a sweep of runs, not a run"))?;
    let mut config = RunConfig::new(run.motion());
    config.outputs.words = Words::Flags;
    for field in fields::of(run) {
        let given = match matches.value_source(field.name) {
            Some(ValueSource::CommandLine) => true,
            Some(ValueSource::DefaultValue) => own_defaults && own_default(field),
            _ => false,
        };
        if given {
            config.set(field.name, value(field, matches))?;
        }
    }
    Ok(config)
}

/// The fields `command`'s line gives (by name), not those left at their defaults.
pub fn given_fields(command: &Command) -> Vec<&'static str> {
    let Some((run, matches)) = command.run() else {
        return Vec::new();
    };
    (fields::of(run))
        .filter(|f| matches.value_source(f.name) == Some(ValueSource::CommandLine))
        .map(|f| f.name)
        .collect()
}

/// Whether `field`'s default on the command line is the binary's own (the library declares
/// none: `--trail`'s).
fn own_default(field: &Field) -> bool {
    field.default.shown().is_none()
}

/// The value clap parsed for `field` (present), as the configuration takes it.
fn value(field: &Field, matches: &ArgMatches) -> Value {
    let name = field.name;
    match field.kind {
        Kind::Flag => Value::Flag(matches.get_flag(name)),
        Kind::Number => Value::Number(get(matches, name)),
        Kind::Count => Value::Count(get(matches, name)),
        Kind::Path => Value::Path(get(matches, name)),
        Kind::Paths => Value::Paths(all(matches, name)),
        Kind::Texts => Value::Texts(all(matches, name)),
        Kind::PerJoint | Kind::Numbers => Value::PerJoint(get::<JointValues>(matches, name).0),
        Kind::Text | Kind::Choice(_) | Kind::Center | Kind::Motors => Value::Text(get(matches, name)),
    }
}

/// Every value of a repeatable `name`, each of which clap parsed as a `T`.
fn all<T: Clone + Send + Sync + 'static>(matches: &ArgMatches, name: &str) -> Vec<T> {
    matches.get_many::<T>(name).into_iter().flatten().cloned().collect()
}

/// The value of `name`, which clap parsed as a `T` ([`super::args`] gives each kind its parser).
fn get<T: Clone + Send + Sync + 'static>(matches: &ArgMatches, name: &str) -> T {
    (matches.get_one::<T>(name).cloned()).unwrap_or_else(|| panic!("clap parses --{name} by its kind"))
}
