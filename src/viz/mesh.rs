//! Triangle meshes for drawing: mesh files (read by [`crate::geometry::mesh`]) → indexed meshes
//! with crease-aware normals, primitive shapes, and the compact form the viewer receives
//! (quantised positions, packed normals, 16-bit indices where they fit).

use std::collections::HashMap;
use std::path::Path;

use crate::error::Result;
use crate::geometry::mesh::{Rgba, read_mesh};

/// Normals of faces meeting at a vertex are averaged when they differ by less than this angle;
/// sharper edges keep one vertex per side (CAD parts: flat faces, sharp edges).
pub const CREASE_ANGLE_DEG: f32 = 35.0;

/// An indexed triangle mesh with one unit normal per vertex (f32, metres).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Three vertex indices per triangle.
    pub indices: Vec<u32>,
}

impl TriMesh {
    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// Axis-aligned bounds (min, max); zeros for an empty mesh.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        if self.positions.is_empty() {
            return ([0.0; 3], [0.0; 3]);
        }
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &self.positions {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        (lo, hi)
    }

    /// Indexes a triangle soup (three corners per triangle): identical positions are merged,
    /// degenerate triangles dropped, and each corner gets the area-weighted normal of the faces
    /// around its position that lie within [`CREASE_ANGLE_DEG`] of its own face; corners with
    /// the same position and normal become one vertex.
    pub fn from_soup(corners: &[[f32; 3]]) -> TriMesh {
        // 1. weld identical positions (-0.0 and 0.0 are the same point)
        let key = |p: &[f32; 3]| [(p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits(), (p[2] + 0.0).to_bits()];
        let mut welded: HashMap<[u32; 3], u32> = HashMap::with_capacity(corners.len() / 3);
        let mut points: Vec<[f32; 3]> = Vec::with_capacity(corners.len() / 3);
        let mut tri: Vec<[u32; 3]> = Vec::with_capacity(corners.len() / 3);
        let mut face_n: Vec<V3> = Vec::with_capacity(corners.len() / 3);
        for c in corners.chunks_exact(3) {
            let mut t = [0u32; 3];
            for (k, p) in c.iter().enumerate() {
                t[k] = *welded.entry(key(p)).or_insert_with(|| {
                    points.push(*p);
                    (points.len() - 1) as u32
                });
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                continue;
            }
            let (a, b, d) = (V3::from(c[0]), V3::from(c[1]), V3::from(c[2]));
            let n = (b - a).cross(&(d - a)); // length = 2·area
            if n.norm_squared().is_nan() || n.norm_squared() <= 0.0 {
                continue;
            }
            tri.push(t);
            face_n.push(n);
        }
        // 2. faces around each point (CSR)
        let mut start = vec![0u32; points.len() + 1];
        for t in &tri {
            for &v in t {
                start[v as usize + 1] += 1;
            }
        }
        for i in 0..points.len() {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut around = vec![0u32; tri.len() * 3];
        for (f, t) in tri.iter().enumerate() {
            for &v in t {
                around[fill[v as usize] as usize] = f as u32;
                fill[v as usize] += 1;
            }
        }
        let unit: Vec<V3> = face_n.iter().map(|&n| unit_or_z(n)).collect();
        let cos_crease = CREASE_ANGLE_DEG.to_radians().cos();
        // 3. crease-aware corner normals, and vertices = distinct (point, normal)
        let mut mesh = TriMesh::default();
        let mut vertex: HashMap<(u32, [u32; 3]), u32> = HashMap::with_capacity(points.len() * 2);
        for (f, t) in tri.iter().enumerate() {
            for &v in t {
                let mut n = V3::zeros();
                for &g in &around[start[v as usize] as usize..start[v as usize + 1] as usize] {
                    if unit[f].dot(&unit[g as usize]) >= cos_crease {
                        n += face_n[g as usize];
                    }
                }
                let n: [f32; 3] = unit_or_z(n).into();
                let k = (v, [n[0].to_bits(), n[1].to_bits(), n[2].to_bits()]);
                let index = *vertex.entry(k).or_insert_with(|| {
                    mesh.positions.push(points[v as usize]);
                    mesh.normals.push(n);
                    (mesh.positions.len() - 1) as u32
                });
                mesh.indices.push(index);
            }
        }
        mesh
    }

    /// This mesh with every position multiplied by `scale` per axis (normals recomputed by
    /// re-indexing, so non-uniform and mirroring scales shade correctly).
    pub fn scaled(&self, scale: [f32; 3]) -> TriMesh {
        if scale == [1.0; 3] {
            return self.clone();
        }
        let soup: Vec<[f32; 3]> = self
            .indices
            .iter()
            .map(|&i| {
                let p = self.positions[i as usize];
                [p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]]
            })
            .collect();
        TriMesh::from_soup(&soup)
    }

    /// An axis-aligned box with side lengths `size`, centred on the origin.
    pub fn cuboid(size: [f32; 3]) -> TriMesh {
        let h = [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0];
        let mut mesh = TriMesh::default();
        // each face: its normal axis and sign, and two in-plane axes forming a right-handed frame
        for (axis, sign) in [(0, 1.0f32), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = mesh.positions.len() as u32;
            for (a, b) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0; 3];
                p[axis] = sign * h[axis];
                p[u] = a * h[u] * sign;
                p[w] = b * h[w];
                let mut n = [0.0; 3];
                n[axis] = sign;
                mesh.positions.push(p);
                mesh.normals.push(n);
            }
            mesh.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        mesh
    }

    /// A cylinder of `radius` and `length` along z, centred on the origin, with `segments`
    /// sides.
    pub fn cylinder(radius: f32, length: f32, segments: usize) -> TriMesh {
        let mut mesh = TriMesh::default();
        let h = length / 2.0;
        let ring = |k: usize| {
            let a = std::f32::consts::TAU * k as f32 / segments as f32;
            (a.cos(), a.sin())
        };
        // side
        for k in 0..=segments {
            let (c, s) = ring(k);
            mesh.positions.push([radius * c, radius * s, -h]);
            mesh.normals.push([c, s, 0.0]);
            mesh.positions.push([radius * c, radius * s, h]);
            mesh.normals.push([c, s, 0.0]);
        }
        for k in 0..segments as u32 {
            let (a, b) = (2 * k, 2 * k + 2);
            mesh.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
        // caps
        for (z, nz) in [(h, 1.0f32), (-h, -1.0)] {
            let centre = mesh.positions.len() as u32;
            mesh.positions.push([0.0, 0.0, z]);
            mesh.normals.push([0.0, 0.0, nz]);
            for k in 0..segments {
                let (c, s) = ring(k);
                mesh.positions.push([radius * c, radius * s, z]);
                mesh.normals.push([0.0, 0.0, nz]);
            }
            for k in 0..segments as u32 {
                let (a, b) = (centre + 1 + k, centre + 1 + (k + 1) % segments as u32);
                if nz > 0.0 {
                    mesh.indices.extend([centre, a, b]);
                } else {
                    mesh.indices.extend([centre, b, a]);
                }
            }
        }
        mesh
    }

    /// A capsule of `radius` along z, centred on the origin: a UV sphere (`rings` latitude bands,
    /// made even, `sectors` ≥ 3 longitude bands) cut at its equator, its halves moved apart by
    /// `length`, and the cylinder between them.
    pub fn capsule(radius: f32, length: f32, rings: usize, sectors: usize) -> TriMesh {
        let mut mesh = TriMesh::default();
        let half = rings.max(2).div_ceil(2);
        // the latitude rows, the equator twice (the top half's, then the bottom half's)
        let rows = (0..=half)
            .map(|r| (r, length / 2.0))
            .chain((half..=2 * half).map(|r| (r, -length / 2.0)));
        for (r, z) in rows {
            let theta = std::f32::consts::PI * r as f32 / (2 * half) as f32;
            let (st, ct) = match r {
                0 => (0.0, 1.0),
                r if r == 2 * half => (0.0, -1.0),
                r if r == half => (1.0, 0.0),
                _ => theta.sin_cos(),
            };
            for s in 0..=sectors {
                let phi = std::f32::consts::TAU * (s % sectors) as f32 / sectors as f32;
                let n = [st * phi.cos(), st * phi.sin(), ct];
                mesh.positions.push([radius * n[0], radius * n[1], radius * n[2] + z]);
                mesh.normals.push(n);
            }
        }
        let w = sectors as u32 + 1;
        let last = 2 * half as u32 + 1;
        for r in 0..last {
            for s in 0..sectors as u32 {
                let (a, b) = (r * w + s, (r + 1) * w + s);
                if r > 0 {
                    mesh.indices.extend([a, b, a + 1]);
                }
                if r + 1 < last {
                    mesh.indices.extend([a + 1, b, b + 1]);
                }
            }
        }
        mesh
    }

    /// A UV sphere of `radius` centred on the origin (`rings` ≥ 2 latitude bands, `sectors` ≥ 3
    /// longitude bands).
    pub fn sphere(radius: f32, rings: usize, sectors: usize) -> TriMesh {
        let mut mesh = TriMesh::default();
        for r in 0..=rings {
            let theta = std::f32::consts::PI * r as f32 / rings as f32;
            // exact poles and seam, so that welding the sphere merges them
            let (st, ct) = match r {
                0 => (0.0, 1.0),
                r if r == rings => (0.0, -1.0),
                _ => theta.sin_cos(),
            };
            for s in 0..=sectors {
                let phi = std::f32::consts::TAU * (s % sectors) as f32 / sectors as f32;
                let n = [st * phi.cos(), st * phi.sin(), ct];
                mesh.positions.push([radius * n[0], radius * n[1], radius * n[2]]);
                mesh.normals.push(n);
            }
        }
        let w = sectors as u32 + 1;
        for r in 0..rings as u32 {
            for s in 0..sectors as u32 {
                let (a, b) = (r * w + s, (r + 1) * w + s);
                if r > 0 {
                    mesh.indices.extend([a, b, a + 1]);
                }
                if r + 1 < rings as u32 {
                    mesh.indices.extend([a + 1, b, b + 1]);
                }
            }
        }
        mesh
    }
}

