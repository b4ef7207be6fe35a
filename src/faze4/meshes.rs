//! The official Faze4 link meshes, built into the binary, so that the real arm is drawn with no
//! file around (an installed `faze4` run in any folder).
//!
//! `build.rs` reads `assets/faze4_description/meshes/<link>.STL` at build time and stores each
//! as a welded indexed mesh: the distinct corner positions, exactly the file's f32 coordinates
//! (no quantisation), and three indices per triangle (16-bit: every mesh has fewer than 65,536
//! vertices). Every triangle of the file is kept, in file order, so [`IndexedMesh::corners`]
//! gives back the file's triangles bit for bit (a test checks it against the STL reader). The
//! six meshes take 12 bytes per vertex and 6 per triangle in the binary.
//!
//! A reference to one of them in a URDF, `package://faze4_description/meshes/<link>.STL` (our
//! URDFs) or `package://Final_light_assembly_URDF/meshes/<link>.STL` (the official one), falls
//! back to the built-in copy when the file is not found on disk ([`for_uri`]).

/// A mesh as `build.rs` wrote it (see the module documentation).
struct EmbeddedMesh {
    /// The link name, which is the file name without `.STL`.
    name: &'static str,
    /// Number of vertices.
    vertices: usize,
    /// Number of triangles.
    triangles: usize,
    /// Bytes per index: 2 or 4.
    index_bytes: usize,
    /// Positions (3 f32 per vertex), then indices (3 per triangle), little-endian.
    bytes: &'static [u8],
    /// Its triangles' hierarchy (see [`hierarchy`]).
    bvh: &'static [u8],
}

const MESHES: &[EmbeddedMesh] = include!(concat!(env!("OUT_DIR"), "/meshes.rs"));

/// The package names under which URDFs refer to the official meshes: ours, and the official
/// URDF's (`Final_light_assembly_URDF.urdf`).
pub const PACKAGES: [&str; 2] = ["faze4_description", "Final_light_assembly_URDF"];

/// An indexed triangle mesh with the exact vertex coordinates of its STL file (f32, metres, in
/// the link's frame).
#[derive(Clone, Debug, PartialEq)]
pub struct IndexedMesh {
    /// Distinct vertex positions, in order of first appearance in the file.
    pub positions: Vec<[f32; 3]>,
    /// Three indices into `positions` per triangle, the file's triangles in file order
    /// (degenerate ones included).
    pub indices: Vec<u32>,
}

impl IndexedMesh {
    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// The triangles as the file lists them: three corners per triangle.
    pub fn corners(&self) -> Vec<[f32; 3]> {
        self.indices.iter().map(|&i| self.positions[i as usize]).collect()
    }
}

/// The names of the built-in meshes (link names, sorted).
pub fn names() -> impl Iterator<Item = &'static str> {
    MESHES.iter().map(|m| m.name)
}

/// Bytes the built-in meshes take in the binary.
pub fn embedded_bytes() -> usize {
    MESHES.iter().map(|m| m.bytes.len()).sum()
}

/// The built-in mesh of link `name` (e.g. `lakat`), decoded.
pub fn mesh(name: &str) -> Option<IndexedMesh> {
    let m = MESHES.iter().find(|m| m.name == name)?;
    let (positions, indices) = m.bytes.split_at(12 * m.vertices);
    let f32_at = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    let positions = positions
        .chunks_exact(12)
        .map(|p| [f32_at(&p[0..]), f32_at(&p[4..]), f32_at(&p[8..])])
        .collect();
    let indices: Vec<u32> = match m.index_bytes {
        2 => indices
            .chunks_exact(2)
            .map(|i| u16::from_le_bytes([i[0], i[1]]) as u32)
            .collect(),
        _ => indices
            .chunks_exact(4)
            .map(|i| u32::from_le_bytes([i[0], i[1], i[2], i[3]]))
            .collect(),
    };
    debug_assert_eq!(indices.len(), 3 * m.triangles);
    Some(IndexedMesh { positions, indices })
}

