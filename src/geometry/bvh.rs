//! A bounding-volume hierarchy of a triangle mesh's triangles, flat in memory, and the nearest
//! triangle to a point.
//!
//! This file uses nothing but `std`: `build.rs` includes it (`#[path]`) to build the Faze4's
//! hierarchies at build time, which the binary then carries ([`Bvh::to_bytes`],
//! [`Bvh::from_bytes`], which checks what it reads). A node's box is the smallest box of its
//! triangles' corners in f64, computed from the same points the searches read (an inner box read
//! back from bytes is that box rounded outwards to f32).
//!
//! Layout: one node per triangle (a leaf) and one per split (2n − 1 in all), node 0 the root,
//! each inner node's two children stored side by side. A node's triangles, sorted by centroid
//! along each axis, are split where the surface-area heuristic is lowest (the smaller the
//! children's boxes, the fewer pairs of them a search opens).

/// A point (m), or a vector.
pub type Point = [f64; 3];

/// One node of a [`Bvh`]: its box and either its triangle (a leaf) or its two children.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// The box's smallest corner (m).
    pub lo: Point,
    /// The box's largest corner (m).
    pub hi: Point,
    /// A leaf's triangle, or an inner node's first child (the second is next to it).
    item: u32,
    /// Whether it is a leaf.
    leaf: bool,
}

impl Node {
    /// Whether it is a leaf (one triangle).
    pub fn is_leaf(&self) -> bool {
        self.leaf
    }
}

/// A bounding-volume hierarchy over the triangles of a mesh (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
}

impl Bvh {
    /// The hierarchy of `triangles` (three indices each into `points`); empty for no
    /// triangles.
    pub fn build(points: &[Point], triangles: &[[u32; 3]]) -> Bvh {
        let mut items: Vec<(u32, Point)> = (triangles.iter().enumerate())
            .map(|(i, t)| {
                let c = t.map(|v| points[v as usize]);
                (i as u32, [0, 1, 2].map(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0))
            })
            .collect();
        let mut bvh = Bvh {
            nodes: Vec::with_capacity((2 * triangles.len()).saturating_sub(1)),
        };
        if !items.is_empty() {
            bvh.nodes.push(Node {
                lo: [0.0; 3],
                hi: [0.0; 3],
                item: 0,
                leaf: true,
            });
            bvh.split(0, &mut items, points, triangles);
        }
        bvh
    }

