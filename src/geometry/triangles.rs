//! A mesh's exact triangles as the clearance searches read them: its points (f64, metres, the
//! mesh's frame), three indices per triangle, and their bounding-volume hierarchy ([`Bvh`],
//! `bvh.rs`). The hierarchy is made once: at build time for the Faze4's built-in meshes
//! (`build.rs`), in the user's cache for any other mesh (`mesh_cache.rs`), else here.

use parry3d_f64::math::Vector as PVector;
use parry3d_f64::shape::Triangle;

use super::bvh::{Bvh, Node, point_triangle_squared};
use super::node_hulls::{NodeHull, NodeHulls};

/// A triangle mesh with its hierarchy (see the module documentation).
pub(super) struct Triangles {
    points: Vec<PVector>,
    indices: Vec<[u32; 3]>,
    bvh: Bvh,
    /// The hulls of its upper nodes.
    hulls: NodeHulls,
}

impl Triangles {
    /// The mesh of `points` and `indices` (at least one triangle), with `made` its hierarchy
    /// and its nodes' hulls when they were made before (a hierarchy of these triangles), else
    /// a hierarchy built now (its hulls made at their first use).
    pub(super) fn new(points: Vec<PVector>, indices: Vec<[u32; 3]>, made: Option<(Bvh, NodeHulls)>) -> Triangles {
        let (bvh, hulls) = made.unwrap_or_else(|| {
            let bvh = Bvh::build(&arrays(&points), &indices);
            let hulls = NodeHulls::new(&bvh);
            (bvh, hulls)
        });
        Triangles {
            points,
            indices,
            bvh,
            hulls,
        }
    }

    /// Triangle `i` (m, the mesh's frame); an index past the end reads as the last triangle
    /// (a seed carried from another reading of the mesh is then only a poor seed).
    pub(super) fn triangle(&self, i: u32) -> Triangle {
        let t = self.indices[(i as usize).min(self.indices.len() - 1)];
        Triangle::new(
            self.points[t[0] as usize],
            self.points[t[1] as usize],
            self.points[t[2] as usize],
        )
    }

    /// Its hierarchy.
    pub(super) fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Whether node `i` of its hierarchy may have a hull (it holds enough triangles).
    pub(super) fn may_have_hull(&self, i: u32) -> bool {
        self.hulls.has(i)
    }

    /// The hull of node `i`'s triangles' corners, if it has one (made at its first use).
    pub(super) fn node_hull(&self, i: u32) -> Option<&NodeHull> {
        self.hulls.get(i, &self.bvh, &self.points, &self.indices)
    }

    /// How many triangles it has.
    pub(super) fn len(&self) -> usize {
        self.indices.len()
    }

    /// The triangle nearest point `p` (the mesh's frame).
    pub(super) fn nearest(&self, p: PVector) -> u32 {
        let corners = |t: u32| self.indices[t as usize].map(|v| self.points[v as usize].to_array());
        let p = p.to_array();
        (self.bvh.nearest(p, 0, |t| point_triangle_squared(p, corners(t)))).map_or(0, |(t, _)| t)
    }
}

/// A node's box: its smallest and largest corners.
pub(super) fn node_box(n: &Node) -> (PVector, PVector) {
    (PVector::from_array(n.lo), PVector::from_array(n.hi))
}

/// Points as the hierarchy reads them.
pub(super) fn arrays(points: &[PVector]) -> Vec<[f64; 3]> {
    points.iter().map(|p| p.to_array()).collect()
}
