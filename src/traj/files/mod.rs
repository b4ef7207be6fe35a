//! Time-stamped trajectory files, read into and written from a [`TimedTrajectory`] (docs/
//! trajectories.md). [`open`] reads what a `--q-traj` is, a file told by its first bytes where it
//! has a magic number (a bag: [`bag`]; a `.npy`), else by its extension, a folder being a
//! rosbag2 bag ([`bag::folder`]) or a LeRobot dataset ([`lerobot`]); [`write()`] writes the
//! format its extension names:
//!
//! * `.yaml`/`.yml`: a `trajectory_msgs/msg/JointTrajectory` as `ros2 topic echo` prints it,
//!   one or more messages separated by `---` ([`yaml`]);
//! * `.json`: the same structure, one message or an array of them ([`json`]);
//! * `.mcap`: a rosbag2 MCAP file, a `JointTrajectory` topic or a recorded
//!   `sensor_msgs/msg/JointState` topic ([`mcap`]);
//! * `.csv`: a time column and one column per joint ([`csv`]).
//!
//! A YAML or JSON document is read for the message it is (a goal, MoveIt's messages, ROS 1's
//! layout, JointState echoes: `messages.rs`). A recorded `JointState` stream, whatever holds
//! it, becomes a trajectory through [`joint_states::recorded_motion`]. Every format's joint
//! names are renamed by [`Selection::rename`].
//!
//! [`read`] returns a checked trajectory ([`TimedTrajectory::check`]); [`write()`] writes one so
//! that [`read`] gives it back bit for bit (the ROS formats hold whole nanoseconds: see
//! [`TimedTrajectory::round_times_to_nanoseconds`]).

pub mod bag;
pub mod bounded;
pub mod csv;
pub mod joint_states;
pub mod json;
pub mod lerobot;
pub mod mcap;
mod messages;
pub mod reading;
pub mod ros;
pub mod sniff;
pub mod yaml;

pub use reading::{Note, Read, Rename};

use std::path::Path;

use crate::atomic::Outputs;
use crate::error::{Error, Result};
use crate::input::{
    MAX_NPY_BYTES, MAX_TRAJECTORY_TEXT_BYTES, MAX_YAML_TRAJECTORY_BYTES, read_stream_capped, too_large,
};
use crate::traj::{TimedTrajectory, npy};
use sniff::{Magic, peek, shown};

/// Which message or topic of a file to read, and how (`--message K`, `--topic NAME`,
/// `--rename FROM=TO`, the LeRobot options).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Selection {
    /// The K-th trajectory of a YAML or JSON file (a DisplayTrajectory's counted one by one)
    /// or of a bag's topic, counted from 1; `None`: the first.
    pub message: Option<usize>,
    /// The MCAP topic; `None`: the file's one `JointTrajectory` topic, else its one
    /// `JointState` topic.
    pub topic: Option<String>,
    /// A LeRobot dataset's episode, from 0 (`None`: 0).
    pub episode: Option<usize>,
    /// A LeRobot dataset's column of joint values (`None`: `action`).
    pub lerobot_key: Option<String>,
    /// What a LeRobot dataset's values are (`None`: `calibration`'s, else taken as radians).
    pub units: Option<lerobot::Units>,
    /// LeRobot's calibration file of the arm, which turns normalised values into radians.
    pub calibration: Option<std::path::PathBuf>,
    /// The joint names' prefixes renamed, in every format ([`Rename`]).
    pub rename: Vec<Rename>,
    /// The model's joints: a recorded `JointState` stream's other joints are left out (with a
    /// [`Note`]); `None`: every joint kept.
    pub joints: Option<Vec<String>>,
    /// The interpolation the trajectory will be played with, when given: a recorded stream's
    /// velocities then choose nothing ([`Note::VelocitiesChoseCubic`] is not said).
    pub interpolation: Option<crate::traj::Interpolation>,
}

