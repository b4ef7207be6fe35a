//! Distances between the collision objects of a robot at a pose, with parry3d (f64).
//!
//! Two readings of a mesh, as [`ClearanceGeometry`] says:
//!
//! * `Hull`: each mesh is replaced by its convex hull (as Drake's SceneGraph does for
//!   proximity queries). The value is the signed distance: the gap between the two convex
//!   shapes when they are apart, minus the penetration depth (the shortest translation that
//!   separates them) when they overlap.
//! * `Mesh`: the exact triangles. The value is the smallest distance between any two
//!   triangles, 0 with `intersecting` when two triangles cross (one mesh wholly inside another
//!   without a crossing reads as the gap between the surfaces).
//!
//! Boxes, cylinders and spheres are exact in both readings (they are convex), and their signed
//! distance is used in both.
//!
//! Two meshes are compared by a simultaneous traversal of their bounding-volume hierarchies
//! (parry's `Bvh::leaf_pairs`): a pair of nodes is opened only while the distance between their
//! boxes is below the best triangle distance found so far (plus a round-off margin, so that
//! triangle pairs tying with the best to round-off are all looked at and the smallest computed
//! distance wins whatever the order of the search). That distance is bounded below twice,
//! the second box re-boxed in the first mesh's frame and the first box in the second's (each a
//! lower bound of the distance of any triangles inside; a rotated box grows when re-boxed, so
//! the two differ), and the larger is used; the relative pose's rotation matrix and its
//! absolute values are computed once per query for that. Each pair of
//! leaves is one triangle–triangle distance (parry's GJK), unless a cheaper lower bound (exact
//! boxes of the two triangles, their projections on the line through their centroids) already
//! reaches the best distance; the leaves' own boxes are not re-boxed first (the triangles'
//! exact boxes are tighter). The search starts from the two
//! triangles that were closest at the previous query of that pair (a good bound at once when
//! the poses change little from sample to sample).
//!
//! Pruning in [`CollisionSet::accumulate`] uses lower bounds of a pair's distance: the last
//! lower bound found for the pair less how far its shapes can have moved relative to each other
//! since (see [`moved`]), the bounding spheres' gap `|c₁ − c₂| − r₁ − r₂`, the gap between the
//! convex shapes' projections on the axis that separated them at the pair's last GJK (see
//! [`CollisionSet::separation_along`]: two support points, and tight when the pair moves
//! little), and (for meshes) the hulls' signed distance, since a mesh lies inside its hull. A
//! pair whose bound is not below its smallest distance so far cannot lower it and needs no
//! exact query. A pair whose hulls
//! are apart may be proven by them ([`CollisionSet::proven_by_hulls`]); one whose hulls
//! overlap is only tested for crossing triangles at the sample (the same traversal, opening
//! just the boxes that touch, which stops at the first crossing pair), unless that test runs
//! over a budget (meshes a fraction of a millimetre apart all along a joint's parts, whose
//! boxes touch all the way down): such a pair is searched at each sample, bounded by its
//! smallest distance so far. The samples whose
//! distance is left open wait for [`CollisionSet::finish`], which searches them in order of
//! their upper bound, each search raising the other samples' lower bounds by its distance less
//! the relative motion between the two samples.

use std::cell::Cell;

use parry3d_f64::math::{Mat3 as PMat3, Pose as PPose, Rot3 as PRot3, Vector as PVector};
use parry3d_f64::partitioning::BvhNode;
use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::query::{
    self, ClosestPoints, DefaultQueryDispatcher, PointQueryWithLocation, QueryDispatcher, details,
};
use parry3d_f64::shape::{Ball, ConvexPolyhedron, Cuboid, Cylinder, Shape, SupportMap, TriMesh, Triangle};
use parry3d_f64::transformation::try_convex_hull;
use rayon::prelude::*;

use super::hull::{Adjacency, Climber};
use super::mesh::load;
use super::pairs::{PairFilter, checked_pairs};
use super::report::{ClearanceGeometry, ClearanceReport, PairDistance};
use super::{GeometryModel, GeometryObject};
use crate::error::{Error, Result};
use crate::model::{Geometry, Model};
use crate::spatial::{Mat3, Pose, Vec3};

/// Something left out of the clearance, reported as a value for the caller to print.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Warning {
    /// A collision mesh whose file was not found: that object is not checked.
    MeshNotFound {
        /// The URDF file.
        file: String,
        /// The link it belongs to.
        link: String,
        /// The reference as the URDF writes it.
        uri: String,
    },
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Warning::MeshNotFound { file, link, uri } => write!(
                f,
                "{file}: link '{link}' <collision>: mesh '{uri}' not found, its clearance is not checked ({})",
                crate::model::not_found_advice(uri)
            ),
        }
    }
}

/// How close (m) an actual pair of parts must come to the hulls' distance for
/// [`CollisionSet::proven_by_hulls`] to take it as the distance: far below the oracle
/// tests' 1e-6 m, far above GJK's round-off.
const HULL_CERTIFICATE: f64 = 1e-9;

