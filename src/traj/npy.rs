//! Joint trajectories as NumPy `.npy` files: N×dof arrays of float64 or float32, C or
//! Fortran order. Reading reports exactly what a bad file holds.

use std::io::Cursor;
use std::path::Path;

use ndarray::Array2;
use ndarray_npy::npy::header::Header;
use ndarray_npy::{ReadNpyExt, WriteNpyExt};

use crate::atomic::Outputs;
use crate::error::{Error, Result, one_line};
use crate::input::{MAX_NPY_BYTES, read_capped, size_text};

/// Reads an N×C array of samples (rows) from `path`: float64 or float32, any memory order,
/// N ≥ 2 rows, every value finite. At most [`MAX_NPY_BYTES`] are read (a stream too).
pub fn read_samples(path: &Path) -> Result<Vec<Vec<f64>>> {
    let bytes = read_capped(path, MAX_NPY_BYTES, "an .npy trajectory")?;
    parse_samples(&bytes, path)
}

/// [`read_samples`] on the bytes of a file; `path` names it in errors.
pub fn parse_samples(bytes: &[u8], path: &Path) -> Result<Vec<Vec<f64>>> {
    // ndarray-npy's messages can quote the header over several lines
    let bad = |message: String| Error::InvalidData {
        path: path.to_path_buf(),
        message: one_line(&message),
    };
    // ndarray-npy allocates what the file claims before reading it: check the claims against
    // the bytes there are first.
    if let Some((start, end)) = claimed_header(bytes) {
        if end > bytes.len() as u64 {
            return Err(bad(format!(
                "truncated: the header claims to end at byte {end}, the file has {} bytes",
                bytes.len()
            )));
        }
        // ndarray-npy's parser of the header's Python literal takes exponential time on nested
        // brackets (a 128-byte header took over 10 s); an array header nests 2 deep
        let depth = bracket_depth(&bytes[start as usize..end as usize]);
        if depth > MAX_HEADER_NESTING {
            return Err(bad(format!(
                "not a NumPy .npy array header: its brackets nest {depth} deep (an array's nest 2)"
            )));
        }
    }
    let mut cursor = Cursor::new(bytes);
    let header = Header::from_reader(&mut cursor).map_err(|e| bad(format!("not a NumPy .npy file ({e})")))?;
    let descr = header.type_descriptor.to_string();
    let found = || format!("dtype {descr}, shape {:?}", header.shape);
    if header.shape.len() != 2 {
        return Err(bad(format!(
            "expected a 2-D N×dof array of joint angles, found {}",
            found()
        )));
    }
    let (double, item_size) = match descr.trim_matches('\'') {
        "<f8" | ">f8" | "=f8" => (true, 8),
        "<f4" | ">f4" | "=f4" => (false, 4),
        _ => return Err(bad(format!("expected float64 or float32 values, found {}", found()))),
    };
    let available = bytes.len() as u64 - cursor.position();
    let needed = (header.shape.iter()).try_fold(item_size, |n: u64, &d| n.checked_mul(d as u64));
    if needed.is_none_or(|n| n > available) {
        return Err(bad(format!(
            "cannot read the {} data: it needs {} bytes, the file has {available} after the header",
            found(),
            needed.map_or("more than 2^64".into(), |n| n.to_string())
        )));
    }
    let data = |e: ndarray_npy::ReadNpyError| bad(format!("cannot read the {} data: {e}", found()));
    let array: Array2<f64> = match double {
        true => Array2::<f64>::read_npy(Cursor::new(bytes)).map_err(data)?,
        false => Array2::<f32>::read_npy(Cursor::new(bytes))
            .map_err(data)?
            .mapv(f64::from),
    };
    check_frames(array.view(), bad, found)
}

/// An N×dof array of joint positions given in memory (the Python binding's `q_traj`), checked
/// as [`read_samples`] checks a file's, `path` naming it in the messages.
pub fn samples_from_array(path: &Path, array: ndarray::ArrayView2<f64>) -> Result<Vec<Vec<f64>>> {
    let bad = |message: String| Error::InvalidData {
        path: path.to_path_buf(),
        message,
    };
    check_frames(array, bad, || format!("shape {:?}", array.shape()))
}

/// Refuses an array of `shape` given in memory (Python's `q_traj`, `t`, `v`, `a`; `name` names
/// it) whose float64 values a `.npy` file could not hold: more than [`MAX_NPY_BYTES`] of them
/// (docs/development.md, Caps). Checked before anything is copied: a 960 MB array took 11.4 GB
/// as a replay's frames (issue 49).
pub fn check_array_size(name: &Path, shape: &[usize]) -> Result<()> {
    match shape.iter().try_fold(8u64, |bytes, &n| bytes.checked_mul(n as u64)) {
        Some(bytes) if bytes <= MAX_NPY_BYTES => Ok(()),
        bytes => Err(Error::InvalidData {
            path: name.to_path_buf(),
            message: format!(
                "shape {shape:?}: {} of float64 values, more than the {} an .npy trajectory may hold (docs/development.md, Caps)",
                bytes.map_or("more than 16 EiB".into(), size_text),
                size_text(MAX_NPY_BYTES)
            ),
        }),
    }
}

