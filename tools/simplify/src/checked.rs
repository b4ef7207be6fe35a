//! A simplifier whose every edge collapse is checked, as it is made, against a bound `ε` on the
//! distance between the simplified and the original surfaces in both directions
//! (docs/clearance.md, "Simplified meshes").
//!
//! Half-edge collapses `u → v` (`u` removed, its triangles given to `v`; every kept vertex is an
//! original vertex at its exact coordinates), tried in the order of their quadric error (Garland
//! and Heckbert's, as meshoptimizer orders them). A collapse is made only when both proofs below
//! hold for the triangles it changes; the mesh then stays within `ε` of the original both ways
//! after every collapse, whatever the order. The proofs use one fact (the convexity argument of
//! [`one_sided`](super::simplify::one_sided)): for a triangle `t`, `dist(·, t)` is convex, so over
//! a triangular cell it is largest at one of the cell's three corners, and any surface holding
//! `t` is at most that far from every point of the cell.
//!
//! * **simplified → original**: each new triangle is cut into cells (split in four up to
//!   [`MAX_DEPTH`] times, [`MAX_CELLS`] cells at most) until each cell has an original triangle
//!   (the nearest to one of its corners or its centroid) within `ε` of its three corners, or a
//!   centroid whose distance to the original plus the cell's radius is within `ε` (distances are
//!   1-Lipschitz). The triangles it does not change were proven when they were made.
//! * **original → simplified**: each original triangle keeps a *cover*, a few current triangles
//!   such that its cells (split likewise) each have one of them within `ε` of their corners. A
//!   collapse removes the triangles around `u`, so every original triangle whose cover held one
//!   of them is proven again against what remains of its cover, the new triangles and the
//!   triangles around `v`, and its cover becomes the triangles that proof used.
//!
//! A proof that fails (a point farther than `ε` from its candidates, or a cell at the depth
//! limit) refuses the collapse: the checks are conservative, never optimistic. Orientation and
//! manifoldness are not kept (a distance does not depend on them); a new triangle that repeats
//! one already around `v` is dropped.

use super::bvh::{Bvh, Point, point_triangle_squared};
use super::simplify::{SLACK, Simplified, certify};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// How many times a cell is split in four at most before a proof gives up.
const MAX_DEPTH: u32 = 12;

/// How many cells one proof may examine before it gives up.
const MAX_CELLS: usize = 4096;

/// A symmetric 4×4 quadric (upper triangle, row by row): the sum of the squared distances to
/// the planes of a vertex's original triangles, weighted by their areas.
type Quadric = [f64; 10];

/// A triangle's corners.
type Corners = [Point; 3];

/// The mesh being simplified, and what the proofs keep.
struct Collapser<'a> {
    /// The original vertices (m); every kept vertex is one of them.
    points: &'a [Point],
    /// The original triangles.
    original: &'a [[u32; 3]],
    /// The original triangles' hierarchy.
    bvh: Bvh,
    /// `ε²` (m²).
    bound_squared: f64,
    /// Every triangle made so far (current and removed), by id.
    triangles: Vec<[u32; 3]>,
    /// Whether each triangle is current.
    alive: Vec<bool>,
    /// Per vertex, the triangles around it (removed ones are dropped when next read).
    around: Vec<Vec<u32>>,
    /// Per original triangle, its cover: current triangles that hold it within `ε`.
    covers: Vec<Vec<u32>>,
    /// Per triangle, the original triangles whose cover may hold it.
    covering: Vec<Vec<u32>>,
    /// Per vertex, its quadric.
    quadric: Vec<Quadric>,
    /// Per vertex, bumped when its quadric or its existence changes (older queue entries lapse).
    stamp: Vec<u32>,
    /// Per original triangle, the last collapse that gathered it.
    seen: Vec<u64>,
    /// Collapses tried so far.
    tries: u64,
    /// Per vertex, an original triangle that has it (0 for a vertex of none).
    incident: Vec<u32>,
}

/// The mesh of `points` and `triangles` simplified by [`simplify`] within `bound` less twice
/// [`one_sided`](super::simplify::one_sided)'s slack, and certified: both one-sided distances are
/// then at most `bound` (m) (unless `one_sided` reaches its depth limit).
pub fn certified(points: &[Point], triangles: &[[u32; 3]], bound: f64) -> Simplified {
    let kept = simplify(points, triangles, (bound - 2.0 * SLACK).max(0.0));
    certify(points, triangles, &kept)
}

