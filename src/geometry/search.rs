//! Searches of two triangle meshes by a simultaneous traversal of their bounding-volume
//! hierarchies: their distance ([`mesh_distance`]) and whether they touch ([`meshes_touch`]);
//! and of a mesh against a convex shape (a primitive) by a traversal of the mesh's hierarchy
//! against the shape's box and bounding sphere ([`mesh_shape_distance`], [`mesh_touches_shape`]).
//! Single-pose queries of [`super::CollisionSet`]; see its module doc for the bounds.

use std::cell::Cell;

use parry3d_f64::math::{Mat3 as PMat3, Pose as PPose, Vector as PVector};
use parry3d_f64::query::{DefaultQueryDispatcher, QueryDispatcher};
use parry3d_f64::shape::{Shape, Triangle};

use super::bvh::Node;
use super::node_hulls::apart;
use super::triangles::{Triangles, node_box};
/// A margin (m) far above the round-off of distances and their lower bounds (~1e-15 m) and far
/// below any distance that matters: a pair of boxes or triangles, or a sample, is passed over
/// only when its lower bound exceeds the best distance by this much, so that among triangle
/// pairs (or samples) whose distances tie to round-off the smallest computed distance is
/// found, whatever the order of the search ([`super::CollisionSet::touch`] looks inside boxes and triangles
/// this close to each other).
pub(super) const ROUND_OFF: f64 = 1e-9;

/// The smallest distance between a triangle of `m1` and a triangle of `m2` (`pos12`: `m2`'s
/// frame in `m1`'s), if below `bound`; `closest` seeds the search with a pair of triangles and
/// receives the closest pair found. 0 as soon as two triangles touch.
///
/// With a `tolerance` > 0 (m) the search stops short: a pair of nodes or triangles is passed
/// over as soon as its lower bound reaches the best distance found less the tolerance. What
/// it returns is still the distance of an actual pair of triangles, and the meshes' distance
/// is at most `tolerance` below it (`None`: not below `bound − tolerance`). It can pass over an
/// intersection only once it has found triangles within `tolerance` of each other (until then
/// everything it passes over has a positive lower bound): the caller searches exactly when it
/// returns a distance that small, or knows the meshes are apart.
pub(super) fn mesh_distance(
    m1: &Triangles,
    m2: &Triangles,
    pos12: &PPose,
    closest: &mut (u32, u32),
    bound: f64,
    tolerance: f64,
) -> Option<f64> {
    let triangles = |pair| triangle_distance(m1, m2, pos12, pair);
    let seeded = triangles(*closest);
    let best = Cell::new(if seeded < bound { seeded } else { bound });
    let found = Cell::new((seeded < bound).then_some(*closest));
    // each box re-boxed in the other's frame bounds the distance, and so does the gap of the
    // two boxes' projections on the line through their centres ([`Rebox::axis_gap`]): a pair
    // of nodes is opened only when all three are below the reach
    let (two_in_one, one_in_two) = (Rebox::new(pos12), Rebox::new(&pos12.inverse()));
    // what could be closer, or tie with the best to round-off, is looked at (with a
    // tolerance: what could be closer by more than it)
    let slack = if tolerance > 0.0 { -tolerance } else { ROUND_OFF };
    let reach = || best.get() + slack;
    let boxes_closer = |(i, n1): (u32, &Node), (j, n2): (u32, &Node)| {
        if best.get() <= 0.0 || reach() <= 0.0 {
            return false;
        }
        if n1.is_leaf() && n2.is_leaf() {
            // triangle_gap's exact boxes of the two triangles do better
            return true;
        }
        let (box1, box2) = (node_box(n1), node_box(n2));
        if !(nodes_within(&two_in_one, &one_in_two, n1, n2, reach() * reach())
            && two_in_one.axis_gap(&one_in_two, box1, box2) < reach())
        {
            return false;
        }
        // two upper nodes: their hulls' gap
        if m1.may_have_hull(i)
            && m2.may_have_hull(j)
            && let (Some(h1), Some(h2)) = (m1.node_hull(i), m2.node_hull(j))
        {
            let start = (box1.0 + box1.1) * 0.5 - two_in_one.point((box2.0 + box2.1) * 0.5);
            return !apart(h1, h2, pos12, start, reach());
        }
        true
    };
    m1.bvh().leaf_pairs(m2.bvh(), boxes_closer, |i, j| {
        if triangle_gap(&m1.triangle(i), &m2.triangle(j), &two_in_one) >= reach() {
            return true;
        }
        let d = triangles((i, j));
        if d < best.get() {
            best.set(d);
            found.set(Some((i, j)));
        }
        d > 0.0
    });
    let pair = found.get()?;
    *closest = pair;
    Some(best.get())
}

