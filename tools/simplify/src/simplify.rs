//! A collision mesh simplified under an error bound, with both one-sided distances between the
//! simplified and the original surfaces bounded above (certified), so that a distance measured
//! on the simplified meshes bounds the original meshes' distance both ways (docs/clearance.md,
//! "Simplified meshes").
//!
//! Two simplifiers are judged: meshoptimizer's ([`simplify`], the `meshopt` crate: edge collapses
//! ordered by a quadric error, stopped at an absolute error target, an estimate and not a bound)
//! and our own whose every collapse is checked against the bound (`checked.rs`). Both keep a
//! subset of the original vertices, at their exact coordinates; the certified bounds are
//! [`one_sided`]'s ([`certify`]): for every point `p` of one surface, `dist(p, other) ≤ bound`.
//!
//! It uses `std`, `meshopt` and faze4's `src/geometry/bvh.rs` (included by `main.rs`) alone.

use super::bvh::{Bvh, Point, point_triangle_squared};

/// A simplification is kept only when it has at most this share of the original's triangles
/// (else the original is searched as it is).
pub const MOST_KEPT: f64 = 0.8;

/// How much a certified bound may exceed the largest distance actually found (m): cells of a
/// triangle are split until their bound is within it (or [`MAX_DEPTH`] is reached).
pub const SLACK: f64 = 1e-6;

/// How many times a triangle's cells are split at most (4 cells per split).
const MAX_DEPTH: u32 = 14;

/// A mesh simplified, with the certified one-sided distances to its original.
#[derive(Clone, Debug, PartialEq)]
pub struct Simplified {
    /// Its vertices (m, the mesh's frame): original vertices, at their exact coordinates.
    pub points: Vec<Point>,
    /// Three indices into `points` per triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Its triangles' hierarchy.
    pub bvh: Bvh,
    /// An upper bound (m) of the distance from any point of the simplified surface to the
    /// original surface: `max_{p ∈ S} dist(p, O)`.
    pub to_original: f64,
    /// An upper bound (m) of the distance from any point of the original surface to the
    /// simplified surface: `max_{p ∈ O} dist(p, S)`.
    pub from_original: f64,
}

/// The mesh of `points` and `triangles` simplified within `error` (m) and certified, or `None`
/// when the simplifier keeps more than [`MOST_KEPT`] of its triangles.
pub fn simplify(points: &[Point], triangles: &[[u32; 3]], error: f64) -> Option<Simplified> {
    let positions: Vec<f32> = points.iter().flat_map(|p| p.map(|c| c as f32)).collect();
    let bytes: Vec<u8> = positions.iter().flat_map(|c| c.to_le_bytes()).collect();
    let adapter = meshopt::VertexDataAdapter::new(&bytes, 12, 0).ok()?;
    let indices: Vec<u32> = triangles.iter().flatten().copied().collect();
    let kept = meshopt::simplify(
        &indices,
        &adapter,
        0,
        error as f32,
        meshopt::SimplifyOptions::ErrorAbsolute,
        None,
    );
    if kept.is_empty() || kept.len() as f64 > MOST_KEPT * indices.len() as f64 {
        return None;
    }
    let kept: Vec<[u32; 3]> = kept.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Some(certify(points, triangles, &kept))
}

/// The simplification `kept` (triangles of the original vertices `points`) of the mesh of
/// `points` and `triangles`, with its own vertices (those it uses, in their order of first use),
/// its hierarchy and both one-sided distances to the original certified by [`one_sided`].
pub fn certify(points: &[Point], triangles: &[[u32; 3]], kept: &[[u32; 3]]) -> Simplified {
    let mut index = vec![u32::MAX; points.len()];
    let mut kept_points = Vec::new();
    let kept_triangles: Vec<[u32; 3]> = (kept.iter())
        .map(|t| {
            t.map(|v| {
                let v = v as usize;
                if index[v] == u32::MAX {
                    index[v] = kept_points.len() as u32;
                    kept_points.push(points[v]);
                }
                index[v]
            })
        })
        .collect();
    let bvh = Bvh::build(&kept_points, &kept_triangles);
    let original = Bvh::build(points, triangles);
    let to_original = one_sided((&kept_points, &kept_triangles), (points, triangles, &original));
    let from_original = one_sided((points, triangles), (&kept_points, &kept_triangles, &bvh));
    Simplified {
        points: kept_points,
        triangles: kept_triangles,
        bvh,
        to_original,
        from_original,
    }
}