impl Selection {
    /// Whether a recorded stream's joint `name` (as the file names it) is kept: renamed, it is
    /// one of [`Selection::joints`] (or no joints are given).
    pub fn keeps(&self, name: &str) -> bool {
        self.joints
            .as_ref()
            .is_none_or(|joints| joints.iter().any(|j| *j == Rename::apply(&self.rename, name)))
    }

    /// The LeRobot option given, if any (for a refusal on another input).
    fn lerobot_option(&self) -> Option<&'static str> {
        [
            (self.episode.is_some(), "episode"),
            (self.lerobot_key.is_some(), "lerobot_key"),
            (self.units.is_some(), "units"),
            (self.calibration.is_some(), "calibration"),
        ]
        .into_iter()
        .find_map(|(given, field)| given.then_some(field))
    }
}

/// A time-stamped trajectory file's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `.yaml`, `.yml`.
    Yaml,
    /// `.json`.
    Json,
    /// `.mcap`.
    Mcap,
    /// `.csv`.
    Csv,
}

impl Format {
    /// The format `path`'s extension names (any case), if it names one.
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "yaml" | "yml" => Some(Format::Yaml),
            "json" => Some(Format::Json),
            "mcap" => Some(Format::Mcap),
            "csv" => Some(Format::Csv),
            _ => None,
        }
    }
}

/// The extensions [`read`] and [`write()`] know, for messages.
pub const EXTENSIONS: &str = ".yaml, .yml, .json, .mcap or .csv";

/// What a `--q-traj` holds.
#[derive(Clone, Debug, PartialEq)]
pub enum Content {
    /// A time-stamped trajectory, checked ([`TimedTrajectory::check`]).
    Timed(TimedTrajectory),
    /// A `.npy`'s evenly spaced frames (N×dof).
    Samples(Vec<Vec<f64>>),
}

/// A `--q-traj` read ([`open`]): what it holds and what it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Opened {
    /// What it holds.
    pub content: Content,
    /// What the input is and what was taken from it, for people, where its name does not say
    /// it (`a rosbag2 folder of 2 MCAP files, topic /joint_states`); `None` for a file of the
    /// format its extension names.
    pub what: Option<String>,
    /// What reading noticed, for people (a LeRobot gripper column left out).
    pub warnings: Vec<String>,
    /// What reading a message or a recorded stream decided ([`Note`]).
    pub notes: Vec<Note>,
    /// Said after a joint-limit refusal of the trajectory: the likely cause (a LeRobot
    /// dataset's values taken as radians unasked).
    pub limit_hint: Option<String>,
}