    /// Fills node `at` with `items` (triangle, centroid), splitting them below it.
    fn split(&mut self, at: usize, items: &mut [(u32, Point)], points: &[Point], triangles: &[[u32; 3]]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for (t, c) in items.iter() {
            for v in triangles[*t as usize] {
                let p = points[v as usize];
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            for k in 0..3 {
                clo[k] = clo[k].min(c[k]);
                chi[k] = chi[k].max(c[k]);
            }
        }
        (self.nodes[at].lo, self.nodes[at].hi) = (lo, hi);
        if items.len() == 1 {
            self.nodes[at].item = items[0].0;
            return;
        }
        // the cheapest split of the three axes' (ties to the earlier axis)
        let sort = |items: &mut [(u32, Point)], axis: usize| {
            items.sort_unstable_by(|x, y| x.1[axis].total_cmp(&y.1[axis]).then(x.0.cmp(&y.0)))
        };
        let mut best = (f64::INFINITY, 0, 0);
        for axis in 0..3 {
            if chi[axis] > clo[axis] {
                sort(items, axis);
                let (cost, at) = surface_split(items, points, triangles);
                if cost < best.0 {
                    best = (cost, axis, at);
                }
            }
        }
        let (_, axis, mut half) = best;
        sort(items, axis);
        if half == 0 {
            half = items.len() / 2;
        }
        let first = self.nodes.len();
        self.nodes[at].item = first as u32;
        self.nodes[at].leaf = false;
        let empty = Node {
            lo,
            hi,
            item: 0,
            leaf: true,
        };
        self.nodes.extend([empty, empty]);
        let (left, right) = items.split_at_mut(half);
        self.split(first, left, points, triangles);
        self.split(first + 1, right, points, triangles);
    }

    /// Whether it has no triangle.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// How many nodes it has (node 0 the root).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Node `i`'s triangle (a leaf) or its two children (an inner node).
    pub fn below(&self, i: u32) -> Result<u32, [u32; 2]> {
        let n = &self.nodes[i as usize];
        if n.leaf { Ok(n.item) } else { Err(self.children(n)) }
    }

    /// The two children of inner node `n`.
    fn children(&self, n: &Node) -> [u32; 2] {
        [n.item, n.item + 1]
    }

    /// Every pair of leaves (a triangle of this mesh, a triangle of `other`'s) reached by a
    /// simultaneous descent that opens a pair of nodes only when `open` says so (it is asked of
    /// every pair reached, leaves included), each told to `leaf`, which returns whether to go
    /// on. Depth first, the larger box of a pair split first.
    pub fn leaf_pairs(
        &self,
        other: &Bvh,
        mut open: impl FnMut((u32, &Node), (u32, &Node)) -> bool,
        mut leaf: impl FnMut(u32, u32) -> bool,
    ) {
        if self.is_empty() || other.is_empty() {
            return;
        }
        let mut stack: Vec<(u32, u32)> = Vec::with_capacity(64);
        stack.push((0, 0));
        while let Some((i, j)) = stack.pop() {
            let (n1, n2) = (&self.nodes[i as usize], &other.nodes[j as usize]);
            if !open((i, n1), (j, n2)) {
                continue;
            }
            match (n1.leaf, n2.leaf) {
                (true, true) => {
                    if !leaf(n1.item, n2.item) {
                        return;
                    }
                }
                (false, true) => stack.extend(self.children(n1).map(|c| (c, j)).iter().rev()),
                (true, false) => stack.extend(other.children(n2).map(|c| (i, c)).iter().rev()),
                (false, false) => {
                    if extent(n1) >= extent(n2) {
                        stack.extend(self.children(n1).map(|c| (c, j)).iter().rev());
                    } else {
                        stack.extend(other.children(n2).map(|c| (i, c)).iter().rev());
                    }
                }
            }
        }
    }

    /// Every leaf reached by a descent that opens a node only when `open` says so (leaves
    /// included), each triangle told to `leaf`, which returns whether to go on.
    pub fn leaves(&self, mut open: impl FnMut(&Node) -> bool, mut leaf: impl FnMut(u32) -> bool) {
        if self.is_empty() {
            return;
        }
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        stack.push(0);
        while let Some(i) = stack.pop() {
            let n = &self.nodes[i as usize];
            if !open(n) {
                continue;
            }
            if n.leaf {
                if !leaf(n.item) {
                    return;
                }
            } else {
                stack.extend(self.children(n).iter().rev());
            }
        }
    }

    /// The triangle nearest point `p` and its distance (m), `squared(t)` giving triangle `t`'s
    /// squared distance to `p`; `start` (a triangle, e.g. the last answer nearby) bounds the
    /// search at once. `None` when empty.
    pub fn nearest(&self, p: Point, start: u32, squared: impl Fn(u32) -> f64) -> Option<(u32, f64)> {
        let root = self.nodes.first()?;
        let mut best = (start, squared(start));
        let mut stack: Vec<(u32, f64)> = Vec::with_capacity(64);
        stack.push((0, box_squared(root, p)));
        while let Some((i, gap)) = stack.pop() {
            if gap >= best.1 {
                continue;
            }
            let n = &self.nodes[i as usize];
            if n.leaf {
                let d = squared(n.item);
                if d < best.1 {
                    best = (n.item, d);
                }
                continue;
            }
            let [l, r] = self.children(n);
            let (gl, gr) = (
                box_squared(&self.nodes[l as usize], p),
                box_squared(&self.nodes[r as usize], p),
            );
            // the nearer child on top
            if gl <= gr {
                stack.extend([(r, gr), (l, gl)]);
            } else {
                stack.extend([(l, gl), (r, gr)]);
            }
        }
        Some((best.0, best.1.sqrt()))
    }

    /// The hierarchy as bytes (little-endian): a u32 node count; per node a u32, its triangle
    /// (a leaf, top bit set) or its first child; then per inner node, in order, its box as six
    /// f32 rounded outwards (so that it still holds its triangles). A leaf's box is its
    /// triangle's, computed again when read ([`Bvh::from_bytes`]).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(4 + 4 * self.nodes.len() + 12 * self.nodes.len());
        out.extend((self.nodes.len() as u32).to_le_bytes());
        for n in &self.nodes {
            out.extend((n.item | if n.leaf { 1 << 31 } else { 0 }).to_le_bytes());
        }
        for n in self.nodes.iter().filter(|n| !n.leaf) {
            for (lo, hi) in n.lo.iter().zip(&n.hi) {
                out.extend(outwards(*lo, true).to_le_bytes());
                out.extend(outwards(*hi, false).to_le_bytes());
            }
        }
        out
    }