/// The nearest triangle of a mesh to a point, and its distance.
type Near = (u32, f64);

/// An upper bound (m) of `max_{p ∈ from} dist(p, to)`, the one-sided distance from the surface
/// `from` to the surface `to` (with `to`'s hierarchy), within [`SLACK`] of the largest distance
/// found at a point of `from` unless a triangle's cells reach [`MAX_DEPTH`].
///
/// Why it bounds: for any triangle `t` of `to`, `dist(p, to) ≤ dist(p, t)`, and `dist(·, t)`
/// is convex, so over a triangular cell of `from` it is largest at one of the cell's three
/// corners. Each cell's bound is therefore `min_t max_corner dist(corner, t)` over a few
/// candidate triangles `t` (those nearest its corners and its centroid); a cell whose bound is
/// above the largest distance found so far (plus [`SLACK`]) is split into four at its edges'
/// midpoints. The largest cell bound bounds every point of `from`.
pub fn one_sided((points, triangles): (&[Point], &[[u32; 3]]), to: (&[Point], &[[u32; 3]], &Bvh)) -> f64 {
    let (to_points, to_triangles, bvh) = to;
    let corners = |t: u32| to_triangles[t as usize].map(|v| to_points[v as usize]);
    let near = |p: Point, start: u32| -> Near {
        bvh.nearest(p, start, |t| point_triangle_squared(p, corners(t)))
            .unwrap_or((0, f64::INFINITY))
    };
    // the largest distance found at a point: every vertex of a triangle (a vertex of none is
    // not on the surface), every centroid
    let mut used = vec![false; points.len()];
    triangles.iter().flatten().for_each(|&v| used[v as usize] = true);
    let mut start = 0;
    let vertices: Vec<Near> = (points.iter().zip(used))
        .map(|(&p, used)| {
            if !used {
                return (0, 0.0);
            }
            let n = near(p, start);
            start = n.0;
            n
        })
        .collect();
    let centroid = |c: [Point; 3]| [0, 1, 2].map(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0);
    let centroids: Vec<Near> = triangles
        .iter()
        .map(|t| near(centroid(t.map(|v| points[v as usize])), vertices[t[0] as usize].0))
        .collect();
    let mut lower = (vertices.iter().chain(&centroids)).fold(0.0f64, |m, n| m.max(n.1));
    let mut upper = lower;
    let bound = |c: &[Point; 3], candidates: &[u32]| {
        (candidates.iter())
            .map(|&t| (c.iter()).fold(0.0f64, |m, &p| m.max(point_triangle_squared(p, corners(t)))))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    };
    let mut cells: Vec<([Point; 3], [Near; 3], u32)> = Vec::new();
    for (t, mid) in triangles.iter().zip(&centroids) {
        let c = t.map(|v| points[v as usize]);
        let n = t.map(|v| vertices[v as usize]);
        if bound(&c, &[n[0].0, n[1].0, n[2].0, mid.0]) <= lower + SLACK {
            continue;
        }
        cells.push((c, n, 0));
        while let Some((c, n, depth)) = cells.pop() {
            let m = near(centroid(c), n[0].0);
            lower = lower.max(m.1);
            let b = bound(&c, &[n[0].0, n[1].0, n[2].0, m.0]);
            if b <= lower + SLACK || depth >= MAX_DEPTH {
                upper = upper.max(b);
                continue;
            }
            let half = |i: usize, j: usize| [0, 1, 2].map(|k| (c[i][k] + c[j][k]) / 2.0);
            let (p01, p12, p20) = (half(0, 1), half(1, 2), half(2, 0));
            let (n01, n12, n20) = (near(p01, n[0].0), near(p12, n[1].0), near(p20, n[2].0));
            lower = lower.max(n01.1).max(n12.1).max(n20.1);
            cells.extend([
                ([c[0], p01, p20], [n[0], n01, n20], depth + 1),
                ([p01, c[1], p12], [n01, n[1], n12], depth + 1),
                ([p20, p12, c[2]], [n20, n12, n[2]], depth + 1),
                ([p01, p12, p20], [n01, n12, n20], depth + 1),
            ]);
        }
    }
    upper.max(lower)
}
