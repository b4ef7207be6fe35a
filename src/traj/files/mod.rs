//! Time-stamped trajectory files, read into and written from a [`TimedTrajectory`], the format
//! chosen by the file's extension (docs/trajectories.md):
//!
//! * `.yaml`/`.yml`: a `trajectory_msgs/msg/JointTrajectory` as `ros2 topic echo` prints it,
//!   one or more messages separated by `---` ([`yaml`]);
//! * `.json`: the same structure, one message or an array of them ([`json`]);
//! * `.mcap`: a rosbag2 MCAP file, a `JointTrajectory` topic or a recorded
//!   `sensor_msgs/msg/JointState` topic ([`mcap`]);
//! * `.csv`: a time column and one column per joint ([`csv`]).
//!
//! A recorded `JointState` stream, whatever holds it, becomes a trajectory through
//! [`joint_states::recorded_motion`].
//!
//! [`read`] returns a checked trajectory ([`TimedTrajectory::check`]); [`write()`] writes one so
//! that [`read`] gives it back bit for bit (the ROS formats hold whole nanoseconds: see
//! [`TimedTrajectory::round_times_to_nanoseconds`]).

pub mod csv;
pub mod joint_states;
pub mod json;
pub mod mcap;
mod messages;
pub mod reading;
pub mod ros;
pub mod yaml;

pub use reading::{Note, Read, Rename};

use std::path::Path;

use crate::atomic::Outputs;
use crate::error::{Error, Result};
use crate::input::{MAX_MCAP_BYTES, MAX_TRAJECTORY_TEXT_BYTES, MAX_YAML_TRAJECTORY_BYTES, read_capped};
use crate::traj::TimedTrajectory;

/// Which message or topic of a file to read, and how (`--message K`, `--topic NAME`,
/// `--rename FROM=TO`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Selection {
    /// The K-th trajectory of a YAML or JSON file (a DisplayTrajectory's counted one by one)
    /// or of an MCAP topic, counted from 1; `None`: the first.
    pub message: Option<usize>,
    /// The MCAP topic; `None`: the file's one `JointTrajectory` topic, else its one
    /// `JointState` topic.
    pub topic: Option<String>,
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

/// Reads the trajectory in `path`, its format by extension, the message or topic `selection`
/// names, its joints renamed; the trajectory is checked ([`TimedTrajectory::check`]) and
/// returned with what reading it noticed ([`Read`]). The file is read whole, at
/// most [`MAX_YAML_TRAJECTORY_BYTES`] of YAML, [`MAX_TRAJECTORY_TEXT_BYTES`] of JSON or CSV,
/// [`MAX_MCAP_BYTES`] of MCAP (a stream too). Every error is one line
/// naming the file (or the option, for a `--message` or `--topic` that does not fit it).
pub fn read(path: &Path, selection: &Selection) -> Result<Read> {
    let format = format_of(path)?;
    if selection.topic.is_some() && format != Format::Mcap {
        return Err(Error::option("topic", "picks a topic of an .mcap file"));
    }
    if selection.message == Some(0) {
        return Err(Error::option("message", "messages are counted from 1"));
    }
    // read whole, under a cap checked before memory is taken (a stream up to it)
    let bytes = match format {
        Format::Mcap => read_capped(path, MAX_MCAP_BYTES, "an .mcap trajectory")?,
        Format::Yaml => read_capped(path, MAX_YAML_TRAJECTORY_BYTES, "a YAML trajectory")?,
        _ => read_capped(path, MAX_TRAJECTORY_TEXT_BYTES, "a trajectory text file")?,
    };
    parse(&bytes, format, selection, path)
}

/// [`read`] on a file's `bytes` in `format`; `path` names it in the errors.
pub fn parse(bytes: &[u8], format: Format, selection: &Selection, path: &Path) -> Result<Read> {
    let mut read = match format {
        Format::Yaml => yaml::parse(text(bytes, path)?, selection, path)?,
        Format::Json => json::parse(text(bytes, path)?, selection, path)?,
        Format::Mcap => mcap::parse(bytes, selection, path)?,
        Format::Csv => {
            if selection.message.is_some() {
                return Err(Error::option(
                    "message",
                    "picks a message of a .yaml, .json or .mcap file",
                ));
            }
            csv::parse(bytes, path)?.into()
        }
    };
    reading::rename(&mut read.trajectory, &selection.rename, path)?;
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

fn text<'a>(bytes: &'a [u8], path: &Path) -> Result<&'a str> {
    std::str::from_utf8(bytes).map_err(|e| Error::InvalidData {
        path: path.to_path_buf(),
        message: format!("not UTF-8 text ({e})"),
    })
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
                same_bits(&read(&path, &Selection::default()).unwrap().trajectory, &t);
            }
        }
        // CSV holds any f64 time, not only whole nanoseconds
        let mut t = awkward(true, true);
        t.points[1].time_from_start += 1e-12;
        let path = dir.join("fine.csv");
        write(&path, &t).unwrap();
        same_bits(&read(&path, &Selection::default()).unwrap().trajectory, &t);
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
            "`topic`: picks a topic of an .mcap file"
        );
        let message = Selection {
            message: Some(1),
            ..Default::default()
        };
        assert!(read(&path, &message).unwrap_err().to_string().starts_with("`message`"));
        let e = read(&dir.join("t.txt"), &Selection::default()).unwrap_err().to_string();
        assert!(e.contains("its extension must be .yaml"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