/// The distance between triangle `i` of `m1` and triangle `j` of `m2` (`pos12`: `m2`'s frame
/// in `m1`'s), parry's GJK; 0 when they touch or cross.
fn triangle_distance(m1: &Triangles, m2: &Triangles, pos12: &PPose, (i, j): (u32, u32)) -> f64 {
    DefaultQueryDispatcher
        .distance(pos12, &m1.triangle(i), &m2.triangle(j))
        .expect("parry supports triangle pairs")
        .distance
}

/// Whether the boxes of node `n1` (of m1) and node `n2` (of m2) may be closer than
/// `√squared_reach`: each box re-boxed in the other's frame (`two_in_one`: m2's in m1's,
/// `one_in_two` the inverse) bounds the distance of the triangles inside from below, and both
/// bounds must be below.
fn nodes_within(two_in_one: &Rebox, one_in_two: &Rebox, n1: &Node, n2: &Node, squared_reach: f64) -> bool {
    let (box1, box2) = (node_box(n1), node_box(n2));
    two_in_one.squared_gap(box1, box2) < squared_reach && one_in_two.squared_gap(box2, box1) < squared_reach
}

/// A relative pose `a_T_b` ready to re-box boxes of b in a's frame: its rotation matrix `R`,
/// `|R|` (entrywise absolute values) and its translation, computed once per mesh query instead
/// of once per box.
struct Rebox {
    rotation: PMat3,
    spread: PMat3,
    translation: PVector,
}

impl Rebox {
    /// The re-boxing by `a_T_b`.
    fn new(a_t_b: &PPose) -> Rebox {
        let rotation = PMat3::from_quat(a_t_b.rotation);
        Rebox {
            rotation,
            spread: rotation.abs(),
            translation: a_t_b.translation,
        }
    }

    /// Point `p` of b (b's frame) in a's frame.
    fn point(&self, p: PVector) -> PVector {
        self.rotation * p + self.translation
    }

    /// The gap between the box `(lo_a, hi_a)` of a (a's frame) and the box of b (b's frame)
    /// along the line through their centres: with `u` its direction (a's frame) and `c_a`,
    /// `c_b` the centres in a's frame, `|c_b − c_a| − |u|·h_a − |Rᵀu|·h_b` (each box's
    /// projection on `u` reaches `|u|·h` from its centre's, `h` its half extents in its own
    /// frame). Any direction separates two sets by the gap of their projections on it; along
    /// the centres' line, a box's reach is smaller than the re-boxed box's when the two are
    /// apart along a diagonal (`inverse` holds `Rᵀ`).
    fn axis_gap(&self, inverse: &Rebox, (lo_a, hi_a): (PVector, PVector), (lo_b, hi_b): (PVector, PVector)) -> f64 {
        let centre_a = (lo_a + hi_a) * 0.5;
        let between = self.point((lo_b + hi_b) * 0.5) - centre_a;
        let length = between.length();
        if length <= 0.0 {
            return f64::NEG_INFINITY;
        }
        let u = between / length;
        length - u.abs().dot((hi_a - lo_a) * 0.5) - (inverse.rotation * u).abs().dot((hi_b - lo_b) * 0.5)
    }

