//! `.mcap`: a rosbag2 MCAP file (the default storage since ROS 2 Iron), read with the `mcap`
//! crate; its messages are plain CDR (`message_encoding` `cdr`: a 4-byte encapsulation header,
//! `00 01` little-endian or `00 00` big-endian, then the fields in order, each aligned to its
//! size from the end of the header), decoded with the `cdr-encoding` crate into the structs of
//! [`super::ros`].
//!
//! The topic: `--topic NAME`, else the file's one `trajectory_msgs/msg/JointTrajectory` topic,
//! else its one `sensor_msgs/msg/JointState` topic (several candidates: an error that lists
//! them). A JointTrajectory topic gives one message (`--message K`, in log-time order); a
//! JointState topic is a recorded motion: every message a point, its header stamp the time
//! (from the first), its positions (and its velocities when every message has them).

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::Path;

use ::mcap::sans_io::LinearReaderOptions;
use byteorder::{BigEndian, LittleEndian};
use serde::de::DeserializeOwned;

use super::joint_states::{StampedState, recorded_motion};
use super::ros::{JOINT_STATE, JOINT_TRAJECTORY, JOINT_TRAJECTORY_DEFINITION, JointStateMsg, JointTrajectoryMsg};
use super::{Read, Selection, invalid, pick};
use crate::error::{Error, Result, quoted};
use crate::input::{MAX_MCAP_MESSAGE_BYTES, size_text};
use crate::traj::TimedTrajectory;

/// The topic [`to_bytes`] writes the trajectory on.
pub const TOPIC: &str = "/joint_trajectory";

/// A topic of the file: its name, type (the schema's name) and message encoding.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Topic {
    name: String,
    kind: String,
    encoding: String,
}

impl Topic {
    fn describe(&self) -> String {
        format!("{} ({})", self.name, self.kind)
    }
}

/// Calls `each` with every message of the MCAP file `bytes` in file order: its topic (the
/// channel's, with its schema's name and the channel's message encoding), log time and data.
///
/// The records are read by the `mcap` crate's linear reader (magic, record lengths, chunks
/// decompressed, CRCs; a record, or one inside a compressed chunk, whatever size it claims,
/// is read only up to [`MAX_MCAP_MESSAGE_BYTES`]), and the three this needs (schema, channel,
/// message) are decoded here, each length checked against what its record holds: the crate's
/// own decoding reserves whatever a string's length claims (a 300-byte file claiming a 4 GB
/// profile string asked for 4 GB). Each chunk is handed to a second reader of its own, after
/// [`check_uncompressed_chunk`]: the crate's reader does not check a record inside an
/// uncompressed chunk against what the chunk has left (mcap 0.26, `linear_reader.rs:745`, an
/// underflow: a panic in a debug build, records read past the chunk in a release one). The
/// summary after the data end repeats schemas and channels and is not read.
fn each_message(bytes: &[u8], path: &Path, mut each: impl FnMut(&Topic, u64, &[u8]) -> Result<()>) -> Result<()> {
    use ::mcap::records::op;
    let bad = |what: String| invalid(path, format!("not a readable MCAP file: {what}"));
    let options = LinearReaderOptions::default().with_record_length_limit(MAX_MCAP_MESSAGE_BYTES as usize);
    // schema id → name; channel id → its topic
    let mut schemas: BTreeMap<u16, String> = BTreeMap::new();
    let mut channels: BTreeMap<u16, Topic> = BTreeMap::new();
    let mut record = |opcode: u8, data: &[u8]| -> Result<()> {
        let mut r = Fields(data);
        let malformed = |record: &str| bad(format!("a malformed {record} record"));
        match opcode {
            op::SCHEMA => {
                // id, name, encoding, data (u32-prefixed)
                let (id, name) = (r.u16(), r.string());
                let (Some(id), Some(name)) = (id, name) else {
                    return Err(malformed("schema"));
                };
                schemas.insert(id, name);
            }
            op::CHANNEL => {
                // id, schema id, topic, message encoding, metadata
                let (id, schema, topic, encoding) = (r.u16(), r.u16(), r.string(), r.string());
                let (Some(id), Some(schema), Some(name), Some(encoding)) = (id, schema, topic, encoding) else {
                    return Err(malformed("channel"));
                };
                let kind = match schema {
                    0 => String::new(),
                    id => (schemas.get(&id).cloned())
                        .ok_or_else(|| bad(format!("channel {id}'s schema {schema} is not declared before it")))?,
                };
                channels.insert(id, Topic { name, kind, encoding });
            }
            op::MESSAGE => {
                // channel id, sequence, log time, publish time, then the data
                let (channel, _sequence, log_time, _publish) = (r.u16(), r.u32(), r.u64(), r.u64());
                let (Some(channel), Some(log_time)) = (channel, log_time) else {
                    return Err(malformed("message"));
                };
                let topic = (channels.get(&channel)).ok_or_else(|| {
                    bad(format!(
                        "a message on channel {channel}, which no channel record declares"
                    ))
                })?;
                each(topic, log_time, r.0)?;
            }
            op::CHUNK => return Err(bad("a chunk inside a chunk".into())),
            _ => {}
        }
        Ok(())
    };
    // the file's own records, its chunks as they are
    each_record(
        &[bytes],
        options.clone().with_emit_chunks(true),
        &bad,
        &mut |opcode, data| {
            if opcode != op::CHUNK {
                return record(opcode, data);
            }
            check_uncompressed_chunk(data).map_err(&bad)?;
            // the chunk alone, as a file without magic: its records, decompressed
            let mut header = [op::CHUNK; 9];
            header[1..].copy_from_slice(&(data.len() as u64).to_le_bytes());
            let alone = options.clone().with_skip_start_magic(true).with_skip_end_magic(true);
            each_record(&[&header, data], alone, &bad, &mut record)
        },
    )
}

