//! The shapes attached to a robot's frames, beside the dynamics [`Model`] (as Pinocchio keeps
//! a `GeometryModel` beside its `Model`): the URDF's visuals and collision elements, each on
//! the frame of its link, and the self-clearance of the collision geometry along a motion.
//!
//! | file | holds |
//! |---|---|
//! | `mod.rs` | [`GeometryModel`], [`GeometryObject`] |
//! | `mesh.rs` | [`mesh::read_mesh`]: STL (binary, ASCII), COLLADA, OBJ (mesh-loader) → exact f32 vertices, welded indices |
//! | `claims.rs` | what a mesh file claims (counts, nesting, a binary STL's length) checked against what it holds, before mesh-loader allocates |
//! | `pairs.rs` | which pairs of collision objects are checked ([`PairFilter`]) |
//! | `collision_set.rs` | [`CollisionSet`] (the loaded parry shapes and pairs), [`GeometryData`] (workspace), queries at one pose |
//! | `bvh.rs` | `Bvh`: a mesh's bounding-volume hierarchy, flat; nearest triangle to a point (std only: `build.rs` builds the Faze4's with it) |
//! | `triangles.rs` | a mesh's exact triangles with their hierarchy, as the searches read them |
//! | `mesh_cache.rs` | each mesh's hierarchy made once: carried in the binary for the Faze4, kept in the user's cache folder for other meshes ([`cache_folder`]) |
//! | `search.rs` | the two-mesh BVH traversals (distance, crossing test) the set's queries use |
//! | `clearance.rs` | [`Clearance`]: a run's accumulator, sample by sample, into a [`ClearanceReport`] |
//! | `path.rs` | [`PathClearance`]: a path's bounds, computed once, shared by the runs that follow it |
//! | `contact.rs` | [`ContactGeometry`]: penetrating convex pairs as contact points (point, normal, φ) |
//! | `report.rs` | [`ClearanceReport`]: per pair minimum over a run, serialisable |

mod bvh;
mod claims;
mod clearance;
mod collision_set;
mod contact;
mod hull;
pub mod mesh;
mod mesh_cache;
mod motion_bound;
mod node_hulls;
mod pairs;
mod path;
mod report;
mod search;
mod triangles;

pub use clearance::Clearance;
pub use collision_set::{CollisionSet, GeometryData, Warning};
pub use contact::{Contact, ContactData, ContactGeometry, REFRESH_EVERY, REFRESH_MOTION};
pub use mesh_cache::{FORMAT as CACHE_FORMAT, folder as cache_folder};
pub use pairs::{PairFilter, checked_pairs};
pub use path::{MAX_PATH_BYTES, PathBuilder, PathClearance};
pub use report::{ClearanceGeometry, ClearanceReport, PairDistance, PairReport};

use std::path::Path;

use crate::error::Result;
use crate::faze4;
use crate::model::{
    FrameId, Geometry, LoadOptions, LoadWarning, Model, PackagePaths, ReadOptions, RobotDescription, describe_file,
    urdf,
};
use crate::spatial::Pose;

/// A robot as read from a file: the dynamics [`Model`] and, beside it, the shapes attached to
/// its frames.
#[derive(Clone, Debug)]
pub struct Robot {
    /// Kinematics and dynamics.
    pub model: Model,
    /// Visuals and collision geometry, by frame.
    pub geometry: GeometryModel,
    /// What reading the file skipped or changed (transmissions skipped, inertias balanced).
    pub warnings: Vec<LoadWarning>,
}

impl Robot {
    /// Reads and validates the robot file at `path`, of any format faze4 reads (URDF, xacro
    /// without arguments, MJCF: [`crate::model::robot_file`]): its model and its geometry. Mesh
    /// files are only located (`packages` resolves `package://`), not read.
    pub fn from_urdf_file(path: &Path, packages: &PackagePaths) -> Result<Robot> {
        let read = ReadOptions {
            packages: packages.clone(),
            xacro_args: Vec::new(),
        };
        Robot::from_file_with(path, &read, &LoadOptions::default())
    }

