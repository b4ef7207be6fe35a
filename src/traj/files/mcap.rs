//! `.mcap`: a rosbag2 MCAP file (the default storage since ROS 2 Iron), written here with the
//! `mcap` crate, read by [`super::bag`] (its records by [`super::bag::mcap`]); its messages are
//! plain CDR (`message_encoding` `cdr`: a 4-byte encapsulation header, `00 01` little-endian or
//! `00 00` big-endian, then the fields in order, each aligned to its size from the end of the
//! header), encoded with the `cdr-encoding` crate from the structs of [`super::ros`].

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::Path;

use byteorder::LittleEndian;

use super::bag::Collected;
use super::ros::{JOINT_TRAJECTORY, JOINT_TRAJECTORY_DEFINITION, JointTrajectoryMsg};
use super::{Read, Selection, invalid};
use crate::error::Result;
use crate::traj::TimedTrajectory;

/// The topic [`to_bytes`] writes the trajectory on.
pub const TOPIC: &str = "/joint_trajectory";

/// The trajectory `selection` picks in an MCAP file's bytes, unchecked, with what reading it
/// noticed (see [`super::bag`]).
pub fn parse(bytes: &[u8], selection: &Selection, path: &Path) -> Result<Read> {
    let mut bag = Collected::default();
    super::bag::mcap::collect(&mut &bytes[..], &mut bag, path)?;
    Ok(bag.trajectory(selection, path)?.0)
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
    use crate::traj::files::ros::{Header, JOINT_STATE, JointStateMsg, RosTime};

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
            "b.mcap: has 2 candidate topics: /left (sensor_msgs/msg/JointState, 1 message), /right (sensor_msgs/msg/JointState, 1 message); pick one with `topic`"
        );
        assert_eq!(read(&two, Some("/right")).unwrap().joint_names, ["a"]);
        let e = read(&two, Some("/chatter")).unwrap_err().to_string();
        assert!(
            e.starts_with("`topic`: /chatter in b.mcap is of type std_msgs/msg/String"),
            "{e}"
        );
        let e = read(&two, Some("/nope")).unwrap_err().to_string();
        assert!(
            e.contains("no such topic (its topics: /chatter (std_msgs/msg/String, 1 message), /left"),
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