    /// The squared distance (m²) between the box `(mins, maxs)` of a (in a's frame) and the
    /// box of b `(mins, maxs)` (in b's frame) re-boxed in a's frame: a lower bound of the
    /// squared distance of any points inside the two. The box of b with centre `c` and half
    /// extents `h` re-boxes to centre `R c + t` and half extents `|R| h`; two boxes with
    /// centres `c₁`, `c₂` and half extents `h₁`, `h₂` are apart along each axis by
    /// `max(|c₁ − c₂| − h₁ − h₂, 0)`.
    fn squared_gap(&self, (mins_a, maxs_a): (PVector, PVector), (mins_b, maxs_b): (PVector, PVector)) -> f64 {
        let centre_b = self.point((mins_b + maxs_b) * 0.5);
        let half_b = self.spread * ((maxs_b - mins_b) * 0.5);
        let (centre_a, half_a) = ((mins_a + maxs_a) * 0.5, (maxs_a - mins_a) * 0.5);
        ((centre_a - centre_b).abs() - half_a - half_b)
            .max(PVector::ZERO)
            .length_squared()
    }
}

/// What [`meshes_touch`] found.
pub(super) enum Touch {
    /// Two triangles touch or cross.
    Crossing,
    /// No two triangles touch; the distance of the pair of triangles tried first (m), an
    /// upper bound of the meshes' distance.
    Apart(f64),
    /// The test opened more pairs of nodes than its budget before it could tell.
    Undecided,
}

/// Whether a triangle of `m1` and a triangle of `m2` (`pos12`: `m2`'s frame in `m1`'s) touch
/// or cross (parry's triangle distance 0, as [`mesh_distance`] reads an intersection), with
/// `closest` set to such a pair when they do. `closest` is tried first; then the traversal
/// opens only pairs of nodes whose boxes (each re-boxed in the other's frame) are within
/// [`ROUND_OFF`] of each other, and runs the triangle distance only on pairs of leaves that
/// [`triangle_gap`] does not put that far apart: far fewer than a distance search opens when
/// the meshes are some millimetres apart. Meshes a fraction of a millimetre apart along
/// large surfaces (the parts of a joint) have boxes touching all the way down, though: after
/// `budget` pairs of nodes the test gives up ([`Touch::Undecided`]).
pub(super) fn meshes_touch(
    m1: &Triangles,
    m2: &Triangles,
    pos12: &PPose,
    closest: &mut (u32, u32),
    budget: usize,
) -> Touch {
    let triangles = |pair| triangle_distance(m1, m2, pos12, pair);
    let seeded = triangles(*closest);
    if seeded <= 0.0 {
        return Touch::Crossing;
    }
    let (two_in_one, one_in_two) = (Rebox::new(pos12), Rebox::new(&pos12.inverse()));
    let slack = ROUND_OFF * ROUND_OFF;
    let opened = Cell::new(0);
    let boxes_touch = |(_, n1): (u32, &Node), (_, n2): (u32, &Node)| {
        opened.set(opened.get() + 1);
        opened.get() <= budget && nodes_within(&two_in_one, &one_in_two, n1, n2, slack)
    };
    let mut crossing = None;
    m1.bvh().leaf_pairs(m2.bvh(), boxes_touch, |i, j| {
        let touches =
            triangle_gap(&m1.triangle(i), &m2.triangle(j), &two_in_one) < ROUND_OFF && triangles((i, j)) <= 0.0;
        if touches {
            crossing = Some((i, j));
        }
        !touches
    });
    if let Some(pair) = crossing {
        *closest = pair;
        Touch::Crossing
    } else if opened.get() > budget {
        Touch::Undecided
    } else {
        Touch::Apart(seeded)
    }
}

/// A lower bound of the distance between triangle `t1` and triangle `t2` placed by `two_in_one`,
/// cheaper than the distance itself: the larger of the gap between their exact bounding boxes
/// (in `t1`'s frame) and the gap between their projections on the line through their
/// centroids (any direction separates by the gap of the projections).
fn triangle_gap(t1: &Triangle, t2: &Triangle, two_in_one: &Rebox) -> f64 {
    let (a, b, c) = (two_in_one.point(t2.a), two_in_one.point(t2.b), two_in_one.point(t2.c));
    let (lo1, hi1) = (t1.a.min(t1.b).min(t1.c), t1.a.max(t1.b).max(t1.c));
    let (lo2, hi2) = (a.min(b).min(c), a.max(b).max(c));
    let boxes = (lo1 - hi2).max(lo2 - hi1).max(PVector::ZERO).length();
    let axis = (a + b + c - t1.a - t1.b - t1.c).normalize_or_zero();
    let top1 = axis.dot(t1.a).max(axis.dot(t1.b)).max(axis.dot(t1.c));
    let bottom2 = axis.dot(a).min(axis.dot(b)).min(axis.dot(c));
    boxes.max(bottom2 - top1)
}