    /// [`Bvh::to_bytes`] read back from the front of `bytes` as a hierarchy of `triangles`
    /// (indices into `points`), and the bytes after it; `None` unless it is one, whatever the
    /// bytes: every triangle a leaf exactly once, every other node the parent of two nodes
    /// after it, and every inner box holding its children's (the leaves' boxes are computed from
    /// the triangles). A hierarchy that passes may be a poor one, never a wrong one: every box
    /// holds the triangles below it.
    pub fn from_bytes<'b>(bytes: &'b [u8], points: &[Point], triangles: &[[u32; 3]]) -> Option<(Bvh, &'b [u8])> {
        let u32_at = |b: &[u8]| u32::from_le_bytes(b.try_into().unwrap());
        let count = u32_at(bytes.get(..4)?) as usize;
        if count != (2 * triangles.len()).saturating_sub(1) {
            return None;
        }
        let words = bytes.get(4..4 + 4 * count)?;
        let mut nodes: Vec<Node> = (words.chunks_exact(4))
            .map(|w| {
                let word = u32_at(w);
                Node {
                    lo: [0.0; 3],
                    hi: [0.0; 3],
                    item: word & !(1 << 31),
                    leaf: word >> 31 == 1,
                }
            })
            .collect();
        let inner = nodes.iter().filter(|n| !n.leaf).count();
        let boxes_end = (4 + 4 * count).checked_add(inner.checked_mul(24)?)?;
        let boxes = bytes.get(4 + 4 * count..boxes_end)?;
        // each triangle once, each node but the root below exactly one parent, after it
        let (mut leaf_of, mut parents) = (vec![false; triangles.len()], vec![0u8; count]);
        for (i, n) in nodes.iter().enumerate() {
            let c = n.item as usize;
            match n.leaf {
                true => {
                    if c >= triangles.len() || std::mem::replace(&mut leaf_of[c], true) {
                        return None;
                    }
                }
                false => {
                    if c <= i || c + 1 >= count {
                        return None;
                    }
                    parents[c] += 1;
                    parents[c + 1] += 1;
                }
            }
        }
        if parents.iter().skip(1).any(|&p| p != 1) || parents.first().is_some_and(|&p| p != 0) {
            return None;
        }
        let mut stored = boxes.chunks_exact(24);
        for n in nodes.iter_mut() {
            if n.leaf {
                let c = triangles[n.item as usize].map(|v| points.get(v as usize).copied());
                let [Some(a), Some(b), Some(c)] = c else {
                    return None;
                };
                n.lo = [0, 1, 2].map(|k| a[k].min(b[k]).min(c[k]));
                n.hi = [0, 1, 2].map(|k| a[k].max(b[k]).max(c[k]));
            } else {
                let b = stored.next()?;
                let f = |k: usize| f32::from_le_bytes(b[4 * k..4 * k + 4].try_into().unwrap()) as f64;
                n.lo = [f(0), f(2), f(4)];
                n.hi = [f(1), f(3), f(5)];
            }
        }
        // children come after their parents: each box is checked against its children's
        for i in (0..count).rev() {
            if nodes[i].leaf {
                continue;
            }
            let [l, r] = [nodes[i].item as usize, nodes[i].item as usize + 1];
            let holds = |c: &Node| (0..3).all(|k| nodes[i].lo[k] <= c.lo[k] && c.hi[k] <= nodes[i].hi[k]);
            if !holds(&nodes[l]) || !holds(&nodes[r]) {
                return None;
            }
        }
        Some((Bvh { nodes }, &bytes[boxes_end..]))
    }
}

/// `x` as an f32 no larger (`down`) or no smaller than it.
fn outwards(x: f64, down: bool) -> f32 {
    let f = x as f32;
    match down {
        true if f as f64 > x => f.next_down(),
        false if (f as f64) < x => f.next_up(),
        _ => f,
    }
}