/// Calls `record` with the opcode and data of each record the linear reader with `options`
/// yields from `parts` (read one after the other), up to the data end.
fn each_record(
    parts: &[&[u8]],
    options: LinearReaderOptions,
    bad: &impl Fn(String) -> Error,
    record: &mut impl FnMut(u8, &[u8]) -> Result<()>,
) -> Result<()> {
    use ::mcap::records::op;
    use ::mcap::sans_io::{LinearReadEvent, LinearReader};
    let mut reader = LinearReader::new_with_options(options);
    let (mut part, mut fed) = (0, 0);
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| bad(e.to_string()))? {
            LinearReadEvent::ReadRequest(need) => {
                while part < parts.len() && fed == parts[part].len() {
                    (part, fed) = (part + 1, 0);
                }
                let rest = parts.get(part).map_or(&[][..], |p| &p[fed..]);
                let n = need.min(rest.len());
                reader.insert(n).copy_from_slice(&rest[..n]);
                reader.notify_read(n);
                fed += n;
            }
            LinearReadEvent::Record {
                opcode: op::DATA_END, ..
            } => break,
            LinearReadEvent::Record { opcode, data } => record(opcode, data)?,
        }
    }
    Ok(())
}

/// Checks that each record inside an uncompressed chunk (its data, after the opcode and
/// length) fits in what the chunk has left; a compressed chunk is left to the reader, which
/// checks its records against what was decompressed.
fn check_uncompressed_chunk(chunk: &[u8]) -> std::result::Result<(), String> {
    let mut r = Fields(chunk);
    // message start and end times, uncompressed size and CRC, compression, records
    let (_start, _end, _size, _crc) = (r.u64(), r.u64(), r.u64(), r.u32());
    let (Some(compression), Some(records_len)) = (r.string(), r.u64()) else {
        return Err("a malformed chunk record".into());
    };
    if !compression.is_empty() {
        return Ok(());
    }
    // the records the reader walks: as many bytes as the chunk says, at most what it has
    let mut records = &r.0[..r.0.len().min(usize::try_from(records_len).unwrap_or(usize::MAX))];
    while !records.is_empty() {
        let mut head = Fields(records);
        let (Some(_opcode), Some(len)) = (head.take::<1>(), head.u64()) else {
            return Err(format!(
                "a chunk ends inside a record's header ({} bytes left)",
                records.len()
            ));
        };
        let left = head.0.len();
        if len > left as u64 {
            return Err(format!(
                "a record inside a chunk claims {len} bytes where the chunk has {left} left"
            ));
        }
        records = &head.0[len as usize..];
    }
    Ok(())
}

