//! LeRobot datasets (<https://github.com/huggingface/lerobot>): a folder holding
//! `meta/info.json` and the frames as Parquet tables, read with the `parquet` crate (its row
//! API; only the Snappy and zstd codecs built in: LeRobot writes Snappy).
//!
//! * v3.0: the frames of every episode in `data/chunk-*/file-*.parquet`, the episode's rows
//!   told by `episode_index` (a row group whose `episode_index` statistics exclude it is
//!   skipped);
//! * v2.x: one file per episode, `data_path` of `info.json` with `episode_chunk` =
//!   `episode_index / chunks_size`.
//!
//! The joints are one column (`action` by default, or `--lerobot-key observation.state`), a
//! list per frame named by `features.<key>.names` (`shoulder_pan.pos` is joint
//! `shoulder_pan`), the time is `timestamp` (s, from the episode's first frame). LeRobot
//! stores a joint as −100…100 normalised by the arm's calibration (`MotorNormMode.RANGE_M100_100`)
//! unless the arm was recorded in degrees (`use_degrees`), and the gripper as 0…100 % of its
//! range (`RANGE_0_100`): `--calibration FILE.json` turns normalised values into radians,
//! `--units deg|rad` says the values are angles; a gripper column is left out (the gripper
//! holds) with a warning. docs/trajectories.md, "LeRobot datasets".

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::file::statistics::Statistics;
use parquet::record::Field;
use parquet::schema::types::Type;
use serde::Deserialize;

use super::{Selection, invalid};
use crate::error::{Error, Result, quoted};
use crate::input::{MAX_META_BYTES, MAX_SIDE_FILE_BYTES, read_file_capped, regular_file, too_large};
use crate::traj::{TimedTrajectory, TrajectoryPoint};

/// The file that makes a folder a LeRobot dataset.
pub const INFO: &str = "meta/info.json";

/// Largest Parquet file of a dataset read (1 GiB; LeRobot writes files of about 100 MB,
/// `data_files_size_in_mb`): it is read in place, a row group at a time.
pub const MAX_PARQUET_BYTES: u64 = 1 << 30;

/// Most frames an episode may have (1 million: 9 hours at 30 frames a second).
pub const MAX_EPISODE_FRAMES: usize = 1_000_000;

/// The counts of a motor's position a turn: 4096 for the Feetech STS3215 (SO-100, SO-101) and
/// the Dynamixel XL330/XL430 (Koch), LeRobot's `model_resolution_table`.
pub const RESOLUTION: f64 = 4096.0;

/// What the values of a dataset are, as the user says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// Radians (`--units rad`).
    Rad,
    /// Degrees (`--units deg`: a LeRobot arm recorded with `use_degrees`).
    Deg,
}

crate::choice::choice_words!(Units { Deg => "deg", Rad => "rad" });

/// `meta/info.json`: the fields read.
#[derive(Debug, Deserialize)]
struct Info {
    codebase_version: String,
    #[serde(default)]
    data_path: Option<String>,
    #[serde(default)]
    chunks_size: Option<usize>,
    #[serde(default)]
    total_episodes: Option<usize>,
    features: BTreeMap<String, Feature>,
}

#[derive(Debug, Deserialize)]
struct Feature {
    #[serde(default)]
    names: Option<serde_json::Value>,
}

/// One motor of LeRobot's calibration file (`MotorCalibration` in `lerobot/motors/motors_bus.py`).
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct MotorCalibration {
    /// 1: the motor turns the other way (its normalised value is negated).
    pub drive_mode: i64,
    /// The motor's raw position at one end of its range (counts).
    pub range_min: f64,
    /// At the other end.
    pub range_max: f64,
}

impl MotorCalibration {
    /// The angle (rad) of the normalised value `n` (−100…100): LeRobot's `_normalize` (n =
    /// (raw − min)/(max − min)·200 − 100, negated under drive mode 1) inverted, and its
    /// `DEGREES` mode's angle of that raw value, (raw − (min + max)/2)·360/(4096 − 1), in
    /// radians: n·(max − min)/200 · 2π/4095.
    pub fn radians(&self, n: f64) -> f64 {
        let n = if self.drive_mode != 0 { -n } else { n };
        n * (self.range_max - self.range_min) / 200.0 * 2.0 * PI / (RESOLUTION - 1.0)
    }
}

