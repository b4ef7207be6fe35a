//! ROS 1 bags (format 2.0, <http://wiki.ros.org/Bags/Format/2.0>), read by a small reader of
//! faze4's own, and ROS 1's serialization of the two messages faze4 plays.
//!
//! A bag is `#ROSBAG V2.0\n`, then records: a `u32` header length, the header (fields, each a
//! `u32` length and `name=value`, `op` the record's kind), a `u32` data length, the data. The
//! records read here are connections (`op` 7: `conn`, `topic`; the data holds the type),
//! messages (`op` 2: `conn`, `time` as `u32` seconds and nanoseconds) and chunks (`op` 5:
//! `compression` `none`, `bz2` or `lz4`, `size` decompressed; the data holds connections and
//! messages); the bag header, index data and chunk infos are skipped. Every length is checked
//! against [`MAX_MCAP_MESSAGE_BYTES`] before it is read, a chunk's decompression stops there.
//! (The `rosbag` crate memory-maps a path, so no stream, and reserves whatever size a chunk
//! claims.)
//!
//! ROS 1's serialization is little-endian and unaligned; an array or string is a `u32` count
//! then its elements; a `time` is `u32` seconds and nanoseconds, a `duration` `i32` ones, and a
//! `Header` starts with a `u32 seq`.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

use super::{Collected, ROS1, Topic};
use crate::error::Result;
use crate::input::{MAX_MCAP_MESSAGE_BYTES, MAX_MOVING_JOINTS, MAX_TRAJECTORY_POINTS, size_text};
use crate::traj::files::invalid;
use crate::traj::files::ros::{Header, JointStateMsg, JointTrajectoryMsg, JointTrajectoryPointMsg, RosTime};
use crate::traj::files::sniff::ROS1_MAGIC;
use crate::traj::timed::ros_sec_nanosec;

/// The record kinds (`op`) read.
const MESSAGE: u8 = 0x02;
const CHUNK: u8 = 0x05;
const CONNECTION: u8 = 0x07;

/// Reads every connection and message of the ROS 1 bag `source` (its magic line included) into
/// `bag`, messages in file order, their `time` as the log time.
pub fn collect(source: &mut dyn Read, bag: &mut Collected, path: &Path) -> Result<()> {
    let bad = |what: String| invalid(path, format!("not a readable ROS 1 bag: {what}"));
    let mut magic = [0u8; ROS1_MAGIC.len()];
    source.read_exact(&mut magic).map_err(|e| bad(e.to_string()))?;
    if magic != ROS1_MAGIC {
        return Err(bad("it does not start with #ROSBAG V2.0".into()));
    }
    let mut connections: BTreeMap<u32, Topic> = BTreeMap::new();
    let mut records = Records { source, path };
    while let Some((fields, data)) = records.next()? {
        record(&fields, &data, &mut connections, bag, path)?;
    }
    Ok(())
}

