//! The records of an MCAP file (rosbag2's storage since ROS 2 Iron), streamed: its schemas,
//! channels and messages, each handed to a [`Collected`].

use std::collections::BTreeMap;
use std::io::{Cursor, Read};
use std::path::Path;

use ::mcap::records::op;
use ::mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::{Collected, Topic};
use crate::error::{Error, Result};
use crate::input::MAX_MCAP_MESSAGE_BYTES;
use crate::traj::files::invalid;

/// Reads every record of the MCAP stream `source` into `bag`: its topics (the channel's name,
/// its schema's name as the type, the channel's message encoding) and messages in file order
/// with their log times.
///
/// The records are read by the `mcap` crate's linear reader (magic, record lengths, chunks
/// decompressed, CRCs; a record, or one inside a compressed chunk, whatever size it claims,
/// is read only up to [`MAX_MCAP_MESSAGE_BYTES`]), and the three this needs (schema, channel,
/// message) are decoded here, each length checked against what its record holds: the crate's
/// own decoding reserves whatever a string's length claims (a 300-byte file claiming a 4 GB
/// profile string asked for 4 GB). Each chunk is handed to a second reader of its own, after
/// `check_uncompressed_chunk`: the crate's reader does not check a record inside an
/// uncompressed chunk against what the chunk has left (mcap 0.26, `linear_reader.rs:745`, an
/// underflow: a panic in a debug build, records read past the chunk in a release one). The
/// summary after the data end repeats schemas and channels and is not read.
pub fn collect(source: &mut dyn Read, bag: &mut Collected, path: &Path) -> Result<()> {
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
                let topic = Topic { name, kind, encoding };
                bag.declare(&topic);
                channels.insert(id, topic);
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
                bag.add(topic, log_time, r.0, path)?;
            }
            op::CHUNK => return Err(bad("a chunk inside a chunk".into())),
            _ => {}
        }
        Ok(())
    };
    // the file's own records, its chunks as they are
    each_record(
        source,
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
            each_record(&mut Cursor::new(header).chain(data), alone, &bad, &mut record)
        },
    )
}

/// The most bytes asked of the source at once (1 MiB).
const READ_PIECE: usize = 1 << 20;

/// Calls `record` with the opcode and data of each record the linear reader with `options`
/// yields from `source`, up to the data end.
fn each_record(
    source: &mut dyn Read,
    options: LinearReaderOptions,
    bad: &impl Fn(String) -> Error,
    record: &mut impl FnMut(u8, &[u8]) -> Result<()>,
) -> Result<()> {
    let mut reader = LinearReader::new_with_options(options);
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| bad(e.to_string()))? {
            LinearReadEvent::ReadRequest(need) => {
                // a piece at a time: the buffer grows with what the file holds, not with what
                // a record's length claims (a 5 kB file claiming a 250 MB record had the
                // reader allocate and clear all of it first)
                let n = source
                    .read(reader.insert(need.min(READ_PIECE)))
                    .map_err(|e| bad(format!("reading it: {e}")))?;
                reader.notify_read(n);
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