/// A convex shape placed in a mesh's frame, ready for the bounds of [`mesh_shape_distance`]
/// and [`mesh_touches_shape`]: its box and its bounding sphere in that frame.
struct PlacedShape<'a> {
    shape: &'a dyn Shape,
    /// The shape's frame in the mesh's.
    pose: &'a PPose,
    /// Its axis-aligned box in the mesh's frame (`mins`, `maxs`).
    aabb: (PVector, PVector),
    /// Its bounding sphere in the mesh's frame: centre and radius (m).
    sphere: (PVector, f64),
}

impl<'a> PlacedShape<'a> {
    fn new(shape: &'a dyn Shape, pose: &'a PPose) -> PlacedShape<'a> {
        let aabb = shape.compute_aabb(pose);
        let sphere = shape.compute_bounding_sphere(pose);
        PlacedShape {
            shape,
            pose,
            aabb: (aabb.mins, aabb.maxs),
            sphere: (sphere.center, sphere.radius),
        }
    }

    /// A lower bound of the distance between the shape and anything inside the box `(lo, hi)`
    /// (mesh frame): the largest of the gap between the two boxes, the gap between the box and
    /// the bounding sphere (`|c − clamp(c, lo, hi)| − r`), and the shape's distance to the
    /// box's centre less its half diagonal (distances are 1-Lipschitz).
    fn gap(&self, (lo, hi): (PVector, PVector)) -> f64 {
        let boxes = self.box_gap((lo, hi));
        let (c, r) = self.sphere;
        let sphere = (c - c.clamp(lo, hi)).length() - r;
        let centre = self.to_point((lo + hi) * 0.5) - (hi - lo).length() * 0.5;
        boxes.max(sphere).max(centre)
    }

    /// The distance from point `p` (mesh frame) to the shape, solid (0 inside): parry's exact
    /// point query.
    fn to_point(&self, p: PVector) -> f64 {
        self.shape.distance_to_point(self.pose, p, true)
    }

    /// The gap between the box `(lo, hi)` (mesh frame) and the shape's box.
    fn box_gap(&self, (lo, hi): (PVector, PVector)) -> f64 {
        let (mins, maxs) = self.aabb;
        (lo - maxs).max(mins - hi).max(PVector::ZERO).length()
    }

    /// A lower bound of the distance between the shape and triangle `t`: the shape's
    /// distance to the triangle's centroid less the centroid's distance to the farthest
    /// corner, or [`PlacedShape::box_gap`] to the triangle's exact box if that is larger.
    fn triangle_gap(&self, t: &Triangle) -> f64 {
        let centroid = (t.a + t.b + t.c) / 3.0;
        let reach = (t.a - centroid)
            .length()
            .max((t.b - centroid).length())
            .max((t.c - centroid).length());
        let boxes = self.box_gap((t.a.min(t.b).min(t.c), t.a.max(t.b).max(t.c)));
        boxes.max(self.to_point(centroid) - reach)
    }

    /// The distance between triangle `i` of `m` and the shape (parry's GJK; 0 when they touch).
    fn distance(&self, m: &Triangles, i: u32) -> f64 {
        DefaultQueryDispatcher
            .distance(self.pose, &m.triangle(i), self.shape)
            .expect("parry supports triangles against convex shapes")
            .distance
    }
}