/// Reads the `--q-traj` in `path`, whatever it is: a file or stream told by its first bytes
/// (a bag: MCAP, a rosbag2 SQLite `.db3`, a ROS 1 `.bag`, any of them compressed whole with
/// zstd; a `.npy`), else by its extension (`.yaml`, `.yml`, `.json`, `.csv`); a rosbag2
/// folder ([`bag::folder`]). `selection` picks the message or topic. Every file is read under
/// its cap (docs/development.md, "Caps"), a bag streamed; every error is one line naming the
/// file (or the option, for a `--message` or `--topic` that does not fit it).
pub fn open(path: &Path, selection: &Selection) -> Result<Opened> {
    if selection.message == Some(0) {
        return Err(Error::option("message", "messages are counted from 1"));
    }
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_dir() && path.join(lerobot::INFO).is_file() {
        let episode = lerobot::read(path, selection)?;
        let (what, warnings) = (Some(episode.what), episode.warnings);
        return timed(
            episode.trajectory.into(),
            what,
            warnings,
            episode.limit_hint,
            selection,
            path,
        );
    }
    if let Some(field) = selection.lerobot_option() {
        return Err(Error::option(
            field,
            "applies to a LeRobot dataset (a folder holding meta/info.json)",
        ));
    }
    if meta.is_dir() {
        return folder(path, selection);
    }
    let file = crate::input::open(path, &meta)?;
    let (head, source) = peek(bag::Capped::new(file)).map_err(io)?;
    let magic = Magic::of(&head);
    let whole = |source, cap: u64, what: &str| match meta.is_file() && meta.len() > cap {
        true => Err(too_large(path, Some(meta.len()), cap, what)),
        false => read_stream_capped(source, path, cap, what),
    };
    let format = Format::of(path);
    if magic == Some(Magic::Parquet) {
        return Err(invalid(
            path,
            "a Parquet file: a LeRobot dataset is read from its folder, the one holding meta/info.json (`q_traj` DIR `episode` N)",
        ));
    }
    let samples = magic == Some(Magic::Npy) || (magic.is_none() && is_npy(path));
    if magic.is_some() && !samples || format == Some(Format::Mcap) {
        let mut found = bag::Collected::default();
        let storage = bag::collect_stream(magic, &head, source, meta.is_file(), &mut found, path)?;
        return timed_from_bag(found, storage.to_string(), selection, path);
    }
    if selection.topic.is_some() {
        return Err(Error::option("topic", TOPIC_PICKS));
    }
    if samples {
        if selection.message.is_some() {
            return Err(Error::option(
                "message",
                "picks from a .yaml, .json or bag file, not a .npy",
            ));
        }
        let bytes = whole(source, MAX_NPY_BYTES, "an .npy trajectory")?;
        return Ok(Opened {
            content: Content::Samples(npy::parse_samples(&bytes, path)?),
            what: None,
            warnings: Vec::new(),
            notes: Vec::new(),
            limit_hint: None,
        });
    }
    let Some(format) = format else {
        return Err(invalid(
            path,
            format!(
                "not a trajectory faze4 reads: its extension must be {EXTENSIONS}, or it must be a bag (MCAP, rosbag2 SQLite, ROS 1) or a NumPy .npy, whatever its name; it starts with {}",
                shown(&head)
            ),
        ));
    };
    let bytes = match format {
        Format::Yaml => whole(source, MAX_YAML_TRAJECTORY_BYTES, "a YAML trajectory")?,
        _ => whole(source, MAX_TRAJECTORY_TEXT_BYTES, "a trajectory text file")?,
    };
    timed(
        parse(&bytes, format, selection, path)?,
        None,
        Vec::new(),
        None,
        selection,
        path,
    )
}

/// `read` as a `--q-traj`'s content, its joints renamed ([`Selection::rename`]) and checked.
fn timed(
    mut read: Read,
    what: Option<String>,
    warnings: Vec<String>,
    limit_hint: Option<String>,
    selection: &Selection,
    path: &Path,
) -> Result<Opened> {
    reading::rename(&mut read.trajectory, &selection.rename, path)?;
    read.trajectory.check(path)?;
    Ok(Opened {
        content: Content::Timed(read.trajectory),
        what,
        warnings,
        notes: read.notes,
        limit_hint,
    })
}

/// What `--topic` picks from, for its error.
const TOPIC_PICKS: &str = "picks a topic of a bag (.mcap, .db3, .bag, a rosbag2 folder)";

/// Whether `path`'s extension says `.npy`.
fn is_npy(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("npy"))
}

/// A folder: a rosbag2 bag, its files read in order into one bag.
fn folder(dir: &Path, selection: &Selection) -> Result<Opened> {
    let (files, what) = bag::folder::files(dir)?;
    let mut found = bag::Collected::default();
    for file in &files {
        bag::collect_file(file, &mut found)?;
    }
    timed_from_bag(found, what, selection, dir)
}

/// The trajectory `selection` picks from the bag `found`, `what` saying what the bag is.
fn timed_from_bag(found: bag::Collected, what: String, selection: &Selection, path: &Path) -> Result<Opened> {
    let (read, topic) = found.trajectory(selection, path)?;
    timed(
        read,
        Some(format!("{what}, topic {topic}")),
        Vec::new(),
        None,
        selection,
        path,
    )
}