    /// Reads and validates the robot file at `path` in whichever format it is (URDF, xacro,
    /// MJCF: [`crate::model::robot_file`]), with `read` (packages, xacro arguments) and `options`.
    /// A file that is a byte-for-byte copy of a description faze4 bundles
    /// ([`faze4::is_bundled_file`]) gets that arm's facts (its defaults and built-in meshes); one
    /// that only looks like it is told what it gets instead ([`faze4::not_bundled`]).
    pub fn from_file_with(path: &Path, read: &ReadOptions, options: &LoadOptions) -> Result<Robot> {
        let robot = Robot::from_description_with(&describe_file(path, read)?, options)?;
        Ok(robot.with_facts_of(faze4::is_bundled_file(path)))
    }

    /// This robot with the bundled Faze4's facts when `bundled` (its description is one faze4
    /// bundles): its defaults ([`faze4::defaults`]) and the built-in meshes; otherwise, when it
    /// looks like the Faze4, a warning saying what it gets instead.
    fn with_facts_of(mut self, bundled: bool) -> Robot {
        match bundled {
            true => {
                self.model.defaults = faze4::defaults();
                self.geometry.built_in_meshes = true;
            }
            false => {
                self.warnings.extend(
                    faze4::not_bundled(&self.model).map(|(like, gets)| LoadWarning::NotBundled {
                        file: self.model.source.clone(),
                        like,
                        gets: gets.to_string(),
                    }),
                )
            }
        }
        self
    }

    /// The bundled Faze4 with its geometry: the model of `urdf/faze4_arm.urdf`
    /// ([`faze4::model`]), and the visuals and collision geometry of `urdf/faze4_real.urdf` (the
    /// same links in the same order, with the same frames and dynamics: `tests/it/real_model.rs`),
    /// so the real arm is drawn and its real meshes are checked for clearance. The meshes are
    /// the built-in copies unless found on disk.
    pub fn faze4() -> Robot {
        let real = Robot::from_urdf_str(
            faze4::REAL_URDF,
            "bundled urdf/faze4_real.urdf",
            None,
            &PackagePaths::default(),
        )
        .expect("the bundled URDF is valid (tested)");
        Robot {
            model: faze4::model(),
            geometry: real.geometry,
            warnings: Vec::new(),
        }
    }

    /// Reads and validates URDF `text`; `file` names it in errors, `base_dir` anchors relative
    /// mesh paths.
    pub fn from_urdf_str(text: &str, file: &str, base_dir: Option<&Path>, packages: &PackagePaths) -> Result<Robot> {
        Robot::from_urdf_str_with(text, file, base_dir, packages, &LoadOptions::default())
    }

    /// [`Robot::from_urdf_str`] read with `options`.
    pub fn from_urdf_str_with(
        text: &str,
        file: &str,
        base_dir: Option<&Path>,
        packages: &PackagePaths,
        options: &LoadOptions,
    ) -> Result<Robot> {
        let robot = Robot::from_description_with(&urdf::describe(text, file, base_dir, packages)?, options)?;
        Ok(robot.with_facts_of(faze4::is_bundled(text.as_bytes())))
    }

    /// The robot `desc` describes, read with `options`: the description's facts alone (no
    /// arm's defaults, no built-in meshes; [`Robot::from_file_with`] adds a bundled arm's).
    pub fn from_description_with(desc: &RobotDescription, options: &LoadOptions) -> Result<Robot> {
        let (model, warnings) = Model::from_description_with(desc, options)?;
        let geometry = GeometryModel::new(&model, desc);
        Ok(Robot {
            model,
            geometry,
            warnings,
        })
    }
}

