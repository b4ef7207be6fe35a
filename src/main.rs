//! The `faze4` binary: the command line of the library. Its arguments are built from the
//! options the library declares (`faze4::config::fields`), clap lives only here
//! ([`cli`]), and so do the command line's own conventions: flags, the default trail file,
//! the exit statuses.

#![forbid(unsafe_code)]

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