/// Reads the time-stamped trajectory in `path` ([`open`]; a `.npy` is refused: its frames are
/// not time-stamped); the trajectory is renamed and checked ([`TimedTrajectory::check`]); what
/// reading noticed is left out (see [`Opened::notes`]).
pub fn read(path: &Path, selection: &Selection) -> Result<TimedTrajectory> {
    match open(path, selection)?.content {
        Content::Timed(trajectory) => Ok(trajectory),
        Content::Samples(_) => Err(invalid(
            path,
            "a NumPy array of evenly spaced frames, not a time-stamped trajectory",
        )),
    }
}

/// [`read`] on a file's `bytes` in `format` (its names not renamed), with what reading it
/// noticed; `path` names it in the errors.
pub fn parse(bytes: &[u8], format: Format, selection: &Selection, path: &Path) -> Result<Read> {
    let read = match format {
        Format::Yaml => yaml::parse(text(bytes, path)?, selection, path)?,
        Format::Json => json::parse(text(bytes, path)?, selection, path)?,
        Format::Mcap => match Magic::of(bytes) {
            // another bag in memory (ROS 1, SQLite, zstd): told by its bytes, as `open` tells it
            Some(magic @ (Magic::Ros1 | Magic::Sqlite | Magic::Zstd)) => {
                let mut found = bag::Collected::default();
                bag::collect_stream(Some(magic), bytes, Box::new(bytes), false, &mut found, path)?;
                found.trajectory(selection, path)?.0
            }
            _ => mcap::parse(bytes, selection, path)?,
        },
        Format::Csv => {
            if selection.message.is_some() {
                return Err(Error::option(
                    "message",
                    "picks a message of a .yaml, .json or .mcap file",
                ));
            }
            csv::parse(unmarked(bytes), path)?.into()
        }
    };
    read.trajectory.check(path)?;
    Ok(read)
}

/// Writes `trajectory` to `path` in the format of its extension, whole or not at all. The
/// trajectory must pass [`TimedTrajectory::check`] (else the error, and nothing written).
pub fn write(path: &Path, trajectory: &TimedTrajectory) -> Result<()> {
    write_within(&Outputs::immediate(), path, trajectory)
}

/// [`write()`] as a file of `outputs` (it appears when they are committed).
pub fn write_within(outputs: &Outputs, path: &Path, trajectory: &TimedTrajectory) -> Result<()> {
    let format = format_of(path)?;
    trajectory.check(path)?;
    let bytes = match format {
        Format::Yaml => yaml::to_string(trajectory, path)?.into_bytes(),
        Format::Json => json::to_string(trajectory, path)?.into_bytes(),
        Format::Mcap => mcap::to_bytes(trajectory, path)?,
        Format::Csv => csv::to_string(trajectory).into_bytes(),
    };
    outputs.write(path, &bytes)
}

fn format_of(path: &Path) -> Result<Format> {
    Format::of(path).ok_or_else(|| Error::InvalidData {
        path: path.to_path_buf(),
        message: format!("not a time-stamped trajectory file: its extension must be {EXTENSIONS}"),
    })
}

/// `bytes` as UTF-8 text, without a byte order mark ([`unmarked`]).
fn text<'a>(bytes: &'a [u8], path: &Path) -> Result<&'a str> {
    std::str::from_utf8(unmarked(bytes)).map_err(|e| Error::InvalidData {
        path: path.to_path_buf(),
        message: format!("not UTF-8 text ({e})"),
    })
}

/// `bytes` without the UTF-8 byte order mark Windows editors put first (Notepad, Excel's "CSV
/// UTF-8"): no part of the text (libyaml read it as a second document, the CSV reader as part
/// of the first column's name).
fn unmarked(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)
}

/// An [`Error::InvalidData`] for `path`, its message on one line.
fn invalid(path: &Path, message: impl AsRef<str>) -> Error {
    Error::InvalidData {
        path: path.to_path_buf(),
        message: crate::error::one_line(message.as_ref()),
    }
}