/// The fields of one MCAP record, read in order (little-endian); `None` past its end.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let (head, rest) = self.0.split_first_chunk::<N>()?;
        self.0 = rest;
        Some(*head)
    }

    fn u16(&mut self) -> Option<u16> {
        self.take().map(u16::from_le_bytes)
    }

    fn u32(&mut self) -> Option<u32> {
        self.take().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Option<u64> {
        self.take().map(u64::from_le_bytes)
    }

    /// A u32-prefixed UTF-8 string, its length at most what the record holds (lossy: a name is
    /// only compared and shown, escaped).
    fn string(&mut self) -> Option<String> {
        let n = usize::try_from(self.u32()?).ok()?;
        if n > self.0.len() {
            return None;
        }
        let (text, rest) = self.0.split_at(n);
        self.0 = rest;
        Some(String::from_utf8_lossy(text).into_owned())
    }
}

/// The trajectory `selection` picks in an MCAP file's bytes, unchecked.
pub fn parse(bytes: &[u8], selection: &Selection, path: &Path) -> Result<Read> {
    // every topic with its messages' count; the messages of the JointTrajectory and JointState
    // topics (small), with their log times
    let mut topics: BTreeMap<Topic, usize> = BTreeMap::new();
    let mut candidates: BTreeMap<String, Vec<(u64, Vec<u8>)>> = BTreeMap::new();
    // a record (a message, or one inside a compressed chunk, whatever size it claims) is read
    // only up to the cap, and what is kept of the messages too (MAX_MCAP_MESSAGE_BYTES)
    let mut kept: u64 = 0;
    each_message(bytes, path, |topic, log_time, data| {
        if [JOINT_TRAJECTORY, JOINT_STATE].contains(&topic.kind.as_str()) {
            // each message kept costs its bytes and its place in the list
            kept += (data.len() + std::mem::size_of::<(u64, Vec<u8>)>()) as u64;
            if kept > MAX_MCAP_MESSAGE_BYTES {
                return Err(invalid(
                    path,
                    format!(
                        "its trajectory topics hold more than {} of messages once decompressed (faze4 keeps them in memory; docs/development.md, Caps)",
                        size_text(MAX_MCAP_MESSAGE_BYTES)
                    ),
                ));
            }
            (candidates.entry(topic.name.clone()).or_default()).push((log_time, data.to_vec()));
        }
        *topics.entry(topic.clone()).or_default() += 1;
        Ok(())
    })?;
    let listed = |topics: &mut dyn Iterator<Item = &Topic>| topics.map(Topic::describe).collect::<Vec<_>>().join(", ");
    let topic = match &selection.topic {
        Some(name) => topics.keys().find(|t| &t.name == name).cloned().ok_or_else(|| {
            Error::option(
                "topic",
                format!(
                    "{name}: {} has no such topic (its topics: {})",
                    path.display(),
                    listed(&mut topics.keys())
                ),
            )
        })?,
        None => {
            let of = |kind: &str| topics.keys().filter(|t| t.kind == kind).cloned().collect::<Vec<_>>();
            let (trajectories, states) = (of(JOINT_TRAJECTORY), of(JOINT_STATE));
            let found = if trajectories.is_empty() { states } else { trajectories };
            match found.as_slice() {
                [one] => one.clone(),
                [] => {
                    return Err(invalid(
                        path,
                        format!(
                            "has no {JOINT_TRAJECTORY} or {JOINT_STATE} topic (its topics: {})",
                            match topics.is_empty() {
                                true => "none".to_string(),
                                false => listed(&mut topics.keys()),
                            }
                        ),
                    ));
                }
                several => {
                    return Err(invalid(
                        path,
                        format!(
                            "has {} candidate topics: {}; pick one with --topic",
                            several.len(),
                            listed(&mut several.iter())
                        ),
                    ));
                }
            }
        }
    };
    if topic.kind != JOINT_TRAJECTORY && topic.kind != JOINT_STATE {
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
    }
    if topic.encoding != "cdr" {
        return Err(invalid(
            path,
            format!(
                "topic {} is encoded as {}; faze4 reads ROS 2's cdr",
                topic.name,
                quoted(&topic.encoding)
            ),
        ));
    }
    let mut messages = candidates.remove(&topic.name).unwrap_or_default();
    // log-time order (a stable sort keeps the file's order among equal times)
    messages.sort_by_key(|(log_time, _)| *log_time);
    if topic.kind == JOINT_TRAJECTORY {
        let k = pick(messages.len(), selection.message, "messages on the topic", path)?;
        let msg: JointTrajectoryMsg = decode(&messages[k].1, path, &topic, k)?;
        return Ok(msg.into_trajectory().into());
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
    let states = (messages.iter().enumerate())
        .map(|(k, (log_time, data))| {
            let message = decode::<JointStateMsg>(data, path, &topic, k)?;
            Ok(StampedState {
                log_time: Some(*log_time),
                message,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let recording = recorded_motion(states, Some(&topic.name), selection, path)?;
    Ok(Read {
        trajectory: recording.trajectory,
        notes: recording.notes,
    })
}

/// A CDR message (encapsulation header, then the fields) of `topic`, its `k`-th (0-based).
fn decode<T: DeserializeOwned>(data: &[u8], path: &Path, topic: &Topic, k: usize) -> Result<T> {
    let bad = |what: String| {
        invalid(
            path,
            format!(
                "topic {}, message {}: not a {} in CDR: {what}",
                topic.name,
                k + 1,
                topic.kind
            ),
        )
    };
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
    decoded.map(|(value, _)| value).map_err(|e| bad(e.to_string()))
}

/// `trajectory` as a rosbag2 MCAP file: profile `ros2`, one schema
/// (`trajectory_msgs/msg/JointTrajectory`, encoding `ros2msg`), one channel on [`TOPIC`]
/// (`cdr`), one message at log time 0 (header stamp 0, times in whole nanoseconds), zstd chunks.
pub fn to_bytes(trajectory: &TimedTrajectory, path: &Path) -> Result<Vec<u8>> {
    let bad = |e: ::mcap::McapError| invalid(path, format!("writing MCAP: {e}"));
    let msg = JointTrajectoryMsg::of(trajectory)
        .ok_or_else(|| invalid(path, "a time is beyond the ±68 years a ROS Duration holds"))?;
    let mut data = vec![0u8, 1, 0, 0];
    data.extend(cdr_encoding::to_vec::<_, LittleEndian>(&msg).map_err(|e| invalid(path, format!("CDR: {e}")))?);
    let mut writer = ::mcap::WriteOptions::new()
        .profile("ros2")
        .create(Cursor::new(Vec::new()))
        .map_err(bad)?;
    let schema =
        (writer.add_schema(JOINT_TRAJECTORY, "ros2msg", JOINT_TRAJECTORY_DEFINITION.as_bytes())).map_err(bad)?;
    let channel = writer
        .add_channel(schema, TOPIC, "cdr", &BTreeMap::new())
        .map_err(bad)?;
    let header = ::mcap::records::MessageHeader {
        channel_id: channel,
        sequence: 0,
        log_time: 0,
        publish_time: 0,
    };
    writer.write_to_known_channel(&header, &data).map_err(bad)?;
    writer.finish().map_err(bad)?;
    Ok(writer.into_inner().into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::files::ros::{Header, RosTime};

    /// An MCAP file with the given topics, each `(topic, type, messages' CDR bodies)`.
    fn bag(topics: &[(&str, &str, Vec<Vec<u8>>)]) -> Vec<u8> {
        let mut w = ::mcap::WriteOptions::new()
            .profile("ros2")
            .create(Cursor::new(Vec::new()))
            .unwrap();
        for (topic, kind, messages) in topics {
            let schema = w.add_schema(kind, "ros2msg", b"").unwrap();
            let channel = w.add_channel(schema, topic, "cdr", &BTreeMap::new()).unwrap();
            for (k, body) in messages.iter().enumerate() {
                let mut data = vec![0u8, 1, 0, 0];
                data.extend(body);
                let header = ::mcap::records::MessageHeader {
                    channel_id: channel,
                    sequence: k as u32,
                    log_time: k as u64,
                    publish_time: k as u64,
                };
                w.write_to_known_channel(&header, &data).unwrap();
            }
        }
        w.finish().unwrap();
        w.into_inner().into_inner()
    }

    fn state(sec: i32, nanosec: u32, names: &[&str], q: &[f64], v: &[f64]) -> Vec<u8> {
        let msg = JointStateMsg {
            header: Header {
                stamp: RosTime { sec, nanosec },
                frame_id: String::new(),
            },
            name: names.iter().map(|s| s.to_string()).collect(),
            position: q.to_vec(),
            velocity: v.to_vec(),
            effort: Vec::new(),
        };
        cdr_encoding::to_vec::<_, LittleEndian>(&msg).unwrap()
    }

    fn read(bytes: &[u8], topic: Option<&str>) -> Result<TimedTrajectory> {
        let selection = Selection {
            topic: topic.map(String::from),
            ..Default::default()
        };
        parse(bytes, &selection, Path::new("b.mcap")).map(|read| read.trajectory)
    }

    #[test]
    fn joint_states_are_a_recorded_motion() {
        let states = vec![
            state(1_700_000_000, 999_000_000, &["a", "b"], &[1.0, 2.0], &[0.5, 0.0]),
            state(1_700_000_001, 1_000_000, &["b", "a"], &[2.0, 1.001], &[0.0, 0.5]),
        ];
        let t = read(&bag(&[("/joint_states", JOINT_STATE, states)]), None).unwrap();
        assert_eq!(t.joint_names, ["a", "b"]);
        assert_eq!(t.points[1].time_from_start, 0.002);
        assert_eq!(t.points[1].positions, [1.001, 2.0]);
        assert_eq!(t.points[1].velocities, [0.5, 0.0]);
    }

    #[test]
    fn topics_are_picked_or_listed() {
        let s = || vec![state(0, 0, &["a"], &[1.0], &[])];
        let two = bag(&[
            ("/left", JOINT_STATE, s()),
            ("/right", JOINT_STATE, s()),
            ("/chatter", "std_msgs/msg/String", vec![vec![1, 0, 0, 0, 0]]),
        ]);
        let e = read(&two, None).unwrap_err().to_string();
        assert_eq!(
            e,
            "b.mcap: has 2 candidate topics: /left (sensor_msgs/msg/JointState), /right (sensor_msgs/msg/JointState); pick one with --topic"
        );
        assert_eq!(read(&two, Some("/right")).unwrap().joint_names, ["a"]);
        let e = read(&two, Some("/chatter")).unwrap_err().to_string();
        assert!(
            e.starts_with("`topic`: /chatter in b.mcap is of type std_msgs/msg/String"),
            "{e}"
        );
        let e = read(&two, Some("/nope")).unwrap_err().to_string();
        assert!(
            e.contains("no such topic (its topics: /chatter (std_msgs/msg/String), /left"),
            "{e}"
        );
        let none = bag(&[("/chatter", "std_msgs/msg/String", vec![vec![1, 0, 0, 0, 0]])]);
        assert!(
            read(&none, None)
                .unwrap_err()
                .to_string()
                .contains("has no trajectory_msgs/msg/JointTrajectory or sensor_msgs/msg/JointState topic")
        );
        let e = read(b"not an mcap", None).unwrap_err().to_string();
        assert!(e.starts_with("b.mcap: not a readable MCAP file"), "{e}");
        let broken = bag(&[("/j", JOINT_TRAJECTORY, vec![vec![7, 0, 0, 0]])]);
        let e = read(&broken, None).unwrap_err().to_string();
        assert!(
            e.starts_with("b.mcap: topic /j, message 1: not a trajectory_msgs/msg/JointTrajectory in CDR"),
            "{e}"
        );
    }

    /// A small file whose trajectory topic holds more than the kept-messages cap once
    /// decompressed (257 messages of 1 MiB, compressed to a few kB) is refused when the cap is
    /// passed, not read into memory without end; one message fewer than the cap is read on.
    #[test]
    fn messages_past_the_kept_cap_are_refused() {
        let mib = vec![0u8; 1 << 20];
        let messages = |n: usize| vec![mib.clone(); n];
        let over = bag(&[("/joint_states", JOINT_STATE, messages(257))]);
        assert!(over.len() < (8 << 20), "compressed: {} bytes", over.len());
        let e = read(&over, None).unwrap_err().to_string();
        assert!(
            e.contains("its trajectory topics hold more than 256 MiB of messages once decompressed"),
            "{e}"
        );
        // under the cap the messages are kept and decoded (zeros decode as empty JointStates)
        let under = bag(&[("/joint_states", JOINT_STATE, messages(250))]);
        let e = read(&under, None).unwrap_err().to_string();
        assert!(
            e.ends_with("topic /joint_states's JointState messages name no joint"),
            "{e}"
        );
    }

    /// A schema or channel whose string claims more than its record holds is refused as
    /// malformed, without taking what it claims (the mcap crate's decoding reserved it).
    #[test]
    fn strings_longer_than_their_record_are_refused() {
        let record = |op: u8, content: &[u8]| {
            let mut r = vec![op];
            r.extend((content.len() as u64).to_le_bytes());
            r.extend(content);
            r
        };
        let string = |s: &str| [&(s.len() as u32).to_le_bytes()[..], s.as_bytes()].concat();
        let claims = |n: u32| [&n.to_le_bytes()[..], b"abc"].concat();
        let file = |records: &[Vec<u8>]| {
            let mut f = b"\x89MCAP0\r\n".to_vec();
            f.extend(record(0x01, &[string("ros2"), string("")].concat()));
            for r in records {
                f.extend(r);
            }
            f
        };
        let schema = |name: &[u8]| record(0x03, &[&1u16.to_le_bytes()[..], name].concat());
        let e = read(&file(&[schema(&claims(0xF000_0000))]), None)
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("not a readable MCAP file: a malformed schema record"),
            "{e}"
        );
        let channel = |topic: &[u8]| {
            record(
                0x04,
                &[&1u16.to_le_bytes()[..], &0u16.to_le_bytes(), topic, &string("cdr")].concat(),
            )
        };
        let e = read(&file(&[channel(&claims(4))]), None).unwrap_err().to_string();
        assert!(
            e.ends_with("not a readable MCAP file: a malformed channel record"),
            "{e}"
        );
        // a message on a channel never declared
        let message = record(0x05, &[&7u16.to_le_bytes()[..], &[0; 20]].concat());
        let e = read(&file(&[message]), None).unwrap_err().to_string();
        assert!(
            e.contains("a message on channel 7, which no channel record declares"),
            "{e}"
        );
    }
}
