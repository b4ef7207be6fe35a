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
//! the two differ), and the larger is used, then a third time by the gap of the two boxes'
//! projections on the line through their centres (tighter when they lie apart along a
//! diagonal of the axes); the relative pose's rotation matrix and its
//! absolute values are computed once per query for that. Each pair of
//! leaves is one triangle–triangle distance (parry's GJK), unless a cheaper lower bound (exact
//! boxes of the two triangles, their projections on the line through their centroids) already
//! reaches the best distance; the leaves' own boxes are not re-boxed first (the triangles'
//! exact boxes are tighter). The search starts from the two
//! triangles that were closest at the previous query of that pair (a good bound at once when
//! the poses change little from sample to sample). The traversals are in `search.rs`.
//!
//! A pair with a mesh is first tried on its hulls ([`CollisionSet::proven_by_hulls`]): a mesh
//! lies inside its hull, so an actual pair of parts no further apart than the hulls' distance
//! (plus [`HULL_CERTIFICATE`]) is the distance.
//!
//! This is the set alone: the loaded shapes and queries at one pose. A run's clearance, which
//! carries bounds from one sample to the next, is [`super::Clearance`]; the contacts
//! ([`super::ContactGeometry`]) use the same queries.

use parry3d_f64::math::{Mat3 as PMat3, Pose as PPose, Rot3 as PRot3, Vector as PVector};
use parry3d_f64::query::details::closest_points_support_map_support_map_with_params;
use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::query::{self, ClosestPoints, details};
use parry3d_f64::shape::{Ball, Capsule, ConvexPolyhedron, Cuboid, Cylinder, Shape, SupportMap};
use parry3d_f64::transformation::try_convex_hull;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use super::hull::{Adjacency, Climber, hull_candidates};
use super::mesh::load_shape;
use super::mesh_cache;
use super::pairs::{PairFilter, checked_pairs};
use super::report::{ClearanceGeometry, ClearanceReport, PairDistance};
use super::search::{Touch, mesh_distance, mesh_shape_distance, mesh_touches_shape, meshes_touch};
use super::triangles::Triangles;
use super::{GeometryModel, GeometryObject};
use crate::error::{Error, Result, shortest};
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

/// How many pairs of nodes [`CollisionSet::touch`] may open at a sample (a distance search opens
/// some thousands): past it, the pair's distance is searched at each sample instead.
pub(super) const TOUCH_BUDGET: usize = 1000;

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
    /// The convex shape: a primitive, or a mesh's convex hull (shared by the objects that
    /// use the same mesh file at the same scale).
    convex: Arc<dyn Shape>,
    /// The exact triangles of a mesh (for [`ClearanceGeometry::Mesh`]; shared as `convex`),
    /// with their BVH.
    triangles: Option<Arc<Triangles>>,
    /// A hull's vertex adjacency, for its support map by hill climbing (`None`: a primitive).
    climb: Option<Arc<Adjacency>>,
    /// Bounding sphere centre in the shape frame (m).
    centre: PVector,
    /// Bounding sphere radius (m).
    radius: f64,
}

impl Object {
    /// The exact triangles of a mesh; `None` for a primitive or a mesh read as its hull.
    fn mesh(&self) -> Option<&Triangles> {
        self.triangles.as_deref()
    }

