//! The convex hulls of a mesh's upper hierarchy nodes: a lower bound of two nodes' distance
//! that does not lose their boxes' size when they lie apart along a diagonal.
//!
//! A triangle lies in the hull of its three corners, so the hull of the corners of a node's
//! triangles holds every triangle under the node, and the distance between two nodes' hulls is
//! at most the distance between any triangle of one and any triangle of the other. Any
//! direction `u` separates two convex sets by the gap of their projections on it,
//! `min_{y∈H₂} u·y − max_{x∈H₁} u·x`: GJK probes such directions (its lower bound at each
//! iteration is that gap, from the two support points), and [`apart`] stops it as
//! soon as one gap exceeds the reach, so what passes a pair of nodes over is the gap of two
//! support points, not GJK's converged distance.
//!
//! Hulls are made for the inner nodes of at least [`MIN_TRIANGLES`] triangles: a node's hull is
//! the hull of its children's hull vertices (or of its triangles' corners where a child has
//! none). The Faze4's built-in meshes carry theirs in the binary: `build.rs` includes this file
//! and makes them with parry at build time ([`NodeHulls::to_bytes`], read back by
//! [`NodeHulls::from_bytes`]). Any other mesh's are made at their first use, once per process
//! (about 0.5 G instructions for meshes the Faze4's size): storing them in the user's cache
//! would need their containment checked when read, which costs more than making them
//! (docs/clearance.md, "Speed").

use std::collections::HashMap;
use std::sync::OnceLock;

use parry3d_f64::math::{Pose as PPose, Vector as PVector};
use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::shape::SupportMap;
use parry3d_f64::transformation::try_convex_hull;

use super::bvh::Bvh;
use super::hull::{Adjacency, Climber, hull_candidates};

/// The fewest triangles a node must hold to be given a hull.
const MIN_TRIANGLES: u32 = 2048;

/// No hull for a node.
const NONE: u32 = u32::MAX;

/// One node's hull: its vertices (a subset of the mesh's points) and their edges, for a support
/// map by hill climbing.
pub(super) struct NodeHull {
    points: Vec<PVector>,
    adjacency: Adjacency,
    /// The vertices' places among the mesh's points.
    vertices: Vec<u32>,
    /// Its triangles (indices into `points`), for [`NodeHulls::to_bytes`].
    #[cfg_attr(not(test), allow(dead_code, reason = "read by build.rs, which includes this file"))]
    faces: Vec<[u32; 3]>,
}

impl NodeHull {
    /// The hull of vertices `vertices` (places among `points`) and triangles `faces`.
    fn of(vertices: Vec<u32>, faces: Vec<[u32; 3]>, points: &[PVector]) -> NodeHull {
        NodeHull {
            points: vertices.iter().map(|&v| points[v as usize]).collect(),
            adjacency: Adjacency::of(vertices.len(), &faces),
            vertices,
            faces,
        }
    }
}

/// The hulls of a hierarchy's upper nodes (see the module documentation), each made when a
/// search first asks for it unless read with the hierarchy ([`NodeHulls::from_bytes`]): far
/// pairs reach only the top of the hierarchy, and a node's hull is always made from its
/// children's (or its corners) whichever search asks first, so the same hull whatever the order.
pub(super) struct NodeHulls {
    /// Per node, its place in `hulls` when it holds at least [`MIN_TRIANGLES`] triangles,
    /// else [`NONE`].
    of: Vec<u32>,
    hulls: Vec<OnceLock<Option<NodeHull>>>,
}

impl NodeHulls {
    /// Room for the hulls of `bvh`'s inner nodes of at least [`MIN_TRIANGLES`] triangles.
    pub(super) fn new(bvh: &Bvh) -> NodeHulls {
        let n = bvh.len();
        // children are stored after their parent: from the end, children first
        let mut count = vec![0u32; n];
        for i in (0..n).rev() {
            count[i] = match bvh.below(i as u32) {
                Ok(_) => 1,
                Err([l, r]) => count[l as usize] + count[r as usize],
            };
        }
        let mut hulls = 0;
        let of = (count.iter())
            .map(|&c| match c >= MIN_TRIANGLES {
                true => {
                    hulls += 1;
                    hulls - 1
                }
                false => NONE,
            })
            .collect();
        NodeHulls {
            of,
            hulls: (0..hulls).map(|_| OnceLock::new()).collect(),
        }
    }

