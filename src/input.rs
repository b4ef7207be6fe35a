//! Files read whole, each under a documented cap checked before memory is taken, and streams
//! (a FIFO, `/dev/stdin`, `/dev/zero`) read only up to that cap. docs/development.md
//! ("Reliability", "Caps") says why each cap has its value.
//!
//! A regular file larger than its cap is refused from its size, before any byte is read; a
//! stream is read up to one byte past the cap and refused if that byte comes. Inputs that must
//! be files (a mesh, a sweep part and its `.meta`, whose sizes are checked) refuse streams and
//! directories by name ("is a FIFO").

use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};

/// Largest URDF read (16 MiB). The descriptions we know are under 1 MB; urdf-rs holds about
/// fifty times the text while it parses (a 3 MB URDF of 10,000 links peaked at 145 MB).
pub const MAX_URDF_BYTES: u64 = 16 << 20;
/// Most `<link>`s a URDF may have (4,096): every link is a frame, placed at every recorded
/// sample and drawn in the views; an arm has tens, a humanoid with its hands about a hundred.
pub const MAX_LINKS: usize = 4096;
/// Most moving joints (bodies, mimic followers included) a model may have (256). A step factors
/// the n×n mass matrix (n³/6 multiplications) and tuning decomposes a 2n×2n matrix: at 128
/// joints a step took about 3 ms, and the cost grows as n³ (256 joints: about 8× that, so a
/// default 8 s run about a quarter of an hour; a 1,000-joint chain took 107 s for 250 steps;
/// 10,000 joints asked for 800 MB matrices and aborted). A humanoid with its fingers has about
/// 60; the 200-link chain of tests/it/coupled_stability.rs is the longest the tests run.
pub const MAX_MOVING_JOINTS: usize = 256;
/// Most points a ROS trajectory may have (1 million: 16 minutes at 1 kHz), a `JointTrajectory`'s
/// `points` in any file or bag, or the messages of a `JointState` topic, counted as they are
/// read: each point costs about 100 bytes beside its values once read, so a bag of empty points
/// (24 bytes each in CDR, compressed to almost nothing) would otherwise take gigabytes (10
/// million took 1.37 GB, issue 49). A LeRobot episode has its own cap of as many frames;
/// `retime` writes at most 100,001 points.
pub const MAX_TRAJECTORY_POINTS: usize = 1_000_000;
/// Most samples a shape may have (`shape_points`, 100,000): each is an IK solve and about 200
/// bytes of plan (100 million asked for 19.5 GB). The default loop of 12 s at the default
/// step of 0.2 ms has 60,000 steps, so more samples than this are finer than the steps.
pub const MAX_SHAPE_POINTS: usize = 100_000;
/// Most grid intervals `retime` takes (`grid`, 100,000): each grid point holds about 2 kB (the
/// path's derivatives, the solver's rows, the timing written out; 100,000 peaked at 204 MB and
/// wrote a 53 MB YAML timing), and a billion aborted on a 48 GB allocation. The default is 200;
/// toppra's examples use a few hundred.
pub const MAX_RETIME_INTERVALS: usize = 100_000;
/// Largest mesh file read (256 MiB): a binary STL of [`MAX_MESH_TRIANGLES`] (250 MB) fits.
pub const MAX_MESH_BYTES: u64 = 256 << 20;
/// Most triangles one mesh file may hold (5 million). Each triangle costs about 300 bytes while
/// the mesh is welded, its hull computed and its BVH built, so 5 million take about 1.5 GB;
/// the Faze4's meshes hold under 70,000 each.
pub const MAX_MESH_TRIANGLES: u64 = 5_000_000;
/// Deepest element nesting of a COLLADA file (256): mesh-loader reads `<node>`s recursively
/// (100,000 nested ones overflowed the stack); CAD exports nest a few dozen deep.
pub const MAX_COLLADA_NESTING: usize = 256;
/// Largest `.npy` trajectory read (256 MiB): an hour at 1 kHz of 7 joints is 200 MB.
pub const MAX_NPY_BYTES: u64 = 256 << 20;
/// Largest time-stamped trajectory text read (`.json`, `.csv`: 64 MiB). The ROS
/// trajectories we know hold tens to thousands of points (a few hundred bytes each); 64 MiB
/// is about 300,000 points of 7 joints. JSON is parsed into a tree first (serde's untagged
/// buffering), several times the text: a 64 MiB JSON trajectory peaked at 422 MB, a CSV at
/// 286 MB (docs/development.md, "Caps").
pub const MAX_TRAJECTORY_TEXT_BYTES: u64 = 64 << 20;
/// Largest YAML trajectory read (16 MiB, about 60,000 points as `ros2 topic echo` prints them):
/// serde_norway lists every event of the document before it builds anything, about 13 times the
/// text (a 64 MiB YAML trajectory peaked at 876 MB; docs/development.md, "Caps").
pub const MAX_YAML_TRAJECTORY_BYTES: u64 = 16 << 20;
/// Most values (numbers, strings, lists, mappings and keys alike) a YAML or JSON trajectory
/// file's documents may hold together (4 Mi), counted as they are built, a YAML alias counted
/// each time it repeats a value: a 15 MB YAML list of one-letter names took 1.43 GB as a tree
/// (issue 49). `ros2 topic echo`'s 60,000 points of 6 joints at the YAML cap hold about 1.8
/// million, the 64 MiB JSON of 355,850 points about 3.6 million (docs/development.md, "Caps").
pub const MAX_TEXT_VALUES: usize = 4 << 20;
/// Deepest nesting of a YAML trajectory file (64 collections, flow and block together), counted
/// before the YAML parser sees the text: libyaml's time grows as the square of the depth (a
/// 200 kB file of 100,000 nested `[` took 59 s, issue 49). A message echoed by ROS nests
/// about 8 deep; serde_norway itself stops at 128.
pub const MAX_YAML_NESTING: usize = 64;
/// Largest bag read into memory whole (256 MiB, the `.npy` cap): a rosbag2 `.db3` from a stream
/// or a `.db3.zstd` (SQLite opens it there); other bags are streamed (see [`MAX_BAG_BYTES`]).
pub const MAX_MCAP_BYTES: u64 = 256 << 20;
/// Most bytes an `.mcap` file's trajectory messages may hold once decompressed (256 MiB), and
/// the largest record it may have: a compressed chunk may claim any size, so what is kept and
/// each record are bounded, not the file. About 18 minutes of `JointState` at 1 kHz.
pub const MAX_MCAP_MESSAGE_BYTES: u64 = 256 << 20;
/// Most bytes a bag file (MCAP, ROS 1 `.bag`, a stream, a zstd file decompressed) may stream
/// (64 GiB): a bag is read record by record, its joint topics kept (under
/// [`MAX_MCAP_MESSAGE_BYTES`]) and the rest only counted, so memory does not grow with it; a
/// recording with cameras runs to gigabytes.
pub const MAX_BAG_BYTES: u64 = 64 << 30;
/// Largest motors file read (1 MiB): one `[[joint]]` takes a few hundred bytes.
pub const MAX_MOTORS_BYTES: u64 = 1 << 20;
/// Largest sweep part metadata read (16 MiB): it lists each varied option's values.
pub const MAX_META_BYTES: u64 = 16 << 20;
/// Largest side file read (an OBJ's `.mtl`, a package's `package.xml`): 1 MiB.
pub const MAX_SIDE_FILE_BYTES: u64 = 1 << 20;