/// An episode read: its trajectory, what it is for people and what was noticed.
#[derive(Clone, Debug, PartialEq)]
pub struct Episode {
    /// The trajectory (unchecked).
    pub trajectory: TimedTrajectory,
    /// `a LeRobot v3.0 dataset, episode 3 (of 4), action`.
    pub what: String,
    /// Warnings (the gripper column left out).
    pub warnings: Vec<String>,
    /// Said with a joint-limit refusal when the values were taken as radians unasked.
    pub limit_hint: Option<String>,
}

/// The episode `selection` picks (`episode`, default 0) from the dataset folder `dir`.
pub fn read(dir: &Path, selection: &Selection) -> Result<Episode> {
    if selection.message.is_some() || selection.topic.is_some() {
        let field = if selection.message.is_some() {
            "message"
        } else {
            "topic"
        };
        return Err(Error::option(
            field,
            "picks from a file or bag, not a LeRobot dataset (use `episode`)",
        ));
    }
    if selection.units.is_some() && selection.calibration.is_some() {
        return Err(Error::option(
            "units",
            "and `calibration` both say what the values are: `calibration` for LeRobot's normalised values, `units` for angles",
        ));
    }
    let info_path = dir.join(INFO);
    let text = read_file_capped(&info_path, MAX_META_BYTES, "a LeRobot info.json")?;
    let info: Info = serde_json::from_slice(&text).map_err(|e| {
        invalid(
            &info_path,
            format!("not a LeRobot info.json: {}", crate::error::file_words(&e.to_string())),
        )
    })?;
    layout(&info, &info_path)?;
    let episode = selection.episode.unwrap_or(0);
    if let Some(total) = info.total_episodes
        && episode >= total
    {
        return Err(Error::option(
            "episode",
            format!("{episode}: {} holds {total} episodes, counted from 0", dir.display()),
        ));
    }
    let key = selection.lerobot_key.as_deref().unwrap_or("action");
    let names = column_names(&info, key, &info_path)?;
    let frames = frames(dir, &info, episode, key, names.len())?;
    if frames.is_empty() {
        return Err(Error::option(
            "episode",
            format!("{episode}: {} has no frame of that episode", dir.display()),
        ));
    }
    let calibration = match &selection.calibration {
        Some(path) => Some(calibration(path)?),
        None => None,
    };
    let source = Source {
        dir,
        info: &info,
        episode,
        key,
    };
    episode_trajectory(&source, &names, frames, selection.units, calibration.as_ref())
}

/// Which episode of which dataset, for the trajectory's description.
#[derive(Clone, Copy)]
struct Source<'a> {
    dir: &'a Path,
    info: &'a Info,
    episode: usize,
    key: &'a str,
}

/// The joint names of column `key`: `features.<key>.names`, a list or `{"motors": [...]}`.
fn column_names(info: &Info, key: &str, path: &Path) -> Result<Vec<String>> {
    let feature = info.features.get(key).ok_or_else(|| {
        let keys: Vec<&str> = (info.features.iter())
            .filter(|(_, f)| f.names.as_ref().is_some_and(|n| n.is_array() || n.is_object()))
            .map(|(k, _)| k.as_str())
            .collect();
        Error::option(
            "lerobot_key",
            format!(
                "{key}: {} has no such feature (its features with names: {})",
                path.display(),
                keys.join(", ")
            ),
        )
    })?;
    let list = match &feature.names {
        Some(serde_json::Value::Array(list)) => Some(list),
        Some(serde_json::Value::Object(map)) if map.len() == 1 => map.values().next().and_then(|v| v.as_array()),
        _ => None,
    };
    (list.into_iter().flatten())
        .map(|n| n.as_str().map(String::from))
        .collect::<Option<Vec<_>>>()
        .filter(|names| !names.is_empty())
        .ok_or_else(|| {
            invalid(
                path,
                format!("feature {key} names no joints (its `names` is not a list of strings)"),
            )
        })
}

/// One frame: its timestamp and the column's values.
type Frame = (f64, Vec<f64>);

