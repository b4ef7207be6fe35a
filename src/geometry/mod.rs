//! The shapes attached to a robot's frames, beside the dynamics [`Model`] (as Pinocchio keeps
//! a `GeometryModel` beside its `Model`): the URDF's visuals and collision elements, each on
//! the frame of its link, and the self-clearance of the collision geometry along a motion.
//!
//! | file | holds |
//! |---|---|
//! | `mod.rs` | [`GeometryModel`], [`GeometryObject`] |
//! | `mesh.rs` | [`mesh::read_mesh`]: STL (binary, ASCII) → exact f32 vertices, welded indices |
//! | `pairs.rs` | which pairs of collision objects are checked ([`PairFilter`]) |
//! | `clearance.rs` | [`CollisionSet`] (parry shapes), [`GeometryData`] (workspace), distances at a pose |
//! | `report.rs` | [`ClearanceReport`]: per pair minimum over a run, serialisable |

mod clearance;
pub mod mesh;
mod pairs;
mod report;

pub use clearance::{ClearanceGeometry, CollisionSet, GeometryData, PairDistance, Warning};
pub use pairs::{PairFilter, checked_pairs};
pub use report::{ClearanceReport, PairReport};

use crate::model::{Geometry, Model, RobotDescription};
use crate::spatial::Pose;

/// One shape fixed to a model frame.
#[derive(Clone, Debug, PartialEq)]
pub struct GeometryObject {
    /// The URDF link it belongs to.
    pub link: String,
    /// Index of that link's frame in [`Model::frames`].
    pub frame: usize,
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
    /// `[parent, child]` link frames (indices into [`Model::frames`]) of every moving joint:
    /// the links a joint connects directly, whose pairs [`PairFilter::NonAdjacent`] skips.
    pub joined: Vec<[usize; 2]>,
}

impl GeometryModel {
    /// The geometry of `desc`, placed on the frames of `model` (built from that description).
    pub fn new(model: &Model, desc: &RobotDescription) -> GeometryModel {
        let mut geometry = GeometryModel::default();
        for (frame, f) in model.frames.iter().enumerate() {
            let Some(link) = desc.links.iter().find(|l| l.name == f.name) else {
                continue;
            };
            let object = |placement: Pose, geometry: &Geometry, rgba| GeometryObject {
                link: link.name.clone(),
                frame,
                placement,
                geometry: geometry.clone(),
                rgba,
            };
            (geometry.visuals).extend(link.visuals.iter().map(|v| object(v.origin, &v.geometry, v.rgba)));
            (geometry.collisions).extend(link.collisions.iter().map(|c| object(c.origin, &c.geometry, None)));
        }
        for joint in &desc.joints {
            if let (Some(parent), Some(child)) = (model.frame_index(&joint.parent), model.frame_index(&joint.child))
                && model.frames[parent].body != model.frames[child].body
            {
                geometry.joined.push([parent, child]);
            }
        }
        geometry
    }

    /// This geometry without its collision elements (collision checking off).
    pub fn without_collisions(&self) -> GeometryModel {
        GeometryModel {
            collisions: Vec::new(),
            ..self.clone()
        }
    }
}