/// The mesh of `points` and `triangles` simplified by collapses each checked to keep both
/// one-sided distances to the original within `bound` (m): the kept triangles (indices into
/// `points`).
pub fn simplify(points: &[Point], triangles: &[[u32; 3]], bound: f64) -> Vec<[u32; 3]> {
    let mut c = Collapser::new(points, triangles, bound);
    let mut queue = BinaryHeap::new();
    for t in 0..triangles.len() as u32 {
        c.push_edges(t, &mut queue);
    }
    while let Some((_, u, v, stamp_u, stamp_v)) = queue.pop() {
        if c.stamp[u as usize] != stamp_u || c.stamp[v as usize] != stamp_v {
            continue;
        }
        if c.collapse(u, v) {
            for t in c.current_around(v) {
                c.push_edges(t, &mut queue);
            }
        }
    }
    (0..c.triangles.len())
        .filter(|&t| c.alive[t])
        .map(|t| c.triangles[t])
        .collect()
}

/// A queue entry: the cost (as bits of a non-negative f64, lowest first), `u`, `v` and their stamps.
type Entry = (Reverse<u64>, u32, u32, u32, u32);

impl<'a> Collapser<'a> {
    fn new(points: &'a [Point], original: &'a [[u32; 3]], bound: f64) -> Self {
        let mut quadric = vec![[0.0; 10]; points.len()];
        for t in original {
            let q = plane_quadric(t.map(|v| points[v as usize]));
            for &v in t {
                for (a, b) in quadric[v as usize].iter_mut().zip(q) {
                    *a += b;
                }
            }
        }
        let mut around = vec![Vec::new(); points.len()];
        for (i, t) in original.iter().enumerate() {
            for &v in t {
                around[v as usize].push(i as u32);
            }
        }
        let incident = around.iter().map(|a| a.first().copied().unwrap_or(0)).collect();
        Collapser {
            points,
            original,
            bvh: Bvh::build(points, original),
            bound_squared: bound * bound,
            triangles: original.to_vec(),
            alive: vec![true; original.len()],
            around,
            covers: (0..original.len() as u32).map(|t| vec![t]).collect(),
            covering: (0..original.len() as u32).map(|t| vec![t]).collect(),
            quadric,
            stamp: vec![0; points.len()],
            seen: vec![0; original.len()],
            tries: 0,
            incident,
        }
    }

    /// The corners of triangle `t`.
    fn corners(&self, t: [u32; 3]) -> Corners {
        t.map(|v| self.points[v as usize])
    }

    /// The current triangles around vertex `v` (its list cleaned of removed ones).
    fn current_around(&mut self, v: u32) -> Vec<u32> {
        let alive = &self.alive;
        self.around[v as usize].retain(|&t| alive[t as usize]);
        self.around[v as usize].clone()
    }