/// A margin (m) far above the round-off of distances and their lower bounds (~1e-15 m) and far
/// below any distance that matters: a pair of boxes or triangles, or a sample, is passed over
/// only when its lower bound exceeds the best distance by this much, so that among triangle
/// pairs (or samples) whose distances tie to round-off the smallest computed distance is
/// found, whatever the order of the search ([`meshes_touch`] looks inside boxes and triangles
/// this close to each other).
const ROUND_OFF: f64 = 1e-9;

/// How many pairs of nodes [`meshes_touch`] may open at a sample (a distance search opens
/// some thousands): past it, the pair's distance is searched at each sample instead.
const TOUCH_BUDGET: usize = 1000;

/// One collision object, loaded.
struct Object {
    /// Its index in [`GeometryModel::collisions`].
    source: usize,
    /// Its link.
    link: String,
    /// The frame it is fixed to.
    frame: usize,
    /// `frame_T_shape` in parry's form (for cylinders, parry's y axis turned onto URDF's z).
    placement: PPose,
    /// The convex shape: a primitive, or a mesh's convex hull.
    convex: Box<dyn Shape>,
    /// The exact triangles of a mesh (for [`ClearanceGeometry::Mesh`]).
    triangles: Option<TriMesh>,
    /// A hull's vertex adjacency, for its support map by hill climbing (`None`: a primitive).
    climb: Option<Adjacency>,
    /// Bounding sphere centre in the shape frame (m).
    centre: PVector,
    /// Bounding sphere radius (m).
    radius: f64,
}

impl Object {
    /// Its convex shape's support map: a hull's climbing from vertex `start`, a primitive's
    /// own.
    fn support(&self, start: u32) -> Support<'_> {
        match (self.convex.as_convex_polyhedron(), &self.climb) {
            (Some(hull), Some(adjacency)) => Support::Hull(Climber::new(hull, adjacency, start)),
            _ => Support::Primitive(
                (self.convex.as_support_map()).expect("parry's boxes, balls and cylinders have support maps"),
            ),
        }
    }

    /// Collision element `g` (number `source`) loaded as `kind` reads it; `None` for a mesh
    /// found nowhere.
    fn load(source: usize, g: &GeometryObject, kind: ClearanceGeometry) -> Result<Option<Object>> {
        let axis_fix = Pose::new(
            Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0), // parry y → URDF z
            Vec3::zeros(),
        );
        type Loaded = (Box<dyn Shape>, Option<TriMesh>, Pose, Option<Adjacency>);
        let (convex, triangles, placement, climb): Loaded = match &g.geometry {
            Geometry::Box { size } => (
                Box::new(Cuboid::new(PVector::new(size.x, size.y, size.z) / 2.0)),
                None,
                g.placement,
                None,
            ),
            Geometry::Sphere { radius } => (Box::new(Ball::new(*radius)), None, g.placement, None),
            Geometry::Cylinder { radius, length } => (
                Box::new(Cylinder::new(length / 2.0, *radius)),
                None,
                g.placement.compose(&axis_fix),
                None,
            ),
            Geometry::Mesh { uri, path, scale } => {
                let Some(mesh) = load(uri, path.as_deref()) else {
                    return Ok(None);
                };
                let mesh = mesh?.mesh;
                let path = path.clone().unwrap_or_else(|| uri.into());
                let points: Vec<PVector> = (mesh.vertices.iter())
                    .map(|v| PVector::new(v[0] as f64 * scale.x, v[1] as f64 * scale.y, v[2] as f64 * scale.z))
                    .collect();
                // parry's ConvexPolyhedron::from_convex_hull, keeping the hull's triangles for
                // the climb's edges
                let no_hull = || Error::InvalidData {
                    path: path.clone(),
                    message: "the mesh spans no volume (no convex hull)".into(),
                };
                let (corners, faces) = try_convex_hull(&points).map_err(|_| no_hull())?;
                let climb = Adjacency::of(corners.len(), &faces);
                let hull = ConvexPolyhedron::from_convex_mesh(corners, &faces).ok_or_else(no_hull)?;
                let triangles = match kind {
                    ClearanceGeometry::Hull => None,
                    ClearanceGeometry::Mesh => {
                        Some(TriMesh::new(points, mesh.triangles).map_err(|e| Error::InvalidData {
                            path: path.clone(),
                            message: format!("not a triangle mesh: {e}"),
                        })?)
                    }
                };
                (Box::new(hull), triangles, g.placement, Some(climb))
            }
        };
        let sphere = convex.compute_local_bounding_sphere();
        Ok(Some(Object {
            source,
            link: g.link.clone(),
            frame: g.frame.0,
            placement: to_parry(&placement),
            convex,
            triangles,
            climb,
            centre: sphere.center,
            radius: sphere.radius,
        }))
    }
}

/// The collision objects of a robot loaded as parry shapes, and the pairs that are checked.
/// Immutable; built once per run. Queries go through a [`GeometryData`].
pub struct CollisionSet {
    geometry: ClearanceGeometry,
    objects: Vec<Object>,
    pairs: Vec<(usize, usize)>,
    unchecked: Vec<String>,
}