/// The `k`-th (from 1; `None`: the first) of `count` messages, as an index, or the error.
fn pick(count: usize, k: Option<usize>, what: &str, path: &Path) -> Result<usize> {
    match k {
        None if count == 0 => Err(invalid(path, format!("holds no {what}"))),
        None => Ok(0),
        Some(k) if k > count => Err(Error::option(
            "message",
            format!("{k}: {} holds {count} {what}", path.display()),
        )),
        Some(k) => Ok(k - 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::TrajectoryPoint;

    /// A trajectory whose values exercise the formats: subnormal, negative zero, large and
    /// tiny exponents, and times on ROS's nanosecond grid.
    pub(crate) fn awkward(velocities: bool, accelerations: bool) -> TimedTrajectory {
        let names = ["shoulder_pan_joint", "yes", "a b:c", "j-3"];
        let values = |k: usize, s: f64| -> Vec<f64> {
            (0..names.len())
                .map(|i| match (k + i) % 5 {
                    0 => -0.0,
                    1 => 1e-310 * s,
                    2 => 123_456_789.123_456_79 * s,
                    3 => -1.0 / 3.0 * s,
                    _ => 2.5e-17 * s,
                })
                .collect()
        };
        let mut t = TimedTrajectory {
            joint_names: names.map(String::from).to_vec(),
            points: (0..4)
                .map(|k| TrajectoryPoint {
                    time_from_start: 0.1 * k as f64 + 1.0 / 3.0,
                    positions: values(k, 1.0),
                    velocities: if velocities { values(k + 1, 0.7) } else { Vec::new() },
                    accelerations: if accelerations { values(k + 2, -3.0) } else { Vec::new() },
                })
                .collect(),
        };
        t.round_times_to_nanoseconds();
        t
    }

    fn same_bits(a: &TimedTrajectory, b: &TimedTrajectory) {
        assert_eq!(a.joint_names, b.joint_names);
        assert_eq!(a.points.len(), b.points.len());
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for (p, q) in a.points.iter().zip(&b.points) {
            assert_eq!(p.time_from_start.to_bits(), q.time_from_start.to_bits());
            assert_eq!(bits(&p.positions), bits(&q.positions));
            assert_eq!(bits(&p.velocities), bits(&q.velocities));
            assert_eq!(bits(&p.accelerations), bits(&q.accelerations));
        }
    }

    #[test]
    fn every_format_reads_back_what_it_wrote_bit_for_bit() {
        let dir = std::env::temp_dir().join(format!("faze4-traj-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for ext in ["yaml", "yml", "json", "mcap", "csv"] {
            for (v, a) in [(false, false), (true, false), (true, true)] {
                let t = awkward(v, a);
                let path = dir.join(format!("t.{ext}"));
                write(&path, &t).unwrap();
                same_bits(&read(&path, &Selection::default()).unwrap(), &t);
            }
        }
        // CSV holds any f64 time, not only whole nanoseconds
        let mut t = awkward(true, true);
        t.points[1].time_from_start += 1e-12;
        let path = dir.join("fine.csv");
        write(&path, &t).unwrap();
        same_bits(&read(&path, &Selection::default()).unwrap(), &t);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn selections_that_do_not_fit_are_refused() {
        let dir = std::env::temp_dir().join(format!("faze4-traj-select-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.csv");
        write(&path, &awkward(false, false)).unwrap();
        let topic = Selection {
            topic: Some("/x".into()),
            ..Default::default()
        };
        assert_eq!(
            read(&path, &topic).unwrap_err().to_string(),
            "`topic`: picks a topic of a bag (.mcap, .db3, .bag, a rosbag2 folder)"
        );
        let message = Selection {
            message: Some(1),
            ..Default::default()
        };
        assert!(read(&path, &message).unwrap_err().to_string().starts_with("`message`"));
        std::fs::write(dir.join("t.txt"), "t,q1\n").unwrap();
        let e = read(&dir.join("t.txt"), &Selection::default()).unwrap_err().to_string();
        assert!(
            e.contains("not a trajectory faze4 reads: its extension must be .yaml")
                && e.ends_with("it starts with t,q1\\x0a"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