    /// Queues both collapses of each edge of triangle `t`.
    fn push_edges(&self, t: u32, queue: &mut BinaryHeap<Entry>) {
        let t = self.triangles[t as usize];
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            for (u, v) in [(a, b), (b, a)] {
                let q = add(self.quadric[u as usize], self.quadric[v as usize]);
                let cost = evaluate(q, self.points[v as usize]).max(0.0);
                queue.push((
                    Reverse(cost.to_bits()),
                    u,
                    v,
                    self.stamp[u as usize],
                    self.stamp[v as usize],
                ));
            }
        }
    }

    /// Collapses `u` into `v` when both proofs hold; whether it did.
    fn collapse(&mut self, u: u32, v: u32) -> bool {
        self.tries += 1;
        let removed = self.current_around(u);
        if !removed.iter().any(|&t| self.triangles[t as usize].contains(&v)) {
            return false;
        }
        let beside: Vec<u32> = (self.current_around(v).into_iter())
            .filter(|t| !removed.contains(t))
            .collect();
        let mut made: Vec<[u32; 3]> = Vec::new();
        for &t in &removed {
            let t = self.triangles[t as usize];
            if t.contains(&v) {
                continue;
            }
            let n = t.map(|w| if w == u { v } else { w });
            let same = |o: &[u32; 3]| sorted(*o) == sorted(n);
            if !(beside.iter().any(|&b| same(&self.triangles[b as usize])) || made.iter().any(same)) {
                made.push(n);
            }
        }
        // simplified → original, for the triangles it makes: first a quick look for a point
        // beyond the bound (most refusals), then the proofs
        let beyond = |p: Point, start: u32| self.nearest(p, start).1 > self.bound_squared;
        let probes = |c: Corners| [centroid(c), half(c[0], c[1]), half(c[1], c[2]), half(c[2], c[0])];
        let start = self.incident[v as usize];
        if made
            .iter()
            .any(|&n| probes(self.corners(n)).into_iter().any(|p| beyond(p, start)))
        {
            return false;
        }
        if !made.iter().all(|&n| self.near_original(n)) {
            return false;
        }
        // original → simplified, for the original triangles it uncovers
        let first = self.triangles.len() as u32;
        let mut candidates: Vec<(u32, Corners)> = (made.iter().enumerate())
            .map(|(i, &n)| (first + i as u32, self.corners(n)))
            .chain(beside.iter().map(|&b| (b, self.corners(self.triangles[b as usize]))))
            .collect();
        let shared = candidates.len();
        let mut recovered: Vec<(u32, Vec<u32>)> = Vec::new();
        for &t in &removed {
            for &o in &self.covering[t as usize] {
                if self.seen[o as usize] == self.tries || !self.covers[o as usize].contains(&t) {
                    continue;
                }
                self.seen[o as usize] = self.tries;
                candidates.truncate(shared);
                for &k in &self.covers[o as usize] {
                    if !removed.contains(&k) && !beside.contains(&k) {
                        candidates.push((k, self.corners(self.triangles[k as usize])));
                    }
                }
                match self.covered(self.corners(self.original[o as usize]), &candidates) {
                    Some(cover) => recovered.push((o, cover)),
                    None => return false,
                }
            }
        }
        self.commit(u, v, &removed, made, recovered);
        true
    }

    /// Makes a checked collapse: `removed` go, `made` come, each original triangle of
    /// `recovered` gets its new cover.
    fn commit(&mut self, u: u32, v: u32, removed: &[u32], made: Vec<[u32; 3]>, recovered: Vec<(u32, Vec<u32>)>) {
        for &t in removed {
            self.alive[t as usize] = false;
            self.covering[t as usize] = Vec::new();
        }
        for n in made {
            let id = self.triangles.len() as u32;
            self.triangles.push(n);
            self.alive.push(true);
            self.covering.push(Vec::new());
            for w in n {
                self.around[w as usize].push(id);
            }
        }
        for (o, cover) in recovered {
            for &k in &cover {
                if !self.covers[o as usize].contains(&k) {
                    self.covering[k as usize].push(o);
                }
            }
            self.covers[o as usize] = cover;
        }
        self.around[u as usize] = Vec::new();
        self.quadric[v as usize] = add(self.quadric[v as usize], self.quadric[u as usize]);
        self.stamp[u as usize] += 1;
        self.stamp[v as usize] += 1;
    }

    /// The nearest original triangle to `p` and its squared distance (m²).
    fn nearest(&self, p: Point, start: u32) -> (u32, f64) {
        let (t, d) = (self.bvh)
            .nearest(p, start, |t| {
                point_triangle_squared(p, self.corners(self.original[t as usize]))
            })
            .unwrap_or((start, f64::INFINITY));
        (t, d * d)
    }

    /// Whether every point of the triangle of vertices `n` is proven within `ε` of the original surface.
    fn near_original(&self, n: [u32; 3]) -> bool {
        // its corners are original vertices, on the original triangles around them
        let (c, near) = (self.corners(n), n.map(|v| self.incident[v as usize]));
        let mut cells = vec![(c, near, 0u32)];
        let mut examined = 0;
        while let Some((c, n, depth)) = cells.pop() {
            let fits = |t: u32| fits(c, self.corners(self.original[t as usize]), self.bound_squared);
            if fits(n[0]) || (n[1] != n[0] && fits(n[1])) || (n[2] != n[0] && n[2] != n[1] && fits(n[2])) {
                continue;
            }
            let middle = centroid(c);
            let (m, d) = self.nearest(middle, n[0]);
            if d > self.bound_squared {
                return false;
            }
            // or distances are 1-Lipschitz: dist(p, O) ≤ dist(centre, O) + |p − centre|
            let radius = (c.iter()).fold(0.0f64, |r, &p| r.max(squared(p, middle))).sqrt();
            if fits(m) || d.sqrt() + radius <= self.bound_squared.sqrt() {
                continue;
            }
            examined += 1;
            if depth >= MAX_DEPTH || examined > MAX_CELLS {
                return false;
            }
            let mids = [half(c[0], c[1]), half(c[1], c[2]), half(c[2], c[0])];
            let mut near_mid = [0u32; 3];
            for k in 0..3 {
                let (t, d) = self.nearest(mids[k], n[k]);
                if d > self.bound_squared {
                    return false;
                }
                near_mid[k] = t;
            }
            cells.extend(split(c, n, mids, near_mid).map(|(c, n)| (c, n, depth + 1)));
        }
        true
    }

    /// The triangles of `candidates` that prove every point of the original triangle `c`
    /// within `ε` of them (a cover), or `None` when no proof is found.
    fn covered(&self, c: Corners, candidates: &[(u32, Corners)]) -> Option<Vec<u32>> {
        let mut cover: Vec<u32> = Vec::new();
        let mut cells = vec![(c, 0u32)];
        let mut examined = 0;
        while let Some((c, depth)) = cells.pop() {
            // the triangles already in the cover first, then the others: the first that fits
            let (used, others): (Vec<_>, Vec<_>) = candidates.iter().partition(|(k, _)| cover.contains(k));
            let fit = (used.into_iter().chain(others))
                .find(|&&(_, t)| fits(c, t, self.bound_squared))
                .map(|&(k, _)| k);
            if let Some(id) = fit {
                if !cover.contains(&id) {
                    cover.push(id);
                }
                continue;
            }
            let beyond = |p: Point| {
                candidates
                    .iter()
                    .all(|&(_, t)| point_triangle_squared(p, t) > self.bound_squared)
            };
            examined += 1;
            if depth >= MAX_DEPTH || examined > MAX_CELLS || c.into_iter().any(beyond) {
                return None;
            }
            let mids = [half(c[0], c[1]), half(c[1], c[2]), half(c[2], c[0])];
            cells.extend(split(c, [0; 3], mids, [0; 3]).map(|(c, _)| (c, depth + 1)));
        }
        Some(cover)
    }
}