/// The smallest distance between a triangle of `m` and the convex `shape` (`pos12`: the
/// shape's frame in `m`'s), if below `bound`; `closest` seeds the search with a triangle and
/// receives the closest found. 0 as soon as a triangle touches the shape. The mesh is its
/// triangles (a surface), as in [`mesh_distance`]: the value is parry's distance of the mesh
/// and the shape, computed triangle by triangle on the same relative pose.
///
/// A node of `m`'s hierarchy is opened only while [`PlacedShape::gap`] is below the best
/// distance found; `tolerance` as in [`mesh_distance`] (and, as there, it can pass over a
/// touching triangle only once it has found one within `tolerance` of the shape).
pub(super) fn mesh_shape_distance(
    m: &Triangles,
    shape: &dyn Shape,
    pos12: &PPose,
    closest: &mut u32,
    bound: f64,
    tolerance: f64,
) -> Option<f64> {
    let placed = PlacedShape::new(shape, pos12);
    let seeded = placed.distance(m, *closest);
    let best = Cell::new(if seeded < bound { seeded } else { bound });
    let mut found = (seeded < bound).then_some(*closest);
    let slack = if tolerance > 0.0 { -tolerance } else { ROUND_OFF };
    let reach = || best.get() + slack;
    let open = |n: &Node| best.get() > 0.0 && reach() > 0.0 && placed.gap(node_box(n)) < reach();
    m.bvh().leaves(open, |i| {
        if placed.triangle_gap(&m.triangle(i)) >= reach() {
            return true;
        }
        let d = placed.distance(m, i);
        if d < best.get() {
            best.set(d);
            found = Some(i);
        }
        d > 0.0
    });
    *closest = found?;
    Some(best.get())
}

