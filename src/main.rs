//! The `faze4` binary: everything is in the library's `cli` module.

fn main() -> std::process::ExitCode {
    faze4::cli::main()
}
