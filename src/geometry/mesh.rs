//! Triangle meshes as files hold them: STL (binary and ASCII) → exact f32 vertices, welded,
//! with three indices per triangle. [`read_mesh`] is the one place a mesh file is read.

use std::collections::HashMap;
use std::path::Path;

use crate::error::{Error, Result};

/// An indexed triangle mesh: the file's exact f32 vertices (metres, in the mesh's own frame),
/// identical positions welded into one vertex, and three vertex indices per triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Distinct vertex positions (m).
    pub vertices: Vec<[f32; 3]>,
    /// Three indices into `vertices` per triangle; no triangle repeats an index.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Indexes a triangle soup (three corners per triangle): bit-identical positions become one
    /// vertex (`-0.0` and `0.0` are the same point), and triangles whose corners weld together
    /// (zero area by repetition) are dropped. Coordinates are kept exactly.
    pub fn from_soup(corners: &[[f32; 3]]) -> Mesh {
        let key = |p: &[f32; 3]| [(p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits(), (p[2] + 0.0).to_bits()];
        let mut welded: HashMap<[u32; 3], u32> = HashMap::with_capacity(corners.len() / 3);
        let mut mesh = Mesh {
            vertices: Vec::with_capacity(corners.len() / 3),
            triangles: Vec::with_capacity(corners.len() / 3),
        };
        for c in corners.chunks_exact(3) {
            let t = [0, 1, 2].map(|k| {
                *welded.entry(key(&c[k])).or_insert_with(|| {
                    mesh.vertices.push(c[k]);
                    (mesh.vertices.len() - 1) as u32
                })
            });
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                mesh.triangles.push(t);
            }
        }
        mesh
    }

    /// The triangle corners again, three per triangle (the soup this mesh indexes).
    pub fn soup(&self) -> Vec<[f32; 3]> {
        (self.triangles.iter())
            .flat_map(|t| t.map(|i| self.vertices[i as usize]))
            .collect()
    }
}

/// Reads the mesh file at `path` (STL, binary or ASCII) into a welded indexed [`Mesh`]. Every
/// mesh faze4 uses, for drawing or for distances, is read here.
///
/// Errors: [`Error::Io`] if the file cannot be read, [`Error::InvalidData`] if it is not an STL,
/// [`Error::MeshNotFinite`] for a NaN or infinite coordinate, [`Error::MeshEmpty`] if no
/// triangle of non-zero extent remains.
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_mesh(&bytes, path)
}

/// The mesh a URDF mesh reference stands for: the file it resolved to (`path`), read by
/// [`read_mesh`], else the copy built into the binary when `uri` names one of the official
/// Faze4 meshes ([`crate::faze4::meshes::for_uri`]); `None` when there is neither. Every mesh
/// reference, visual or collision, is loaded here.
pub fn load(uri: &str, path: Option<&Path>) -> Option<Result<Mesh>> {
    match path {
        Some(path) => Some(read_mesh(path)),
        None => crate::faze4::meshes::for_uri(uri).map(|mesh| Ok(Mesh::from_soup(&mesh.corners()))),
    }
}

/// [`read_mesh`] on a file's contents already in memory; `path` names it in errors.
pub fn parse_mesh(bytes: &[u8], path: &Path) -> Result<Mesh> {
    let soup = parse_stl(bytes).map_err(|message| Error::InvalidData {
        path: path.to_path_buf(),
        message,
    })?;
    if let Some(i) = soup.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(Error::MeshNotFinite {
            path: path.to_path_buf(),
            triangle: i / 3,
        });
    }
    let mesh = Mesh::from_soup(&soup);
    if mesh.triangles.is_empty() {
        return Err(Error::MeshEmpty {
            path: path.to_path_buf(),
        });
    }
    Ok(mesh)
}

