//! Recorded bags, whatever their storage: an MCAP file, a rosbag2 SQLite `.db3`, a ROS 1
//! `.bag`, and a rosbag2 folder of them (`metadata.yaml`, split files, zstd per file or per
//! message). Each container's reader hands its topics and messages to one [`Collected`], which
//! keeps the messages of the joint topics (bounded: [`MAX_MCAP_MESSAGE_BYTES`] once
//! decompressed); [`Collected::trajectory`] picks the topic, decodes its messages into the
//! structs of [`super::ros`] (ROS 2's CDR, or ROS 1's serialization) and hands them to the one
//! conversion ([`super::joint_states::recorded_motion`] for a JointState stream).
//!
//! The topic: `--topic NAME`, else the bag's one `JointTrajectory` topic, else its one
//! `JointState` topic (several candidates: an error that lists them; none: an error that lists
//! every topic and its type). A JointTrajectory topic gives one message (`--message K`, in
//! log-time order); a JointState topic is a recorded motion.

pub mod db3;
pub mod folder;
pub mod mcap;
pub mod ros1;

use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

use byteorder::{BigEndian, LittleEndian};
use serde::de::DeserializeOwned;

use super::joint_states::{StampedState, recorded_motion};
use super::ros::{JOINT_STATE, JOINT_TRAJECTORY, JointStateMsg, JointTrajectoryMsg};
use super::sniff::{Magic, ZSTD_MAGIC, peek, shown};
use super::{Selection, invalid, pick};
use crate::error::{Error, Result, quoted};
use crate::input::{
    MAX_BAG_BYTES, MAX_MCAP_BYTES, MAX_MCAP_MESSAGE_BYTES, MAX_TRAJECTORY_POINTS, read_stream_capped, size_text,
    too_large,
};

/// The message encoding of ROS 1's serialization (a `.bag`'s connections).
pub const ROS1: &str = "ros1";

/// A topic of a bag: its name, type and message encoding (`cdr` for ROS 2, [`ROS1`]).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Topic {
    /// The topic's name.
    pub name: String,
    /// Its message type as the bag names it (`sensor_msgs/msg/JointState`,
    /// `sensor_msgs/JointState` in ROS 1); empty when the bag gives none.
    pub kind: String,
    /// Its messages' encoding.
    pub encoding: String,
}

/// The two message types faze4 plays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Joint {
    /// `trajectory_msgs/JointTrajectory`.
    Trajectory,
    /// `sensor_msgs/JointState`.
    State,
}

/// Which of the two a type name is, in ROS 2's spelling or ROS 1's.
fn joint(kind: &str) -> Option<Joint> {
    match kind {
        JOINT_TRAJECTORY | "trajectory_msgs/JointTrajectory" => Some(Joint::Trajectory),
        JOINT_STATE | "sensor_msgs/JointState" => Some(Joint::State),
        _ => None,
    }
}

/// What a bag's readers found: every topic with its number of messages, and the messages of
/// the joint topics with their log times (ns), decompressed. A topic is its name, type and
/// encoding: one name recorded with two types is two topics, never one list of messages.
#[derive(Debug, Default)]
pub struct Collected {
    topics: BTreeMap<Topic, usize>,
    messages: BTreeMap<Topic, Vec<(u64, Vec<u8>)>>,
    /// The bytes kept, with each message's place in its list.
    kept: u64,
}

impl Collected {
    /// Notes `topic` (a topic without messages is listed too).
    pub fn declare(&mut self, topic: &Topic) {
        self.topics.entry(topic.clone()).or_default();
    }

    /// Counts a message of `topic` logged at `log_time` (ns), and keeps it if the topic is a
    /// joint topic: a message compressed alone (a zstd frame: rosbag2's
    /// `compression_mode: MESSAGE`) decompressed, the kept bytes bounded by
    /// [`MAX_MCAP_MESSAGE_BYTES`].
    pub fn add(&mut self, topic: &Topic, log_time: u64, data: &[u8], path: &Path) -> Result<()> {
        *self.topics.entry(topic.clone()).or_default() += 1;
        if joint(&topic.kind).is_none() {
            return Ok(());
        }
        let over = || {
            invalid(
                path,
                format!(
                    "its trajectory topics hold more than {} of messages once decompressed (faze4 keeps them in memory; docs/development.md, Caps)",
                    size_text(MAX_MCAP_MESSAGE_BYTES)
                ),
            )
        };
        let left = MAX_MCAP_MESSAGE_BYTES.saturating_sub(self.kept);
        let data = match data.starts_with(ZSTD_MAGIC) {
            false => data.to_vec(),
            true => {
                let mut out = Vec::new();
                let decoder = zstd::stream::read::Decoder::new(data)
                    .map_err(|e| invalid(path, format!("topic {}: a zstd message: {e}", topic.name)))?;
                decoder.take(left + 1).read_to_end(&mut out).map_err(|e| {
                    invalid(
                        path,
                        format!(
                            "topic {}: a message compressed with zstd does not decompress: {e}",
                            topic.name
                        ),
                    )
                })?;
                out
            }
        };
        // each message kept costs its bytes and its place in the list
        self.kept += (data.len() + std::mem::size_of::<(u64, Vec<u8>)>()) as u64;
        if self.kept > MAX_MCAP_MESSAGE_BYTES {
            return Err(over());
        }
        (self.messages.entry(topic.clone()).or_default()).push((log_time, data));
        Ok(())
    }