/// One record, `fields` its header's: a chunk's records in turn.
fn record(
    fields: &Fields,
    data: &[u8],
    connections: &mut BTreeMap<u32, Topic>,
    bag: &mut Collected,
    path: &Path,
) -> Result<()> {
    let bad = |what: String| invalid(path, format!("not a readable ROS 1 bag: {what}"));
    match fields.op(&bad)? {
        CONNECTION => {
            let conn = fields.u32("conn", &bad)?;
            let topic = fields.text("topic", &bad)?;
            let connection =
                Fields::parse(data).ok_or_else(|| bad(format!("connection {conn}'s header is malformed")))?;
            let kind = connection.get("type").map(|t| String::from_utf8_lossy(t).into_owned());
            let topic = Topic {
                name: topic,
                kind: kind.unwrap_or_default(),
                encoding: ROS1.into(),
            };
            bag.declare(&topic);
            connections.insert(conn, topic);
        }
        MESSAGE => {
            let conn = fields.u32("conn", &bad)?;
            let time = fields.get("time").and_then(|t| <[u8; 8]>::try_from(t).ok());
            let time = time.ok_or_else(|| bad("a message without its 8-byte time".into()))?;
            let (sec, nsec) = (
                u32::from_le_bytes(time[..4].try_into().unwrap()),
                u32::from_le_bytes(time[4..].try_into().unwrap()),
            );
            let topic = (connections.get(&conn)).ok_or_else(|| {
                bad(format!(
                    "a message on connection {conn}, which no connection record declares"
                ))
            })?;
            bag.add(topic, sec as u64 * 1_000_000_000 + nsec as u64, data, path)?;
        }
        CHUNK => {
            let records = chunk(fields, data, &bad)?;
            let mut inner = Records {
                source: &mut &records[..],
                path,
            };
            while let Some((fields, data)) = inner.next()? {
                if fields.op(&bad)? == CHUNK {
                    return Err(bad("a chunk inside a chunk".into()));
                }
                record(&fields, &data, connections, bag, path)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// A chunk's records, decompressed (at most [`MAX_MCAP_MESSAGE_BYTES`]).
fn chunk(fields: &Fields, data: &[u8], bad: &impl Fn(String) -> crate::Error) -> Result<Vec<u8>> {
    let compression = fields.text("compression", bad)?;
    let size = fields.u32("size", bad)? as u64;
    if size > MAX_MCAP_MESSAGE_BYTES {
        return Err(bad(format!(
            "a chunk claims {} once decompressed, more than the {} a record may hold (docs/development.md, Caps)",
            size_text(size),
            size_text(MAX_MCAP_MESSAGE_BYTES)
        )));
    }
    let mut out = Vec::new();
    let read = match compression.as_str() {
        "none" => return Ok(data.to_vec()),
        "bz2" => bzip2::read::BzDecoder::new(data).take(size + 1).read_to_end(&mut out),
        "lz4" => lz4::Decoder::new(data).and_then(|d| d.take(size + 1).read_to_end(&mut out)),
        other => {
            return Err(bad(format!(
                "a chunk compressed with {other:?} (ROS 1 writes none, bz2 or lz4)"
            )));
        }
    };
    read.map_err(|e| bad(format!("a {compression} chunk does not decompress: {e}")))?;
    if out.len() as u64 != size {
        return Err(bad(format!(
            "a {compression} chunk claims {size} bytes and holds {}{}",
            if out.len() as u64 > size { "more than" } else { "" },
            out.len().min(size as usize)
        )));
    }
    Ok(out)
}

/// The records of a stream, each read only once its lengths are checked.
struct Records<'a> {
    source: &'a mut dyn Read,
    path: &'a Path,
}

impl Records<'_> {
    /// The next record's header fields and data; `None` at the end of the stream.
    fn next(&mut self) -> Result<Option<(Fields, Vec<u8>)>> {
        let bad = |what: String| invalid(self.path, format!("not a readable ROS 1 bag: {what}"));
        let mut length = [0u8; 4];
        // the end of the stream, between records
        match self.source.read(&mut length[..1]) {
            Ok(0) => return Ok(None),
            Ok(_) => {}
            Err(e) => return Err(bad(e.to_string())),
        }
        self.source
            .read_exact(&mut length[1..])
            .map_err(|_| bad("it ends inside a record".into()))?;
        let header = self.block(u32::from_le_bytes(length), "header")?;
        let fields = Fields::parse(&header).ok_or_else(|| bad("a record's header is malformed".into()))?;
        self.source
            .read_exact(&mut length)
            .map_err(|_| bad("it ends inside a record".into()))?;
        let data = self.block(u32::from_le_bytes(length), "data")?;
        Ok(Some((fields, data)))
    }

    fn block(&mut self, length: u32, what: &str) -> Result<Vec<u8>> {
        let bad = |what: String| invalid(self.path, format!("not a readable ROS 1 bag: {what}"));
        if length as u64 > MAX_MCAP_MESSAGE_BYTES {
            return Err(bad(format!(
                "a record's {what} claims {}, more than the {} a record may hold (docs/development.md, Caps)",
                size_text(length as u64),
                size_text(MAX_MCAP_MESSAGE_BYTES)
            )));
        }
        let mut out = Vec::new();
        (&mut *self.source)
            .take(length as u64)
            .read_to_end(&mut out)
            .map_err(|e| bad(e.to_string()))?;
        if out.len() != length as usize {
            return Err(bad(format!(
                "it ends inside a record's {what} ({} of {length} bytes)",
                out.len()
            )));
        }
        Ok(out)
    }
}

/// A record header's fields: `name=value` pairs.
struct Fields(Vec<(Vec<u8>, Vec<u8>)>);

impl Fields {
    fn parse(mut bytes: &[u8]) -> Option<Fields> {
        let mut fields = Vec::new();
        while !bytes.is_empty() {
            let (length, rest) = bytes.split_first_chunk::<4>()?;
            let (field, rest) = rest.split_at_checked(u32::from_le_bytes(*length) as usize)?;
            let eq = field.iter().position(|&b| b == b'=')?;
            fields.push((field[..eq].to_vec(), field[eq + 1..].to_vec()));
            bytes = rest;
        }
        Some(Fields(fields))
    }

    fn get(&self, name: &str) -> Option<&[u8]> {
        self.0.iter().find(|(n, _)| n == name.as_bytes()).map(|(_, v)| &v[..])
    }

    fn op(&self, bad: &impl Fn(String) -> crate::Error) -> Result<u8> {
        match self.get("op") {
            Some([op]) => Ok(*op),
            _ => Err(bad("a record without its one-byte op".into())),
        }
    }

    fn u32(&self, name: &str, bad: &impl Fn(String) -> crate::Error) -> Result<u32> {
        (self.get(name).and_then(|v| <[u8; 4]>::try_from(v).ok()))
            .map(u32::from_le_bytes)
            .ok_or_else(|| bad(format!("a record without its 4-byte {name}")))
    }

    fn text(&self, name: &str, bad: &impl Fn(String) -> crate::Error) -> Result<String> {
        (self.get(name).map(|v| String::from_utf8_lossy(v).into_owned()))
            .ok_or_else(|| bad(format!("a record without its {name}")))
    }
}

/// A message faze4 reads in ROS 1's serialization.
pub trait Decode: Sized {
    /// The message in `data` (all of it: bytes left over are an error).
    fn decode_ros1(data: &[u8]) -> std::result::Result<Self, String>;
}

impl Decode for JointStateMsg {
    fn decode_ros1(data: &[u8]) -> std::result::Result<Self, String> {
        let mut r = Ros1(data);
        let message = JointStateMsg {
            header: r.header()?,
            name: r.strings()?,
            position: r.floats()?,
            velocity: r.floats()?,
            effort: r.floats()?,
        };
        r.end().map(|_| message)
    }
}

impl Decode for JointTrajectoryMsg {
    fn decode_ros1(data: &[u8]) -> std::result::Result<Self, String> {
        let mut r = Ros1(data);
        let header = r.header()?;
        let joint_names = r.strings()?;
        let count = r.count(4 * 4 + 8, MAX_TRAJECTORY_POINTS, "points")?;
        let mut points = Vec::with_capacity(count);
        for _ in 0..count {
            points.push(JointTrajectoryPointMsg {
                positions: r.floats()?,
                velocities: r.floats()?,
                accelerations: r.floats()?,
                effort: r.floats()?,
                time_from_start: r.duration()?,
            });
        }
        let message = JointTrajectoryMsg {
            header,
            joint_names,
            points,
        };
        r.end().map(|_| message)
    }
}

/// A ROS 1 message's bytes, read field by field.
struct Ros1<'a>(&'a [u8]);

impl Ros1<'_> {
    fn take<const N: usize>(&mut self) -> std::result::Result<[u8; N], String> {
        let (head, rest) = (self.0.split_first_chunk::<N>()).ok_or_else(|| "it ends inside a field".to_string())?;
        self.0 = rest;
        Ok(*head)
    }

    fn u32(&mut self) -> std::result::Result<u32, String> {
        self.take().map(u32::from_le_bytes)
    }

    /// An array's count, checked against what is left (each element at least `least` bytes)
    /// and against `max` (docs/development.md, Caps), `what` naming its elements.
    fn count(&mut self, least: usize, max: usize, what: &str) -> std::result::Result<usize, String> {
        let n = self.u32()? as usize;
        if n > max {
            return Err(format!(
                "an array claims {n} {what}, more than the {max} a message may hold (docs/development.md, Caps)"
            ));
        }
        match n.checked_mul(least).is_some_and(|b| b <= self.0.len()) {
            true => Ok(n),
            false => Err(format!(
                "an array claims {n} elements where {} bytes are left",
                self.0.len()
            )),
        }
    }

    fn string(&mut self) -> std::result::Result<String, String> {
        let n = self.count(1, usize::MAX, "bytes")?;
        let (text, rest) = self.0.split_at(n);
        self.0 = rest;
        String::from_utf8(text.to_vec()).map_err(|_| "a string is not UTF-8".to_string())
    }

    fn strings(&mut self) -> std::result::Result<Vec<String>, String> {
        let n = self.count(4, MAX_MOVING_JOINTS, "joint names")?;
        (0..n).map(|_| self.string()).collect()
    }

    fn floats(&mut self) -> std::result::Result<Vec<f64>, String> {
        let n = self.count(8, MAX_MOVING_JOINTS, "values")?;
        (0..n).map(|_| self.take().map(f64::from_le_bytes)).collect()
    }

    fn header(&mut self) -> std::result::Result<Header, String> {
        let _seq = self.u32()?;
        let (sec, nsec) = (self.u32()?, self.u32()?);
        let stamp = time(sec as i64 * 1_000_000_000 + nsec as i64)?;
        Ok(Header {
            stamp,
            frame_id: self.string()?,
        })
    }

    fn duration(&mut self) -> std::result::Result<RosTime, String> {
        let (sec, nsec) = (
            self.take().map(i32::from_le_bytes)?,
            self.take().map(i32::from_le_bytes)?,
        );
        time(sec as i64 * 1_000_000_000 + nsec as i64)
    }

    fn end(&self) -> std::result::Result<(), String> {
        match self.0.len() {
            0 => Ok(()),
            n => Err(format!("{n} bytes are left after its last field")),
        }
    }
}

/// Whole nanoseconds as a ROS 2 time (seconds in an `i32`: until 2038).
fn time(ns: i64) -> std::result::Result<RosTime, String> {
    let (sec, nanosec) = ros_sec_nanosec(ns);
    let sec = i32::try_from(sec).map_err(|_| format!("a time of {sec} s is beyond the 68 years a ROS 2 time holds"))?;
    Ok(RosTime { sec, nanosec })
}
