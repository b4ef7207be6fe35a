//! xacro files → URDF text, as ROS's `xacro` (2.1, the PyPI package) expands them, without
//! ROS or Python: properties (lazy, scoped, property blocks), macros (defaults, `^` forwarding,
//! `*` and `**` blocks), `xacro:include`, `xacro:if`/`unless`, `xacro:arg` and
//! `--xacro-arg NAME:=VALUE`, `$(arg)`, `$(find PKG)` (`--package-path`, `ROS_PACKAGE_PATH`),
//! `$(env)`, `$(optenv)`, `$(dirname)`, `$(eval)`, and `${…}` Python expressions
//! (`expr.rs`) with `xacro.load_yaml` (`yaml.rs`). What is not supported is refused naming the
//! construct, its file and line (docs/robots.md, "xacro").
//!
//! Why not the `xacro` crate (0.1.3): its macros, conditionals and loops return their input
//! unchanged, properties are replaced by name only (no expressions, no scopes), and it reads
//! no YAML and finds no packages; the UR and Franka descriptions need all of these.
//!
//! The expansion is bounded (docs/development.md, "Caps"): every file read as a URDF is
//! (16 MiB), includes nest at most [`MAX_INCLUDE_DEPTH`], macros [`MAX_MACRO_DEPTH`], the
//! expansion as a whole [`MAX_DEPTH`], and the text and elements made at most [`MAX_BUDGET`].

mod dom;
mod expand;
mod expr;
mod value;
mod yaml;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::PackagePaths;
use crate::error::{Error, Result};
use crate::input::MAX_URDF_BYTES;

/// Deepest nesting of `xacro:include`s (32): an include of itself would never end.
pub const MAX_INCLUDE_DEPTH: usize = 32;
/// Deepest nesting of macro calls (100): a macro calling itself would never end.
pub const MAX_MACRO_DEPTH: usize = 100;
/// Deepest nesting of the expansion's elements, macros and includes together (250): it
/// recurses (the UR and Franka descriptions nest about 12).
pub const MAX_DEPTH: usize = 250;
/// Most text (bytes) and elements (64 units each) an expansion may make, YAML values included
/// (64 Mi units): macros calling each other twice per level grow exponentially.
pub const MAX_BUDGET: usize = 64 << 20;
/// Longest text a value may be (the URDF cap, 16 MiB).
pub const MAX_TEXT_BYTES: usize = MAX_URDF_BYTES as usize;

/// A xacro file expanded: the URDF text, and what it was expanded from.
#[derive(Clone, Debug)]
pub struct Expanded {
    /// The URDF text.
    pub urdf: String,
    /// The xacro file.
    pub path: PathBuf,
    /// The arguments given (`NAME`, `VALUE`), in order.
    pub args: Vec<(String, String)>,
}

impl Expanded {
    /// Where the model came from, for the banner, the summary and messages:
    /// `PATH, NAME:=VALUE, …` (the arguments given).
    pub fn label(&self) -> String {
        let mut label = self.path.display().to_string();
        for (name, value) in &self.args {
            label += &format!(", {name}:={value}");
        }
        label
    }
}

/// The arguments `NAME:=VALUE` as (name, value) pairs; a text without `:=` or a name that is
/// not a word is refused naming `xacro_arg`.
pub fn parse_args(args: &[String]) -> Result<Vec<(String, String)>> {
    args.iter()
        .map(|a| match a.split_once(":=") {
            Some((name, value)) if !name.is_empty() && !name.contains(char::is_whitespace) => {
                Ok((name.to_string(), value.to_string()))
            }
            _ => Err(Error::option(
                "xacro_arg",
                format!("'{a}' is not NAME:=VALUE (e.g. ur_type:=ur5e)"),
            )),
        })
        .collect()
}

/// Expands the xacro `text` of the file `path` with the arguments `args` (`NAME:=VALUE`; a
/// later one of a name wins); `packages` finds `$(find PKG)`.
pub fn expand(text: &str, path: &Path, args: &[String], packages: &PackagePaths) -> Result<Expanded> {
    let args = parse_args(args)?;
    let label: Rc<str> = path.display().to_string().into();
    let failed = |file: &str, line: usize, message: String| Error::Xacro {
        file: file.to_string(),
        line,
        message: crate::error::one_line(&message),
    };
    let root = dom::parse(text, &label).map_err(|(line, message)| failed(&label, line, message))?;
    let given: HashMap<String, String> = args.iter().cloned().collect();
    let mut expander = expand::Expander::new(path, label.clone(), given, packages);
    let expanded = expander
        .document(&root)
        .map_err(|f| failed(&f.file, f.line, f.message))?;
    let (unknown, known) = expander.unknown_args(&args);
    if let Some(name) = unknown.first() {
        return Err(Error::option(
            "xacro_arg",
            format!(
                "{name}: {label} neither declares nor reads an argument {} (it knows {}): a misspelled argument would leave the one meant at its default",
                crate::error::quoted(name),
                match known.is_empty() {
                    true => "none".to_string(),
                    false => known
                        .iter()
                        .map(|k| crate::error::quoted(k))
                        .collect::<Vec<_>>()
                        .join(", "),
                }
            ),
        ));
    }
    let urdf = dom::write(&expanded);
    if urdf.len() as u64 > MAX_URDF_BYTES {
        return Err(failed(
            &label,
            root.line,
            format!(
                "expands to {} bytes of URDF, more than the {} a URDF may hold (docs/development.md, Caps)",
                urdf.len(),
                crate::input::size_text(MAX_URDF_BYTES)
            ),
        ));
    }
    Ok(Expanded {
        urdf,
        path: path.to_path_buf(),
        args,
    })
}
