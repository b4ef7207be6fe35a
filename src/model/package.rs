//! Resolving mesh references: `package://name/…`, `file://…`, relative and absolute paths.

use std::path::{Path, PathBuf};

use crate::input::MAX_SIDE_FILE_BYTES;

/// Where `package://` references are looked for: the directories given on the command line
/// (`--package-path`), then those of `ROS_PACKAGE_PATH`, as ROS users expect.
///
/// For `package://NAME/rest` and each directory D, in order: `D/NAME/rest`; `D/rest` when D
/// itself is the package (its name is NAME, or its `package.xml` says so); a sub-directory of D
/// (up to three levels) that is the package; finally `D/rest`, so that pointing at a
/// description folder works whatever its package name (as for the official Faze4 files).
#[derive(Clone, Debug, Default)]
pub struct PackagePaths {
    dirs: Vec<PathBuf>,
}

impl PackagePaths {
    /// Search `dirs` only.
    pub fn new(dirs: Vec<PathBuf>) -> Self {
        Self { dirs }
    }

    /// Search `dirs`, then every entry of the `ROS_PACKAGE_PATH` environment variable.
    pub fn with_ros_package_path(mut dirs: Vec<PathBuf>) -> Self {
        if let Some(ros) = std::env::var_os("ROS_PACKAGE_PATH") {
            dirs.extend(std::env::split_paths(&ros).filter(|p| !p.as_os_str().is_empty()));
        }
        Self { dirs }
    }

    /// The directories searched, in order.
    pub fn dirs(&self) -> &[PathBuf] {
        &self.dirs
    }

    /// What `uri` refers to, if it exists (a file, or a directory or FIFO that its reader then
    /// names as such). Relative paths are taken from `base_dir` (the URDF's directory).
    ///
    /// A `package://` reference stays in its package: its package name must be a name (not
    /// `..`), and the entry found must lie inside the package's folder once `..` and symbolic
    /// links are resolved; else the error says where it leads. (A workspace built with
    /// `colcon build --symlink-install` links each installed file to its source: give
    /// `--package-path` the source folder then.)
    pub fn resolve(&self, uri: &str, base_dir: Option<&Path>) -> Result<Option<PathBuf>, String> {
        if let Some(rest) = uri.strip_prefix("package://") {
            let Some((name, rel)) = rest.split_once('/') else {
                return Ok(None);
            };
            if name.is_empty() || name == "." || name == ".." {
                return Err(format!("'{name}' is not a package name"));
            }
            return self.resolve_package(name, rel);
        }
        let path = match uri.strip_prefix("file://") {
            Some(p) => PathBuf::from(p),
            None => PathBuf::from(uri),
        };
        let path = match (path.is_relative(), base_dir) {
            (true, Some(base)) => base.join(path),
            _ => path,
        };
        Ok(path.exists().then_some(path))
    }

    /// `rel` in the package `name` (see [`PackagePaths`] for the order of the search).
    fn resolve_package(&self, name: &str, rel: &str) -> Result<Option<PathBuf>, String> {
        // (package folder, candidate) in the order of the search
        let candidates = (self.dirs.iter().map(|d| d.join(name)))
            .chain(self.dirs.iter().filter(|d| is_package(d, name)).cloned())
            .chain(self.dirs.iter().filter_map(|d| find_package_below(d, name, 3)))
            .chain(self.dirs.iter().cloned());
        for package in candidates {
            let path = package.join(rel);
            if !path.exists() {
                continue;
            }
            let inside = match (std::fs::canonicalize(&package), std::fs::canonicalize(&path)) {
                (Ok(package), Ok(found)) => found.starts_with(&package).then_some(()).ok_or(found),
                (_, Err(e)) => return Err(format!("{}: {e}", path.display())),
                (Err(e), _) => return Err(format!("{}: {e}", package.display())),
            };
            return match inside {
                Ok(()) => Ok(Some(path)),
                Err(found) => Err(format!(
                    "leaves its package: {} resolves to {}, outside the package folder {}",
                    path.display(),
                    found.display(),
                    package.display()
                )),
            };
        }
        Ok(None)
    }
}

/// What to do about a mesh reference that was not found, for its warning: for
/// `package://NAME/…`, ROS's rule (give `` `package_path` `` the folder that contains the package
/// folder NAME, or set `ROS_PACKAGE_PATH`); for a path, where it was looked for.
pub fn not_found_advice(uri: &str) -> String {
    match uri.strip_prefix("package://").and_then(|rest| rest.split_once('/')) {
        Some((name, _)) => format!(
            "package '{name}': give `package_path` the folder that contains the package folder '{name}', as ROS_PACKAGE_PATH would"
        ),
        None => "a relative path is taken from the robot file's folder".to_string(),
    }
}

/// Whether directory `dir` is the ROS package `name`.
fn is_package(dir: &Path, name: &str) -> bool {
    if dir.file_name().is_some_and(|n| n == name) {
        return true;
    }
    let xml = crate::input::read_file_capped(&dir.join("package.xml"), MAX_SIDE_FILE_BYTES, "a package.xml");
    xml.is_ok_and(|xml| String::from_utf8_lossy(&xml).contains(&format!("<name>{name}</name>")))
}

fn find_package_below(dir: &Path, name: &str, depth: usize) -> Option<PathBuf> {
    if depth == 0 {
        return None;
    }
    let mut subdirs: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    subdirs.sort();
    subdirs
        .iter()
        .find(|d| is_package(d, name))
        .cloned()
        .or_else(|| subdirs.iter().find_map(|d| find_package_below(d, name, depth - 1)))
}