/// The layouts faze4 reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Layout {
    /// v2.x: a file per episode, `data_path`.
    V2,
    /// v3.x: `data/chunk-*/file-*.parquet`, episodes told by `episode_index`.
    V3,
}

/// The layout of `info`'s `codebase_version` (`path` its file, for errors): told by its major
/// version, v2.x or v3.x; any other (v1.6, a word) is refused naming it (it was read as v3 and
/// said to have no `data/chunk-*` files).
fn layout(info: &Info, path: &Path) -> Result<Layout> {
    let major = (info.codebase_version.strip_prefix('v'))
        .and_then(|v| v.split('.').next())
        .and_then(|m| m.parse::<u32>().ok());
    match major {
        Some(2) => Ok(Layout::V2),
        Some(3) => Ok(Layout::V3),
        _ => Err(invalid(
            path,
            format!(
                "codebase_version {}: faze4 reads LeRobot datasets v2.x and v3.x (LeRobot's own scripts convert older ones)",
                quoted(&info.codebase_version)
            ),
        )),
    }
}

/// The frames of `episode`, in file and row order.
fn frames(dir: &Path, info: &Info, episode: usize, key: &str, width: usize) -> Result<Vec<Frame>> {
    let files = match layout(info, &dir.join(INFO))? {
        Layout::V2 => {
            let template = info
                .data_path
                .as_deref()
                .unwrap_or("data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet");
            let chunk = episode / info.chunks_size.unwrap_or(1000).max(1);
            let file = formatted(template, &[("episode_chunk", chunk), ("episode_index", episode)]);
            // inside the dataset: an absolute path or `..` would read any file (links are
            // followed: the Hugging Face cache links a snapshot's files to its blobs)
            if Path::new(&file)
                .components()
                .any(|c| !matches!(c, std::path::Component::Normal(_) | std::path::Component::CurDir))
            {
                return Err(invalid(
                    &dir.join(INFO),
                    format!(
                        "data_path {} gives {}, outside the dataset's folder: its files are inside it",
                        quoted(template),
                        quoted(&file)
                    ),
                ));
            }
            vec![dir.join(file)]
        }
        Layout::V3 => data_files(dir)?,
    };
    let mut frames = Vec::new();
    for file in &files {
        frames_of(file, episode as i64, key, width, &mut frames)?;
    }
    Ok(frames)
}

/// `template` (Python's `str.format` with `{name:03d}` fields) with `values`.
fn formatted(template: &str, values: &[(&str, usize)]) -> String {
    let mut out = template.to_string();
    for (name, value) in values {
        for width in 0..=9 {
            let field = match width {
                0 => format!("{{{name}}}"),
                w => format!("{{{name}:0{w}d}}"),
            };
            out = out.replace(&field, &format!("{value:0width$}"));
        }
    }
    out
}

/// A v3 dataset's data files, `data/chunk-*/file-*.parquet` in order.
fn data_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let listed = |d: &Path| -> Result<Vec<PathBuf>> {
        let entries = std::fs::read_dir(d).map_err(|source| Error::Io {
            path: d.to_path_buf(),
            source,
        })?;
        let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
        paths.sort();
        Ok(paths)
    };
    let name = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let mut files = Vec::new();
    for chunk in listed(&dir.join("data"))?
        .into_iter()
        .filter(|p| name(p).starts_with("chunk-"))
    {
        files.extend(
            (listed(&chunk)?.into_iter()).filter(|p| name(p).starts_with("file-") && name(p).ends_with(".parquet")),
        );
    }
    if files.is_empty() {
        return Err(invalid(dir, "a LeRobot dataset without data/chunk-*/file-*.parquet"));
    }
    Ok(files)
}