/// The workspace of clearance queries: world poses of the objects and the last distances.
/// Sized once by [`GeometryData::new`]; queries allocate nothing, except the samples
/// [`CollisionSet::accumulate`] leaves for [`CollisionSet::finish`] (one relative pose per
/// waiting sample and pair, kept until `finish`, whose buffers are reused).
pub struct GeometryData {
    /// World pose of each object's shape (parry's form).
    poses: Vec<PPose>,
    /// The last [`CollisionSet::distances`], one per pair in [`CollisionSet::pair_links`] order.
    pub distances: Vec<PairDistance>,
    /// Whether each pair intersects at the last [`CollisionSet::accumulate`]d pose, in
    /// [`CollisionSet::pair_links`] order.
    pub intersecting: Vec<bool>,
    /// What each pair carries from one query to the next.
    memory: Vec<PairMemory>,
}

/// One pair's state between queries.
#[derive(Clone)]
struct PairMemory {
    /// The two triangles found closest at its last exact mesh query.
    closest: (u32, u32),
    /// The two hull vertices last found furthest along GJK's directions (hill climbing starts).
    support: (u32, u32),
    /// The unit direction from a to b along the convex shapes' closest points at their last
    /// GJK, in a's shape frame (zero: none, or they touched).
    axis: PVector,
    /// A lower bound of its distance and the relative pose `a_T_b` it holds at.
    reference: (f64, PPose),
    /// What the last [`CollisionSet::accumulate`] found: the distance, if it was computed.
    found: Option<PairDistance>,
    /// An actual distance of the pair at some sample so far (m): the run's smallest is no
    /// larger.
    upper: f64,
    /// Samples left for [`CollisionSet::finish`]: apart, but not proven by the hulls.
    pending: Vec<Pending>,
    /// Whether a crossing test of the pair ran out of [`TOUCH_BUDGET`]: its hulls overlapping,
    /// its distance is then searched at each sample rather than tested and left for
    /// [`CollisionSet::finish`].
    search_now: bool,
}

/// A sample whose exact distance is left for [`CollisionSet::finish`].
#[derive(Clone, Copy)]
struct Pending {
    /// Its time (s).
    t: f64,
    /// The pair's relative pose `a_T_b` then.
    pose_ab: PPose,
    /// The hulls' distance then (m), a lower bound of the pair's.
    lower: f64,
    /// An actual distance of two of its parts then (m), an upper bound of the pair's.
    upper: f64,
    /// Whether its hulls were apart. Its lower bound then serves
    /// [`CollisionSet::proven_by_hulls`] as the hulls' distance would (any lower bound proves
    /// an actual pair no further apart than it plus [`HULL_CERTIFICATE`]); a sample whose
    /// hulls overlapped is searched triangle by triangle.
    hulls_apart: bool,
}

impl GeometryData {
    /// A workspace for `set`.
    pub fn new(set: &CollisionSet) -> GeometryData {
        GeometryData {
            poses: vec![PPose::IDENTITY; set.objects.len()],
            distances: vec![
                PairDistance {
                    distance: f64::INFINITY,
                    intersecting: false
                };
                set.pairs.len()
            ],
            intersecting: vec![false; set.pairs.len()],
            memory: vec![
                PairMemory {
                    closest: (0, 0),
                    support: (0, 0),
                    axis: PVector::ZERO,
                    reference: (f64::NEG_INFINITY, PPose::IDENTITY),
                    found: None,
                    upper: f64::INFINITY,
                    pending: Vec::new(),
                    search_now: false,
                };
                set.pairs.len()
            ],
        }
    }
}

/// Our pose in parry's form (rotation as a unit quaternion).
fn to_parry(p: &Pose) -> PPose {
    let r = p.rot.as_slice(); // column-major
    let m = PMat3::from_cols_array(&[r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]]);
    PPose::from_parts(PVector::new(p.pos.x, p.pos.y, p.pos.z), PRot3::from_mat3(&m))
}

impl CollisionSet {
    /// Loads the collision objects of `geometry` (on `model`'s frames) and lists the pairs
    /// `filter` checks. Meshes are loaded through [`load`] (the file, else the built-in Faze4 copy); a mesh found nowhere
    /// is left out and reported as a [`Warning`] (and in the report's `unchecked`).
    ///
    /// Errors: a mesh found but unreadable, non-finite or empty (see [`super::mesh::read_mesh`]); a mesh
    /// whose points span no volume (no convex hull).
    pub fn new(
        model: &Model,
        geometry: &GeometryModel,
        kind: ClearanceGeometry,
        filter: PairFilter,
    ) -> Result<(CollisionSet, Vec<Warning>)> {
        // the objects are loaded in parallel (hulls and BVHs of big meshes take a while), and
        // kept in document order
        let loaded: Vec<Result<Option<Object>>> = (geometry.collisions.par_iter().enumerate())
            .map(|(source, g)| Object::load(source, g, kind))
            .collect();
        let (mut warnings, mut unchecked, mut kept, mut objects) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (g, object) in geometry.collisions.iter().zip(loaded) {
            match object? {
                Some(object) => {
                    objects.push(object);
                    kept.push(g.clone());
                }
                None => {
                    let Geometry::Mesh { uri, .. } = &g.geometry else {
                        unreachable!("only a mesh can be missing")
                    };
                    warnings.push(Warning::MeshNotFound {
                        file: model.source.clone(),
                        link: g.link.clone(),
                        uri: uri.clone(),
                    });
                    unchecked.push(g.link.clone());
                }
            }
        }
        let pairs = checked_pairs(model, &kept, &geometry.joined, filter);
        let set = CollisionSet {
            geometry: kind,
            objects,
            pairs,
            unchecked,
        };
        Ok((set, warnings))
    }