    /// Whether node `i` may have a hull.
    pub(super) fn has(&self, i: u32) -> bool {
        self.of[i as usize] != NONE
    }

    /// Node `i`'s hull (of `bvh`'s triangles `indices` into `points`), made now if not yet;
    /// `None` for a node too small or whose points span no volume.
    pub(super) fn get(&self, i: u32, bvh: &Bvh, points: &[PVector], indices: &[[u32; 3]]) -> Option<&NodeHull> {
        let cell = self.hulls.get(*self.of.get(i as usize)? as usize)?;
        cell.get_or_init(|| {
            let Err(children) = bvh.below(i) else {
                return None;
            };
            let mut input: Vec<u32> = Vec::new();
            for c in children {
                match self.get(c, bvh, points, indices) {
                    Some(hull) => input.extend(&hull.vertices),
                    None => input.extend(corners(bvh, c, indices)),
                }
            }
            let place: HashMap<[u64; 3], u32> = (input.iter())
                .map(|&v| (points[v as usize].to_array().map(f64::to_bits), v))
                .collect();
            let input: Vec<PVector> = input.iter().map(|&v| points[v as usize]).collect();
            let (hull, faces) = try_convex_hull(&hull_candidates(&input)).ok()?;
            // parry's vertices are copies of its input points
            let vertices = hull.iter().map(|p| place[&p.to_array().map(f64::to_bits)]).collect();
            (!faces.is_empty()).then(|| NodeHull::of(vertices, faces, points))
        })
        .as_ref()
    }

    /// Every hull, made now where not yet, as bytes (little-endian): per node that may have
    /// one, in order, a u32 vertex count (0: none), each vertex's place among the mesh's
    /// points (u32), a u32 triangle count and three u32 per triangle (indices into the
    /// vertices).
    #[cfg_attr(not(test), allow(dead_code, reason = "build.rs, which includes this file, calls it"))]
    pub(super) fn to_bytes(&self, bvh: &Bvh, points: &[PVector], indices: &[[u32; 3]]) -> Vec<u8> {
        let mut out = Vec::new();
        for i in (0..bvh.len() as u32).filter(|&i| self.has(i)) {
            let put = |out: &mut Vec<u8>, x: u32| out.extend(x.to_le_bytes());
            match self.get(i, bvh, points, indices) {
                None => put(&mut out, 0),
                Some(hull) => {
                    put(&mut out, hull.vertices.len() as u32);
                    hull.vertices.iter().for_each(|&v| put(&mut out, v));
                    put(&mut out, hull.faces.len() as u32);
                    hull.faces.iter().flatten().for_each(|&v| put(&mut out, v));
                }
            }
        }
        out
    }

    /// The hulls of `bvh`'s nodes read from [`NodeHulls::to_bytes`]'s `bytes` (all of them),
    /// over the mesh's `points`; `None` when the bytes are not a list of hulls for these nodes
    /// with every index in range. Their containment is not checked: these are the hulls
    /// `build.rs` made of the very triangles the binary carries, with this code (checking it
    /// costs about five times making them: docs/clearance.md, "Speed").
    pub(super) fn from_bytes(bytes: &[u8], bvh: &Bvh, points: &[PVector]) -> Option<NodeHulls> {
        let hulls = NodeHulls::new(bvh);
        if !bytes.len().is_multiple_of(4) {
            return None;
        }
        let mut words = bytes.chunks_exact(4).map(|w| u32::from_le_bytes(w.try_into().unwrap()));
        for cell in &hulls.hulls {
            let count = words.next()? as usize;
            if count == 0 {
                let _ = cell.set(None);
                continue;
            }
            let vertices: Vec<u32> = (0..count).map(|_| words.next()).collect::<Option<_>>()?;
            let faces = words.next()? as usize;
            let faces: Vec<[u32; 3]> = (0..faces)
                .map(|_| Some([words.next()?, words.next()?, words.next()?]))
                .collect::<Option<_>>()?;
            if count < 4
                || vertices.iter().any(|&v| v as usize >= points.len())
                || faces.iter().flatten().any(|&k| k as usize >= count)
            {
                return None;
            }
            let _ = cell.set(Some(NodeHull::of(vertices, faces, points)));
        }
        words.next().is_none().then_some(hulls)
    }
}

