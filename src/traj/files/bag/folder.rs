//! A rosbag2 bag as `ros2 bag record` writes it: a folder holding `metadata.yaml` and the
//! storage files it lists (`relative_file_paths`, in order: a split bag's files one after the
//! other), each an MCAP file or an SQLite `.db3`, compressed whole with zstd under
//! `compression_mode: FILE` (`bag_0.mcap.zstd`), or message by message under `MESSAGE` (each
//! message a zstd frame). A folder without `metadata.yaml` (a recording that was cut short)
//! is read from its `.mcap` and `.db3` files in split order (`name_0`, `name_1`, …).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::{Result, quoted};
use crate::input::{MAX_META_BYTES, read_file_capped};
use crate::traj::files::invalid;

/// The file that makes a folder a rosbag2 bag.
pub const METADATA: &str = "metadata.yaml";

/// `metadata.yaml`: the fields read.
#[derive(Debug, Deserialize)]
struct Metadata {
    rosbag2_bagfile_information: Information,
}

#[derive(Debug, Deserialize)]
struct Information {
    #[serde(default)]
    storage_identifier: String,
    #[serde(default)]
    relative_file_paths: Vec<String>,
    #[serde(default)]
    compression_format: String,
    #[serde(default)]
    compression_mode: String,
}

/// The storage files of the rosbag2 folder `dir`, in order, and what it is, for people
/// (`a rosbag2 folder of 2 MCAP files, zstd per message`).
pub fn files(dir: &Path) -> Result<(Vec<PathBuf>, String)> {
    let metadata = dir.join(METADATA);
    if !metadata.exists() {
        return unlisted(dir);
    }
    let bytes = read_file_capped(&metadata, MAX_META_BYTES, "a rosbag2 metadata.yaml")?;
    let text = String::from_utf8_lossy(&bytes);
    let info = serde_norway::from_str::<Metadata>(&text)
        .map_err(|e| {
            invalid(
                &metadata,
                format!(
                    "not a rosbag2 metadata.yaml: {}",
                    crate::error::file_words(&e.to_string())
                ),
            )
        })?
        .rosbag2_bagfile_information;
    let compression = match (
        info.compression_format.as_str(),
        info.compression_mode.to_ascii_uppercase().as_str(),
    ) {
        (_, "" | "NONE") => String::new(),
        ("zstd", "FILE") => ", each file compressed with zstd".into(),
        ("zstd", "MESSAGE") => ", each message compressed with zstd".into(),
        (format, mode) => {
            return Err(invalid(
                &metadata,
                format!(
                    "compression {} of mode {}: faze4 reads zstd, per file or per message",
                    quoted(format),
                    quoted(mode)
                ),
            ));
        }
    };
    if info.relative_file_paths.is_empty() {
        return Err(invalid(&metadata, "lists no file (relative_file_paths is empty)"));
    }
    let files = (info.relative_file_paths.iter())
        .map(|name| {
            // relative to the folder; bags of ROS 2 Foxy and before name the folder too
            let candidates = [dir.join(name), dir.parent().unwrap_or(dir).join(name)];
            let by_name = Path::new(name).file_name().map(|f| dir.join(f));
            (candidates.into_iter().chain(by_name))
                .find(|p| p.exists())
                .ok_or_else(|| {
                    invalid(
                        &metadata,
                        format!("lists {}, which is not in {}", quoted(name), dir.display()),
                    )
                })
        })
        .collect::<Result<Vec<_>>>()?;
    let storage = match info.storage_identifier.as_str() {
        "mcap" => "MCAP",
        "sqlite3" => "SQLite",
        other => other,
    };
    let what = format!(
        "a rosbag2 folder of {} {storage} file{}{compression}",
        files.len(),
        if files.len() == 1 { "" } else { "s" }
    );
    Ok((files, what))
}

/// A folder without `metadata.yaml`: its `.mcap` and `.db3` files (zstd-compressed ones too),
/// in split order.
fn unlisted(dir: &Path) -> Result<(Vec<PathBuf>, String)> {
    let entries = std::fs::read_dir(dir).map_err(|source| crate::Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut files: Vec<(String, u64, PathBuf)> = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let stem = name.strip_suffix(".zstd").unwrap_or(&name);
        let Some(stem) = stem.strip_suffix(".mcap").or_else(|| stem.strip_suffix(".db3")) else {
            continue;
        };
        // bag_12 → ("bag", 12): split files in numeric order
        let (base, index) = match stem.rsplit_once('_') {
            Some((base, k)) if k.parse::<u64>().is_ok() => (base.to_string(), k.parse().unwrap_or(0)),
            _ => (stem.to_string(), 0),
        };
        files.push((base, index, entry.path()));
    }
    files.sort();
    if files.is_empty() {
        return Err(invalid(
            dir,
            format!(
                "is a directory holding neither a rosbag2 bag ({METADATA}, .mcap or .db3 files) nor a LeRobot dataset (meta/info.json)"
            ),
        ));
    }
    let what = format!(
        "a rosbag2 folder without {METADATA} ({} file{} read in split order)",
        files.len(),
        if files.len() == 1 { "" } else { "s" }
    );
    Ok((files.into_iter().map(|(_, _, p)| p).collect(), what))
}