/// The triangle corners of an STL file's contents (three per triangle), exactly as stored.
/// Binary when the size matches the triangle count in the header (SolidWorks writes binary
/// files that start with "solid"), ASCII when the text starts with `solid`. Non-finite
/// coordinates are passed through (see [`parse_mesh`]).
pub fn parse_stl(bytes: &[u8]) -> std::result::Result<Vec<[f32; 3]>, String> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len()) {
            let mut soup = Vec::with_capacity(3 * n);
            for t in bytes[84..].chunks_exact(50) {
                for k in 0..3 {
                    let o = 12 + 12 * k;
                    let f = |i: usize| f32::from_le_bytes([t[o + i], t[o + i + 1], t[o + i + 2], t[o + i + 3]]);
                    soup.push([f(0), f(4), f(8)]);
                }
            }
            return Ok(soup);
        }
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|_| "neither a binary STL (size does not match its triangle count) nor ASCII text".to_string())?;
    if !text.trim_start().starts_with("solid") {
        return Err(
            "neither a binary STL (size does not match its triangle count) nor an ASCII STL (no 'solid')".into(),
        );
    }
    let mut soup = Vec::new();
    let mut words = text.split_ascii_whitespace();
    while let Some(w) = words.next() {
        if w == "vertex" {
            let mut p = [0.0f32; 3];
            for c in &mut p {
                let word = words.next().ok_or("a 'vertex' with fewer than 3 numbers")?;
                *c = word
                    .parse()
                    .map_err(|_| format!("'vertex' coordinate '{word}' is not a number"))?;
            }
            soup.push(p);
        }
    }
    if soup.len() % 3 != 0 {
        return Err(format!("{} vertices: not a whole number of triangles", soup.len()));
    }
    Ok(soup)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A unit cube centred on the origin as 12 triangles (36 corners), outward winding.
    pub(crate) fn cube_soup() -> Vec<[f32; 3]> {
        let mut soup = Vec::new();
        for (axis, sign) in [(0, 1.0f32), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f32, b: f32| {
                let mut p = [0.0; 3];
                p[axis] = sign * 0.5;
                p[u] = a * 0.5 * sign;
                p[w] = b * 0.5;
                p
            };
            let q = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            soup.extend([q[0], q[1], q[2], q[0], q[2], q[3]]);
        }
        soup
    }

    pub(crate) fn binary_stl(soup: &[[f32; 3]], header: &[u8]) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b[..header.len()].copy_from_slice(header);
        b.extend((soup.len() as u32 / 3).to_le_bytes());
        for t in soup.chunks(3) {
            b.extend([0u8; 12]); // facet normal, ignored
            for p in t {
                for c in p {
                    b.extend(c.to_le_bytes());
                }
            }
            b.extend([0u8; 2]);
        }
        b
    }

    fn ascii_stl(soup: &[[f32; 3]]) -> String {
        let mut s = String::from("solid cube\n");
        for t in soup.chunks(3) {
            s += "  facet normal 0 0 0\n    outer loop\n";
            for p in t {
                s += &format!("      vertex {:e} {} {}\n", p[0], p[1], p[2]);
            }
            s += "    endloop\n  endfacet\n";
        }
        s + "endsolid cube\n"
    }

    #[test]
    fn binary_and_ascii_stl_give_the_same_welded_cube() {
        let soup = cube_soup();
        let here = Path::new("cube.stl");
        // a binary file whose header starts with "solid", as SolidWorks writes them
        let bin = parse_mesh(&binary_stl(&soup, b"solid SolidWorks export"), here).unwrap();
        let txt = parse_mesh(ascii_stl(&soup).as_bytes(), here).unwrap();
        assert_eq!(bin, txt);
        assert_eq!(bin.vertices.len(), 8, "each corner welded once");
        assert_eq!(bin.triangles.len(), 12);
        assert_eq!(bin.soup(), soup, "exact coordinates, same order");
    }

    #[test]
    fn welding_drops_collapsed_triangles_and_merges_signed_zeros() {
        let soup = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [-0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mesh = Mesh::from_soup(&soup);
        assert_eq!(mesh.vertices.len(), 3);
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn malformed_stl_is_refused_with_a_reason() {
        let here = Path::new("bad.stl");
        let e = parse_mesh(b"hello", here).unwrap_err().to_string();
        assert!(e.starts_with("bad.stl: neither"), "{e}");
        let e = parse_stl(b"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 zero\n").unwrap_err();
        assert!(e.contains("'zero'"), "{e}");
        let e = parse_stl(b"solid x\n vertex 0 0 0\n vertex 1 0 0\n endsolid").unwrap_err();
        assert!(e.contains("whole number"), "{e}");
        let mut bin = binary_stl(&cube_soup(), b"");
        bin[84 + 50 + 12..84 + 50 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(matches!(
            parse_mesh(&bin, here),
            Err(Error::MeshNotFinite { triangle: 1, .. })
        ));
        assert!(matches!(
            parse_mesh(b"solid empty\nendsolid empty\n", here),
            Err(Error::MeshEmpty { .. })
        ));
        let collapsed = binary_stl(&[[1.0, 2.0, 3.0]; 3], b"");
        assert!(matches!(parse_mesh(&collapsed, here), Err(Error::MeshEmpty { .. })));
    }
}