    /// Its convex shape's support map: a hull's climbing from vertex `start`, a primitive's
    /// own.
    fn support(&self, start: u32) -> Support<'_> {
        match (self.convex.as_convex_polyhedron(), &self.climb) {
            (Some(hull), Some(adjacency)) => Support::Hull(Climber::new(hull, adjacency, start)),
            _ => Support::Primitive(
                (self.convex.as_support_map()).expect("parry's boxes, balls, cylinders and capsules have support maps"),
            ),
        }
    }

    /// Collision element `g` (number `source`) loaded as `kind` reads it, its mesh (if it is
    /// one) taken from `meshes`; `None` for a mesh found nowhere.
    fn load(source: usize, g: &GeometryObject, meshes: &HashMap<MeshKey, Option<MeshShape>>) -> Option<Object> {
        let axis_fix = Pose::new(
            Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0), // parry y → URDF z
            Vec3::zeros(),
        );
        let (convex, triangles, placement, climb): (Arc<dyn Shape>, _, _, _) = match &g.geometry {
            Geometry::Box { size } => (
                Arc::new(Cuboid::new(PVector::new(size.x, size.y, size.z) / 2.0)),
                None,
                g.placement,
                None,
            ),
            Geometry::Sphere { radius } => (Arc::new(Ball::new(*radius)), None, g.placement, None),
            Geometry::Cylinder { radius, length } => (
                Arc::new(Cylinder::new(length / 2.0, *radius)),
                None,
                g.placement.compose(&axis_fix),
                None,
            ),
            Geometry::Capsule { radius, length } => {
                (Arc::new(Capsule::new_z(length / 2.0, *radius)), None, g.placement, None)
            }
            Geometry::Mesh { .. } => {
                let mesh = meshes.get(&MeshKey::of(g)?)?.as_ref()?;
                (
                    mesh.hull.clone() as Arc<dyn Shape>,
                    mesh.triangles.clone(),
                    g.placement,
                    Some(mesh.climb.clone()),
                )
            }
        };
        let sphere = convex.compute_local_bounding_sphere();
        Some(Object {
            source,
            link: g.link.clone(),
            frame: g.frame.0,
            placement: to_parry(&placement),
            convex,
            triangles,
            climb,
            centre: sphere.center,
            radius: sphere.radius,
        })
    }
}

/// A mesh file at a scale: the objects that share one share its loaded shapes.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct MeshKey {
    /// The reference as the URDF writes it.
    uri: String,
    /// The file it resolved to, if any.
    path: Option<PathBuf>,
    /// `<mesh scale>`, bit for bit.
    scale: [u64; 3],
}

impl MeshKey {
    /// The key of a mesh element; `None` for a primitive.
    fn of(g: &GeometryObject) -> Option<MeshKey> {
        let Geometry::Mesh { uri, path, scale } = &g.geometry else {
            return None;
        };
        Some(MeshKey {
            uri: uri.clone(),
            path: path.clone(),
            scale: [scale.x.to_bits(), scale.y.to_bits(), scale.z.to_bits()],
        })
    }
}