/// [`meshes_touch`] for a mesh and a convex shape: whether a triangle of `m` touches or
/// crosses `shape` (`pos12`: the shape's frame in `m`'s), with `closest` set to such a
/// triangle when one does. Opens only the nodes whose [`PlacedShape::gap`] is below
/// [`ROUND_OFF`], at most `budget` of them.
pub(super) fn mesh_touches_shape(
    m: &Triangles,
    shape: &dyn Shape,
    pos12: &PPose,
    closest: &mut u32,
    budget: usize,
) -> Touch {
    let placed = PlacedShape::new(shape, pos12);
    let seeded = placed.distance(m, *closest);
    if seeded <= 0.0 {
        return Touch::Crossing;
    }
    let opened = Cell::new(0);
    let open = |n: &Node| {
        opened.set(opened.get() + 1);
        opened.get() <= budget && placed.gap(node_box(n)) < ROUND_OFF
    };
    let mut crossing = None;
    m.bvh().leaves(open, |i| {
        let touches = placed.triangle_gap(&m.triangle(i)) < ROUND_OFF && placed.distance(m, i) <= 0.0;
        if touches {
            crossing = Some(i);
        }
        !touches
    });
    if let Some(i) = crossing {
        *closest = i;
        Touch::Crossing
    } else if opened.get() > budget {
        Touch::Undecided
    } else {
        Touch::Apart(seeded)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use parry3d_f64::math::Rot3 as PRot3;
    use parry3d_f64::query;
    use parry3d_f64::shape::{Ball, Cuboid, Cylinder, TriMesh};

    /// The built-in gripper mesh of the Faze4 (2,672 triangles), in metres: ours, and parry's
    /// `TriMesh` of the same triangles.
    fn gripper() -> (Triangles, TriMesh) {
        let mesh = crate::faze4::meshes::mesh("hvataljka").expect("built in");
        let points: Vec<PVector> = (mesh.positions.iter())
            .map(|p| PVector::new(p[0] as f64, p[1] as f64, p[2] as f64))
            .collect();
        let triangles: Vec<[u32; 3]> = mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let parry = TriMesh::new(points.clone(), triangles.clone()).unwrap();
        (Triangles::new(points, triangles, None), parry)
    }

    /// `n` seeded pseudo-random poses: turns up to ±3 rad about a random axis or (every other
    /// one, on average) about x, and offsets within `reach` (m) of `centre`.
    pub(in crate::geometry) fn poses(n: usize, centre: PVector, reach: f64) -> Vec<PPose> {
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        (0..n)
            .map(|_| {
                let axis = match next() > 0.0 {
                    true => PVector::new(next(), next(), next()).normalize_or(PVector::X),
                    false => PVector::X,
                };
                let rotation = PRot3::from_scaled_axis(axis * 3.0 * next());
                PPose::from_parts(centre + PVector::new(next(), next(), next()) * reach, rotation)
            })
            .collect()
    }

    /// The gaps that pass a pair of nodes over are lower bounds of their boxes' distance (parry's
    /// cuboid–cuboid distance) at any relative pose, and the gap along the centres' line is
    /// the tighter one on some of them (boxes apart along a diagonal).
    #[test]
    fn the_gaps_between_two_boxes_are_below_their_distance() {
        let (lo_a, hi_a) = (PVector::new(-0.01, 0.0, -0.02), PVector::new(0.03, 0.004, 0.01));
        let (lo_b, hi_b) = (PVector::new(0.0, -0.015, 0.002), PVector::new(0.002, 0.025, 0.03));
        let cuboid =
            |lo: PVector, hi: PVector| (Cuboid::new((hi - lo) * 0.5), PPose::from_translation((lo + hi) * 0.5));
        let ((box_a, at_a), (box_b, at_b)) = (cuboid(lo_a, hi_a), cuboid(lo_b, hi_b));
        let mut tighter = 0;
        for pose in poses(200, PVector::ZERO, 0.08) {
            let (two_in_one, one_in_two) = (Rebox::new(&pose), Rebox::new(&pose.inverse()));
            let distance = query::distance(&at_a, &box_a, &(pose * at_b), &box_b).unwrap().distance;
            let axis = two_in_one.axis_gap(&one_in_two, (lo_a, hi_a), (lo_b, hi_b));
            let reboxed = two_in_one.squared_gap((lo_a, hi_a), (lo_b, hi_b)).sqrt();
            assert!(axis <= distance + 1e-12, "{axis} above {distance} at {pose:?}");
            assert!(reboxed <= distance + 1e-12, "{reboxed} above {distance} at {pose:?}");
            tighter += usize::from(axis > reboxed + 1e-4);
        }
        assert!(
            tighter > 20,
            "the centres' line is the tighter bound {tighter} times of 200"
        );
    }

    #[test]
    fn the_mesh_shape_search_is_parrys_distance_and_its_crossing_test_agrees() {
        let (m, parry_mesh) = gripper();
        let shapes: [Box<dyn Shape>; 3] = [
            Box::new(Ball::new(0.01)),
            Box::new(Cuboid::new(PVector::new(0.01, 0.02, 0.005))),
            Box::new(Cylinder::new(0.02, 0.008)),
        ];
        let (mut touching, mut apart) = (0, 0);
        for shape in &shapes {
            let mut closest = 0;
            for pose in poses(60, parry_mesh.local_aabb().center(), 0.06) {
                let parry = query::distance(&PPose::IDENTITY, &parry_mesh, &pose, &**shape)
                    .unwrap()
                    .distance;
                // exact, seeded by the previous pose's closest triangle, bit for bit
                let ours = mesh_shape_distance(&m, &**shape, &pose, &mut closest, f64::INFINITY, 0.0);
                assert_eq!(ours, Some(parry), "{pose:?}");
                // bounded: nothing when it is not below the bound
                let (mut seed, bound) = (0, parry);
                assert_eq!(mesh_shape_distance(&m, &**shape, &pose, &mut seed, bound, 0.0), None);
                // within a tolerance: an actual distance at most that far above
                let mut seed = 0;
                let near = mesh_shape_distance(&m, &**shape, &pose, &mut seed, f64::INFINITY, 0.002).unwrap();
                assert!(near >= parry && near <= parry + 0.002, "{near} against {parry}");
                let d = query::distance(&PPose::IDENTITY, &m.triangle(seed), &pose, &**shape)
                    .unwrap()
                    .distance;
                assert_eq!(d, near, "the triangle it names is at that distance");
                // the crossing test, with no budget, agrees with the distance
                let mut seed = 0;
                match mesh_touches_shape(&m, &**shape, &pose, &mut seed, usize::MAX) {
                    Touch::Crossing => {
                        assert_eq!(parry, 0.0);
                        touching += 1;
                    }
                    Touch::Apart(upper) => {
                        assert!(parry > 0.0 && upper >= parry);
                        apart += 1;
                    }
                    Touch::Undecided => unreachable!("no budget"),
                }
            }
        }
        assert!(
            touching > 10 && apart > 10,
            "both cases exercised: {touching} touching, {apart} apart"
        );
    }
}
