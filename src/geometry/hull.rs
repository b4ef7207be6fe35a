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
    /// The edges of the triangles `triangles` over `points` vertices: each vertex's
    /// neighbours once each, in the order the triangles first give them.
    pub(super) fn of(points: usize, triangles: &[[u32; 3]]) -> Adjacency {
        // every edge both ways, bucketed by its first vertex (a counting sort)
        let mut offsets = vec![0u32; points + 1];
        for t in triangles {
            for v in t {
                offsets[*v as usize + 1] += 2;
            }
        }
        for v in 0..points {
            offsets[v + 1] += offsets[v];
        }
        let mut next = offsets.clone();
        let mut neighbours = vec![0u32; offsets[points] as usize];
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                for (x, y) in [(a, b), (b, a)] {
                    neighbours[next[x as usize] as usize] = y;
                    next[x as usize] += 1;
                }
            }
        }
        // each bucket's repeats dropped (its first of each kept, in order), the buckets moved
        // together
        let mut kept = 0;
        for v in 0..points {
            let (from, to) = (offsets[v] as usize, offsets[v + 1] as usize);
            offsets[v] = kept as u32;
            let start = kept;
            for i in from..to {
                let y = neighbours[i];
                if !neighbours[start..kept].contains(&y) {
                    neighbours[kept] = y;
                    kept += 1;
                }
            }
        }
        offsets[points] = kept as u32;
        neighbours.truncate(kept);
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
        Climber::over(hull.points(), adjacency, start)
    }

    /// The support map of the hull of vertices `points` (edges `adjacency`), starting at vertex
    /// `start`.
    pub(super) fn over(points: &'a [PVector], adjacency: &'a Adjacency, start: u32) -> Climber<'a> {
        Climber {
            points,
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

/// Below this many points [`hull_candidates`] keeps them all (the filter would cost more than
/// it saves).
const FEW_POINTS: usize = 256;

/// How far inside the polytope of the extreme points (a share of the points' box diagonal) a
/// point must be for [`hull_candidates`] to leave it out: far above round-off, far below any
/// distance parry's hull could tell apart.
const INSIDE_MARGIN: f64 = 1e-6;

/// The points of `points` (in their order) that can be vertices of their convex hull: all but
/// those inside the convex hull of their extreme points along the 26 directions of a cube's
/// faces, edges and corners by more than [`INSIDE_MARGIN`] of the points' box (Akl and
/// Toussaint's throw-away heuristic, 1978). That polytope lies inside the whole hull, so a
/// point inside it is inside the hull and none of its vertices: the hull of what is kept is
/// the hull of all. parry's `try_convex_hull` allocates a vector of every point at every
/// vertex it adds, which made the Faze4's six hulls 12 % of a whole default wave's
/// instructions. A polytope without volume (flat points) leaves every point in.
pub(super) fn hull_candidates(points: &[PVector]) -> Vec<PVector> {
    if points.len() < FEW_POINTS {
        return points.to_vec();
    }
    // the 13 directions of a cube's faces, edges and corners up to sign, each giving the
    // points furthest both ways, in one pass
    let axes: Vec<PVector> = (-1..=1)
        .flat_map(|x| (-1..=1).flat_map(move |y| (-1..=1).map(move |z| PVector::new(x as f64, y as f64, z as f64))))
        .filter(|d| d.to_array().into_iter().find(|&c| c != 0.0) == Some(1.0))
        .collect();
    let mut ends = vec![((f64::INFINITY, 0), (f64::NEG_INFINITY, 0)); axes.len()];
    for (i, p) in points.iter().enumerate() {
        for (axis, (low, high)) in axes.iter().zip(&mut ends) {
            let d = axis.dot(*p);
            if d < low.0 {
                *low = (d, i);
            }
            if d > high.0 {
                *high = (d, i);
            }
        }
    }
    let mut extremes: Vec<usize> = ends.iter().flat_map(|(low, high)| [low.1, high.1]).collect();
    extremes.sort_unstable();
    extremes.dedup();
    let corners: Vec<PVector> = extremes.iter().map(|&i| points[i]).collect();
    let Ok((corners, faces)) = parry3d_f64::transformation::try_convex_hull(&corners) else {
        return points.to_vec();
    };
    let (lo, hi) = (points.iter()).fold((points[0], points[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let margin = INSIDE_MARGIN * (hi - lo).length();
    let centre = corners.iter().sum::<PVector>() / corners.len() as f64;
    // each face's outward unit normal and offset
    let planes: Vec<(PVector, f64)> = (faces.iter())
        .map(|f| {
            let [a, b, c] = f.map(|v| corners[v as usize]);
            let n = (b - a).cross(c - a).normalize_or_zero();
            let n = if n.dot(centre - a) > 0.0 { -n } else { n };
            (n, n.dot(a))
        })
        .collect();
    // a face without area bounds nothing: every point is kept
    if planes.iter().any(|&(n, _)| n == PVector::ZERO) {
        return points.to_vec();
    }
    let inside = |p: &PVector| planes.iter().all(|&(n, offset)| n.dot(*p) - offset < -margin);
    points.iter().filter(|p| !inside(p)).copied().collect()
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

    /// The hull of the points [`hull_candidates`] keeps has the vertices of parry's hull of all
    /// of them (the same set; parry lists them in another order), on the Faze4's six meshes
    /// (33 % to 60 % of their points kept, two fifths in all); few points are kept as they are.
    #[test]
    fn the_hull_of_the_candidates_is_the_hull_of_all() {
        let mut clouds = clouds();
        for name in crate::faze4::meshes::names() {
            let mesh = crate::faze4::meshes::mesh(name).expect("built in");
            clouds.push(
                (mesh.positions.iter())
                    .map(|p| PVector::new(p[0] as f64, p[1] as f64, p[2] as f64) * 1e-3)
                    .collect(),
            );
        }
        let (mut kept_shares, mut counts) = (Vec::new(), (0, 0));
        for points in clouds {
            let kept = hull_candidates(&points);
            kept_shares.push(kept.len() as f64 / points.len() as f64);
            counts = (counts.0 + kept.len(), counts.1 + points.len());
            let (mut all, _) = try_convex_hull(&points).unwrap();
            let (mut some, _) = try_convex_hull(&kept).unwrap();
            let order = |a: &PVector, b: &PVector| a.to_array().partial_cmp(&b.to_array()).unwrap();
            all.sort_by(order);
            some.sort_by(order);
            assert_eq!(all, some, "{} points, {} kept", points.len(), kept.len());
        }
        let meshes = &kept_shares[2..];
        assert!(meshes.len() == 6 && meshes.iter().all(|&k| k < 0.65), "{kept_shares:?}");
        assert!(counts.0 * 2 < counts.1, "{counts:?} kept of all");
        assert_eq!(kept_shares[..2], [1.0, 1.0], "few points are all kept");
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