/// Where to split `items` (sorted along an axis): the split that minimises the surface-area
/// heuristic, `area(left)·|left| + area(right)·|right|` (the boxes' half surfaces), over every
/// position (ties to the middle): its cost and position.
fn surface_split(items: &[(u32, Point)], points: &[Point], triangles: &[[u32; 3]]) -> (f64, usize) {
    let n = items.len();
    let grow = |b: &mut (Point, Point), t: u32| {
        for v in triangles[t as usize] {
            let p = points[v as usize];
            for k in 0..3 {
                b.0[k] = b.0[k].min(p[k]);
                b.1[k] = b.1[k].max(p[k]);
            }
        }
    };
    let area = |b: &(Point, Point)| {
        let d = [0, 1, 2].map(|k| (b.1[k] - b.0[k]).max(0.0));
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    };
    let empty = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    // the area of the right part from each position on
    let mut right = vec![0.0; n];
    let mut b = empty;
    for i in (1..n).rev() {
        grow(&mut b, items[i].0);
        right[i] = area(&b);
    }
    let (mut best, mut at) = (f64::INFINITY, n / 2);
    let mut b = empty;
    for i in 1..n {
        grow(&mut b, items[i - 1].0);
        let cost = area(&b) * i as f64 + right[i] * (n - i) as f64;
        if cost < best || (cost == best && i.abs_diff(n / 2) < at.abs_diff(n / 2)) {
            (best, at) = (cost, i);
        }
    }
    (best, at)
}

/// A node's box size: the sum of its three extents.
fn extent(n: &Node) -> f64 {
    (n.hi[0] - n.lo[0]) + (n.hi[1] - n.lo[1]) + (n.hi[2] - n.lo[2])
}

/// The squared distance (m²) from point `p` to node `n`'s box (0 inside).
fn box_squared(n: &Node, p: Point) -> f64 {
    (0..3)
        .map(|k| {
            let d = (n.lo[k] - p[k]).max(p[k] - n.hi[k]).max(0.0);
            d * d
        })
        .sum()
}

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The squared distance (m²) from point `p` to the triangle `(a, b, c)` (its closest point by
/// Voronoi regions, as in Ericson's *Real-Time Collision Detection* §5.1.5).
pub fn point_triangle_squared(p: Point, [a, b, c]: [Point; 3]) -> f64 {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    let closest = if d1 <= 0.0 && d2 <= 0.0 {
        a
    } else {
        let bp = sub(p, b);
        let (d3, d4) = (dot(ab, bp), dot(ac, bp));
        let cp = sub(p, c);
        let (d5, d6) = (dot(ab, cp), dot(ac, cp));
        let (vc, vb, va) = (d1 * d4 - d3 * d2, d5 * d2 - d1 * d6, d3 * d6 - d5 * d4);
        let along =
            |from: Point, dir: Point, t: f64| [from[0] + t * dir[0], from[1] + t * dir[1], from[2] + t * dir[2]];
        if d3 >= 0.0 && d4 <= d3 {
            b
        } else if d6 >= 0.0 && d5 <= d6 {
            c
        } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            along(a, ab, d1 / (d1 - d3))
        } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            along(a, ac, d2 / (d2 - d6))
        } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)))
        } else {
            let denom = va + vb + vc;
            if denom.abs() <= f64::MIN_POSITIVE || !denom.is_finite() {
                // a triangle with no area: the nearest of its three edges
                return [(a, b), (b, c), (c, a)]
                    .map(|(s, e)| point_segment_squared(p, s, e))
                    .into_iter()
                    .fold(f64::INFINITY, f64::min);
            }
            let (v, w) = (vb / denom, vc / denom);
            [0, 1, 2].map(|k| a[k] + ab[k] * v + ac[k] * w)
        }
    };
    let d = sub(p, closest);
    dot(d, d)
}

