//! Contact points between the checked pairs of a robot's collision objects, for
//! `--self-collisions` (docs/contact.md).
//!
//! A contact is reported, as Drake's point contact does, only for a pair of convex shapes
//! (primitives, or meshes read as their convex hulls) that penetrate: parry's `contact` gives
//! the point of each shape deepest inside the other, `p_a` and `p_b`, and the unit normal
//! `n̂` pointing out of the first shape towards the second. Then
//!
//! ```text
//!   φ = −|penetration depth| < 0,      p_C = w_a p_a + w_b p_b,  w_a = k_a/(k_a + k_b) = ½
//! ```
//!
//! (Drake's weighting by the two stiffnesses, equal here). With exact meshes
//! ([`ClearanceGeometry::Mesh`]) a pair whose hulls penetrate is checked triangle by triangle;
//! if the meshes themselves intersect, [`ContactGeometry::find`] fails with
//! [`Error::MeshContact`]: contact between two triangle meshes is not modelled.
//!
//! Pruning: a pair is queried only when a lower bound of its distance is not positive. The
//! bounds are the pair's last positive distance less how far its shapes can have moved
//! relative to each other since (the Lipschitz bound of the clearance), and the gap of the two
//! bounding spheres.

use std::sync::Arc;

use std::cell::Cell;

use parry3d_f64::math::{Pose as PPose, Vector as PVector};
use parry3d_f64::query::{self, details};
use parry3d_f64::shape::{ConvexPolyhedron, SupportMap};

use super::CollisionSet;
use super::clearance::{motion_bound, parry_pose};
use super::report::ClearanceGeometry;
use crate::error::{Error, Result};
use crate::model::{JointId, Model};
use crate::spatial::{Pose, Vec3};

/// One contact at a pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The pair, as an index into [`ContactGeometry::pair_links`].
    pub pair: usize,
    /// The bodies the two objects are fixed to (`None`: the world), first then second.
    pub bodies: [Option<JointId>; 2],
    /// The contact point p_C in world coordinates (m).
    pub point: Vec3,
    /// Unit normal from the first object towards the second, world coordinates.
    pub normal: Vec3,
    /// Signed distance φ (m), negative: the penetration depth.
    pub phi: f64,
}

/// The collision objects of a [`CollisionSet`] (its parry shapes, its pairs, its reading of
/// meshes) and each object's body. Immutable; built once per run.
pub struct ContactGeometry {
    set: Arc<CollisionSet>,
    bodies: Vec<Option<JointId>>,
    /// Per object, its bounding sphere's centre in its model frame (m) and radius (m).
    spheres: Vec<(Vec3, f64)>,
    /// Per object, a mesh hull's vertex adjacency (`None` for a primitive).
    climbs: Vec<Option<Adjacency>>,
}