/// One shape fixed to a model frame.
#[derive(Clone, Debug, PartialEq)]
pub struct GeometryObject {
    /// The URDF link it belongs to.
    pub link: String,
    /// That link's frame.
    pub frame: FrameId,
    /// Its placement `frame_T_geometry` in that frame (the URDF `<origin>`). The frame's own
    /// placement in its body is [`crate::model::Frame::placement`]: this is the only place the
    /// geometry's offset is stored.
    pub placement: Pose,
    /// The shape (sizes in m; a mesh as its file reference).
    pub geometry: Geometry,
    /// RGBA colour in 0..1 (visuals that give one).
    pub rgba: Option<[f64; 4]>,
}

/// A robot's visuals and collision geometry, each on a model frame. Immutable, like the model;
/// mesh files are located, not read (see [`CollisionSet`] for the loaded collision shapes).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeometryModel {
    /// `<visual>` elements, in frame order (root first, depth-first) then document order.
    pub visuals: Vec<GeometryObject>,
    /// `<collision>` elements, in the same order.
    pub collisions: Vec<GeometryObject>,
    /// `[parent, child]` link frames of every moving joint: the links a joint connects
    /// directly, whose pairs [`PairFilter::NonAdjacent`] skips.
    pub joined: Vec<[FrameId; 2]>,
    /// Whether a mesh reference not found on disk is loaded from the Faze4's meshes built into
    /// the binary ([`crate::faze4::meshes`]): only for a description faze4 bundles.
    pub built_in_meshes: bool,
}

impl GeometryModel {
    /// The geometry of `desc`, placed on the frames of `model` (built from that description).
    pub fn new(model: &Model, desc: &RobotDescription) -> GeometryModel {
        let mut geometry = GeometryModel::default();
        // by name, so that thousands of links take no longer than a pass
        let links: std::collections::HashMap<&str, &crate::model::LinkDesc> =
            desc.links.iter().map(|l| (l.name.as_str(), l)).collect();
        let frames: std::collections::HashMap<&str, FrameId> = (model.frames.iter().enumerate())
            .map(|(i, f)| (f.name.as_str(), FrameId(i)))
            .collect();
        for (frame, f) in model.frames.iter().enumerate() {
            let Some(&link) = links.get(f.name.as_str()) else {
                continue;
            };
            let object = |placement: Pose, geometry: &Geometry, rgba| GeometryObject {
                link: link.name.clone(),
                frame: FrameId(frame),
                placement,
                geometry: geometry.clone(),
                rgba,
            };
            (geometry.visuals).extend(link.visuals.iter().map(|v| object(v.origin, &v.geometry, v.rgba)));
            (geometry.collisions).extend(link.collisions.iter().map(|c| object(c.origin, &c.geometry, None)));
        }
        for joint in &desc.joints {
            if let (Some(&parent), Some(&child)) = (frames.get(joint.parent.as_str()), frames.get(joint.child.as_str()))
                && model.frame(parent).body != model.frame(child).body
            {
                geometry.joined.push([parent, child]);
            }
        }
        geometry
    }

    /// The mesh files its visuals and collision elements refer to (those found on disk), each
    /// with its link, in order, as often as they are used.
    pub fn mesh_files(&self) -> impl Iterator<Item = (&str, &Path)> {
        (self.visuals.iter().chain(&self.collisions)).filter_map(|g| match &g.geometry {
            Geometry::Mesh { path: Some(path), .. } => Some((g.link.as_str(), path.as_path())),
            _ => None,
        })
    }

    /// This geometry without its collision elements (collision checking off).
    pub fn without_collisions(&self) -> GeometryModel {
        GeometryModel {
            collisions: Vec::new(),
            ..self.clone()
        }
    }
}

impl std::fmt::Debug for CollisionSet {
    /// How meshes are read, the checked pairs by link, and the links left out.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionSet")
            .field("geometry", &self.geometry())
            .field("pairs", &self.pair_links().collect::<Vec<_>>())
            .field("unchecked", &self.unchecked())
            .finish()
    }
}