/// At least 2 rows, a column, every value finite: the rows.
fn check_frames(
    array: ndarray::ArrayView2<f64>,
    bad: impl Fn(String) -> Error,
    found: impl Fn() -> String,
) -> Result<Vec<Vec<f64>>> {
    let (rows, columns) = array.dim();
    if rows < 2 {
        return Err(bad(format!("needs at least 2 frames (rows), found {}", found())));
    }
    if columns == 0 {
        return Err(bad(format!("has no columns ({})", found())));
    }
    if let Some(((r, c), v)) = array.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(bad(format!(
            "frame {r}, joint {} is {v}: every value must be finite",
            c + 1
        )));
    }
    Ok(array.rows().into_iter().map(|row| row.to_vec()).collect())
}

/// Deepest bracket nesting accepted in a header (an array's is 2: the dict and the shape).
const MAX_HEADER_NESTING: usize = 4;

/// Where the header text of `.npy` bytes starts and where the header says it ends (after the
/// magic string, version and header length field), if the bytes get as far as the length
/// field of a known version.
fn claimed_header(bytes: &[u8]) -> Option<(u64, u64)> {
    if bytes.get(..6)? != b"\x93NUMPY" {
        return None;
    }
    let (length_field, rest) = match bytes.get(6..8)? {
        [1, 0] => (2, bytes.get(8..10).map(|b| u16::from_le_bytes([b[0], b[1]]) as u64)?),
        [2 | 3, 0] => (
            4,
            bytes
                .get(8..12)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64)?,
        ),
        _ => return None,
    };
    Some((8 + length_field, 8 + length_field + rest))
}

/// The deepest nesting of `{`, `[`, `(` in `text`, outside quoted strings.
fn bracket_depth(text: &[u8]) -> usize {
    let (mut depth, mut deepest, mut quote) = (0usize, 0, None);
    for &c in text {
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, b'\'' | b'"') => quote = Some(c),
            (None, b'{' | b'[' | b'(') => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            (None, b'}' | b']' | b')') => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    deepest
}

/// Writes `rows` (N×C) as a float64 C-order `.npy` that NumPy loads, whole or not at all.
pub fn write_samples(path: &Path, rows: &[Vec<f64>]) -> Result<()> {
    write_samples_within(&Outputs::immediate(), path, rows)
}

/// [`write_samples`] as a file of `outputs` (it appears when they are committed).
pub fn write_samples_within(outputs: &Outputs, path: &Path, rows: &[Vec<f64>]) -> Result<()> {
    let columns = rows.first().map_or(0, Vec::len);
    let array = Array2::from_shape_vec((rows.len(), columns), rows.concat()).map_err(|e| Error::InvalidData {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut file = outputs.create(path)?;
    array.write_npy(file.writer()).map_err(|e| Error::InvalidData {
        path: path.to_path_buf(),
        message: format!("writing .npy: {e}"),
    })?;
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bracket_depth_ignores_quoted_brackets() {
        assert_eq!(
            bracket_depth(b"{'descr': '<f8', 'fortran_order': False, 'shape': (10, 6), }"),
            2
        );
        assert_eq!(bracket_depth(b"{'descr': '(((((', 'shape': (1,)}"), 2);
        assert_eq!(bracket_depth(b"{ ({ [ ("), 5);
    }

    #[test]
    fn round_trip_and_fortran_float32() {
        let dir = std::env::temp_dir().join(format!("faze4-npy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let rows = vec![vec![0.1, 0.2, 0.3], vec![0.4, 0.5, 0.6]];
        let p = dir.join("a.npy");
        write_samples(&p, &rows).unwrap();
        assert_eq!(read_samples(&p).unwrap(), rows);
        // float32, Fortran order
        let f = Array2::from_shape_vec((2, 3), vec![1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0])
            .unwrap()
            .reversed_axes();
        let f = f.as_standard_layout().reversed_axes().to_owned(); // 2x3 in Fortran memory order
        assert!(f.t().is_standard_layout());
        let p32 = dir.join("f.npy");
        f.write_npy(std::fs::File::create(&p32).unwrap()).unwrap();
        let back = read_samples(&p32).unwrap();
        assert_eq!(back[0].len(), f.ncols());
        for (r, row) in back.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                assert_eq!(*v, f64::from(f[(r, c)]));
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