/// Reads a mesh file (STL, COLLADA or OBJ, through [`read_mesh`], the one mesh reader) into an
/// indexed mesh with normals (see [`TriMesh::from_soup`]).
pub fn read_trimesh(path: &Path) -> Result<TriMesh> {
    Ok(TriMesh::from_soup(&read_mesh(path)?.soup()))
}

/// The mesh a URDF mesh reference stands for, with normals, and the colour of the file's
/// material if it has one: [`crate::geometry::mesh::load`] (the file, else the built-in Faze4
/// copy when `built_in`, a bundled description's geometry); `None` when there is neither.
pub fn load_mesh(uri: &str, path: Option<&Path>, built_in: bool) -> Option<Result<(TriMesh, Option<Rgba>)>> {
    crate::geometry::mesh::load(uri, path, built_in)
        .map(|file| file.map(|f| (TriMesh::from_soup(&f.mesh.soup()), f.color)))
}

/// Vertex indices in the narrowest type that holds them.
#[derive(Clone, Debug, PartialEq)]
pub enum Indices {
    /// Up to 65,536 vertices.
    U16(Vec<u16>),
    /// More.
    U32(Vec<u32>),
}

/// A mesh as the viewer receives it: positions quantised to 16 bits per axis within the
/// bounding box (error ≤ extent / 131,070 per axis), normals octahedron-encoded in two signed
/// bytes (error < 1°), indices 16-bit where they fit. 8 bytes per vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct CompactMesh {
    /// Bounding box minimum (m).
    pub min: [f32; 3],
    /// Bounding box maximum (m).
    pub max: [f32; 3],
    /// Three u16 per vertex: `p = min + q / 65535 · (max − min)`.
    pub positions: Vec<u16>,
    /// Two i8 per vertex, octahedron encoding of the unit normal.
    pub normals: Vec<i8>,
    /// Three per triangle.
    pub indices: Indices,
}