/// Appends the frames of `episode` in the Parquet file `path` to `frames`.
fn frames_of(path: &Path, episode: i64, key: &str, width: usize, frames: &mut Vec<Frame>) -> Result<()> {
    let bad = |what: String| invalid(path, format!("not a readable LeRobot Parquet file: {what}"));
    let meta = regular_file(path, "a Parquet file")?;
    if meta.len() > MAX_PARQUET_BYTES {
        return Err(too_large(
            path,
            Some(meta.len()),
            MAX_PARQUET_BYTES,
            "a LeRobot Parquet file",
        ));
    }
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let reader = SerializedFileReader::new(file).map_err(|e| bad(e.to_string()))?;
    let metadata = reader.metadata();
    let schema = metadata.file_metadata().schema();
    let wanted = ["timestamp", "episode_index", key];
    let fields: Vec<Arc<Type>> = (schema.get_fields().iter())
        .filter(|f| wanted.contains(&f.name()))
        .cloned()
        .collect();
    if let Some(missing) = wanted.iter().find(|w| !fields.iter().any(|f| f.name() == **w)) {
        return Err(bad(format!("it has no column {}", quoted(missing))));
    }
    let projection = Type::group_type_builder(schema.name())
        .with_fields(fields)
        .build()
        .map_err(|e| bad(e.to_string()))?;
    let episode_column =
        (metadata.file_metadata().schema_descr().columns().iter()).position(|c| c.path().string() == "episode_index");
    for g in 0..metadata.num_row_groups() {
        // a row group whose statistics exclude the episode holds none of its frames
        let stats = episode_column.and_then(|c| metadata.row_group(g).column(c).statistics());
        if let Some(Statistics::Int64(s)) = stats
            && let (Some(min), Some(max)) = (s.min_opt(), s.max_opt())
            && !(*min..=*max).contains(&episode)
        {
            continue;
        }
        let group = reader.get_row_group(g).map_err(|e| bad(e.to_string()))?;
        let rows = group
            .get_row_iter(Some(projection.clone()))
            .map_err(|e| bad(e.to_string()))?;
        for row in rows {
            let row = row.map_err(|e| bad(e.to_string()))?;
            let (mut time, mut index, mut values) = (None, None, None);
            for (name, field) in row.get_column_iter() {
                match name.as_str() {
                    "timestamp" => time = number(field),
                    "episode_index" => index = number(field),
                    _ => {
                        values = match field {
                            Field::ListInternal(list) => list.elements().iter().map(number).collect::<Option<Vec<_>>>(),
                            _ => None,
                        }
                    }
                }
            }
            if index != Some(episode as f64) {
                continue;
            }
            let (Some(time), Some(values)) = (time, values) else {
                return Err(bad(format!(
                    "a frame of episode {episode} without a number timestamp or a list of numbers {key}"
                )));
            };
            if values.len() != width {
                return Err(bad(format!(
                    "a frame's {key} holds {} values where info.json names {width}",
                    values.len()
                )));
            }
            if frames.len() == MAX_EPISODE_FRAMES {
                return Err(bad(format!(
                    "episode {episode} has more than {MAX_EPISODE_FRAMES} frames (docs/development.md, Caps)"
                )));
            }
            frames.push((time, values));
        }
    }
    Ok(())
}

/// A Parquet number as f64 (a float32 column's value exactly).
fn number(field: &Field) -> Option<f64> {
    match *field {
        Field::Float(x) => Some(x as f64),
        Field::Double(x) => Some(x),
        Field::Long(x) => Some(x as f64),
        Field::Int(x) => Some(x as f64),
        _ => None,
    }
}

/// LeRobot's calibration file: a motor's name → its calibration.
fn calibration(path: &Path) -> Result<BTreeMap<String, MotorCalibration>> {
    let bytes = read_file_capped(path, MAX_SIDE_FILE_BYTES, "a LeRobot calibration file")?;
    let file: BTreeMap<String, MotorCalibration> = serde_json::from_slice(&bytes).map_err(|e| {
        Error::option(
            "calibration",
            format!(
                "{}: not a LeRobot calibration file (a motor's name → id, drive_mode, homing_offset, range_min, range_max): {}",
                path.display(),
                crate::error::file_words(&e.to_string())
            ),
        )
    })?;
    if let Some((motor, _)) = file
        .iter()
        .find(|(_, c)| !(c.range_max != c.range_min && c.range_min.is_finite() && c.range_max.is_finite()))
    {
        return Err(Error::option(
            "calibration",
            format!(
                "{}: motor {} has range_min equal to range_max",
                path.display(),
                quoted(motor)
            ),
        ));
    }
    Ok(file)
}