    /// Counts `n` messages of `topic`, none of them kept (a storage that counts them).
    pub fn count(&mut self, topic: &Topic, n: usize) {
        *self.topics.entry(topic.clone()).or_default() += n;
    }

    /// The topics found, for messages: `/a (type, 3 messages), /b (type, 1 message)`, or `none`.
    pub fn topic_list(&self) -> String {
        match self.topics.is_empty() {
            true => "none".into(),
            false => self.listed(self.topics.keys()),
        }
    }

    /// `topics` for messages, each with its type and number of messages.
    fn listed<'a>(&self, topics: impl Iterator<Item = &'a Topic>) -> String {
        (topics.map(|t| {
            let n = self.topics.get(t).copied().unwrap_or(0);
            let kind = if t.kind.is_empty() { "no type" } else { &t.kind };
            format!("{} ({kind}, {n} message{})", t.name, if n == 1 { "" } else { "s" })
        }))
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// The topic `selection` names, else the one candidate.
    fn topic(&self, selection: &Selection, path: &Path) -> Result<Topic> {
        if let Some(name) = &selection.topic {
            let named: Vec<&Topic> = self.topics.keys().filter(|t| &t.name == name).collect();
            return match named.as_slice() {
                [one] => Ok((*one).clone()),
                [] => Err(Error::option(
                    "topic",
                    format!(
                        "{name}: {} has no such topic (its topics: {})",
                        path.display(),
                        self.topic_list()
                    ),
                )),
                several => Err(self.one_name_several_types(several, path)),
            };
        }
        let of = |kind: Joint| {
            (self.topics.keys())
                .filter(|t| joint(&t.kind) == Some(kind))
                .collect::<Vec<_>>()
        };
        let (trajectories, states) = (of(Joint::Trajectory), of(Joint::State));
        let found = if trajectories.is_empty() { states } else { trajectories };
        match found.as_slice() {
            [one] if self.topics.keys().filter(|t| t.name == one.name).count() > 1 => {
                let named: Vec<&Topic> = self.topics.keys().filter(|t| t.name == one.name).collect();
                Err(self.one_name_several_types(&named, path))
            }
            [one] => Ok((*one).clone()),
            [] => Err(invalid(
                path,
                format!(
                    "has no {JOINT_TRAJECTORY} or {JOINT_STATE} topic (its topics: {})",
                    self.topic_list()
                ),
            )),
            several => Err(invalid(
                path,
                format!(
                    "has {} candidate topics: {}; pick one with `topic`",
                    several.len(),
                    self.listed(several.iter().copied())
                ),
            )),
        }
    }

    /// The refusal of a topic name that `topics` (two or more) give with different types or
    /// encodings: their messages are not one stream.
    fn one_name_several_types(&self, topics: &[&Topic], path: &Path) -> Error {
        let kinds: Vec<String> = (topics.iter())
            .map(|t| {
                let n = self.topics.get(*t).copied().unwrap_or(0);
                let kind = if t.kind.is_empty() { "no type" } else { &t.kind };
                format!(
                    "{kind} in {} ({n} message{})",
                    t.encoding,
                    if n == 1 { "" } else { "s" }
                )
            })
            .collect();
        invalid(
            path,
            format!(
                "topic {} is recorded with {} types or encodings ({}): its messages are not one stream; faze4 reads a topic of one type",
                topics[0].name,
                topics.len(),
                kinds.join("; ")
            ),
        )
    }

    /// The trajectory `selection` picks (unchecked), and its topic: one message of a
    /// JointTrajectory topic, or a JointState topic's messages as a recorded motion.
    pub fn trajectory(mut self, selection: &Selection, path: &Path) -> Result<(super::Read, String)> {
        let topic = self.topic(selection, path)?;
        let Some(kind) = joint(&topic.kind) else {
            return Err(Error::option(
                "topic",
                format!(
                    "{} in {} is of type {}; faze4 reads {JOINT_TRAJECTORY} or {JOINT_STATE}",
                    topic.name,
                    path.display(),
                    if topic.kind.is_empty() {
                        "unknown (no schema)"
                    } else {
                        &topic.kind
                    }
                ),
            ));
        };
        if topic.encoding != "cdr" && topic.encoding != ROS1 {
            return Err(invalid(
                path,
                format!(
                    "topic {} is encoded as {}; faze4 reads ROS 2's cdr and ROS 1's serialization",
                    topic.name,
                    quoted(&topic.encoding)
                ),
            ));
        }
        let mut messages = self.messages.remove(&topic).unwrap_or_default();
        // log-time order (a stable sort keeps the file's order among equal times)
        messages.sort_by_key(|(log_time, _)| *log_time);
        if kind == Joint::Trajectory {
            let k = pick(messages.len(), selection.message, "messages on the topic", path)?;
            let msg: JointTrajectoryMsg = decode(&messages[k].1, path, &topic, k)?;
            return Ok((msg.into_trajectory().into(), topic.name));
        }
        if selection.message.is_some() {
            return Err(Error::option(
                "message",
                format!(
                    "{} is a {JOINT_STATE} topic: its messages together are one recorded motion",
                    topic.name
                ),
            ));
        }
        if messages.len() > MAX_TRAJECTORY_POINTS {
            return Err(invalid(
                path,
                format!(
                    "topic {} holds {} messages, more than the {MAX_TRAJECTORY_POINTS} points a trajectory may have (docs/development.md, Caps)",
                    topic.name,
                    messages.len()
                ),
            ));
        }
        // each message decoded and its bytes let go, the decoded ones bounded
        let mut decoded = 0;
        let states = (messages.into_iter().enumerate())
            .map(|(k, (log_time, data))| {
                let message = decode::<JointStateMsg>(&data, path, &topic, k)?;
                decoded += decoded_size(&message);
                if decoded > MAX_DECODED_STATES_BYTES {
                    return Err(invalid(
                        path,
                        format!(
                            "topic {}'s messages take more than {} once decoded, at message {} (docs/development.md, Caps)",
                            topic.name,
                            size_text(MAX_DECODED_STATES_BYTES),
                            k + 1
                        ),
                    ));
                }
                Ok(StampedState {
                    log_time: Some(log_time),
                    message,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let recording = recorded_motion(states, Some(&topic.name), selection, path)?;
        let read = super::Read {
            trajectory: recording.trajectory,
            notes: recording.notes,
        };
        Ok((read, topic.name))
    }
}

/// Most bytes a JointState topic's messages may take once decoded (256 MiB, as much as the
/// bytes kept, [`MAX_MCAP_MESSAGE_BYTES`], which are let go as they are decoded): a decoded name
/// costs a `String` and its allocation, up to seven times its 8 bytes of CDR, so a topic of
/// short messages could otherwise take gigabytes. A recording of 6 joints decodes to about 2.2
/// times its bytes: about 6 minutes at 1 kHz fit, an hour at 100 Hz.
pub const MAX_DECODED_STATES_BYTES: u64 = MAX_MCAP_MESSAGE_BYTES;

/// What `message` takes in memory once decoded: its struct in its list and its allocations, as
/// the system allocator rounds them (16-byte steps beyond 8 bytes of header, 32 bytes at least).
fn decoded_size(message: &JointStateMsg) -> u64 {
    let heap = |bytes: usize| match bytes {
        0 => 0,
        n => (n + 8).next_multiple_of(16).max(32),
    };
    let names = (message.name.iter()).map(|n| heap(n.len())).sum::<usize>();
    let lists = [&message.position, &message.velocity, &message.effort].map(|v| heap(8 * v.len()));
    (std::mem::size_of::<StampedState>()
        + heap(message.header.frame_id.len())
        + heap(std::mem::size_of::<String>() * message.name.len())
        + names
        + lists.iter().sum::<usize>()) as u64
}

/// A message of `topic`, its `k`-th (0-based): ROS 2's CDR (encapsulation header, then the
/// fields) or ROS 1's serialization.
fn decode<T: DeserializeOwned + ros1::Decode>(data: &[u8], path: &Path, topic: &Topic, k: usize) -> Result<T> {
    let bad = |what: String| {
        let encoding = if topic.encoding == ROS1 {
            "ROS 1's serialization"
        } else {
            "CDR"
        };
        invalid(
            path,
            format!(
                "topic {}, message {}: not a {} in {encoding}: {what}",
                topic.name,
                k + 1,
                topic.kind
            ),
        )
    };
    if topic.encoding == ROS1 {
        return T::decode_ros1(data).map_err(bad);
    }
    let (header, body) = data
        .split_at_checked(4)
        .ok_or_else(|| bad("shorter than its header".into()))?;
    let decoded = match header[..2] {
        [0, 1] => cdr_encoding::from_bytes::<T, LittleEndian>(body),
        [0, 0] => cdr_encoding::from_bytes::<T, BigEndian>(body),
        _ => {
            return Err(bad(format!(
                "encapsulation {:02x} {:02x} is not plain CDR (00 00 or 00 01)",
                header[0], header[1]
            )));
        }
    };
    decoded
        .map(|(value, _)| value)
        .map_err(|e| bad(crate::error::file_words(&e.to_string())))
}

/// Reads the bag file (or stream) `path` into `bag`, whatever its name says: MCAP, SQLite,
/// ROS 1, or one of them compressed whole with zstd. Returns what it is, for people. At most
/// [`MAX_BAG_BYTES`] are streamed (a regular file larger is refused from its size).
pub fn collect_file(path: &Path, bag: &mut Collected) -> Result<&'static str> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_file() && meta.len() > MAX_BAG_BYTES {
        return Err(too_large(path, Some(meta.len()), MAX_BAG_BYTES, "a bag file"));
    }
    let file = crate::input::open(path, &meta)?;
    let (head, source) = peek(Capped::new(file)).map_err(io)?;
    collect_stream(Magic::of(&head), &head, source, meta.is_file(), bag, path)
}

/// [`collect_file`] once the first bytes `head` of `source` (which yields them again) told
/// `magic`; `regular`: `path` is a regular file `source` reads from its start.
pub fn collect_stream(
    magic: Option<Magic>,
    head: &[u8],
    mut source: Box<dyn Read + '_>,
    regular: bool,
    bag: &mut Collected,
    path: &Path,
) -> Result<&'static str> {
    match magic {
        Some(Magic::Mcap) => mcap::collect(&mut source, bag, path).map(|_| "an MCAP file"),
        Some(Magic::Ros1) => ros1::collect(&mut source, bag, path).map(|_| "a ROS 1 bag"),
        Some(Magic::Sqlite) if regular => db3::collect_file(path, bag).map(|_| "a rosbag2 SQLite file"),
        Some(Magic::Sqlite) => {
            let bytes = read_stream_capped(source, path, MAX_MCAP_BYTES, "an SQLite bag read into memory")?;
            db3::collect_bytes(&bytes, bag, path).map(|_| "a rosbag2 SQLite file")
        }
        Some(Magic::Zstd) => {
            let bad =
                |e: std::io::Error| invalid(path, format!("a zstd-compressed file that does not decompress: {e}"));
            let decoder = zstd::stream::read::Decoder::new(source).map_err(bad)?;
            let (head, inner) = peek(Capped::new(decoder)).map_err(bad)?;
            match Magic::of(&head) {
                Some(Magic::Mcap) => collect_stream(Some(Magic::Mcap), &head, inner, false, bag, path)
                    .map(|_| "a zstd-compressed MCAP file"),
                Some(Magic::Sqlite) => collect_stream(Some(Magic::Sqlite), &head, inner, false, bag, path)
                    .map(|_| "a zstd-compressed rosbag2 SQLite file"),
                Some(Magic::Ros1) => collect_stream(Some(Magic::Ros1), &head, inner, false, bag, path)
                    .map(|_| "a zstd-compressed ROS 1 bag"),
                _ => Err(invalid(
                    path,
                    format!(
                        "compressed with zstd, and what it holds is not a bag (MCAP, SQLite or ROS 1): it starts with {}",
                        shown(&head)
                    ),
                )),
            }
        }
        _ => Err(invalid(
            path,
            format!(
                "not a bag (MCAP, rosbag2 SQLite, ROS 1 or one of them compressed with zstd): it starts with {}",
                shown(head)
            ),
        )),
    }
}

/// A reader that fails once more than [`MAX_BAG_BYTES`] came through it.
pub(crate) struct Capped<R> {
    inner: R,
    read: u64,
}

impl<R: Read> Capped<R> {
    /// `inner`, capped.
    pub(crate) fn new(inner: R) -> Capped<R> {
        Capped { inner, read: 0 }
    }
}

impl<R: Read> Read for Capped<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.read += n as u64;
        if self.read > MAX_BAG_BYTES {
            return Err(std::io::Error::other(format!(
                "more than the {} a bag may stream (docs/development.md, Caps)",
                size_text(MAX_BAG_BYTES)
            )));
        }
        Ok(n)
    }
}
