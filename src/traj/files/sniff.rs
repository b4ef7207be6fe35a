//! What a file is, by its first bytes, whatever its name says: each format faze4 reads that
//! has a magic number, read from the start of a file or stream without losing those bytes.

use std::io::{Cursor, Read};

/// The magic an MCAP file starts with.
pub const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";
/// The 16 bytes an SQLite database starts with: rosbag2's `.db3`.
pub const SQLITE_MAGIC: &[u8] = b"SQLite format 3\0";
/// The line a ROS 1 bag (format 2.0) starts with.
pub const ROS1_MAGIC: &[u8] = b"#ROSBAG V2.0\n";
/// The magic a zstd frame starts with (RFC 8878 §3.1.1): a `.mcap.zstd` or `.db3.zstd` file
/// (rosbag2's `compression_mode: FILE`), or one message (`compression_mode: MESSAGE`).
pub const ZSTD_MAGIC: &[u8] = &[0x28, 0xb5, 0x2f, 0xfd];

/// A format told by its first bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Magic {
    /// An MCAP file (`\x89MCAP0\r\n`).
    Mcap,
    /// An SQLite database (`SQLite format 3\0`): rosbag2's `.db3`.
    Sqlite,
    /// A ROS 1 bag (`#ROSBAG V2.0\n`).
    Ros1,
    /// A zstd frame (`28 b5 2f fd`): a `.mcap.zstd` or `.db3.zstd`.
    Zstd,
    /// A NumPy array (`\x93NUMPY`).
    Npy,
    /// A Parquet file (`PAR1`): a LeRobot dataset's table.
    Parquet,
}

impl Magic {
    /// The format `head` (a file's first bytes, at least [`HEAD`] of them unless the file is
    /// shorter) starts with.
    pub fn of(head: &[u8]) -> Option<Magic> {
        [
            (MCAP_MAGIC, Magic::Mcap),
            (SQLITE_MAGIC, Magic::Sqlite),
            (ROS1_MAGIC, Magic::Ros1),
            (ZSTD_MAGIC, Magic::Zstd),
            (b"\x93NUMPY".as_slice(), Magic::Npy),
            (b"PAR1".as_slice(), Magic::Parquet),
        ]
        .into_iter()
        .find_map(|(magic, what)| head.starts_with(magic).then_some(what))
    }

    /// The format for people.
    pub fn name(self) -> &'static str {
        match self {
            Magic::Mcap => "an MCAP file",
            Magic::Sqlite => "an SQLite database (rosbag2 .db3)",
            Magic::Ros1 => "a ROS 1 bag",
            Magic::Zstd => "a zstd-compressed file",
            Magic::Npy => "a NumPy .npy file",
            Magic::Parquet => "a Parquet file",
        }
    }
}

/// Bytes read to tell a format: the longest magic (SQLite's).
pub const HEAD: usize = 16;

/// The first [`HEAD`] bytes of `reader` (fewer if it ends first), and a reader that yields
/// them and then the rest.
pub fn peek<'a>(mut reader: impl Read + 'a) -> std::io::Result<(Vec<u8>, Box<dyn Read + 'a>)> {
    let mut head = Vec::with_capacity(HEAD);
    (&mut reader).take(HEAD as u64).read_to_end(&mut head)?;
    Ok((head.clone(), Box::new(Cursor::new(head).chain(reader))))
}

/// `head` for a message: its printable ASCII as it is, other bytes as `\xNN`.
pub fn shown(head: &[u8]) -> String {
    head.iter()
        .map(|&b| match b {
            b' '..=b'~' => (b as char).to_string(),
            _ => format!("\\x{b:02x}"),
        })
        .collect()
}