impl CompactMesh {
    /// Compacts `mesh`.
    pub fn new(mesh: &TriMesh) -> CompactMesh {
        let (min, max) = mesh.bounds();
        let mut positions = Vec::with_capacity(mesh.positions.len() * 3);
        for p in &mesh.positions {
            for a in 0..3 {
                let ext = max[a] - min[a];
                let q = if ext > 0.0 {
                    ((p[a] - min[a]) / ext * 65535.0).round()
                } else {
                    0.0
                };
                positions.push(q.clamp(0.0, 65535.0) as u16);
            }
        }
        let normals = mesh.normals.iter().flat_map(|n| oct_encode(*n)).collect();
        let indices = if mesh.positions.len() <= 1 << 16 {
            Indices::U16(mesh.indices.iter().map(|&i| i as u16).collect())
        } else {
            Indices::U32(mesh.indices.clone())
        };
        CompactMesh {
            min,
            max,
            positions,
            normals,
            indices,
        }
    }

    /// Number of vertices.
    pub fn vertices(&self) -> usize {
        self.positions.len() / 3
    }

    /// The mesh back in f32 (what the viewer draws).
    pub fn expand(&self) -> TriMesh {
        let positions = self
            .positions
            .chunks_exact(3)
            .map(|q| std::array::from_fn(|a| self.min[a] + q[a] as f32 / 65535.0 * (self.max[a] - self.min[a])))
            .collect();
        let normals = self.normals.chunks_exact(2).map(|e| oct_decode([e[0], e[1]])).collect();
        let indices = match &self.indices {
            Indices::U16(i) => i.iter().map(|&i| i as u32).collect(),
            Indices::U32(i) => i.clone(),
        };
        TriMesh {
            positions,
            normals,
            indices,
        }
    }