/// The edges of a convex polyhedron as vertex adjacency lists: vertex v's neighbours are
/// `neighbours[offsets[v]..offsets[v + 1]]`.
struct Adjacency {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl Adjacency {
    /// The edges of `hull`'s faces (consecutive vertices of each face polygon).
    fn of(hull: &ConvexPolyhedron) -> Adjacency {
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
struct Climber<'a> {
    points: &'a [PVector],
    adjacency: &'a Adjacency,
    at: Cell<u32>,
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

/// At most how many calls of [`ContactGeometry::find`] a penetrating pair's contact is followed
/// rigidly between two queries, by default ([`ContactData::refresh_every`]).
pub const REFRESH_EVERY: u32 = 100;

/// How far (m) the points of a penetrating pair may move relative to each other (the bound of
/// the clearance's pruning) before its contact is queried again, by default
/// ([`ContactData::refresh_motion`]).
pub const REFRESH_MOTION: f64 = 1e-4;

/// A contact followed between queries: its two deepest points and its normal, fixed in the
/// shapes they were found on.
#[derive(Clone, Copy, Debug)]
struct Followed {
    /// The first shape's deepest point, in its shape frame.
    point_a: PVector,
    /// The second shape's deepest point, in its shape frame.
    point_b: PVector,
    /// The normal, in the first shape's frame.
    normal_a: PVector,
    /// The relative pose `a_T_b` at the query.
    pose_ab: PPose,
    /// Calls since the query.
    age: u32,
}

/// The workspace of [`ContactGeometry::find`]: object poses, per pair a lower bound of its
/// distance with the relative pose it holds at, and the contacts found. Queries reuse its
/// buffers.
pub struct ContactData {
    poses: Vec<PPose>,
    /// Per object, the vertex its hull's support was last found at.
    support_at: Vec<u32>,
    /// The call each entry of `poses` was computed at, and this call's number.
    posed_at: Vec<u64>,
    call: u64,
    bound: Vec<(f64, PPose)>,
    /// Per pair, the two triangles closest at its last exact query.
    closest: Vec<(u32, u32)>,
    /// Per pair, its contact at the last query if it penetrated.
    followed: Vec<Option<Followed>>,
    /// A penetrating pair is queried again after this many calls (≥ 1; 1: at every call), or
    /// sooner once its shapes have moved [`ContactData::refresh_motion`] relative to each
    /// other; between queries its contact is followed rigidly (see docs/contact.md).
    pub refresh_every: u32,
    /// See [`ContactData::refresh_every`] (m).
    pub refresh_motion: f64,
    /// The contacts at the last [`ContactGeometry::find`].
    pub contacts: Vec<Contact>,
    /// Pair queries run by [`ContactGeometry::find`] so far (the rest were pruned).
    pub queries: u64,
}

impl ContactGeometry {
    /// The contact geometry of `set`, loaded for `model`.
    pub fn new(model: &Model, set: Arc<CollisionSet>) -> ContactGeometry {
        let bodies = set.objects().map(|o| model.frames[o.frame].body).collect();
        let spheres = (set.objects())
            .map(|o| {
                let c = *o.placement * o.sphere.0;
                (Vec3::new(c.x, c.y, c.z), o.sphere.1)
            })
            .collect();
        let climbs = (set.objects())
            .map(|o| o.convex.as_convex_polyhedron().map(Adjacency::of))
            .collect();
        ContactGeometry {
            set,
            bodies,
            spheres,
            climbs,
        }
    }

    /// How meshes are read.
    pub fn geometry(&self) -> ClearanceGeometry {
        self.set.geometry()
    }

    /// A workspace for this geometry.
    pub fn data(&self) -> ContactData {
        let (objects, pairs) = (self.bodies.len(), self.set.object_pairs().len());
        ContactData {
            poses: vec![PPose::IDENTITY; objects],
            posed_at: vec![0; objects],
            support_at: vec![0; objects],
            call: 0,
            bound: vec![(f64::NEG_INFINITY, PPose::IDENTITY); pairs],
            closest: vec![(0, 0); pairs],
            followed: vec![None; pairs],
            refresh_every: REFRESH_EVERY,
            refresh_motion: REFRESH_MOTION,
            contacts: Vec::new(),
            queries: 0,
        }
    }

    /// The checked pairs as link names.
    pub fn pair_links(&self) -> impl Iterator<Item = [&str; 2]> + '_ {
        self.set.pair_links()
    }

    /// The number of vertices of each object's convex shape, by link (a mesh's hull; 0 for a
    /// primitive).
    pub fn hull_vertices(&self) -> Vec<(String, usize)> {
        (self.set.objects())
            .map(|o| {
                let count = o.convex.as_convex_polyhedron().map_or(0, |h| h.points().len());
                (o.link.to_string(), count)
            })
            .collect()
    }

    /// The support map of object `o`: hill climbing on a hull (from `support_at[o]`); `None`
    /// for a primitive.
    fn climber<'a>(&'a self, o: usize, support_at: &[u32]) -> Option<Climber<'a>> {
        let adjacency = self.climbs[o].as_ref()?;
        let hull = self.set.object(o).convex.as_convex_polyhedron()?;
        Some(Climber {
            points: hull.points(),
            adjacency,
            at: Cell::new(support_at[o]),
        })
    }

    /// parry's contact of the convex shapes of objects `a` and `b` (world poses `pa`, `pb`,
    /// `pose_ab = pa⁻¹ pb`), in world coordinates, `None` when apart: two hulls by GJK/EPA on
    /// [`Climber`]s, any other pair by parry's dispatcher.
    fn convex_contact(
        &self,
        a: usize,
        b: usize,
        pa: &PPose,
        pb: &PPose,
        pose_ab: &PPose,
        support_at: &mut [u32],
    ) -> Option<query::Contact> {
        let (oa, ob) = (self.set.object(a), self.set.object(b));
        let (Some(ca), Some(cb)) = (self.climber(a, support_at), self.climber(b, support_at)) else {
            return query::contact(pa, oa.convex, pb, ob.convex, 0.0).expect("parry supports convex pairs");
        };
        let local = details::contact_support_map_support_map(pose_ab, &ca, &cb, 0.0);
        (support_at[a], support_at[b]) = (ca.at.get(), cb.at.get());
        local.map(|c| query::Contact {
            point1: *pa * c.point1,
            point2: *pb * c.point2,
            normal1: pa.rotation * c.normal1,
            normal2: pb.rotation * c.normal2,
            ..c
        })
    }