/// The frames as a trajectory over the joints named by `names` (`X.pos` → `X`), a gripper left
/// out, values converted by `units` or `calibration`.
fn episode_trajectory(
    source: &Source,
    names: &[String],
    frames: Vec<Frame>,
    units: Option<Units>,
    calibration: Option<&BTreeMap<String, MotorCalibration>>,
) -> Result<Episode> {
    let Source {
        dir,
        info,
        episode,
        key,
    } = *source;
    let joint = |name: &str| name.strip_suffix(".pos").unwrap_or(name).to_string();
    let mut warnings = Vec::new();
    // the columns kept: every joint but a gripper (LeRobot's 0–100 % opening)
    let kept: Vec<usize> = (0..names.len())
        .filter(|&i| !joint(&names[i]).ends_with("gripper"))
        .collect();
    for i in (0..names.len()).filter(|i| !kept.contains(i)) {
        warnings.push(format!(
            "{}: column {} is the gripper's opening (LeRobot's 0–100 % of its range, not an angle): the gripper holds its start position",
            dir.display(),
            quoted(&names[i])
        ));
    }
    let convert: Vec<Box<dyn Fn(f64) -> f64>> = (kept.iter())
        .map(|&i| -> Result<Box<dyn Fn(f64) -> f64>> {
            Ok(match (units, calibration) {
                (Some(Units::Deg), _) => Box::new(|x: f64| x.to_radians()),
                (_, Some(motors)) => {
                    let motor = joint(&names[i]);
                    let c = *motors.get(&motor).ok_or_else(|| {
                        Error::option(
                            "calibration",
                            format!(
                                "has no motor {} (it calibrates {})",
                                quoted(&motor),
                                motors.keys().cloned().collect::<Vec<_>>().join(", ")
                            ),
                        )
                    })?;
                    Box::new(move |x: f64| c.radians(x))
                }
                _ => Box::new(|x: f64| x),
            })
        })
        .collect::<Result<_>>()?;
    let start = frames[0].0;
    let points = (frames.iter())
        .map(|(t, values)| TrajectoryPoint {
            time_from_start: t - start,
            positions: kept.iter().zip(&convert).map(|(&i, f)| f(values[i])).collect(),
            ..Default::default()
        })
        .collect();
    let how = match (units, calibration) {
        (Some(u), _) => format!("in {}", crate::choice::Choice::word(u)),
        (_, Some(_)) => "normalised, turned into rad by the calibration".into(),
        _ => "taken as rad".into(),
    };
    let limit_hint = (units.is_none() && calibration.is_none()).then(|| {
        "; the values were taken as radians, but LeRobot stores a joint as −100…100 normalised by the arm's calibration unless the arm was recorded in degrees: give `calibration` FILE.json (the arm's calibration, in ~/.cache/huggingface/lerobot/calibration/robots/) or `units` deg".to_string()
    });
    Ok(Episode {
        trajectory: TimedTrajectory {
            joint_names: kept.iter().map(|&i| joint(&names[i])).collect(),
            points,
        },
        what: format!(
            "a LeRobot {} dataset, episode {episode}{}, {key} ({} frames, {how})",
            info.codebase_version,
            info.total_episodes.map(|n| format!(" of {n}")).unwrap_or_default(),
            frames.len()
        ),
        warnings,
        limit_hint,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn templates_take_python_widths() {
        let t = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet";
        assert_eq!(
            formatted(t, &[("episode_chunk", 1), ("episode_index", 1042)]),
            "data/chunk-001/episode_001042.parquet"
        );
    }

    /// LeRobot's `_normalize` of a raw position, then `radians`, gives the angle of its
    /// `DEGREES` mode (in rad); drive mode 1 negates the normalised value.
    #[test]
    fn calibration_inverts_lerobots_normalisation() {
        let (min, max) = (1000.0, 3000.0);
        for drive_mode in [0, 1] {
            let c = MotorCalibration {
                drive_mode,
                range_min: min,
                range_max: max,
            };
            for raw in [1000.0, 1234.0, 2000.0, 2999.0] {
                let norm = (raw - min) / (max - min) * 200.0 - 100.0;
                let norm = if drive_mode == 1 { -norm } else { norm };
                let degrees = (raw - (min + max) / 2.0) * 360.0 / 4095.0;
                assert!(
                    (c.radians(norm) - degrees.to_radians()).abs() < 1e-12,
                    "{raw} {drive_mode}"
                );
            }
        }
    }
}
