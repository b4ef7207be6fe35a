//! xacro files → URDF text, as ROS's `xacro` expands them.

use std::path::{Path, PathBuf};

use super::PackagePaths;
use crate::error::{Error, Result};

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
    /// `xacro PATH, NAME:=VALUE, …` (the arguments given).
    pub fn label(&self) -> String {
        let mut label = format!("xacro {}", self.path.display());
        for (name, value) in &self.args {
            label += &format!(", {name}:={value}");
        }
        label
    }
}

/// Expands the xacro `text` of the file `path` with the arguments `args` (`NAME:=VALUE`).
pub fn expand(text: &str, path: &Path, args: &[String], packages: &PackagePaths) -> Result<Expanded> {
    let _ = (text, args, packages);
    Err(Error::model(
        &path.display().to_string(),
        "<robot>",
        "is a xacro file, which faze4 does not expand yet",
    ))
}
