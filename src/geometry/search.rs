//! Searches of two triangle meshes by a simultaneous traversal of their bounding-volume
//! hierarchies: their distance ([`mesh_distance`]) and whether they touch ([`meshes_touch`]).
//! Single-pose queries of [`super::CollisionSet`]; see its module doc for the bounds.

use std::cell::Cell;

use parry3d_f64::math::{Mat3 as PMat3, Pose as PPose, Vector as PVector};
use parry3d_f64::partitioning::BvhNode;
use parry3d_f64::query::{DefaultQueryDispatcher, QueryDispatcher};
use parry3d_f64::shape::{TriMesh, Triangle};

use super::collision_set::ROUND_OFF;

/// The smallest distance between a triangle of `m1` and a triangle of `m2` (`pos12`: `m2`'s
/// frame in `m1`'s), if below `bound`; `closest` seeds the search with a pair of triangles and
/// receives the closest pair found. 0 as soon as two triangles touch.
///
/// With a `tolerance` > 0 (m) the search stops short: a pair of nodes or triangles is passed
/// over as soon as its lower bound reaches the best distance found less the tolerance. What
/// it returns is still the distance of an actual pair of triangles, and the meshes' distance
/// is at most `tolerance` below it (`None`: not below `bound − tolerance`). Only for meshes
/// that cannot touch (an intersection could be passed over): the caller knows they are apart.
pub(super) fn mesh_distance(
    m1: &TriMesh,
    m2: &TriMesh,
    pos12: &PPose,
    closest: &mut (u32, u32),
    bound: f64,
    tolerance: f64,
) -> Option<f64> {
    let triangles = |pair| triangle_distance(m1, m2, pos12, pair);
    let seeded = triangles(*closest);
    let best = Cell::new(if seeded < bound { seeded } else { bound });
    let found = Cell::new((seeded < bound).then_some(*closest));
    // each box re-boxed in the other's frame bounds the distance; the larger bound is used
    let (two_in_one, one_in_two) = (Rebox::new(pos12), Rebox::new(&pos12.inverse()));
    // what could be closer, or tie with the best to round-off, is looked at (with a
    // tolerance: what could be closer by more than it)
    let slack = if tolerance > 0.0 { -tolerance } else { ROUND_OFF };
    let reach = || best.get() + slack;
    let boxes_closer = |n1: &BvhNode, n2: &BvhNode| {
        if best.get() <= 0.0 || reach() <= 0.0 {
            return false;
        }
        if n1.is_leaf() && n2.is_leaf() {
            // triangle_gap's exact boxes of the two triangles do better
            return true;
        }
        nodes_within(&two_in_one, &one_in_two, n1, n2, reach() * reach())
    };
    for pair in m1.bvh().leaf_pairs(m2.bvh(), boxes_closer) {
        if triangle_gap(&m1.triangle(pair.0), &m2.triangle(pair.1), &two_in_one) >= reach() {
            continue;
        }
        let d = triangles(pair);
        if d < best.get() {
            best.set(d);
            found.set(Some(pair));
        }
        if d <= 0.0 {
            break;
        }
    }
    let pair = found.get()?;
    *closest = pair;
    Some(best.get())
}

/// The distance between triangle `i` of `m1` and triangle `j` of `m2` (`pos12`: `m2`'s frame
/// in `m1`'s), parry's GJK; 0 when they touch or cross.
fn triangle_distance(m1: &TriMesh, m2: &TriMesh, pos12: &PPose, (i, j): (u32, u32)) -> f64 {
    DefaultQueryDispatcher
        .distance(pos12, &m1.triangle(i), &m2.triangle(j))
        .expect("parry supports triangle pairs")
        .distance
}

/// Whether the boxes of node `n1` (of m1) and node `n2` (of m2) may be closer than
/// `√squared_reach`: each box re-boxed in the other's frame (`two_in_one`: m2's in m1's,
/// `one_in_two` the inverse) bounds the distance of the triangles inside from below, and both
/// bounds must be below.
fn nodes_within(two_in_one: &Rebox, one_in_two: &Rebox, n1: &BvhNode, n2: &BvhNode, squared_reach: f64) -> bool {
    let (box1, box2) = ((n1.mins(), n1.maxs()), (n2.mins(), n2.maxs()));
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
    m1: &TriMesh,
    m2: &TriMesh,
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
    let boxes_touch = |n1: &BvhNode, n2: &BvhNode| {
        opened.set(opened.get() + 1);
        opened.get() <= budget && nodes_within(&two_in_one, &one_in_two, n1, n2, slack)
    };
    for pair in m1.bvh().leaf_pairs(m2.bvh(), boxes_touch) {
        if triangle_gap(&m1.triangle(pair.0), &m2.triangle(pair.1), &two_in_one) < ROUND_OFF && triangles(pair) <= 0.0 {
            *closest = pair;
            return Touch::Crossing;
        }
    }
    if opened.get() > budget {
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