    /// How meshes are read.
    pub fn geometry(&self) -> ClearanceGeometry {
        self.geometry
    }

    /// The checked pairs as link names, in the order of [`GeometryData::distances`].
    pub fn pair_links(&self) -> impl Iterator<Item = [&str; 2]> + '_ {
        (self.pairs.iter()).map(|&(a, b)| [self.objects[a].link.as_str(), self.objects[b].link.as_str()])
    }

    /// The checked pairs as indices into [`GeometryModel::collisions`], in the order of
    /// [`GeometryData::distances`].
    pub fn pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.pairs.iter()).map(|&(a, b)| (self.objects[a].source, self.objects[b].source))
    }

    /// Links whose collision mesh was not found (not checked).
    pub fn unchecked(&self) -> &[String] {
        &self.unchecked
    }

    /// World poses of the objects from the world poses of the model frames (`frame_pose`,
    /// e.g. `algo::Data::frame_pose` after `forward_kinematics`).
    fn place(&self, frame_pose: &[Pose], data: &mut GeometryData) {
        for (o, pose) in self.objects.iter().zip(&mut data.poses) {
            *pose = to_parry(&frame_pose[o.frame]) * o.placement;
        }
    }

    /// The distance of every checked pair at the pose whose frames are at `frame_pose`, into
    /// `data.distances`.
    pub fn distances(&self, frame_pose: &[Pose], data: &mut GeometryData) {
        self.place(frame_pose, data);
        let poses = &data.poses;
        (data.distances.par_iter_mut().zip(&mut data.memory).enumerate()).for_each(|(k, (distance, memory))| {
            let (a, b) = self.pairs[k];
            *distance = self
                .pair_distance(k, (&poses[a], &poses[b]), &mut memory.closest, f64::INFINITY, None)
                .expect("an unbounded search finds the distance");
        });
    }

    /// An empty report for this set's pairs, to [`CollisionSet::accumulate`] a run into.
    pub fn new_report(&self) -> ClearanceReport {
        ClearanceReport::new(self.geometry(), self.pair_links(), self.unchecked().to_vec())
    }

    /// Folds the pose at time `t` (s) into `report`, and sets `data.intersecting` to this
    /// pose's intersecting pairs: each pair's distance is computed only when a lower bound
    /// (the pair's last bound less its relative motion since, bounding spheres, then hulls)
    /// says it could be below the pair's smallest so far or could be an intersection. A mesh
    /// pair whose hulls are apart but do not prove its distance, or whose hulls overlap but
    /// whose triangles do not cross, is not searched now: the sample waits for
    /// [`CollisionSet::finish`], which searches only those that can still hold the minimum.
    /// `report` must come from [`CollisionSet::new_report`] on this set.
    pub fn accumulate(&self, frame_pose: &[Pose], t: f64, data: &mut GeometryData, report: &mut ClearanceReport) {
        self.place(frame_pose, data);
        let poses = &data.poses;
        let smallest = &report.pairs;
        for (k, memory) in data.memory.iter_mut().enumerate() {
            memory.found = self.fold_pair(k, poses, t, smallest[k].min_m, memory);
        }
        for (k, memory) in data.memory.iter().enumerate() {
            data.intersecting[k] = memory.found.is_some_and(|d| d.intersecting);
            if let Some(d) = memory.found {
                report.record(k, d, t);
            }
        }
    }

    /// Completes `report` after the last [`CollisionSet::accumulate`]: each pair's waiting
    /// samples whose lower bound is below the pair's smallest distance so far plus
    /// [`ROUND_OFF`] are searched, the smallest upper bound first (none of them intersects:
    /// their hulls were apart, or their triangles were tested apart). The pairs are searched
    /// in parallel.
    pub fn finish(&self, data: &mut GeometryData, report: &mut ClearanceReport) {
        let smallest = &report.pairs;
        let found: Vec<Option<(PairDistance, f64)>> = (data.memory.par_iter_mut().enumerate())
            .map(|(k, memory)| self.finish_pair(k, memory, smallest[k].min_m))
            .collect();
        for (k, found) in found.into_iter().enumerate() {
            if let Some((d, t)) = found {
                report.record(k, d, t);
            }
        }
    }

    /// Pair `k`'s waiting samples for [`CollisionSet::finish`]: the smallest distance among
    /// them and its time, if below `best` (the pair's smallest so far).
    fn finish_pair(&self, k: usize, memory: &mut PairMemory, mut best: f64) -> Option<(PairDistance, f64)> {
        let b = self.pairs[k].1;
        let mut pending = std::mem::take(&mut memory.pending);
        // the likeliest minimum first (the smallest actual distance seen); each search finds
        // its sample's distance d_j, which bounds every other waiting sample i from below by
        // d_j − moved(j, i) (the pair's relative motion between them)
        pending.sort_by(|x, y| x.upper.total_cmp(&y.upper).then(x.t.total_cmp(&y.t)));
        let (centre, radius) = (self.objects[b].centre, self.objects[b].radius);
        let mut found = None;
        for j in 0..pending.len() {
            let p = pending[j];
            if best <= 0.0 {
                // an intersection: no waiting sample (all apart) can be closer
                break;
            }
            if p.lower >= best + ROUND_OFF {
                continue;
            }
            // distances depend on the relative pose alone; overlapping hulls (0 stands for
            // their distance) prove nothing
            let hull = if p.hulls_apart { p.lower } else { 0.0 };
            let d = (self.pair_distance(
                k,
                (&PPose::IDENTITY, &p.pose_ab),
                &mut memory.closest,
                f64::INFINITY,
                Some(hull),
            ))
            .expect("an unbounded search finds the distance");
            if d.distance < best {
                (best, found) = (d.distance, Some((d, p.t)));
            }
            for other in &mut pending[j + 1..] {
                let bound = d.distance - moved(&p.pose_ab, &other.pose_ab, centre, radius);
                other.lower = other.lower.max(bound);
            }
        }
        pending.clear();
        memory.pending = pending;
        found
    }

    /// Pair `k` at `poses` (time `t`) for [`CollisionSet::accumulate`]: its distance, unless a
    /// lower bound shows that it is positive (no intersection) and not below the pair's
    /// smallest so far (`best`, or an actual distance seen: no new minimum), or the sample is
    /// left for [`CollisionSet::finish`].
    fn fold_pair(&self, k: usize, poses: &[PPose], t: f64, best: f64, memory: &mut PairMemory) -> Option<PairDistance> {
        let (a, b) = self.pairs[k];
        let least = best.min(memory.upper);
        let skip = |lower: f64| lower > 0.0 && lower >= least;
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        let (pa, pb) = (&poses[a], &poses[b]);
        let pose_ab = pa.inv_mul(pb);
        // the lower bound found at an earlier sample, less how far any point of b can have
        // moved relative to a since
        let (lower, then) = &memory.reference;
        if skip(*lower - moved(then, &pose_ab, ob.centre, ob.radius)) {
            return None;
        }
        let gap = (*pa * oa.centre - *pb * ob.centre).length() - oa.radius - ob.radius;
        if skip(gap) {
            memory.reference = (gap, pose_ab);
            return None;
        }
        // the convex shapes' separation along the axis that separated them last time
        if memory.axis != PVector::ZERO {
            let gap = self.separation_along(a, b, &pose_ab, memory.axis, &mut memory.support);
            if skip(gap) {
                memory.reference = (gap, pose_ab);
                return None;
            }
        }
        let d = match (&oa.triangles, &ob.triangles) {
            (None, None) => self.convex_distance(a, b, (pa, pb), Some(&mut memory.support), Some(&mut memory.axis)),
            _ => {
                let hull =
                    (self.convex_distance(a, b, (pa, pb), Some(&mut memory.support), Some(&mut memory.axis))).distance;
                memory.reference = (hull, pose_ab);
                if skip(hull) {
                    return None;
                }
                if hull > 0.0 {
                    match self.proven_by_hulls(a, b, (pa, pb), hull, &mut memory.closest) {
                        Ok(distance) => {
                            memory.upper = memory.upper.min(distance);
                            PairDistance {
                                distance,
                                intersecting: false,
                            }
                        }
                        Err(upper) => {
                            memory.upper = memory.upper.min(upper);
                            memory.pending.push(Pending {
                                t,
                                pose_ab,
                                lower: hull,
                                upper,
                                hulls_apart: true,
                            });
                            return None;
                        }
                    }
                } else if let (Some(ma), Some(mb)) = (&oa.triangles, &ob.triangles)
                    && !(memory.search_now && best > 0.0)
                {
                    // the hulls overlap: whether two triangles cross is tested now (an
                    // intersection must be seen at its sample); the distance of a sample
                    // whose triangles are apart waits for finish like the others, its hulls
                    // bounding it below by 0 (none can lower a smallest distance of 0, and
                    // then the test goes on whatever it costs)
                    let budget = if best > 0.0 { TOUCH_BUDGET } else { usize::MAX };
                    match meshes_touch(ma, mb, &pose_ab, &mut memory.closest, budget) {
                        Touch::Crossing => PairDistance {
                            distance: 0.0,
                            intersecting: true,
                        },
                        Touch::Apart(upper) => {
                            memory.upper = memory.upper.min(upper);
                            if least > 0.0 {
                                memory.pending.push(Pending {
                                    t,
                                    pose_ab,
                                    lower: 0.0,
                                    upper,
                                    hulls_apart: false,
                                });
                            }
                            return None;
                        }
                        Touch::Undecided => {
                            memory.search_now = true;
                            self.search_now(k, (pa, pb), best, hull, memory)?
                        }
                    }
                } else {
                    // a mesh and a primitive, or meshes too close for a crossing test, whose
                    // hulls overlap
                    self.search_now(k, (pa, pb), best, hull, memory)?
                }
            }
        };
        memory.reference = (d.distance, pose_ab);
        Some(d)
    }

    /// For [`CollisionSet::fold_pair`]: the distance of pair `k`, whose hulls overlap (signed
    /// distance `hull`), at the world poses `(pa, pb)` of its objects, searched now, bounded by
    /// the smallest distance so far `best`, or (once the pair has intersected) by the least
    /// positive distance, which still finds an intersection (a pair of meshes is then given
    /// the crossing test, whose budget is lifted).
    fn search_now(
        &self,
        k: usize,
        (pa, pb): (&PPose, &PPose),
        best: f64,
        hull: f64,
        memory: &mut PairMemory,
    ) -> Option<PairDistance> {
        let bound = best.max(f64::MIN_POSITIVE);
        let found = self.pair_distance(k, (pa, pb), &mut memory.closest, bound, Some(hull));
        if found.is_none() {
            memory.reference = (bound, pa.inv_mul(pb));
        }
        found
    }

    /// The distance of pair `k` at the world poses `(pa, pb)` of its objects, as
    /// [`ClearanceGeometry`] reads them, if it
    /// is below `bound` (`None`: not below; convex pairs are always answered). `closest` is
    /// the pair's closest triangles, read as a seed and updated; `hull` the hulls' signed
    /// distance if the caller has it. A pair with a mesh is first tried with
    /// [`CollisionSet::proven_by_hulls`], then searched triangle by triangle.
    fn pair_distance(
        &self,
        k: usize,
        (pa, pb): (&PPose, &PPose),
        closest: &mut (u32, u32),
        bound: f64,
        hull: Option<f64>,
    ) -> Option<PairDistance> {
        let (a, b) = self.pairs[k];
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        if oa.triangles.is_none() && ob.triangles.is_none() {
            return Some(self.convex_distance(a, b, (pa, pb), None, None));
        }
        let hull = hull.unwrap_or_else(|| self.convex_distance(a, b, (pa, pb), None, None).distance);
        if hull >= bound {
            return None;
        }
        if let Ok(distance) = self.proven_by_hulls(a, b, (pa, pb), hull, closest) {
            return (distance < bound).then_some(PairDistance {
                distance,
                intersecting: false,
            });
        }
        let distance = match (&oa.triangles, &ob.triangles) {
            (None, None) => unreachable!("convex pairs are answered above"),
            (Some(ma), Some(mb)) => mesh_distance(ma, mb, &pa.inv_mul(pb), closest, bound)?,
            (Some(ma), None) => {
                query::distance(pa, ma, pb, &*ob.convex)
                    .expect("parry supports meshes against convex shapes")
                    .distance
            }
            (None, Some(mb)) => {
                query::distance(pa, &*oa.convex, pb, mb)
                    .expect("parry supports meshes against convex shapes")
                    .distance
            }
        };
        (distance < bound).then_some(PairDistance {
            distance,
            intersecting: distance <= 0.0,
        })
    }

    /// The distance of objects `a` and `b` (one of them a mesh) proven by their hulls: when
    /// the hulls are apart (`hull` > 0, their distance) and a pair of actual parts (triangles;
    /// a primitive is its own part) is no further apart than `hull` + [`HULL_CERTIFICATE`],
    /// that pair's distance is the objects' distance to within the certificate, since a mesh
    /// lies inside its hull. The parts tried: `closest` (the pair's last closest parts), then
    /// the parts under the hulls' closest points; `closest` receives the closer. Not proven:
    /// `Err` with the smallest actual distance found, an upper bound of the objects'.
    fn proven_by_hulls(
        &self,
        a: usize,
        b: usize,
        (pa, pb): (&PPose, &PPose),
        hull: f64,
        closest: &mut (u32, u32),
    ) -> std::result::Result<f64, f64> {
        let seeded = self.part_distance(a, b, (pa, pb), *closest);
        if hull <= 0.0 {
            return Err(seeded);
        }
        if seeded <= hull + HULL_CERTIFICATE {
            return Ok(seeded);
        }
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        let Ok(ClosestPoints::WithinMargin(ca, cb)) = query::closest_points(pa, &*oa.convex, pb, &*ob.convex, f64::MAX)
        else {
            return Err(seeded);
        };
        // the triangle of a mesh nearest a point on its hull (world frame)
        let part = |o: &Object, pose: &PPose, p: PVector| {
            (o.triangles.as_ref()).map_or(0, |m| {
                m.project_local_point_and_get_location(pose.inverse_transform_point(p), false)
                    .1
                    .0
            })
        };
        let parts = (part(oa, pa, ca), part(ob, pb, cb));
        let under = self.part_distance(a, b, (pa, pb), parts);
        if under < seeded {
            *closest = parts;
        }
        if under <= hull + HULL_CERTIFICATE {
            Ok(under)
        } else {
            Err(under.min(seeded))
        }
    }

    /// The distance between part `i` of `a` and part `j` of `b` (a mesh's triangle, or a
    /// primitive whole).
    fn part_distance(&self, a: usize, b: usize, (pa, pb): (&PPose, &PPose), (i, j): (u32, u32)) -> f64 {
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        let gap = match (&oa.triangles, &ob.triangles) {
            (Some(ma), Some(mb)) => query::distance(pa, &ma.triangle(i), pb, &mb.triangle(j)),
            (Some(ma), None) => query::distance(pa, &ma.triangle(i), pb, &*ob.convex),
            (None, Some(mb)) => query::distance(pa, &*oa.convex, pb, &mb.triangle(j)),
            (None, None) => query::distance(pa, &*oa.convex, pb, &*ob.convex),
        };
        gap.expect("parry supports triangles and convex shapes").distance
    }

    /// The signed distance of the convex shapes of `a` and `b` (negative: penetration depth),
    /// from [`CollisionSet::convex_gap`] (`support`, `axis` as there) and, when they touch,
    /// [`CollisionSet::convex_contact`].
    fn convex_distance(
        &self,
        a: usize,
        b: usize,
        (pa, pb): (&PPose, &PPose),
        mut support: Option<&mut (u32, u32)>,
        axis: Option<&mut PVector>,
    ) -> PairDistance {
        let gap = self.convex_gap(a, b, pa, pb, support.as_deref_mut(), axis);
        if gap > 0.0 {
            return PairDistance {
                distance: gap,
                intersecting: false,
            };
        }
        let depth = (self.convex_contact(a, b, pa, pb, support)).map_or(0.0, |c| c.dist.min(0.0));
        PairDistance {
            distance: depth,
            intersecting: true,
        }
    }

    /// A lower bound of the distance between the convex shapes of `a` and `b` (`pose_ab`: b's
    /// shape frame in a's) from any unit axis `n` (a's frame): the gap between their
    /// projections on it, `n·t + m·s_b(−m) − n·s_a(n)` with `m = Rᵀn` (s the support points,
    /// `at` their climbs' starts, updated). Two convex shapes are at least that far apart; along
    /// the last closest points' axis it is the distance itself when the poses have not changed,
    /// and falls short of it only to second order in the axis' turn.
    fn separation_along(&self, a: usize, b: usize, pose_ab: &PPose, n: PVector, at: &mut (u32, u32)) -> f64 {
        let (sa, sb) = (self.objects[a].support(at.0), self.objects[b].support(at.1));
        let m = pose_ab.rotation.inverse() * n;
        let gap = n.dot(pose_ab.translation) + m.dot(sb.local_support_point(-m)) - n.dot(sa.local_support_point(n));
        *at = (sa.at(at.0), sb.at(at.1));
        gap
    }

    /// The support maps of objects `a` and `b`, hulls climbing from `at` ([`Climber`]); `None`
    /// when neither is a hull (two primitives: parry's own distance and contact are exact
    /// for them).
    fn supports(&self, a: usize, b: usize, at: (u32, u32)) -> Option<(Support<'_>, Support<'_>)> {
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        (oa.climb.is_some() || ob.climb.is_some()).then(|| (oa.support(at.0), ob.support(at.1)))
    }

    /// The distance between the convex shapes of objects `a` and `b` at world poses `pa`, `pb`
    /// (GJK; 0 when they touch or overlap). With `at` (the pair's last support vertices,
    /// updated), a hull's support map climbs from there instead of scanning every vertex, and
    /// `axis` (if given) receives the unit direction from `a` to `b` along their closest points
    /// in `a`'s frame (zero when they touch, or for two primitives).
    pub(super) fn convex_gap(
        &self,
        a: usize,
        b: usize,
        pa: &PPose,
        pb: &PPose,
        at: Option<&mut (u32, u32)>,
        axis: Option<&mut PVector>,
    ) -> f64 {
        if let Some(at) = at
            && let Some((ca, cb)) = self.supports(a, b, *at)
        {
            // parry's distance_support_map_support_map, keeping GJK's separating axis
            let pos12 = pa.inv_mul(pb);
            let start = (-pos12.translation).try_normalize().unwrap_or(PVector::X);
            let mut simplex = VoronoiSimplex::new();
            simplex.reset(CsoPoint::from_shapes(&pos12, &ca, &cb, start));
            let (gap, found) = match gjk::closest_points(&pos12, &ca, &cb, f64::MAX, true, &mut simplex) {
                GJKResult::ClosestPoints(p1, p2, n) => ((p1 - p2).length(), n),
                _ => (0.0, PVector::ZERO),
            };
            if let Some(axis) = axis {
                *axis = found;
            }
            *at = (ca.at(at.0), cb.at(at.1));
            return gap;
        }
        if let Some(axis) = axis {
            *axis = PVector::ZERO;
        }
        let (sa, sb) = (&*self.objects[a].convex, &*self.objects[b].convex);
        (query::distance(pa, sa, pb, sb))
            .expect("parry supports convex pairs")
            .distance
    }

    /// parry's contact of the convex shapes of objects `a` and `b` at world poses `pa`, `pb`,
    /// in world coordinates; `None` when apart. `at` as in [`CollisionSet::convex_gap`] (EPA on
    /// the climbing support maps).
    pub(super) fn convex_contact(
        &self,
        a: usize,
        b: usize,
        pa: &PPose,
        pb: &PPose,
        at: Option<&mut (u32, u32)>,
    ) -> Option<query::Contact> {
        if let Some(at) = at
            && let Some((ca, cb)) = self.supports(a, b, *at)
        {
            let local = details::contact_support_map_support_map(&pa.inv_mul(pb), &ca, &cb, 0.0);
            *at = (ca.at(at.0), cb.at(at.1));
            return local.map(|c| query::Contact {
                point1: *pa * c.point1,
                point2: *pb * c.point2,
                normal1: pa.rotation * c.normal1,
                normal2: pb.rotation * c.normal2,
                ..c
            });
        }
        let (sa, sb) = (&*self.objects[a].convex, &*self.objects[b].convex);
        query::contact(pa, sa, pb, sb, 0.0).expect("parry supports convex pairs")
    }
}

