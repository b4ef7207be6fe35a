//! What a mesh file claims, checked against what it holds before the `mesh-loader` crate
//! allocates it, and its size against [`MAX_MESH_TRIANGLES`]: mesh-loader reserves what a
//! COLLADA count or offset says (an 834-byte file claiming 4 billion triangles asked for 48 GB,
//! an abort), recurses once per nested COLLADA `<node>` (100,000 of them overflowed the stack),
//! and reads a binary STL's triangles from the file's length whatever its header says. Each
//! check is linear in the file and allocates nothing per claim; the error is one line.

use std::borrow::Cow;

use crate::input::{MAX_COLLADA_NESTING, MAX_MESH_TRIANGLES, xml_nested_deeper_than};

/// The mesh formats faze4 reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// STL, binary or ASCII.
    Stl,
    /// COLLADA (`.dae`).
    Collada,
    /// Wavefront OBJ.
    Obj,
}

impl Format {
    /// The format a file name's extension (any case) gives, if any.
    pub fn of_extension(extension: Option<&str>) -> Option<Format> {
        match extension.map(str::to_ascii_lowercase).as_deref() {
            Some("stl") => Some(Format::Stl),
            Some("dae") => Some(Format::Collada),
            Some("obj") => Some(Format::Obj),
            _ => None,
        }
    }

    /// The format of contents whose name says none, as mesh-loader tells it: `solid` in the
    /// first 1,024 bytes is STL, `<COLLADA` there is COLLADA (an OBJ needs its extension).
    pub fn of_contents(bytes: &[u8]) -> Option<Format> {
        let head = &bytes[..bytes.len().min(1024)];
        let has = |needle: &[u8]| head.windows(needle.len()).any(|w| w == needle);
        match (has(b"solid"), has(b"<COLLADA")) {
            (true, _) => Some(Format::Stl),
            (false, true) => Some(Format::Collada),
            _ => None,
        }
    }
}

/// Text as mesh-loader decodes it (COLLADA and OBJ): a UTF-8 byte-order mark dropped, UTF-16
/// with its mark made UTF-8, UTF-32 refused; anything else as it is.
pub fn decode_text(bytes: &[u8]) -> Result<Cow<'_, [u8]>, String> {
    let utf16 = |rest: &[u8], unit: fn([u8; 2]) -> u16| {
        let units = rest.chunks_exact(2).map(|c| unit([c[0], c[1]]));
        char::decode_utf16(units)
            .collect::<Result<String, _>>()
            .map(|s| Cow::Owned(s.into_bytes()))
            .map_err(|e| format!("not UTF-16 text: {e}"))
    };
    if bytes.starts_with(&[0, 0, 0xFE, 0xFF]) || bytes.starts_with(&[0xFF, 0xFE, 0, 0]) {
        Err("UTF-32 text is not read (save it as UTF-8)".into())
    } else if let Some(rest) = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]) {
        Ok(Cow::Borrowed(rest))
    } else if let Some(rest) = bytes.strip_prefix(&[0xFE, 0xFF]) {
        utf16(rest, u16::from_be_bytes)
    } else if let Some(rest) = bytes.strip_prefix(&[0xFF, 0xFE]) {
        utf16(rest, u16::from_le_bytes)
    } else {
        Ok(Cow::Borrowed(bytes))
    }
}

/// Checks what the file claims against what it holds (see the module's documentation).
pub fn check(format: Format, bytes: &[u8]) -> Result<(), String> {
    match format {
        Format::Stl => check_stl(bytes),
        Format::Collada => check_collada(bytes),
        Format::Obj => check_obj(bytes),
    }
}

/// Bytes of a binary STL's header (80) and triangle count (4).
const STL_HEADER: u64 = 84;
/// Bytes of one binary STL triangle.
const STL_TRIANGLE: u64 = 50;

/// Whether STL `bytes` are ASCII STL: `solid` first (after blank space) and nothing but ASCII
/// after the first line (binary files whose header starts with `solid`, as SolidWorks writes
/// them, hold float bytes ≥ 0x80 in any real mesh).
fn is_ascii_stl(bytes: &[u8]) -> bool {
    let text = bytes.trim_ascii_start();
    let after_first_line = text.iter().position(|&c| c == b'\n').map_or(&[][..], |n| &text[n..]);
    text.starts_with(b"solid") && after_first_line.is_ascii()
}