/// Every distinct mesh (file and scale) of `geometry`'s collision elements, loaded once, in parallel (hulls of
/// big meshes take a while); a mesh found nowhere maps to `None`.
fn load_meshes(geometry: &GeometryModel, kind: ClearanceGeometry) -> Result<HashMap<MeshKey, Option<MeshShape>>> {
    // in document order, so that the error reported is the first mesh's that fails
    let mut keys: Vec<MeshKey> = Vec::new();
    for key in geometry.collisions.iter().filter_map(MeshKey::of) {
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    let shapes: Vec<Result<Option<MeshShape>>> = (keys.par_iter())
        .map(|key| MeshShape::load(key, kind, geometry.built_in_meshes))
        .collect();
    let shapes: Vec<Option<MeshShape>> = shapes.into_iter().collect::<Result<_>>()?;
    Ok(keys.into_iter().zip(shapes).collect())
}

/// One mesh's shapes, shared by the objects that use it: its convex hull, the hull's vertex
/// adjacency and (for [`ClearanceGeometry::Mesh`]) its exact triangles with their BVH.
struct MeshShape {
    hull: Arc<ConvexPolyhedron>,
    climb: Arc<Adjacency>,
    triangles: Option<Arc<Triangles>>,
}

impl MeshShape {
    /// The mesh `key` names, read by [`load_shape`] (the file, else the built-in Faze4 copy when
    /// `built_in`, [`GeometryModel::built_in_meshes`]) and
    /// scaled, with (for [`ClearanceGeometry::Mesh`]) its triangles' hierarchy as made before
    /// (`mesh_cache.rs`), else built now; `None` when it is found nowhere.
    ///
    /// Errors: a mesh found but unreadable, non-finite or empty (see [`super::mesh::read_mesh`]);
    /// a mesh whose points span no volume (no convex hull).
    fn load(key: &MeshKey, kind: ClearanceGeometry, built_in: bool) -> Result<Option<MeshShape>> {
        let Some(mesh) = load_shape(&key.uri, key.path.as_deref(), built_in) else {
            return Ok(None);
        };
        let (mesh, contents) = mesh?;
        let path = key.path.clone().unwrap_or_else(|| key.uri.clone().into());
        let scale = key.scale.map(f64::from_bits);
        let points: Vec<PVector> = (mesh.vertices.iter())
            .map(|v| PVector::new(v[0] as f64 * scale[0], v[1] as f64 * scale[1], v[2] as f64 * scale[2]))
            .collect();
        // the hull's volumes are products of three lengths: a scale that makes them overflow
        // (or vanish) is said as such, not as a flat mesh
        let extent = (points.iter()).fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()).max(p.z.abs()));
        let volume = extent * extent * extent;
        if !volume.is_finite() || (extent > 0.0 && volume == 0.0) {
            return Err(Error::InvalidData {
                path: path.clone(),
                message: format!(
                    "<mesh scale=\"{} {} {}\"> makes its coordinates reach {:.3e} m: too {} to compute its hull with (a volume, a length cubed, {} floating-point numbers)",
                    shortest(scale[0]),
                    shortest(scale[1]),
                    shortest(scale[2]),
                    extent,
                    if volume == 0.0 { "small" } else { "large" },
                    if volume == 0.0 { "underflows" } else { "overflows" }
                ),
            });
        }
        // parry's ConvexPolyhedron::from_convex_hull, keeping the hull's triangles for the
        // climb's edges
        let no_hull = || Error::InvalidData {
            path: path.clone(),
            message: "the mesh spans no volume (no convex hull)".into(),
        };
        let (corners, faces) = try_convex_hull(&hull_candidates(&points)).map_err(|_| no_hull())?;
        let climb = Adjacency::of(corners.len(), &faces);
        let hull = ConvexPolyhedron::from_convex_mesh(corners, &faces).ok_or_else(no_hull)?;
        let triangles = match kind {
            ClearanceGeometry::Hull => None,
            ClearanceGeometry::Mesh => {
                let (bvh, hulls, _) = mesh_cache::hierarchy(contents, key.scale, &points, &mesh.triangles);
                Some(Arc::new(Triangles::new(points, mesh.triangles, Some((bvh, hulls)))))
            }
        };
        Ok(Some(MeshShape {
            hull: Arc::new(hull),
            climb: Arc::new(climb),
            triangles,
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

/// The workspace of single-pose queries ([`CollisionSet::distances`]): world poses of the
/// objects, the last distances and each pair's closest parts (the next search's seed). Sized
/// once by [`GeometryData::new`]; queries allocate nothing.
pub struct GeometryData {
    /// World pose of each object's shape (parry's form).
    poses: Vec<PPose>,
    /// The last [`CollisionSet::distances`], one per pair in [`CollisionSet::pair_links`] order.
    pub distances: Vec<PairDistance>,
    /// Each pair's closest triangles at its last query.
    closest: Vec<(u32, u32)>,
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
            closest: vec![(0, 0); set.pairs.len()],
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
    /// `filter` checks. Meshes are loaded through `mesh::load_shape` (the file, else the built-in Faze4 copy for a bundled description); a mesh found nowhere
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
        // each distinct mesh is loaded once, the objects in document order
        let meshes = load_meshes(geometry, kind)?;
        let loaded = (geometry.collisions.iter().enumerate()).map(|(source, g)| Object::load(source, g, &meshes));
        let (mut warnings, mut unchecked, mut kept, mut objects) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (g, object) in geometry.collisions.iter().zip(loaded) {
            match object {
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
    pub(super) fn place(&self, frame_pose: &[Pose], poses: &mut [PPose]) {
        for (o, pose) in self.objects.iter().zip(poses) {
            *pose = to_parry(&frame_pose[o.frame]) * o.placement;
        }
    }

    /// The distance of every checked pair at the pose whose frames are at `frame_pose`, into
    /// `data.distances`.
    pub fn distances(&self, frame_pose: &[Pose], data: &mut GeometryData) {
        self.place(frame_pose, &mut data.poses);
        let poses = &data.poses;
        (data.distances.par_iter_mut().zip(&mut data.closest).enumerate()).for_each(|(k, (distance, closest))| {
            let (a, b) = self.pairs[k];
            *distance = self
                .pair_distance(k, (&poses[a], &poses[b]), closest, f64::INFINITY, None, 0.0)
                .expect("an unbounded search finds the distance");
        });
    }

    /// An empty report for this set's pairs, for a [`super::Clearance`] to fold a run into.
    pub fn new_report(&self) -> ClearanceReport {
        ClearanceReport::new(self.geometry(), self.pair_links(), self.unchecked().to_vec())
    }

    /// Whether a triangle of the mesh of object `a` or `b` touches or crosses the other's
    /// triangles (or the other object whole, a primitive) at their relative pose `pose_ab`
    /// ([`meshes_touch`], [`mesh_touches_shape`], opening at most `budget` nodes or pairs of
    /// nodes; `closest` is tried first and receives a crossing pair); `None` when neither is a
    /// mesh.
    pub(super) fn touch(
        &self,
        a: usize,
        b: usize,
        pose_ab: &PPose,
        closest: &mut (u32, u32),
        budget: usize,
    ) -> Option<Touch> {
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        match (oa.mesh(), ob.mesh()) {
            (Some(ma), Some(mb)) => Some(meshes_touch(ma, mb, pose_ab, closest, budget)),
            (Some(ma), None) => Some(mesh_touches_shape(ma, &*ob.convex, pose_ab, &mut closest.0, budget)),
            (None, Some(mb)) => Some(mesh_touches_shape(
                mb,
                &*oa.convex,
                &pose_ab.inverse(),
                &mut closest.1,
                budget,
            )),
            (None, None) => None,
        }
    }

    /// The distance of pair `k` at the world poses `(pa, pb)` of its objects, as
    /// [`ClearanceGeometry`] reads them, if it is below `bound` (`None`: not below; convex
    /// pairs are always answered). `closest` is the pair's closest triangles, read as a seed
    /// and updated; `hull` the hulls' signed distance if the caller has it. A pair with a mesh
    /// is first tried with [`CollisionSet::proven_by_hulls`], then searched triangle by
    /// triangle. With a `tolerance` > 0 (m; only for pairs known not to touch) a mesh pair's
    /// answer is an actual distance of two parts at most `tolerance` above the pair's (`None`:
    /// the pair is not closer than `bound − tolerance`); 0 is exact.
    pub(super) fn pair_distance(
        &self,
        k: usize,
        (pa, pb): (&PPose, &PPose),
        closest: &mut (u32, u32),
        bound: f64,
        hull: Option<f64>,
        tolerance: f64,
    ) -> Option<PairDistance> {
        let (a, b) = self.pairs[k];
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        if oa.triangles.is_none() && ob.triangles.is_none() {
            return Some(self.convex_distance(a, b, (pa, pb), None, None));
        }
        let hull = hull.unwrap_or_else(|| self.convex_distance(a, b, (pa, pb), None, None).distance);
        if hull >= bound - tolerance {
            return None;
        }
        if let Ok(distance) = self.proven_by_hulls(a, b, (pa, pb), hull, (closest, (0, 0)), tolerance) {
            return (distance < bound).then_some(PairDistance {
                distance,
                intersecting: false,
            });
        }
        let distance = match (oa.mesh(), ob.mesh()) {
            (None, None) => unreachable!("convex pairs are answered above"),
            (Some(ma), Some(mb)) => mesh_distance(ma, mb, &pa.inv_mul(pb), closest, bound, tolerance)?,
            // the relative poses as parry's query::distance forms them, so that the exact
            // search gives its value bit for bit
            (Some(ma), None) => {
                mesh_shape_distance(ma, &*ob.convex, &pa.inv_mul(pb), &mut closest.0, bound, tolerance)?
            }
            (None, Some(mb)) => mesh_shape_distance(
                mb,
                &*oa.convex,
                &pa.inv_mul(pb).inverse(),
                &mut closest.1,
                bound,
                tolerance,
            )?,
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
    /// `Err` with the smallest actual distance found, an upper bound of the objects'. With a
    /// `tolerance` above the certificate, a pair of parts within it of the hulls' distance
    /// proves the distance to within the tolerance. `at`: where the hulls' support maps start
    /// climbing ([`CollisionSet::convex_closest_points`]).
    pub(super) fn proven_by_hulls(
        &self,
        a: usize,
        b: usize,
        (pa, pb): (&PPose, &PPose),
        hull: f64,
        (closest, at): (&mut (u32, u32), (u32, u32)),
        tolerance: f64,
    ) -> std::result::Result<f64, f64> {
        let seeded = self.part_distance(a, b, (pa, pb), *closest);
        if hull <= 0.0 {
            return Err(seeded);
        }
        let certificate = HULL_CERTIFICATE.max(tolerance);
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        let Some((ca, cb)) = self.convex_closest_points(a, b, (pa, pb), at) else {
            return Err(seeded);
        };
        // GJK's distance may stop above the hulls' (by 7.6e-8 m on the SO-101, against coal):
        // a part is accepted against the gap of the hulls' projections on the line through
        // GJK's closest points, which is below their distance whatever GJK's accuracy; it is
        // computed (two support scans) only for a part already within the certificate of
        // GJK's distance, since the gap is no larger
        let lower = std::cell::OnceCell::new();
        let proves = |part: f64| {
            part <= hull + certificate
                && part
                    <= *lower.get_or_init(|| hull.min(projection_gap(pa, &*oa.convex, pb, &*ob.convex, cb - ca)))
                        + certificate
        };
        if proves(seeded) {
            return Ok(seeded);
        }
        // the triangle of a mesh nearest a point on its hull (world frame)
        let part =
            |o: &Object, pose: &PPose, p: PVector| (o.mesh()).map_or(0, |m| m.nearest(pose.inverse_transform_point(p)));
        let parts = (part(oa, pa, ca), part(ob, pb, cb));
        let under = self.part_distance(a, b, (pa, pb), parts);
        if under < seeded {
            *closest = parts;
        }
        if proves(under) {
            Ok(under)
        } else {
            Err(under.min(seeded))
        }
    }

    /// The distance between part `i` of `a` and part `j` of `b` (a mesh's triangle, or a
    /// primitive whole).
    pub(super) fn part_distance(&self, a: usize, b: usize, (pa, pb): (&PPose, &PPose), (i, j): (u32, u32)) -> f64 {
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        let gap = match (oa.mesh(), ob.mesh()) {
            (Some(ma), Some(mb)) => query::distance(pa, &ma.triangle(i), pb, &mb.triangle(j)),
            (Some(ma), None) => query::distance(pa, &ma.triangle(i), pb, &*ob.convex),
            (None, Some(mb)) => query::distance(pa, &*oa.convex, pb, &mb.triangle(j)),
            (None, None) => query::distance(pa, &*oa.convex, pb, &*ob.convex),
        };
        gap.expect("parry supports triangles and convex shapes").distance
    }

    /// The closest points (world frame) of the convex shapes of objects `a` and `b` at world
    /// poses `pa`, `pb`; `None` when they touch. parry's `query::closest_points` (GJK from the
    /// same direction), with a hull's support map climbing from `at` ([`Climber`]) instead of
    /// scanning every vertex: the same points up to ties, for a fraction of the work (parry's
    /// scans of the Faze4's hulls were 7.5 % of the default wave's instructions).
    fn convex_closest_points(
        &self,
        a: usize,
        b: usize,
        (pa, pb): (&PPose, &PPose),
        at: (u32, u32),
    ) -> Option<(PVector, PVector)> {
        let (oa, ob) = (&self.objects[a], &self.objects[b]);
        // parry answers a ball against a convex shape otherwise than by GJK
        let balls = oa.convex.as_ball().is_some() || ob.convex.as_ball().is_some();
        match self.supports(a, b, at).filter(|_| !balls) {
            Some((sa, sb)) => {
                let pos12 = pa.inv_mul(pb);
                let mut simplex = VoronoiSimplex::new();
                match closest_points_support_map_support_map_with_params(&pos12, &sa, &sb, f64::MAX, &mut simplex, None)
                {
                    GJKResult::ClosestPoints(p1, p2, _) => Some((*pa * p1, *pb * pos12.inverse_transform_point(p2))),
                    _ => None,
                }
            }
            None => match query::closest_points(pa, &*oa.convex, pb, &*ob.convex, f64::MAX) {
                Ok(ClosestPoints::WithinMargin(ca, cb)) => Some((ca, cb)),
                _ => None,
            },
        }
    }

    /// The signed distance of the convex shapes of `a` and `b` (negative: penetration depth),
    /// from [`CollisionSet::convex_gap`] (`support`, `axis` as there) and, when they touch,
    /// [`CollisionSet::convex_contact`].
    pub(super) fn convex_distance(
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
    pub(super) fn separation_along(&self, a: usize, b: usize, pose_ab: &PPose, n: PVector, at: &mut (u32, u32)) -> f64 {
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
        convex_pair_distance(pa, &*self.objects[a].convex, pb, &*self.objects[b].convex)
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

/// The distance between two convex shapes at world poses `pa`, `pb` (0 when they touch):
/// parry's, except for two boxes. parry's own box–box distance (its dispatcher's special case)
/// comes out above the distance at some poses (1.9 mm on the Panda's finger boxes, against
/// coal and GJK; dimforge/parry#431 reports it, and 0.31.1 still has it in 3D), and a distance
/// above the true one breaks every lower bound carried from it: two boxes get GJK on their
/// support maps instead.
fn convex_pair_distance(pa: &PPose, sa: &dyn Shape, pb: &PPose, sb: &dyn Shape) -> f64 {
    if let (Some(ca), Some(cb)) = (sa.as_cuboid(), sb.as_cuboid()) {
        return details::distance_support_map_support_map(&pa.inv_mul(pb), ca, cb);
    }
    (query::distance(pa, sa, pb, sb))
        .expect("parry supports convex pairs")
        .distance
}

/// The gap between the projections of two convex shapes (at world poses `pa`, `pb`) on the
/// line along `axis` (world frame, from a towards b): `min n·y − max n·x` over points `y` of b
/// and `x` of a, with `n` the unit axis. Any axis gives a lower bound of their distance
/// (negative when the projections overlap); the axis through their closest points gives the
/// distance itself. `-∞` for a zero axis.
fn projection_gap(pa: &PPose, sa: &dyn Shape, pb: &PPose, sb: &dyn Shape, axis: PVector) -> f64 {
    let Some(n) = axis.try_normalize() else {
        return f64::NEG_INFINITY;
    };
    fn support(s: &dyn Shape) -> &dyn SupportMap {
        s.as_support_map().expect("convex shapes have support maps")
    }
    n.dot(support(sb).support_point(pb, -n)) - n.dot(support(sa).support_point(pa, n))
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
    /// Whether it is a mesh read as [`ClearanceGeometry::Mesh`] (exact triangles).
    pub exact_mesh: bool,
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
            exact_mesh: o.triangles.is_some(),
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
        self.pair_distance(k, (pa, pb), closest, f64::INFINITY, None, 0.0)
            .expect("an unbounded search finds the distance")
    }

    /// The checked pairs as indices into [`CollisionSet::objects`].
    pub(super) fn object_pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// The product of the triangle counts of pair `k`'s objects (a primitive counts 1), for
    /// ordering work by cost.
    pub(super) fn pair_triangles(&self, k: usize) -> usize {
        let count = |o: &Object| o.triangles.as_ref().map_or(1, |t| t.len());
        let (a, b) = self.pairs[k];
        count(&self.objects[a]) * count(&self.objects[b])
    }
}

/// [`to_parry`] for the contact query: our pose in parry's form.
pub(super) fn parry_pose(p: &Pose) -> PPose {
    to_parry(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::search::tests::poses;

    #[test]
    fn two_boxes_are_as_far_apart_as_their_closest_points_where_parrys_box_distance_is_not() {
        // the Panda's finger boxes
        let (a, b) = (
            Cuboid::new(PVector::new(0.011, 0.0075, 0.01)),
            Cuboid::new(PVector::new(0.00875, 0.0035, 0.01175)),
        );
        let mut parry_above = 0;
        for pose in poses(400, PVector::ZERO, 0.06) {
            let ours = convex_pair_distance(&PPose::IDENTITY, &a, &pose, &b);
            let truth = match query::closest_points(&PPose::IDENTITY, &a, &pose, &b, f64::MAX).unwrap() {
                ClosestPoints::WithinMargin(p, q) => (p - q).length(),
                _ => 0.0,
            };
            assert!((ours - truth).abs() < 1e-12, "{ours} against {truth} at {pose:?}");
            let parry = query::distance(&PPose::IDENTITY, &a, &pose, &b).unwrap().distance;
            if parry > truth + 1e-6 {
                parry_above += 1;
            }
        }
        // the case this guards against occurs among these poses
        assert!(parry_above > 0, "parry's box–box distance was right at every pose");
    }
}