    /// Bytes this mesh takes in the viewer's data (before base64).
    pub fn byte_size(&self) -> usize {
        let index_bytes = match &self.indices {
            Indices::U16(i) => 2 * i.len(),
            Indices::U32(i) => 4 * i.len(),
        };
        2 * self.positions.len() + self.normals.len() + index_bytes
    }
}

/// Octahedron encoding of a unit vector into two signed bytes (Cigolle et al. 2014).
pub fn oct_encode(n: [f32; 3]) -> [i8; 2] {
    let l1 = n[0].abs() + n[1].abs() + n[2].abs();
    if l1.is_nan() || l1 <= 0.0 {
        return [0, 0];
    }
    let (mut x, mut y) = (n[0] / l1, n[1] / l1);
    if n[2] < 0.0 {
        let (ox, oy) = (x, y);
        x = (1.0 - oy.abs()) * sign(ox);
        y = (1.0 - ox.abs()) * sign(oy);
    }
    [
        (x.clamp(-1.0, 1.0) * 127.0).round() as i8,
        (y.clamp(-1.0, 1.0) * 127.0).round() as i8,
    ]
}

/// The unit vector of an [`oct_encode`]d pair (what the viewer's shader computes).
pub fn oct_decode(e: [i8; 2]) -> [f32; 3] {
    let (mut x, mut y) = ((e[0] as f32 / 127.0).max(-1.0), (e[1] as f32 / 127.0).max(-1.0));
    let z = 1.0 - x.abs() - y.abs();
    let t = (-z).max(0.0);
    x += if x >= 0.0 { -t } else { t };
    y += if y >= 0.0 { -t } else { t };
    unit_or_z(V3::new(x, y, z)).into()
}

fn sign(v: f32) -> f32 {
    if v >= 0.0 { 1.0 } else { -1.0 }
}

/// 3-vector of `f32`: the meshes' own precision.
type V3 = nalgebra::Vector3<f32>;