/// The distinct corners (places among the mesh's points) of node `i`'s triangles.
fn corners(bvh: &Bvh, i: u32, indices: &[[u32; 3]]) -> Vec<u32> {
    let mut corners: Vec<u32> = Vec::new();
    under(bvh, i, &mut |t| corners.extend(indices[t as usize]));
    corners.sort_unstable();
    corners.dedup();
    corners
}

/// Whether the hulls `h1` (its mesh's frame) and `h2` (placed by `pos12`, its frame in the
/// first's) are apart by more than `reach` along some direction, GJK started along `start`
/// (from the second towards the first, e.g. between the nodes' centres).
pub(super) fn apart(h1: &NodeHull, h2: &NodeHull, pos12: &PPose, start: PVector, reach: f64) -> bool {
    let (s1, s2) = (
        Climber::over(&h1.points, &h1.adjacency, 0),
        Climber::over(&h2.points, &h2.adjacency, 0),
    );
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(pos12, &s1, &s2, start));
    // GJK answers "no intersection within reach" when a gap exceeds it, and also after its
    // last iteration: the gap along its direction is computed again
    match gjk::closest_points(pos12, &s1, &s2, reach, false, &mut simplex) {
        GJKResult::NoIntersection(dir) => {
            dir.dot(s2.support_point(pos12, -dir)) - dir.dot(s1.local_support_point(dir)) > reach
        }
        _ => false,
    }
}

