//! Support maps of convex hulls by hill climbing, for GJK and EPA when poses change little
//! from one query to the next (the clearance's samples, the contact's steps).

use std::cell::Cell;

use parry3d_f64::math::Vector as PVector;
use parry3d_f64::shape::{ConvexPolyhedron, SupportMap};

/// The edges of a convex polyhedron as vertex adjacency lists: vertex v's neighbours are
/// `neighbours[offsets[v]..offsets[v + 1]]`.
pub(super) struct Adjacency {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl Adjacency {
    /// The edges of `hull`'s faces (consecutive vertices of each face polygon).
    pub(super) fn of(hull: &ConvexPolyhedron) -> Adjacency {
        let mut lists = vec![Vec::new(); hull.points().len()];
        let ring = hull.vertices_adj_to_face();
        for face in hull.faces() {
            let (first, count) = (face.first_vertex_or_edge as usize, face.num_vertices_or_edges as usize);
            for k in 0..count {
                let (a, b) = (ring[first + k], ring[first + (k + 1) % count]);
                for (x, y) in [(a, b), (b, a)] {
                    if !lists[x as usize].contains(&y) {
                        lists[x as usize].push(y);
                    }
                }
            }
        }
        let mut offsets = vec![0];
        let mut neighbours = Vec::new();
        for list in lists {
            neighbours.extend(list);
            offsets.push(neighbours.len() as u32);
        }
        Adjacency { offsets, neighbours }
    }
}

/// A hull's support map by hill climbing along its edges from the last support vertex: on a
/// convex polyhedron a vertex no neighbour of which is further along a direction is the
/// furthest of all (the same point as parry's scan of every vertex, up to ties), reached in a
/// few steps when the directions change little.
pub(super) struct Climber<'a> {
    /// The hull's vertices (its frame).
    points: &'a [PVector],
    /// Their edges.
    adjacency: &'a Adjacency,
    /// Where the next climb starts, and where the last one ended (a vertex index).
    pub at: Cell<u32>,
}

impl<'a> Climber<'a> {
    /// The support map of `hull` (edges `adjacency`), starting at vertex `start`.
    pub(super) fn new(hull: &'a ConvexPolyhedron, adjacency: &'a Adjacency, start: u32) -> Climber<'a> {
        Climber {
            points: hull.points(),
            adjacency,
            at: Cell::new(start),
        }
    }
}

impl SupportMap for Climber<'_> {
    fn local_support_point(&self, dir: PVector) -> PVector {
        let (mut best, mut top) = (self.at.get(), dir.dot(self.points[self.at.get() as usize]));
        loop {
            let (from, to) = (
                self.adjacency.offsets[best as usize],
                self.adjacency.offsets[best as usize + 1],
            );
            let next = (self.adjacency.neighbours[from as usize..to as usize].iter())
                .map(|&v| (v, dir.dot(self.points[v as usize])))
                .filter(|&(_, d)| d > top)
                .max_by(|a, b| a.1.total_cmp(&b.1));
            match next {
                Some((v, d)) => (best, top) = (v, d),
                None => break,
            }
        }
        self.at.set(best);
        self.points[best as usize]
    }
}