/// The four cells of triangle `c` cut at its edges' midpoints `mids` (`c₀c₁`, `c₁c₂`, `c₂c₀`),
/// each corner carrying its tag (`n` for `c`, `m` for `mids`).
fn split(c: Corners, n: [u32; 3], mids: Corners, m: [u32; 3]) -> [(Corners, [u32; 3]); 4] {
    [
        ([c[0], mids[0], mids[2]], [n[0], m[0], m[2]]),
        ([mids[0], c[1], mids[1]], [m[0], n[1], m[1]]),
        ([mids[2], mids[1], c[2]], [m[2], m[1], n[2]]),
        (mids, m),
    ]
}

/// Whether every corner of `cell` is within `bound_squared` (m²) of the triangle `t`: by
/// convexity, then every point of `cell` is.
fn fits(cell: Corners, t: Corners, bound_squared: f64) -> bool {
    cell.iter().all(|&p| point_triangle_squared(p, t) <= bound_squared)
}

fn squared(a: Point, b: Point) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

fn half(a: Point, b: Point) -> Point {
    [0, 1, 2].map(|k| (a[k] + b[k]) / 2.0)
}

fn centroid(c: Corners) -> Point {
    [0, 1, 2].map(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0)
}

fn sorted(mut t: [u32; 3]) -> [u32; 3] {
    t.sort_unstable();
    t
}

fn add(a: Quadric, b: Quadric) -> Quadric {
    std::array::from_fn(|i| a[i] + b[i])
}

/// The quadric of the plane of triangle `c`, weighted by its area.
fn plane_quadric(c: Corners) -> Quadric {
    let (e1, e2) = (
        [0, 1, 2].map(|k| c[1][k] - c[0][k]),
        [0, 1, 2].map(|k| c[2][k] - c[0][k]),
    );
    let n = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let twice_area = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if twice_area == 0.0 {
        return [0.0; 10];
    }
    let n = n.map(|x| x / twice_area);
    let d = -(n[0] * c[0][0] + n[1] * c[0][1] + n[2] * c[0][2]);
    let p = [n[0], n[1], n[2], d];
    let w = twice_area / 2.0;
    let mut q = [0.0; 10];
    let mut i = 0;
    for r in 0..4 {
        for s in r..4 {
            q[i] = w * p[r] * p[s];
            i += 1;
        }
    }
    q
}

/// `pᵀ Q p` at the point `x` (`p = (x, 1)`).
fn evaluate(q: Quadric, x: Point) -> f64 {
    let p = [x[0], x[1], x[2], 1.0];
    let mut sum = 0.0;
    let mut i = 0;
    for r in 0..4 {
        for s in r..4 {
            sum += if r == s { 1.0 } else { 2.0 } * q[i] * p[r] * p[s];
            i += 1;
        }
    }
    sum
}