/// A binary STL's length must be its header's: 84 + 50 × the triangle count (one trailing line
/// break tolerated, as mesh-loader does); the count at most [`MAX_MESH_TRIANGLES`]. An ASCII
/// STL holds what it spells out (about 100 bytes a triangle, so the file cap bounds it).
fn check_stl(bytes: &[u8]) -> Result<(), String> {
    if is_ascii_stl(bytes) || bytes.len() < STL_HEADER as usize {
        return Ok(()); // too short: mesh-loader's own error
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    let length = bytes.len() as u64;
    let claimed = STL_HEADER + STL_TRIANGLE * count;
    let newline = bytes.ends_with(b"\r\n") as u64 + bytes.ends_with(b"\n") as u64;
    if length != claimed && length - newline != claimed {
        let body = length - STL_HEADER;
        let worth = match body % STL_TRIANGLE {
            0 => format!("{} triangles' worth", body / STL_TRIANGLE),
            r => format!("{} triangles' worth and {r} bytes", body / STL_TRIANGLE),
        };
        return Err(format!(
            "binary STL: its header says {count} triangles ({claimed} bytes), the file has {length} bytes ({worth}): truncated, or more than one mesh"
        ));
    }
    too_many_triangles(count)
}

/// The error of a mesh of more than [`MAX_MESH_TRIANGLES`] triangles.
fn too_many_triangles(count: u64) -> Result<(), String> {
    match count > MAX_MESH_TRIANGLES {
        true => Err(format!(
            "{count} triangles, more than the {MAX_MESH_TRIANGLES} a mesh file may hold (docs/development.md, Caps): simplify it"
        )),
        false => Ok(()),
    }
}

/// COLLADA: nesting at most [`MAX_COLLADA_NESTING`] deep; every count mesh-loader reserves
/// (an array's `count`, a primitive's `count` times its indices per primitive times its
/// inputs' stride, a `<polylist>`'s `<vcount>` sum) at most the values present; at most
/// [`MAX_MESH_TRIANGLES`] triangles in all. Text that is not UTF-8 or not XML is left to
/// mesh-loader's own error.
fn check_collada(bytes: &[u8]) -> Result<(), String> {
    if let Some(line) = xml_nested_deeper_than(bytes, MAX_COLLADA_NESTING) {
        return Err(format!(
            "COLLADA: elements nest more than {MAX_COLLADA_NESTING} deep (line {line}; docs/development.md, Caps)"
        ));
    }
    let Ok(text) = std::str::from_utf8(bytes) else {
        return Ok(());
    };
    let Ok(doc) = roxmltree::Document::parse(text) else {
        return Ok(());
    };
    let mut triangles = 0u64;
    for e in doc.descendants().filter(|n| n.is_element()) {
        let name = e.tag_name().name();
        let at = || format!("COLLADA line {}: <{name}>", doc.text_pos_at(e.range().start).row);
        let count = || e.attribute("count").and_then(|c| c.trim().parse::<u64>().ok());
        if name.ends_with("_array") {
            if let Some(count) = count()
                && count > values(e)
            {
                return Err(format!("{} claims {count} values, holds {}", at(), values(e)));
            }
            continue;
        }
        let per_primitive = match name {
            "triangles" => Some(3),
            "lines" => Some(2),
            "polylist" | "polygons" | "trifans" | "tristrips" | "linestrips" => None,
            _ => continue,
        };
        let Some(count) = count() else { continue };
        // each vertex of a primitive takes one index per input offset
        let stride = (e.children().filter(|c| c.has_tag_name("input")))
            .filter_map(|i| i.attribute("offset").and_then(|o| o.trim().parse::<u64>().ok()))
            .map(|o| o + 1)
            .max()
            .unwrap_or(0);
        let child = |tag: &str| e.children().find(|c| c.has_tag_name(tag));
        let indices = child("p").map_or(0, values);
        let vertices = match (name, per_primitive) {
            (_, Some(k)) => count.checked_mul(k),
            ("polylist", _) => {
                let vcount = child("vcount");
                let listed = vcount.map_or(0, values);
                if vcount.is_some() && count > listed {
                    return Err(format!("{} claims {count} polygons, its <vcount> lists {listed}", at()));
                }
                let sizes = vcount.and_then(|v| v.text()).unwrap_or("").split_ascii_whitespace();
                let sizes = sizes.take(count as usize).map(|s| s.parse::<u64>().unwrap_or(0));
                triangles += sizes.clone().map(|s| s.saturating_sub(2)).sum::<u64>();
                Some(sizes.fold(0u64, u64::saturating_add))
            }
            _ => {
                // one <p> per polygon
                let polygons = e.children().filter(|c| c.has_tag_name("p")).count() as u64;
                if count > polygons {
                    return Err(format!("{} claims {count} polygons, holds {polygons}", at()));
                }
                triangles = triangles.saturating_add(count);
                continue;
            }
        };
        if child("p").is_none() {
            continue;
        }
        let needed = vertices.and_then(|v| v.checked_mul(stride));
        if needed.is_none_or(|n| n > indices) {
            return Err(format!(
                "{} claims {} indices ({count} primitives, {stride} per vertex), its <p> holds {indices}",
                at(),
                needed.map_or("more than 2^64".to_string(), |n| n.to_string())
            ));
        }
        if name == "triangles" {
            triangles = triangles.saturating_add(count);
        }
    }
    too_many_triangles(triangles)
}

/// The number of values (blank-separated words) in element `e`'s text.
fn values(e: roxmltree::Node) -> u64 {
    e.text().map_or(0, |t| t.split_ascii_whitespace().count() as u64)
}

/// OBJ: every face's vertex references in range (a reference counts from 1, or back from the
/// vertices read so far when negative), said with the file's own number and line; at most
/// [`MAX_MESH_TRIANGLES`] triangles (a face of k corners makes k − 2) and three times as many
/// vertices. A word that is not a number is left to mesh-loader's error.
fn check_obj(bytes: &[u8]) -> Result<(), String> {
    let mut vertices = 0u64;
    let mut triangles = 0u64;
    // the largest positive reference and its line: checked once every vertex is counted
    let mut furthest: Option<(i64, usize)> = None;
    for (k, line) in bytes.split(|&c| c == b'\n').enumerate() {
        let line = line.trim_ascii_start();
        let mut words = line.split(|c| c.is_ascii_whitespace()).filter(|w| !w.is_empty());
        match words.next() {
            Some(b"v") => vertices += 1,
            Some(b"f") => {
                let mut corners = 0u64;
                for word in words {
                    corners += 1;
                    let index = word.split(|&c| c == b'/').next().unwrap_or_default();
                    let Some(i) = std::str::from_utf8(index).ok().and_then(|i| i.parse::<i64>().ok()) else {
                        continue;
                    };
                    if i == 0 || (i < 0 && i.unsigned_abs() > vertices) {
                        return Err(format!(
                            "OBJ line {}: a face refers to vertex {i}, with {vertices} vertices before it{}",
                            k + 1,
                            if i == 0 { " (references count from 1)" } else { "" }
                        ));
                    }
                    if i > 0 && furthest.is_none_or(|(f, _)| i > f) {
                        furthest = Some((i, k + 1));
                    }
                }
                triangles += corners.saturating_sub(2);
            }
            _ => {}
        }
    }
    if let Some((i, line)) = furthest
        && i as u64 > vertices
    {
        return Err(format!(
            "OBJ line {line}: a face refers to vertex {i}, the file has {vertices} vertices"
        ));
    }
    if vertices > 3 * MAX_MESH_TRIANGLES {
        return Err(format!(
            "{vertices} vertices, more than the {} a mesh file may hold (docs/development.md, Caps): simplify it",
            3 * MAX_MESH_TRIANGLES
        ));
    }
    too_many_triangles(triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_binary_stl_is_as_long_as_its_header_says() {
        let mut stl = vec![0u8; 84 + 2 * 50];
        stl[80] = 2;
        assert_eq!(check_stl(&stl), Ok(()));
        stl.push(b'\n');
        assert_eq!(
            check_stl(&stl),
            Ok(()),
            "a trailing line break, as mesh-loader takes it"
        );
        stl[80] = 3;
        let e = check_stl(&stl).unwrap_err();
        assert_eq!(
            e,
            "binary STL: its header says 3 triangles (234 bytes), the file has 185 bytes (2 triangles' worth and 1 bytes): truncated, or more than one mesh"
        );
        stl[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(check_stl(&stl).unwrap_err().contains("4294967295 triangles"));
        assert_eq!(check_stl(b"solid x\nfacet normal 0 0 1\n"), Ok(()), "ASCII");
    }

    #[test]
    fn collada_claims_beyond_the_values_present_are_refused() {
        let triangles = |count: &str, offset: &str, p: &str| {
            format!(
                r##"<COLLADA><library_geometries><geometry><mesh><triangles count="{count}"><input semantic="VERTEX" source="#v" offset="{offset}"/><p>{p}</p></triangles></mesh></geometry></library_geometries></COLLADA>"##
            )
        };
        assert_eq!(check_collada(triangles("1", "0", "0 1 2").as_bytes()), Ok(()));
        let e = check_collada(triangles("4000000000", "0", "0 1 2").as_bytes()).unwrap_err();
        assert_eq!(
            e,
            "COLLADA line 1: <triangles> claims 12000000000 indices (4000000000 primitives, 1 per vertex), its <p> holds 3"
        );
        let e = check_collada(triangles("1", "4000000000", "0 1 2").as_bytes()).unwrap_err();
        assert!(e.contains("4000000001 per vertex"), "{e}");
        let array = r#"<COLLADA><float_array count="4000000000">0 1 2</float_array></COLLADA>"#;
        assert_eq!(
            check_collada(array.as_bytes()).unwrap_err(),
            "COLLADA line 1: <float_array> claims 4000000000 values, holds 3"
        );
        let polylist = r#"<COLLADA><polylist count="1"><input offset="0"/><vcount>4000000000</vcount><p>0 1 2</p></polylist></COLLADA>"#;
        assert!(
            check_collada(polylist.as_bytes())
                .unwrap_err()
                .contains("claims 4000000000 indices")
        );
        let polygons = r#"<COLLADA><polygons count="4000000000"><input offset="0"/><p>0 1 2</p></polygons></COLLADA>"#;
        assert!(
            check_collada(polygons.as_bytes())
                .unwrap_err()
                .contains("claims 4000000000 polygons, holds 1")
        );
        let deep = format!(
            "<COLLADA>{}{}</COLLADA>",
            "<node>".repeat(100_000),
            "</node>".repeat(100_000)
        );
        assert!(
            check_collada(deep.as_bytes())
                .unwrap_err()
                .contains("nest more than 256 deep")
        );
    }

    #[test]
    fn obj_references_are_said_as_the_file_writes_them() {
        let obj = |f: &str| format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf {f}\n");
        assert_eq!(check_obj(obj("1 2 3").as_bytes()), Ok(()));
        assert_eq!(check_obj(obj("-3 -2 -1").as_bytes()), Ok(()));
        assert_eq!(
            check_obj(obj("1 2 -99999").as_bytes()).unwrap_err(),
            "OBJ line 4: a face refers to vertex -99999, with 3 vertices before it"
        );
        assert_eq!(
            check_obj(obj("1/1/1 2 4").as_bytes()).unwrap_err(),
            "OBJ line 4: a face refers to vertex 4, the file has 3 vertices"
        );
        assert!(check_obj(obj("0 1 2").as_bytes()).unwrap_err().contains("count from 1"));
    }

    #[test]
    fn formats_by_name_or_contents() {
        assert_eq!(Format::of_extension(Some("STL")), Some(Format::Stl));
        assert_eq!(Format::of_extension(Some("txt")), None);
        assert_eq!(Format::of_contents(b"<?xml?><COLLADA>"), Some(Format::Collada));
        assert_eq!(Format::of_contents(b"hello"), None);
        assert_eq!(decode_text(b"\xEF\xBB\xBFv 1").unwrap().as_ref(), b"v 1");
        assert_eq!(decode_text(b"\xFF\xFEv\0 \x001\0").unwrap().as_ref(), b"v 1");
    }
}