/// Tells `triangle` every triangle under node `i`.
fn under(bvh: &Bvh, i: u32, triangle: &mut impl FnMut(u32)) {
    match bvh.below(i) {
        Ok(t) => triangle(t),
        Err([l, r]) => {
            under(bvh, l, triangle);
            under(bvh, r, triangle);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::search::tests::poses;
    use crate::geometry::triangles::arrays;
    use parry3d_f64::query;
    use parry3d_f64::shape::TriMesh;

    /// A mesh: points (m) and triangles.
    type Mesh = (Vec<PVector>, Vec<[u32; 3]>);

    /// A built-in Faze4 mesh, in metres.
    fn faze4(name: &str) -> Mesh {
        let mesh = crate::faze4::meshes::mesh(name).expect("built in");
        let points = (mesh.positions.iter())
            .map(|p| PVector::new(p[0] as f64, p[1] as f64, p[2] as f64) * 1e-3)
            .collect();
        (
            points,
            mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        )
    }

    /// A grid of `nu` × `nv` quads (two triangles each) over `point(u, v)`, u and v in [0, 1].
    fn grid(nu: u32, nv: u32, point: impl Fn(f64, f64) -> PVector) -> Mesh {
        let mut points = Vec::new();
        for i in 0..=nu {
            for j in 0..=nv {
                points.push(point(i as f64 / nu as f64, j as f64 / nv as f64));
            }
        }
        let at = |i: u32, j: u32| i * (nv + 1) + j;
        let mut triangles = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        (points, triangles)
    }

    /// Two meshes of our own: a third of a torus (a curved tube, 7,200 triangles) and a strip
    /// bent into a half cylinder with a twist (6,400 triangles).
    fn own() -> [Mesh; 2] {
        let torus = grid(90, 40, |u, v| {
            let (a, b) = (u * std::f64::consts::TAU / 3.0, v * std::f64::consts::TAU);
            let r = 0.08 + 0.025 * b.cos();
            PVector::new(r * a.cos(), r * a.sin(), 0.025 * b.sin())
        });
        let strip = grid(160, 20, |u, v| {
            let a = u * std::f64::consts::PI;
            let w = (v - 0.5) * 0.04;
            let twist = u * 0.8;
            PVector::new(0.07 * a.cos(), 0.07 * a.sin() + w * twist.sin(), w * twist.cos())
        });
        [torus, strip]
    }

    /// A mesh's hierarchy and node hulls, and the nodes that have a hull.
    fn hulls((points, triangles): &Mesh) -> (Bvh, NodeHulls, Vec<u32>) {
        let bvh = Bvh::build(&arrays(points), triangles);
        let hulls = NodeHulls::new(&bvh);
        let with: Vec<u32> = (0..bvh.len() as u32)
            .filter(|&i| hulls.get(i, &bvh, points, triangles).is_some())
            .collect();
        (bvh, hulls, with)
    }

    /// The triangles under node `i`, as parry's mesh.
    fn node_mesh(bvh: &Bvh, i: u32, (points, triangles): &Mesh) -> TriMesh {
        let mut under_i = Vec::new();
        under(bvh, i, &mut |t| under_i.push(triangles[t as usize]));
        TriMesh::new(points.clone(), under_i).unwrap()
    }

    /// Every node hull holds its node's triangles: along 100 directions spread over the
    /// sphere, the climb's support point (from vertex 0) reaches as far as every corner of
    /// every triangle under the node, on the Faze4's meshes and on a torus section and a bent
    /// strip of our own.
    #[test]
    fn each_node_hull_holds_its_triangles() {
        let mut meshes: Vec<Mesh> = ["hvataljka", "saka", "podlaktica"].map(faze4).into();
        meshes.extend(own());
        let directions: Vec<PVector> = (0..100)
            .map(|k| {
                let z = 1.0 - (2 * k + 1) as f64 / 100.0;
                let (a, r) = (k as f64 * 2.399_963_229_728_653, (1.0 - z * z).sqrt());
                PVector::new(r * a.cos(), r * a.sin(), z)
            })
            .collect();
        for mesh in &meshes {
            let (bvh, hulls, with) = hulls(mesh);
            assert!(!with.is_empty(), "{} triangles: some node has a hull", mesh.1.len());
            for &i in &with {
                let hull = hulls.get(i, &bvh, &mesh.0, &mesh.1).unwrap();
                let mut corners = Vec::new();
                under(&bvh, i, &mut |t| {
                    corners.extend(mesh.1[t as usize].map(|v| mesh.0[v as usize]))
                });
                for &u in &directions {
                    let reach = Climber::over(&hull.points, &hull.adjacency, 0)
                        .local_support_point(u)
                        .dot(u);
                    let furthest = corners.iter().map(|p| p.dot(u)).fold(f64::MIN, f64::max);
                    assert!(furthest <= reach, "node {i} along {u:?}: {furthest} beyond {reach}");
                }
            }
        }
    }

    /// Two nodes are passed over only when they are apart by more than the reach: at 25
    /// poses of the torus section against the bent strip and of the Faze4's wrist against
    /// its gripper (overlapping ones among them), for each pair of nodes with hulls, `apart`
    /// at their triangles' exact distance (parry's) plus 1e-12 m is false, and it is true at that distance
    /// less 2 mm for most pairs apart by more (the bound is near the distance).
    #[test]
    fn two_nodes_are_passed_over_only_when_their_triangles_are_farther_apart() {
        let [torus, strip] = own();
        let (mut overlapping, mut tight, mut apart_pairs) = (0, 0, 0);
        for (a, b, centre) in [
            (torus, strip, PVector::new(0.03, 0.05, 0.0)),
            (faze4("saka"), faze4("hvataljka"), PVector::new(0.0, 0.0, 0.06)),
        ] {
            let ((bvh_a, hulls_a, with_a), (bvh_b, hulls_b, with_b)) = (hulls(&a), hulls(&b));
            let meshes_a: Vec<TriMesh> = with_a.iter().map(|&i| node_mesh(&bvh_a, i, &a)).collect();
            let meshes_b: Vec<TriMesh> = with_b.iter().map(|&j| node_mesh(&bvh_b, j, &b)).collect();
            for pose in poses(25, centre, 0.08) {
                for (&i, mesh_i) in with_a.iter().zip(&meshes_a) {
                    for (&j, mesh_j) in with_b.iter().zip(&meshes_b) {
                        let exact = query::distance(&PPose::IDENTITY, mesh_i, &pose, mesh_j)
                            .unwrap()
                            .distance;
                        let (hi, hj) = (
                            hulls_a.get(i, &bvh_a, &a.0, &a.1).unwrap(),
                            hulls_b.get(j, &bvh_b, &b.0, &b.1).unwrap(),
                        );
                        let start = mesh_i.local_aabb().center() - pose * mesh_j.local_aabb().center();
                        // to round-off (the search passes over at 1 nm beyond the best)
                        assert!(
                            !apart(hi, hj, &pose, start, exact + 1e-12),
                            "nodes {i}, {j} at {pose:?}"
                        );
                        if exact <= 0.0 {
                            overlapping += 1;
                        } else if exact > 0.002 {
                            apart_pairs += 1;
                            tight += usize::from(apart(hi, hj, &pose, start, exact - 0.002));
                        }
                    }
                }
            }
        }
        assert!(overlapping > 20, "{overlapping} overlapping node pairs");
        assert!(
            tight * 2 > apart_pairs,
            "{tight} of {apart_pairs} passed over 2 mm short of their distance"
        );
    }

    /// Node `i`'s hull's vertices (places among the mesh's points) and triangles, if any.
    fn parts(hulls: &NodeHulls, i: u32, bvh: &Bvh, (points, triangles): &Mesh) -> Option<(Vec<u32>, Vec<[u32; 3]>)> {
        (hulls.get(i, bvh, points, triangles)).map(|h| (h.vertices.clone(), h.faces.clone()))
    }

    /// The hulls the binary carries (made by `build.rs`) are read, and are the hulls made
    /// here of the same hierarchy: the same vertices and triangles (so they hold their nodes as
    /// those do, `each_node_hull_holds_its_triangles`).
    #[test]
    fn the_built_in_hulls_are_those_made_at_run_time() {
        for name in crate::faze4::meshes::names() {
            let mesh = crate::geometry::mesh::Mesh::built_in(name);
            let bytes = crate::faze4::meshes::hierarchy(name).unwrap();
            let (bvh, rest) = Bvh::from_bytes(bytes, &arrays(&mesh.0), &mesh.1).unwrap();
            let read = NodeHulls::from_bytes(rest, &bvh, &mesh.0).expect(name);
            let made = NodeHulls::new(&bvh);
            let with: Vec<u32> = (0..bvh.len() as u32).filter(|&i| made.has(i)).collect();
            assert!(!with.is_empty(), "{name}");
            for i in with {
                // read: set when read, not made now
                let cell = &read.hulls[read.of[i as usize] as usize];
                assert!(cell.get().is_some(), "{name}: node {i} read");
                assert_eq!(
                    parts(&read, i, &bvh, &mesh),
                    parts(&made, i, &bvh, &mesh),
                    "{name}: node {i}"
                );
            }
        }
    }

    /// Bytes that are not a list of hulls for the hierarchy's nodes, indices in range, are not
    /// read: one word short or long, a vertex past the mesh's points, a triangle's index past
    /// its hull's vertices.
    #[test]
    fn hull_bytes_of_another_mesh_are_refused() {
        let mesh = crate::geometry::mesh::Mesh::built_in("saka");
        let bvh = Bvh::build(&arrays(&mesh.0), &mesh.1);
        let bytes = NodeHulls::new(&bvh).to_bytes(&bvh, &mesh.0, &mesh.1);
        assert!(NodeHulls::from_bytes(&bytes, &bvh, &mesh.0).is_some());
        assert!(NodeHulls::from_bytes(&bytes[..bytes.len() - 4], &bvh, &mesh.0).is_none());
        assert!(NodeHulls::from_bytes(&[&bytes[..], &[0; 4]].concat(), &bvh, &mesh.0).is_none());
        let word = |k: usize| u32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().unwrap());
        let v = word(0) as usize;
        assert!(v >= 4, "the root has a hull");
        let mut far_vertex = bytes.clone();
        far_vertex[4..8].copy_from_slice(&(mesh.0.len() as u32).to_le_bytes());
        assert!(NodeHulls::from_bytes(&far_vertex, &bvh, &mesh.0).is_none());
        let mut far_corner = bytes.clone();
        let face = 4 * (1 + v + 1);
        far_corner[face..face + 4].copy_from_slice(&(v as u32).to_le_bytes());
        assert!(NodeHulls::from_bytes(&far_corner, &bvh, &mesh.0).is_none());
    }
}
