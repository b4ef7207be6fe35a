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
//! relative to each other since, and the gap of the two bounding spheres. How far a shape's
//! points move when the joints move by Δq is bounded without any pose: a revolute joint j
//! moves a point p by at most |Δq_j|·|p − o_j| (o_j on its axis), and |p − o_j| is at most the
//! sum of the joint offsets from j to the shape's body, the frame's offset and the shape's
//! reach, in any configuration; a prismatic joint moves it by |Δq_j|. Two shapes move relative
//! to each other by at most the sum of these over the joints that move one but not the other
//! (the joints that move both move them together).

use std::sync::Arc;

use parry3d_f64::math::{Pose as PPose, Vector as PVector};

use super::CollisionSet;
use super::collision_set::parry_pose;
use super::report::ClearanceGeometry;
use crate::error::{Error, Result};
use crate::model::{JointId, JointKind, Model};
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
    /// Per pair, each joint that moves one object of the pair but not the other, with its
    /// lever (m per rad; 1 for a prismatic joint): a bound of how far that object's points
    /// move per unit of that joint's motion. Joints that move both move them together.
    levers: Vec<Vec<(usize, f64)>>,
}

/// At most how many calls of [`ContactGeometry::find`] a penetrating pair's contact is followed
/// rigidly between two queries, by default ([`ContactData::refresh_every`]).
pub const REFRESH_EVERY: u32 = 100;

/// How far (m) the points of a penetrating pair may have moved relative to each other (the
/// joint-motion bound of the module's pruning) before its contact is queried again, by default
/// ([`ContactData::refresh_motion`]).
pub const REFRESH_MOTION: f64 = 1e-4;