/// The squared distance (m²) from point `p` to the segment from `s` to `e`.
fn point_segment_squared(p: Point, s: Point, e: Point) -> f64 {
    let (se, sp) = (sub(e, s), sub(p, s));
    let len = dot(se, se);
    let t = if len > 0.0 {
        (dot(sp, se) / len).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = [0, 1, 2].map(|k| sp[k] - t * se[k]);
    dot(d, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded pseudo-random number in [-1, 1).
    fn rng(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    #[test]
    fn point_triangle_distance_is_the_least_over_a_fine_sampling() {
        let mut state = 7;
        for _ in 0..200 {
            let tri = [0; 3].map(|_| [0; 3].map(|_| rng(&mut state)));
            let p = [0; 3].map(|_| 2.0 * rng(&mut state));
            let d = point_triangle_squared(p, tri).sqrt();
            // every point of the triangle is at least d away, and some point within 1e-3 of d
            let mut least = f64::INFINITY;
            let n = 200;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    let q = [0, 1, 2].map(|k| tri[0][k] + u * (tri[1][k] - tri[0][k]) + v * (tri[2][k] - tri[0][k]));
                    let e = sub(p, q);
                    least = least.min(dot(e, e).sqrt());
                }
            }
            assert!(d <= least + 1e-12, "{d} above a point at {least}");
            assert!(least - d < 0.02, "{d} against sampled {least}");
        }
        // a degenerate triangle (a segment) and a point on it
        let seg = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert_eq!(point_triangle_squared([1.5, 1.0, 0.0], seg), 1.0);
    }

    #[test]
    fn the_hierarchy_holds_every_triangle_once_and_finds_the_nearest_and_the_pairs_of_a_brute_force() {
        let mut state = 11;
        let points: Vec<Point> = (0..300).map(|_| [0; 3].map(|_| rng(&mut state))).collect();
        let triangles: Vec<[u32; 3]> = (0..200)
            .map(|_| [0; 3].map(|_| ((rng(&mut state) + 1.0) * 150.0) as u32 % 300))
            .collect();
        let bvh = Bvh::build(&points, &triangles);
        let bytes = bvh.to_bytes();
        let (back, rest) = Bvh::from_bytes(&bytes, &points, &triangles).unwrap();
        assert!(rest.is_empty());
        // the same tree, every box holding the one built (the inner ones rounded to f32)
        for (a, b) in back.nodes.iter().zip(&bvh.nodes) {
            assert_eq!((a.item, a.leaf), (b.item, b.leaf));
            assert!((0..3).all(|k| a.lo[k] <= b.lo[k] && b.hi[k] <= a.hi[k] && b.lo[k] - a.lo[k] < 1e-6));
        }
        // another mesh's triangles, a truncated or altered file: refused
        assert!(Bvh::from_bytes(&bytes, &points, &triangles[1..]).is_none());
        assert!(Bvh::from_bytes(&bytes[..bytes.len() - 1], &points, &triangles).is_none());
        let mut shrunk = bytes.clone();
        let at = 4 + 4 * bvh.nodes.len() + 4; // the root's largest x
        shrunk[at..at + 4].copy_from_slice(&(-10.0f32).to_le_bytes());
        assert!(Bvh::from_bytes(&shrunk, &points, &triangles).is_none());
        let corners = |t: u32| triangles[t as usize].map(|v| points[v as usize]);
        let mut seen = vec![0; triangles.len()];
        bvh.leaves(
            |_| true,
            |t| {
                seen[t as usize] += 1;
                true
            },
        );
        assert!(seen.iter().all(|&n| n == 1));
        for _ in 0..50 {
            let p = [0; 3].map(|_| 1.5 * rng(&mut state));
            let (t, d) = bvh.nearest(p, 0, |t| point_triangle_squared(p, corners(t))).unwrap();
            let brute = (0..triangles.len() as u32)
                .map(|t| point_triangle_squared(p, corners(t)).sqrt())
                .fold(f64::INFINITY, f64::min);
            assert_eq!(d, brute);
            assert_eq!(point_triangle_squared(p, corners(t)).sqrt(), d);
        }
        // the pairs whose boxes overlap, against every pair
        let overlap = |a: &Node, b: &Node| (0..3).all(|k| a.lo[k] <= b.hi[k] && b.lo[k] <= a.hi[k]);
        let mut found = Vec::new();
        bvh.leaf_pairs(
            &bvh,
            |(_, a), (_, b)| overlap(a, b),
            |i, j| {
                found.push((i, j));
                true
            },
        );
        found.sort();
        let leaf = |t: u32| {
            let c = corners(t);
            let lo = [0, 1, 2].map(|k| c[0][k].min(c[1][k]).min(c[2][k]));
            let hi = [0, 1, 2].map(|k| c[0][k].max(c[1][k]).max(c[2][k]));
            Node {
                lo,
                hi,
                item: t,
                leaf: true,
            }
        };
        let mut brute = Vec::new();
        for i in 0..triangles.len() as u32 {
            for j in 0..triangles.len() as u32 {
                if overlap(&leaf(i), &leaf(j)) {
                    brute.push((i, j));
                }
            }
        }
        assert_eq!(found, brute);
    }
}
