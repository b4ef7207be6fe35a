//! Builds the official Faze4 meshes into the binary (see `src/faze4/meshes.rs`, which decodes them).
//!
//! For each `assets/faze4_description/meshes/<name>.STL` (binary STL), writes `<name>.mesh` into
//! `OUT_DIR`: the mesh welded into an indexed mesh without changing any coordinate. Vertices are the
//! distinct corner positions (compared bit for bit, so `-0.0` and `0.0` stay apart), in order of
//! first appearance; every triangle of the file is kept, degenerate ones included, so that the
//! file's triangles come back exactly (the STL's facet normals and attribute bytes are dropped:
//! nothing reads them). Layout, little-endian: positions, 3 f32 per vertex (m); then indices, 3
//! per triangle, u16 when the mesh has at most 65,536 vertices, else u32. `meshes.rs` (also in
//! `OUT_DIR`) lists them: name, vertex count, triangle count, index width and the bytes.
//!
//! And `<name>.bvh`: the bounding-volume hierarchy of the mesh's triangles as the collision
//! loader reads them (`geometry::mesh::Mesh::from_indexed`: positions welded again with `-0.0`
//! as `0.0`, triangles whose corners weld together dropped), built by `src/geometry/bvh.rs`
//! (included below), as its `Bvh::to_bytes` writes it, followed by the convex hulls of its upper
//! nodes made by `src/geometry/node_hulls.rs` (included below, with parry as a build dependency)
//! as its `NodeHulls::to_bytes` writes them. The loader checks the hierarchy against the
//! triangles before it uses it (`Bvh::from_bytes`), and of the hulls only that their indices are
//! in range (`NodeHulls::from_bytes`): they are made here of the same triangles by the same
//! code, and a test checks that they equal the hulls made at run time.

#[allow(dead_code)]
#[path = "src/geometry/bvh.rs"]
mod bvh;
#[allow(dead_code)]
#[path = "src/geometry/hull.rs"]
mod hull;
#[allow(dead_code)]
#[path = "src/geometry/node_hulls.rs"]
mod node_hulls;

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

const MESH_DIR: &str = "assets/faze4_description/meshes";

fn main() {
    println!("cargo::rerun-if-changed={MESH_DIR}");
    for source in ["bvh", "hull", "node_hulls"] {
        println!("cargo::rerun-if-changed=src/geometry/{source}.rs");
    }
    let out_dir = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    let mut files: Vec<_> = std::fs::read_dir(MESH_DIR)
        .unwrap_or_else(|e| panic!("{MESH_DIR}: {e}"))
        .map(|entry| entry.expect("readable directory").path())
        .filter(|p| p.extension().is_some_and(|e| e == "STL"))
        .collect();
    files.sort();
    let mut table = String::from("&[\n");
    for file in &files {
        println!("cargo::rerun-if-changed={}", file.display());
        let name = file.file_stem().unwrap().to_str().expect("UTF-8 mesh name");
        let bytes = std::fs::read(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let (positions, indices) = weld(&binary_stl_corners(&bytes, file));
        let wide = positions.len() > 1 << 16;
        let mut blob = Vec::with_capacity(12 * positions.len() + 4 * indices.len());
        blob.extend(positions.iter().flatten().flat_map(|c| c.to_le_bytes()));
        for &i in &indices {
            match wide {
                true => blob.extend(i.to_le_bytes()),
                false => blob.extend((i as u16).to_le_bytes()),
            }
        }
        let blob_path = Path::new(&out_dir).join(format!("{name}.mesh"));
        std::fs::write(&blob_path, blob).unwrap_or_else(|e| panic!("{}: {e}", blob_path.display()));
        let (points, triangles) = as_loaded(&positions, &indices);
        let bvh_path = Path::new(&out_dir).join(format!("{name}.bvh"));
        let bvh = bvh::Bvh::build(&points, &triangles);
        let vectors: Vec<_> = points
            .iter()
            .map(|&p| parry3d_f64::math::Vector::from_array(p))
            .collect();
        let hulls = node_hulls::NodeHulls::new(&bvh).to_bytes(&bvh, &vectors, &triangles);
        let mut bytes = bvh.to_bytes();
        bytes.extend(hulls);
        std::fs::write(&bvh_path, bytes).unwrap_or_else(|e| panic!("{}: {e}", bvh_path.display()));
        writeln!(
            table,
            "    EmbeddedMesh {{ name: {name:?}, vertices: {}, triangles: {}, index_bytes: {}, \
             bytes: include_bytes!(concat!(env!(\"OUT_DIR\"), \"/{name}.mesh\")), \
             bvh: include_bytes!(concat!(env!(\"OUT_DIR\"), \"/{name}.bvh\")) }},",
            positions.len(),
            indices.len() / 3,
            if wide { 4 } else { 2 },
        )
        .unwrap();
    }
    table.push(']');
    let table_path = Path::new(&out_dir).join("meshes.rs");
    std::fs::write(&table_path, table).unwrap_or_else(|e| panic!("{}: {e}", table_path.display()));
}

/// The triangle corners (three per triangle) of a binary STL: 80-byte header, u32 triangle count,
/// then per triangle a normal, three corners (3 f32 each) and two attribute bytes.
fn binary_stl_corners(bytes: &[u8], file: &Path) -> Vec<[f32; 3]> {
    let count = bytes
        .get(80..84)
        .map(|b| u32::from_le_bytes(b.try_into().unwrap()) as usize);
    assert!(
        count.is_some_and(|n| bytes.len() == 84 + 50 * n),
        "{}: not a binary STL (its size does not match its triangle count)",
        file.display()
    );
    let f32_at = |t: &[u8], o: usize| f32::from_le_bytes(t[o..o + 4].try_into().unwrap());
    bytes[84..]
        .chunks_exact(50)
        .flat_map(|t| (0..3).map(move |k| [0, 4, 8].map(|c| f32_at(t, 12 + 12 * k + c))))
        .collect()
}

/// Identical corners (bit for bit) become one vertex: the distinct positions in order of first
/// appearance, and one index per corner.
fn weld(corners: &[[f32; 3]]) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut index_of: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let indices = corners
        .iter()
        .map(|p| {
            *index_of.entry(p.map(f32::to_bits)).or_insert_with(|| {
                positions.push(*p);
                (positions.len() - 1) as u32
            })
        })
        .collect();
    (positions, indices)
}

/// The points (f64) and triangles of the welded mesh `positions`, `indices` as the collision
/// loader reads it (`geometry::mesh::Mesh::from_indexed`, at scale 1): each position welded
/// with the bit-identical ones (`-0.0` as `0.0`) on first use, in order, and the triangles
/// whose corners weld together dropped.
fn as_loaded(positions: &[[f32; 3]], indices: &[u32]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let key = |p: &[f32; 3]| p.map(|c| (c + 0.0).to_bits());
    let mut welded: HashMap<[u32; 3], u32> = HashMap::new();
    let mut vertex_of = vec![u32::MAX; positions.len()];
    let mut points = Vec::new();
    let mut triangles = Vec::new();
    for t in indices.chunks_exact(3) {
        let t = [0, 1, 2].map(|k| {
            let i = t[k] as usize;
            if vertex_of[i] == u32::MAX {
                vertex_of[i] = *welded.entry(key(&positions[i])).or_insert_with(|| {
                    points.push(positions[i].map(f64::from));
                    (points.len() - 1) as u32
                });
            }
            vertex_of[i]
        });
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            triangles.push(t);
        }
    }
    (points, triangles)
}
