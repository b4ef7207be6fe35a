//! rosbag2's SQLite storage (`.db3`, the default storage of ROS 2 Humble and before), read with
//! `rusqlite` and the SQLite it bundles: the table `topics` (`id`, `name`, `type`,
//! `serialization_format`) and the table `messages` (`topic_id`, `timestamp` in ns, `data`),
//! as `rosbag2_storage_sqlite3` writes them.
//!
//! A file is opened read-only and immutable (SQLite reads its pages as it needs them, nothing
//! is written beside it, not even a WAL); a stream, or a `.db3.zstd`, is read into memory
//! first (under [`MAX_MCAP_BYTES`]) and opened there. A value SQLite reads is bounded by
//! [`MAX_MCAP_MESSAGE_BYTES`] (`SQLITE_LIMIT_LENGTH`); only the joint topics' messages are
//! read, the others counted.

use std::path::Path;

use rusqlite::limits::Limit;
use rusqlite::{Connection, OpenFlags};

use super::{Collected, Topic, joint};
use crate::error::Result;
#[cfg(doc)]
use crate::input::MAX_MCAP_BYTES;
use crate::input::MAX_MCAP_MESSAGE_BYTES;
use crate::traj::files::invalid;

/// Reads the rosbag2 SQLite file `path` (a regular file) into `bag`.
pub fn collect_file(path: &Path, bag: &mut Collected) -> Result<()> {
    let bad = |e: rusqlite::Error| invalid(path, format!("not a readable rosbag2 SQLite bag: {e}"));
    let absolute = std::path::absolute(path).map_err(|e| invalid(path, e.to_string()))?;
    let uri = format!(
        "file:{}?immutable=1",
        percent_encoded(absolute.as_os_str().as_encoded_bytes())
    );
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_URI | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let db = Connection::open_with_flags(uri, flags).map_err(bad)?;
    collect(&db, bag, path)
}

/// Reads the rosbag2 SQLite database `bytes` (a whole file) into `bag`; `path` names it.
pub fn collect_bytes(bytes: &[u8], bag: &mut Collected, path: &Path) -> Result<()> {
    let bad = |e: rusqlite::Error| invalid(path, format!("not a readable rosbag2 SQLite bag: {e}"));
    let mut db = Connection::open_in_memory().map_err(bad)?;
    db.deserialize_read_exact(rusqlite::MAIN_DB, bytes, bytes.len(), true)
        .map_err(bad)?;
    collect(&db, bag, path)
}

fn collect(db: &Connection, bag: &mut Collected, path: &Path) -> Result<()> {
    let bad = |e: rusqlite::Error| invalid(path, format!("not a readable rosbag2 SQLite bag: {e}"));
    db.set_limit(Limit::SQLITE_LIMIT_LENGTH, MAX_MCAP_MESSAGE_BYTES as i32)
        .map_err(bad)?;
    let mut topics = db
        .prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id")
        .map_err(bad)?;
    let topics = topics
        .query_map([], |row| {
            let topic = Topic {
                name: row.get(1)?,
                kind: row.get(2)?,
                encoding: row.get(3)?,
            };
            Ok((row.get::<_, i64>(0)?, topic))
        })
        .map_err(bad)?
        .collect::<rusqlite::Result<Vec<_>>>()
        .map_err(bad)?;
    let mut counts = db
        .prepare("SELECT COUNT(*) FROM messages WHERE topic_id = ?1")
        .map_err(bad)?;
    let mut messages = db
        .prepare("SELECT timestamp, data FROM messages WHERE topic_id = ?1 ORDER BY id")
        .map_err(bad)?;
    for (id, topic) in &topics {
        bag.declare(topic);
        if joint(&topic.kind).is_none() {
            let n: i64 = counts.query_row([id], |row| row.get(0)).map_err(bad)?;
            bag.count(topic, n as usize);
            continue;
        }
        let mut rows = messages.query([id]).map_err(bad)?;
        while let Some(row) = rows.next().map_err(bad)? {
            let time: i64 = row.get(0).map_err(bad)?;
            let data = row.get_ref(1).map_err(bad)?.as_blob().map_err(|e| bad(e.into()))?;
            bag.add(topic, time.max(0) as u64, data, path)?;
        }
    }
    Ok(())
}

/// `bytes` with every byte but `A-Z a-z 0-9 / . _ -` as `%XX`, for an SQLite file URI.
fn percent_encoded(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len());
    for &b in bytes {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'.' | b'_' | b'-' => out.push(b as char),
            _ => out.push_str(&format!("%{b:02X}")),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_percent_encoded() {
        assert_eq!(percent_encoded(b"/a b/c?d#e%f.db3"), "/a%20b/c%3Fd%23e%25f.db3");
    }
}