/// Longest wait for a process to open a FIFO input for writing (10 s): opening a FIFO for
/// reading waits for a writer, and a FIFO nobody writes to would wait for ever.
pub const FIFO_WRITER_WAIT: std::time::Duration = std::time::Duration::from_secs(10);

/// `bytes` for people: `32 MiB`, `1.5 GiB`, `812 bytes`.
pub fn size_text(bytes: u64) -> String {
    const UNITS: [(&str, u64); 3] = [("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)];
    for (unit, size) in UNITS {
        if bytes >= size {
            return match bytes % size {
                0 => format!("{} {unit}", bytes / size),
                _ => format!("{:.1} {unit}", bytes as f64 / size as f64),
            };
        }
    }
    format!("{bytes} bytes")
}

/// What a file is, for messages: "a directory", "a FIFO", "a character device"…
fn kind(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// An [`Error::InvalidData`] for `path`.
fn invalid(path: &Path, message: String) -> Error {
    Error::InvalidData {
        path: path.to_path_buf(),
        message,
    }
}

/// The error of a file (or stream) larger than `cap`, `what` naming what it should be.
pub(crate) fn too_large(path: &Path, size: Option<u64>, cap: u64, what: &str) -> Error {
    let size = match size {
        Some(s) => format!("{} ({s} bytes), ", size_text(s)),
        None => "a stream of ".into(),
    };
    invalid(
        path,
        format!(
            "{size}more than the {} {what} may hold (faze4 reads it whole; docs/development.md, Caps)",
            size_text(cap)
        ),
    )
}

/// The bytes of `path`, a file or a stream, at most `cap` of them: a larger regular file is
/// refused from its size before it is read, a stream once byte `cap + 1` arrives. A directory
/// is refused. `what` names the input in the error (`URDF`, `.npy trajectory`).
pub fn read_capped(path: &Path, cap: u64, what: &str) -> Result<Vec<u8>> {
    read(path, cap, what, false)
}

/// [`read_capped`] of a regular file only: a directory, FIFO or device is refused by name.
pub fn read_file_capped(path: &Path, cap: u64, what: &str) -> Result<Vec<u8>> {
    read(path, cap, what, true)
}

fn read(path: &Path, cap: u64, what: &str, file_only: bool) -> Result<Vec<u8>> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    // the kind first, without opening: opening a FIFO for reading waits for a writer
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_dir() || (file_only && !meta.is_file()) {
        return Err(invalid(path, format!("is {}, not {what}", kind(&meta))));
    }
    if meta.is_file() && meta.len() > cap {
        return Err(too_large(path, Some(meta.len()), cap, what));
    }
    let file = open(path, &meta)?;
    let mut bytes = Vec::with_capacity(if meta.is_file() { meta.len() as usize } else { 0 });
    file.take(cap + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > cap {
        // a file that grew while read is refused as a stream is
        return Err(too_large(path, None, cap, what));
    }
    Ok(bytes)
}

/// Opens the input `path` (`meta` its metadata) for reading. A FIFO is opened once a process
/// opens it for writing, within [`FIFO_WRITER_WAIT`]; past that it is refused by name (a pipe,
/// `/dev/stdin` or `<(command)`, has its writer and opens at once).
pub fn open(path: &Path, meta: &std::fs::Metadata) -> Result<std::fs::File> {
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    if !meta.file_type().is_fifo() {
        return std::fs::File::open(path).map_err(io);
    }
    // open() blocks until a writer comes: on a thread, waited for up to the limit
    let (opened, wait) = std::sync::mpsc::channel();
    let fifo = path.to_path_buf();
    std::thread::spawn(move || {
        let _ = opened.send(std::fs::File::open(fifo));
    });
    match wait.recv_timeout(FIFO_WRITER_WAIT) {
        Ok(file) => file.map_err(io),
        Err(_) => {
            // the thread still waits in open(): be its writer for a moment, so that it ends
            let _ = std::fs::OpenOptions::new()
                .write(true)
                .custom_flags(libc::O_NONBLOCK)
                .open(path);
            Err(invalid(
                path,
                format!(
                    "a FIFO that no process opened for writing within {} s (docs/development.md, Caps)",
                    FIFO_WRITER_WAIT.as_secs()
                ),
            ))
        }
    }
}

/// What `reader` (the file or stream `path`) holds, at most `cap` bytes: a stream of more is
/// refused once byte `cap + 1` arrives, `what` naming the input (`a YAML trajectory`).
pub fn read_stream_capped(reader: impl Read, path: &Path, cap: u64, what: &str) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    reader
        .take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
    match bytes.len() as u64 > cap {
        true => Err(too_large(path, None, cap, what)),
        false => Ok(bytes),
    }
}

/// The metadata of `path`, which must be a regular file (links followed): a directory, FIFO or
/// device is refused by name, `what` (with its article) saying what was expected.
pub fn regular_file(path: &Path, what: &str) -> Result<std::fs::Metadata> {
    let meta = std::fs::metadata(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    match meta.is_file() {
        true => Ok(meta),
        false => Err(invalid(path, format!("is {}, not {what}", kind(&meta)))),
    }
}

/// `bytes`, read from `path`, as UTF-8 text.
pub fn into_text(path: &Path, bytes: Vec<u8>) -> Result<String> {
    String::from_utf8(bytes)
        .map_err(|e| invalid(path, format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to())))
}

/// The line on which XML `text` first has more than `limit` elements open, if it does. A
/// lexical scan (comments, CDATA, processing instructions, declarations and quoted attribute
/// values skipped), linear in the length of the text and without recursion; malformed XML is
/// left to the parser. Parsers that walk the element tree recursively (urdf-rs, mesh-loader's
/// COLLADA `<node>`s) overflow the stack on deep nesting, an abort no `catch_unwind` stops, so
/// their input is scanned first.
pub fn xml_nested_deeper_than(text: &[u8], limit: usize) -> Option<usize> {
    let b = text;
    let find = |from: usize, pat: &[u8]| -> usize {
        (b.get(from..).unwrap_or_default().windows(pat.len()))
            .position(|w| w == pat)
            .map_or(b.len(), |p| from + p + pat.len())
    };
    let (mut depth, mut i) = (0usize, 0usize);
    while let Some(p) = b.get(i..).and_then(|rest| rest.iter().position(|&c| c == b'<')) {
        let at = i + p;
        let rest = &b[at..];
        i = if rest.starts_with(b"<!--") {
            find(at + 4, b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            find(at + 9, b"]]>")
        } else if rest.starts_with(b"<?") {
            find(at + 2, b"?>")
        } else if rest.starts_with(b"<!") || rest.starts_with(b"</") {
            depth = depth.saturating_sub(usize::from(rest.starts_with(b"</")));
            find(at + 1, b">")
        } else {
            // a start tag: find its '>' outside quotes; "/>" closes it at once
            let (mut j, mut quote) = (at + 1, None);
            while j < b.len() {
                match (quote, b[j]) {
                    (None, b'"' | b'\'') => quote = Some(b[j]),
                    (Some(q), c) if c == q => quote = None,
                    (None, b'>') => break,
                    _ => {}
                }
                j += 1;
            }
            if b.get(j.wrapping_sub(1)) != Some(&b'/') {
                depth += 1;
                if depth > limit {
                    return Some(1 + b[..at].iter().filter(|&&c| c == b'\n').count());
                }
            }
            j + 1
        };
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_depth_counts_elements_only() {
        let nested = |n: usize| format!("<robot>\n{}{}</robot>", "<a>".repeat(n), "</a>".repeat(n));
        assert_eq!(xml_nested_deeper_than(nested(99).as_bytes(), 100), None);
        assert_eq!(xml_nested_deeper_than(nested(100).as_bytes(), 100), Some(2));
        // siblings, empty elements, comments, CDATA, declarations and quoted '>' do not nest
        let flat = format!(
            "<?xml version=\"1.0\"?><!DOCTYPE robot><robot>{}<!-- {} --><![CDATA[{}]]><a b=\"/>\" c='>'>x</a></robot>",
            "<link name=\"x\"/><joint></joint>".repeat(500),
            "<a>".repeat(500),
            "<a>".repeat(500)
        );
        assert_eq!(xml_nested_deeper_than(flat.as_bytes(), 3), None);
        assert_eq!(xml_nested_deeper_than(b"<a><b><c><d>", 3), Some(1));
        assert_eq!(xml_nested_deeper_than(b"<a", 0), Some(1));
        assert_eq!(xml_nested_deeper_than(b"", 0), None);
    }

    #[test]
    fn sizes_read_as_people_write_them() {
        assert_eq!(size_text(MAX_URDF_BYTES), "16 MiB");
        assert_eq!(size_text(3 << 29), "1.5 GiB");
        assert_eq!(size_text(812), "812 bytes");
    }

    #[test]
    fn a_stream_is_read_up_to_its_cap_and_a_large_file_refused_unread() {
        let e = read_capped(Path::new("/dev/zero"), 1000, "a URDF")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("/dev/zero: a stream of more than the 1000 bytes a URDF may hold"),
            "{e}"
        );
        let e = read_file_capped(Path::new("/dev/zero"), 1000, "a mesh file")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "/dev/zero: is a character device, not a mesh file");
        let e = read_capped(Path::new("/"), 1000, "a URDF").unwrap_err().to_string();
        assert_eq!(e, "/: is a directory, not a URDF");
        let dir = std::env::temp_dir().join(format!("faze4-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("big");
        std::fs::write(&file, vec![b'x'; 2048]).unwrap();
        let e = read_capped(&file, 1024, "a motors file").unwrap_err().to_string();
        assert!(e.ends_with("big: 2 KiB (2048 bytes), more than the 1 KiB a motors file may hold (faze4 reads it whole; docs/development.md, Caps)"), "{e}");
        assert_eq!(read_capped(&file, 2048, "a motors file").unwrap().len(), 2048);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