/// `a` scaled to unit length; +z for a zero vector (a degenerate corner still gets a normal).
fn unit_or_z(a: V3) -> V3 {
    a.try_normalize(0.0).unwrap_or_else(V3::z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube as 12 triangles (36 corners), outward winding.
    fn cube_soup() -> Vec<[f32; 3]> {
        let m = TriMesh::cuboid([1.0, 1.0, 1.0]);
        m.indices.iter().map(|&i| m.positions[i as usize]).collect()
    }

    #[test]
    fn a_cube_keeps_sharp_edges() {
        let mesh = TriMesh::from_soup(&cube_soup());
        assert_eq!(mesh.triangles(), 12);
        // 8 corners × 3 faces each: every edge of a cube is a crease
        assert_eq!(mesh.positions.len(), 24);
        for (t, tri) in mesh.indices.chunks(3).enumerate() {
            let n = mesh.normals[tri[0] as usize];
            assert!(tri.iter().all(|&i| mesh.normals[i as usize] == n), "flat face {t}");
            assert_eq!(n.iter().map(|c| c.abs()).sum::<f32>(), 1.0, "axis normal {n:?}");
        }
    }

    #[test]
    fn a_capsule_is_its_segment_swept_by_its_radius() {
        let (r, length) = (0.02f32, 0.1f32);
        let c = TriMesh::capsule(r, length, 16, 24);
        assert!(c.indices.iter().all(|&i| (i as usize) < c.positions.len()));
        let (mut top, mut bottom) = (f32::MIN, f32::MAX);
        for (p, n) in c.positions.iter().zip(&c.normals) {
            // every vertex lies r from the segment z ∈ [−L/2, L/2], its normal pointing away
            let z = p[2].clamp(-length / 2.0, length / 2.0);
            let d = (p[0] * p[0] + p[1] * p[1] + (p[2] - z) * (p[2] - z)).sqrt();
            assert!((d - r).abs() < 1e-6, "{p:?} is {d} from the segment");
            assert!(V3::new(p[0], p[1], p[2] - z).dot(&V3::from(*n)) > 0.0, "{n:?} at {p:?}");
            (top, bottom) = (top.max(p[2]), bottom.min(p[2]));
        }
        assert_eq!((top, bottom), (length / 2.0 + r, -length / 2.0 - r));
        // closed: every edge is shared by two triangles once the seam and equator are welded
        let soup: Vec<[f32; 3]> = c.indices.iter().map(|&i| c.positions[i as usize]).collect();
        let welded = TriMesh::from_soup(&soup);
        let mut edges = std::collections::HashMap::new();
        for t in welded.indices.chunks(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&k| k == 2), "a closed surface");
    }

    #[test]
    fn smooth_surfaces_share_vertices_and_average_normals() {
        let s = TriMesh::sphere(1.0, 12, 16);
        let soup: Vec<[f32; 3]> = s.indices.iter().map(|&i| s.positions[i as usize]).collect();
        let mesh = TriMesh::from_soup(&soup);
        // the seam and pole duplicates of the UV sphere are welded: 2 poles + 11 rings of 16
        assert_eq!(mesh.positions.len(), 2 + 11 * 16);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!(
                V3::from(*p).dot(&V3::from(*n)) > 0.97,
                "normal {n:?} at {p:?} points outwards"
            );
        }
    }

    #[test]
    fn compaction_round_trip_stays_within_its_error_bounds() {
        let s = TriMesh::sphere(0.13, 20, 30);
        let soup: Vec<[f32; 3]> = s.indices.iter().map(|&i| s.positions[i as usize]).collect();
        let mut mesh = TriMesh::from_soup(&soup);
        // a lopsided box so the three axes have different extents
        for p in &mut mesh.positions {
            p[0] = p[0] * 2.0 + 0.3;
            p[2] -= 1.0;
        }
        let compact = CompactMesh::new(&mesh);
        assert!(matches!(compact.indices, Indices::U16(_)));
        assert_eq!(compact.byte_size(), 8 * mesh.positions.len() + 2 * mesh.indices.len());
        let back = compact.expand();
        assert_eq!(back.indices, mesh.indices);
        let (lo, hi) = mesh.bounds();
        for (a, b) in mesh.positions.iter().zip(&back.positions) {
            for k in 0..3 {
                let bound = (hi[k] - lo[k]) / 131_070.0 + 1e-6 * hi[k].abs().max(lo[k].abs());
                assert!((a[k] - b[k]).abs() <= bound, "axis {k}: {} vs {}", a[k], b[k]);
            }
        }
        let worst = mesh
            .normals
            .iter()
            .zip(&back.normals)
            .map(|(a, b)| V3::from(*a).dot(&V3::from(*b)).min(1.0).acos().to_degrees())
            .fold(0.0f32, f32::max);
        assert!(worst < 1.0, "normal error {worst}°");
        // every direction, including the octants below the equator and the poles
        for n in [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.3, -0.4, -0.866]] {
            let u: [f32; 3] = unit_or_z(V3::from(n)).into();
            let d = oct_decode(oct_encode(u));
            assert!(V3::from(d).dot(&V3::from(u)) > 0.9998, "{n:?} → {d:?}");
        }
    }

    #[test]
    fn primitives_are_closed_with_outward_normals() {
        for mesh in [
            TriMesh::cuboid([0.1, 0.2, 0.3]),
            TriMesh::cylinder(0.05, 0.2, 24),
            TriMesh::sphere(0.1, 8, 12),
        ] {
            for tri in mesh.indices.chunks(3) {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize]);
                let face = (V3::from(b) - V3::from(a)).cross(&(V3::from(c) - V3::from(a)));
                let centre = [
                    (a[0] + b[0] + c[0]) / 3.0,
                    (a[1] + b[1] + c[1]) / 3.0,
                    (a[2] + b[2] + c[2]) / 3.0,
                ];
                assert!(face.dot(&V3::from(centre)) > 0.0, "counter-clockwise seen from outside");
                assert!(V3::from(mesh.normals[tri[0] as usize]).dot(&V3::from(centre)) > 0.0);
            }
        }
        let (lo, hi) = TriMesh::cuboid([0.1, 0.2, 0.3]).bounds();
        assert_eq!((lo, hi), ([-0.05, -0.1, -0.15], [0.05, 0.1, 0.15]));
    }
}