    /// The distance of the convex shapes of objects `a` and `b` (as [`Self::convex_contact`]).
    fn convex_distance(
        &self,
        a: usize,
        b: usize,
        pa: &PPose,
        pb: &PPose,
        pose_ab: &PPose,
        support_at: &mut [u32],
    ) -> f64 {
        let (oa, ob) = (self.set.object(a), self.set.object(b));
        let (Some(ca), Some(cb)) = (self.climber(a, support_at), self.climber(b, support_at)) else {
            return query::distance(pa, oa.convex, pb, ob.convex)
                .expect("parry supports convex pairs")
                .distance;
        };
        let d = details::distance_support_map_support_map(pose_ab, &ca, &cb);
        (support_at[a], support_at[b]) = (ca.at.get(), cb.at.get());
        d
    }

    /// The contacts of the pose whose model frames are at `frame_pose` (world, e.g.
    /// `algo::Data::frame_pose` after `forward_kinematics`), into `data.contacts`. `t` (s)
    /// names the time in the error. Fails if two exact meshes intersect.
    pub fn find(&self, frame_pose: &[Pose], t: f64, data: &mut ContactData) -> Result<()> {
        data.contacts.clear();
        data.call += 1;
        for (k, &(a, b)) in self.set.object_pairs().iter().enumerate() {
            let (oa, ob) = (self.set.object(a), self.set.object(b));
            // bounding spheres apart: no contact (no parry pose needed)
            let centre = |o: usize| frame_pose[self.set.object(o).frame].transform_point(&self.spheres[o].0);
            if (centre(a) - centre(b)).norm() > self.spheres[a].1 + self.spheres[b].1 {
                data.followed[k] = None;
                continue;
            }
            for o in [a, b] {
                if data.posed_at[o] != data.call {
                    data.poses[o] = parry_pose(&frame_pose[self.set.object(o).frame]) * *self.set.object(o).placement;
                    data.posed_at[o] = data.call;
                }
            }
            let (pa, pb) = (data.poses[a], data.poses[b]);
            let bodies = [self.bodies[a], self.bodies[b]];
            let pose_ab = pa.inv_mul(&pb);
            let (every, motion) = (data.refresh_every, data.refresh_motion);
            let fresh = |f: &&mut Followed| f.age + 1 < every && motion_bound(&f.pose_ab, &pose_ab, ob.reach) <= motion;
            if let Some(f) = data.followed[k].as_mut().filter(fresh) {
                // φ ≈ n̂·(p_b − p_a) with the points and the normal moving with their shapes
                f.age += 1;
                let (point_a, point_b, normal) = (pa * f.point_a, pb * f.point_b, pa.rotation * f.normal_a);
                let phi = normal.dot(point_b - point_a);
                if phi < 0.0 {
                    data.contacts.push(contact(k, bodies, point_a, point_b, normal, phi));
                    continue;
                }
            }
            data.followed[k] = None;
            let (lower, then) = &data.bound[k];
            if *lower - motion_bound(then, &pose_ab, ob.reach) > 0.0 {
                continue;
            }
            data.queries += 1;
            let hit = self.convex_contact(a, b, &pa, &pb, &pose_ab, &mut data.support_at);
            let Some(c) = hit.filter(|c| c.dist < 0.0) else {
                let d = self.convex_distance(a, b, &pa, &pb, &pose_ab, &mut data.support_at);
                data.bound[k] = (d, pose_ab);
                continue;
            };
            if oa.triangles.is_some() || ob.triangles.is_some() {
                let exact = self.set.exact_pair_distance(k, &data.poses, &mut data.closest[k]);
                if exact.intersecting {
                    return Err(Error::MeshContact {
                        links: [oa.link.to_string(), ob.link.to_string()],
                        t,
                    });
                }
                data.bound[k] = (exact.distance, pose_ab);
                continue;
            }
            data.bound[k] = (c.dist, pose_ab);
            data.followed[k] = Some(Followed {
                point_a: pa.inverse() * c.point1,
                point_b: pb.inverse() * c.point2,
                normal_a: pa.rotation.inverse() * c.normal1,
                pose_ab,
                age: 0,
            });
            data.contacts
                .push(contact(k, bodies, c.point1, c.point2, c.normal1, c.dist));
        }
        Ok(())
    }
}

/// The contact of pair `k` from the deepest points of its two shapes (world), the normal from
/// the first to the second and φ: the point is their midpoint (equal stiffnesses).
fn contact(k: usize, bodies: [Option<JointId>; 2], a: PVector, b: PVector, normal: PVector, phi: f64) -> Contact {
    let point = 0.5 * (a + b);
    Contact {
        pair: k,
        bodies,
        point: Vec3::new(point.x, point.y, point.z),
        normal: Vec3::new(normal.x, normal.y, normal.z),
        phi,
    }
}