/// The built-in mesh a URDF mesh reference names, if it is one of them:
/// `package://P/meshes/<link>.STL` with P one of [`PACKAGES`].
pub fn for_uri(uri: &str) -> Option<IndexedMesh> {
    mesh(name_of(uri)?)
}

/// Whether `uri` names one of the built-in meshes ([`for_uri`] would give it), without
/// decoding it.
pub fn is_built_in(uri: &str) -> bool {
    name_of(uri).is_some()
}

/// The name of the built-in mesh `package://P/meshes/<link>.STL` names (P one of
/// [`PACKAGES`]), if it is one.
pub fn name_of(uri: &str) -> Option<&'static str> {
    let (package, file) = uri.strip_prefix("package://")?.split_once("/meshes/")?;
    PACKAGES.contains(&package).then_some(())?;
    let name = file.strip_suffix(".STL")?;
    MESHES.iter().find(|m| m.name == name).map(|m| m.name)
}

/// The bounding-volume hierarchy `build.rs` made of built-in mesh `name`'s triangles (as
/// [`crate::geometry::mesh::Mesh::from_indexed`] gives them), in the form
/// `geometry::bvh`'s `Bvh::to_bytes` writes.
pub fn hierarchy(name: &str) -> Option<&'static [u8]> {
    MESHES.iter().find(|m| m.name == name).map(|m| m.bvh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mesh::triangle_corners;
    use std::collections::HashSet;

    const LINKS: [&str; 6] = ["hvataljka", "lakat", "nadlaktica", "podlaktica", "rotary_base", "saka"];

    #[test]
    fn built_in_meshes_are_the_stl_files_bit_for_bit() {
        assert_eq!(names().collect::<Vec<_>>(), LINKS);
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/faze4_description/meshes");
        for link in LINKS {
            let path = dir.join(format!("{link}.STL"));
            let (file, _) = triangle_corners(&std::fs::read(&path).unwrap(), &path, |p: &std::path::Path| {
                std::fs::read(p)
            })
            .unwrap();
            let built_in = mesh(link).unwrap();
            // the loader's shortcut welds it as the file's soup would be
            assert_eq!(
                crate::geometry::mesh::Mesh::from_indexed(&built_in.positions, &built_in.indices),
                crate::geometry::mesh::Mesh::from_soup(&built_in.corners()),
                "{link}"
            );
            let bits = |corners: &[[f32; 3]]| corners.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&built_in.corners()), bits(&file), "{link}: the file's triangles");
            // welded: one vertex per distinct position
            let distinct: HashSet<[u32; 3]> = bits(&file).into_iter().collect();
            assert_eq!(built_in.positions.len(), distinct.len(), "{link}");
            assert!(
                built_in.positions.len() < built_in.triangles(),
                "{link}: shared vertices"
            );
        }
        // 12 bytes per vertex, 6 per triangle
        let size: usize = LINKS
            .map(|l| mesh(l).unwrap())
            .iter()
            .map(|m| 12 * m.positions.len() + 6 * m.triangles())
            .sum();
        assert_eq!(embedded_bytes(), size);
    }

    #[test]
    fn references_to_the_official_meshes_find_them() {
        let lakat = mesh("lakat").unwrap();
        for package in PACKAGES {
            assert_eq!(
                for_uri(&format!("package://{package}/meshes/lakat.STL")).as_ref(),
                Some(&lakat)
            );
        }
        for other in [
            "package://my_arm/meshes/lakat.STL",
            "package://faze4_description/meshes/base_link.STL",
            "package://faze4_description/meshes/lakat.stl",
            "package://faze4_description/lakat.STL",
            "meshes/lakat.STL",
            "/faze4_description/meshes/lakat.STL",
        ] {
            assert_eq!(for_uri(other), None, "{other}");
        }
    }
}
