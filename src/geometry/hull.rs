//! Support maps of convex hulls by hill climbing, for GJK and EPA when poses change little
//! from one query to the next (the clearance's samples, the contact's steps).

use std::cell::Cell;

use parry3d_f64::math::Vector as PVector;
use parry3d_f64::shape::{ConvexPolyhedron, SupportMap};

/// The edges of a convex hull's triangulation as vertex adjacency lists: vertex v's neighbours
/// are `neighbours[offsets[v]..offsets[v + 1]]`.
///
/// From the hull's triangles, not from parry's `ConvexPolyhedron` faces: those merge coplanar
/// triangles into polygons and drop the edges inside them, which leaves a vertex inside a flat
/// region (or on a degenerate face) with too few neighbours, a trap for the climb.
pub(super) struct Adjacency {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl Adjacency {
    /// The edges of the triangles `triangles` over `points` vertices.
    pub(super) fn of(points: usize, triangles: &[[u32; 3]]) -> Adjacency {
        let mut lists = vec![Vec::new(); points];
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
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

/// A hull's support map by hill climbing along its edges from the last support vertex: on the
/// triangulated surface of a convex polyhedron a vertex no neighbour of which is further along
/// a direction is the furthest of all (the same point as parry's scan of every vertex, up to ties), reached in a
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

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::transformation::try_convex_hull;

    /// The points of a box's faces on a grid, each face bulging out by 1e-5 in its middle (its
    /// triangles nearly coplanar: parry's faces merge them and drop the edges of the inner
    /// points, which are vertices of the hull all the same), and of a cylinder's two rims (an
    /// even number of rim points: opposite sides parallel, ties along many directions).
    fn clouds() -> Vec<Vec<PVector>> {
        let grid: Vec<f64> = (0..=4).map(|k| -1.0 + 0.5 * k as f64).collect();
        let mut box_points = Vec::new();
        for &u in &grid {
            for &v in &grid {
                let out = 1.0 + 1e-5 * (2.0 - u * u - v * v);
                for s in [-out, out] {
                    box_points.extend([
                        PVector::new(s, u, 0.7 * v),
                        PVector::new(u, s, 0.7 * v),
                        PVector::new(u, v, 0.7 * s),
                    ]);
                }
            }
        }
        let rim = (0..24).flat_map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 24.0;
            [
                PVector::new(a.cos(), a.sin(), -0.4),
                PVector::new(a.cos(), a.sin(), 0.4),
            ]
        });
        vec![box_points, rim.collect()]
    }

    /// From every vertex, along directions spread over the sphere (axis-aligned ones
    /// included, where faces tie), the climb reaches the largest projection of all vertices.
    #[test]
    fn the_climb_reaches_the_furthest_vertex_from_anywhere() {
        for points in clouds() {
            let (corners, faces) = try_convex_hull(&points).unwrap();
            let adjacency = Adjacency::of(corners.len(), &faces);
            let hull = ConvexPolyhedron::from_convex_mesh(corners, &faces).unwrap();
            let mut directions = vec![
                PVector::X,
                PVector::Y,
                PVector::Z,
                -PVector::X,
                PVector::new(1.0, 1.0, 0.0),
            ];
            for k in 0..200 {
                // a Fibonacci sphere
                let z = 1.0 - (2 * k + 1) as f64 / 200.0;
                let a = k as f64 * 2.399_963_229_728_653;
                let r = (1.0 - z * z).sqrt();
                directions.push(PVector::new(r * a.cos(), r * a.sin(), z));
            }
            for start in 0..hull.points().len() as u32 {
                for &dir in &directions {
                    let furthest = hull.points().iter().map(|p| p.dot(dir)).fold(f64::MIN, f64::max);
                    let climbed = Climber::new(&hull, &adjacency, start).local_support_point(dir).dot(dir);
                    assert!(
                        climbed >= furthest - 1e-12,
                        "from {start} along {dir:?}: {climbed} < {furthest}"
                    );
                }
            }
        }
    }
}