/// The support map of a convex object for GJK and EPA: a hull's by hill climbing, or a
/// primitive's own.
enum Support<'a> {
    Hull(Climber<'a>),
    Primitive(&'a dyn SupportMap),
}

impl Support<'_> {
    /// Where a hull's climb ended (`start` for a primitive).
    fn at(&self, start: u32) -> u32 {
        match self {
            Support::Hull(c) => c.at.get(),
            Support::Primitive(_) => start,
        }
    }
}

impl SupportMap for Support<'_> {
    fn local_support_point(&self, dir: PVector) -> PVector {
        match self {
            Support::Hull(c) => c.local_support_point(dir),
            Support::Primitive(s) => s.local_support_point(dir),
        }
    }
}

/// The smallest distance between a triangle of `m1` and a triangle of `m2` (`pos12`: `m2`'s
/// frame in `m1`'s), if below `bound`; `closest` seeds the search with a pair of triangles and
/// receives the closest pair found. 0 as soon as two triangles touch.
fn mesh_distance(m1: &TriMesh, m2: &TriMesh, pos12: &PPose, closest: &mut (u32, u32), bound: f64) -> Option<f64> {
    let triangles = |pair| triangle_distance(m1, m2, pos12, pair);
    let seeded = triangles(*closest);
    let best = Cell::new(if seeded < bound { seeded } else { bound });
    let found = Cell::new((seeded < bound).then_some(*closest));
    // each box re-boxed in the other's frame bounds the distance; the larger bound is used
    let (two_in_one, one_in_two) = (Rebox::new(pos12), Rebox::new(&pos12.inverse()));
    // what could be closer, or tie with the best to round-off, is looked at
    let reach = || best.get() + ROUND_OFF;
    let boxes_closer = |n1: &BvhNode, n2: &BvhNode| {
        if best.get() <= 0.0 {
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
enum Touch {
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
fn meshes_touch(m1: &TriMesh, m2: &TriMesh, pos12: &PPose, closest: &mut (u32, u32), budget: usize) -> Touch {
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

/// An upper bound of how far a point of b's bounding sphere (`centre`, `radius`, in b's frame)
/// has moved relative to a between the relative poses `then` and `now` (`a_T_b`): a point
/// `c + u` (`|u| ≤ radius`) moves by `(now·c − then·c) + (R_now − R_then) u`, at most
/// `|now·c − then·c| + 2 sin(θ/2) · radius`, with `θ` the angle of the rotation between them
/// (`2 sin(θ/2)` is the spectral norm of `R_now − R_then`, and `sin(θ/2)` the length of the
/// vector part of the unit quaternion `q_then⁻¹ q_now`). Distances are 1-Lipschitz in such a
/// displacement, so a lower bound `L` at `then` gives `L − moved` at `now`.
fn moved(then: &PPose, now: &PPose, centre: PVector, radius: f64) -> f64 {
    let turn = then.rotation.inverse() * now.rotation;
    let half_sine = PVector::new(turn.x, turn.y, turn.z).length();
    (*now * centre - *then * centre).length() + 2.0 * half_sine * radius
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

/// One loaded collision object as the contact query ([`super::contact`]) reads it.
pub(super) struct ObjectView<'a> {
    /// Its link.
    pub link: &'a str,
    /// The model frame it is fixed to.
    pub frame: usize,
    /// `frame_T_shape` in parry's form.
    pub placement: &'a PPose,
    /// The convex shape (a primitive, or a mesh's hull).
    pub convex: &'a dyn Shape,
    /// The exact triangles of a mesh read as [`ClearanceGeometry::Mesh`].
    pub triangles: Option<&'a TriMesh>,
    /// Bounding sphere centre in the shape frame (m) and its radius (m).
    pub sphere: (PVector, f64),
}

impl CollisionSet {
    /// The loaded objects, in the order the pairs of [`CollisionSet::object_pairs`] index.
    pub(super) fn objects(&self) -> impl Iterator<Item = ObjectView<'_>> + '_ {
        (0..self.objects.len()).map(|k| self.object(k))
    }

    /// Object `k` of [`CollisionSet::objects`].
    pub(super) fn object(&self, k: usize) -> ObjectView<'_> {
        let o = &self.objects[k];
        ObjectView {
            link: &o.link,
            frame: o.frame,
            placement: &o.placement,
            convex: &*o.convex,
            triangles: o.triangles.as_ref(),
            sphere: (o.centre, o.radius),
        }
    }

    /// The distance of pair `k` at the world poses `(pa, pb)` of its objects, as this set reads them (the
    /// clearance's own search; `closest` seeds it with the two triangles found closest before,
    /// and receives them).
    pub(super) fn exact_pair_distance(
        &self,
        k: usize,
        (pa, pb): (&PPose, &PPose),
        closest: &mut (u32, u32),
    ) -> PairDistance {
        self.pair_distance(k, (pa, pb), closest, f64::INFINITY, None)
            .expect("an unbounded search finds the distance")
    }

    /// The checked pairs as indices into [`CollisionSet::objects`].
    pub(super) fn object_pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }
}

/// [`to_parry`] for the contact query: our pose in parry's form.
pub(super) fn parry_pose(p: &Pose) -> PPose {
    to_parry(p)
}