/// A contact followed between queries: its two deepest points and its normal, fixed in the
/// model frames of the shapes they were found on.
#[derive(Clone, Copy, Debug)]
struct Followed {
    /// The first shape's deepest point, in its model frame.
    point_a: Vec3,
    /// The second shape's deepest point, in its model frame.
    point_b: Vec3,
    /// The normal, in the first shape's model frame.
    normal_a: Vec3,
    /// A bound of the shapes' relative motion since the query (m).
    moved: f64,
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
    /// Per pair, a lower bound of its distance now (m; −∞: unknown).
    bound: Vec<f64>,
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
        let levers = (set.objects())
            .zip(&spheres)
            .map(|(o, (centre, radius)): (_, &(Vec3, f64))| {
                let frame = &model.frames[o.frame];
                let mut reach = frame.placement.pos.norm() + centre.norm() + radius;
                let mut levers = Vec::new();
                let mut joint = frame.body.map(|JointId(j)| j);
                while let Some(j) = joint {
                    let lever = match model.bodies[j].kind {
                        JointKind::Prismatic => 1.0,
                        JointKind::Revolute | JointKind::Continuous => reach,
                    };
                    levers.push((j, lever));
                    reach += model.tree_pose[j].pos.norm();
                    joint = model.parent[j];
                }
                levers
            })
            .collect::<Vec<Vec<(usize, f64)>>>();
        let levers = (set.object_pairs().iter())
            .map(|&(a, b)| {
                let moves = |o: usize, j: usize| levers[o].iter().any(|&(k, _)| k == j);
                let only = |o: usize, other: usize| levers[o].iter().filter(move |&&(j, _)| !moves(other, j));
                // bodies → the coordinates that move them (a follower's lever scaled by |m|)
                let coordinate = |&(j, lever): &(usize, f64)| {
                    let body = &model.bodies[j];
                    (body.coordinate, body.multiplier.abs() * lever)
                };
                only(a, b).chain(only(b, a)).map(coordinate).collect()
            })
            .collect();
        ContactGeometry {
            set,
            bodies,
            spheres,
            levers,
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
            bound: vec![f64::NEG_INFINITY; pairs],
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

    /// The contacts of the pose whose model frames are at `frame_pose` (world, e.g.
    /// `algo::Data::frame_pose`), into `data.contacts`. `joint_motion[j]` bounds how far joint
    /// j moved since the previous call (|Δq_j|, rad or m; the first call's bounds are unknown
    /// anyway). `t` (s) names the time in the error. Fails if two exact meshes intersect.
    pub fn find(&self, frame_pose: &[Pose], joint_motion: &[f64], t: f64, data: &mut ContactData) -> Result<()> {
        data.contacts.clear();
        data.call += 1;
        let (every, refresh) = (data.refresh_every, data.refresh_motion);
        for (k, &(a, b)) in self.set.object_pairs().iter().enumerate() {
            let motion: f64 = self.levers[k].iter().map(|&(j, lever)| joint_motion[j] * lever).sum();
            data.bound[k] -= motion;
            let (fa, fb) = (
                &frame_pose[self.set.object(a).frame],
                &frame_pose[self.set.object(b).frame],
            );
            let bodies = [self.bodies[a], self.bodies[b]];
            if let Some(f) = data.followed[k].as_mut() {
                f.moved += motion;
                f.age += 1;
                if f.age < every && f.moved <= refresh {
                    // φ ≈ n̂·(p_b − p_a) with the points and the normal moving with their frames
                    let (pa, pb, n) = (
                        fa.transform_point(&f.point_a),
                        fb.transform_point(&f.point_b),
                        fa.rot * f.normal_a,
                    );
                    let phi = n.dot(&(pb - pa));
                    if phi < 0.0 {
                        data.contacts.push(contact(k, bodies, pa, pb, n, phi));
                        continue;
                    }
                }
                data.followed[k] = None;
                data.bound[k] = f64::NEG_INFINITY;
            }
            if data.bound[k] > 0.0 {
                continue;
            }
            // bounding spheres apart: no contact
            let gap = (fa.transform_point(&self.spheres[a].0) - fb.transform_point(&self.spheres[b].0)).norm()
                - self.spheres[a].1
                - self.spheres[b].1;
            if gap > 0.0 {
                data.bound[k] = gap;
                continue;
            }
            for o in [a, b] {
                if data.posed_at[o] != data.call {
                    data.poses[o] = parry_pose(&frame_pose[self.set.object(o).frame]) * *self.set.object(o).placement;
                    data.posed_at[o] = data.call;
                }
            }
            let (pa, pb) = (data.poses[a], data.poses[b]);
            data.queries += 1;
            // two hulls' support maps climb from where they last stopped on each object
            let mut at = (data.support_at[a], data.support_at[b]);
            let hit = (self.set.convex_contact(a, b, &pa, &pb, Some(&mut at))).filter(|c| c.dist < 0.0);
            if hit.is_none() {
                data.bound[k] = self.set.convex_gap(a, b, &pa, &pb, Some(&mut at), None);
            }
            (data.support_at[a], data.support_at[b]) = at;
            let Some(c) = hit else {
                continue;
            };
            let (oa, ob) = (self.set.object(a), self.set.object(b));
            if oa.exact_mesh || ob.exact_mesh {
                let exact = self.set.exact_pair_distance(k, (&pa, &pb), &mut data.closest[k]);
                if exact.intersecting {
                    return Err(Error::MeshContact {
                        links: [oa.link.to_string(), ob.link.to_string()],
                        t,
                    });
                }
                data.bound[k] = exact.distance;
                continue;
            }
            let world = |v: PVector| Vec3::new(v.x, v.y, v.z);
            let (point_a, point_b, normal) = (world(c.point1), world(c.point2), world(c.normal1));
            data.followed[k] = Some(Followed {
                point_a: fa.rot.transpose() * (point_a - fa.pos),
                point_b: fb.rot.transpose() * (point_b - fb.pos),
                normal_a: fa.rot.transpose() * normal,
                moved: 0.0,
                age: 0,
            });
            data.contacts.push(contact(k, bodies, point_a, point_b, normal, c.dist));
        }
        Ok(())
    }
}

/// The contact of pair `k` from the deepest points of its two shapes (world), the normal from
/// the first to the second and φ: the point is their midpoint (equal stiffnesses).
fn contact(k: usize, bodies: [Option<JointId>; 2], a: Vec3, b: Vec3, normal: Vec3, phi: f64) -> Contact {
    Contact {
        pair: k,
        bodies,
        point: 0.5 * (a + b),
        normal,
        phi,
    }
}
