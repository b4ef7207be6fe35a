//! A robot as a file describes it, before validation: links, joints, inertials, visuals and
//! collision elements in plain Rust types. [`crate::model::urdf`] fills it from a URDF,
//! [`crate::model::mjcf`] from an MJCF model; the model builder validates it.

use std::path::PathBuf;

use crate::spatial::{Pose, Vec3};

/// A robot description: what a URDF or an MJCF model says, format-free.
#[derive(Clone, Debug, Default)]
pub struct RobotDescription {
    /// The robot's name.
    pub name: String,
    /// The file it came from (for error messages).
    pub file: String,
    /// The format it was read from, as the banner and summary write it (`urdf`, `xacro`, `mjcf`).
    pub format: String,
    /// What the reader mapped from its format onto faze4's terms, or left out (empty for a
    /// URDF, which says everything in faze4's terms).
    pub mapped: Vec<Mapping>,
    /// A start pose the file offers (MJCF's `home` keyframe): each moving joint's name and
    /// position (rad or m), in document order.
    pub home: Option<Vec<(String, f64)>>,
    /// Links in document order.
    pub links: Vec<LinkDesc>,
    /// Joints in document order.
    pub joints: Vec<JointDesc>,
    /// Motors behind joints, in document order.
    pub transmissions: Vec<TransmissionDesc>,
}

/// One thing a reader mapped from its format onto faze4's terms (MJCF's `armature` as rotor
/// inertia) or left out (a world geom), and the elements it did it for.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Mapping {
    /// What the file says, in its own words (`armature`, `forcerange`, `frictionloss`).
    pub from: String,
    /// What faze4 made of it (`rotor inertia`, `effort limit`), or why it was left out; a run
    /// option it names is written `` `field` ``, for each front end to word
    /// ([`crate::error::in_words`]).
    pub to: String,
    /// The elements concerned (joint, actuator or geom names), in document order.
    pub items: Vec<String>,
    /// Whether it changes the dynamics faze4 simulates from those the file describes (a
    /// property faze4 does not simulate): the reader's caller warns about it.
    pub changes_dynamics: bool,
}

/// A motor driving one joint through a reducer (a URDF `<transmission>` with Drake's
/// `drake:rotor_inertia` and `drake:gear_ratio`).
#[derive(Clone, Debug, PartialEq)]
pub struct TransmissionDesc {
    /// The transmission's name.
    pub name: String,
    /// The joint it drives.
    pub joint: String,
    /// Rotor inertia at the motor shaft (kg·m²), if given (Drake's default is 0).
    pub rotor_inertia: Option<f64>,
    /// Gear ratio (motor turns per joint turn), if given (Drake's default is 1).
    pub gear_ratio: Option<f64>,
}

/// One link.
#[derive(Clone, Debug, Default)]
pub struct LinkDesc {
    /// Link name.
    pub name: String,
    /// Mass properties; `None` for a massless link.
    pub inertial: Option<InertialDesc>,
    /// Visual geometry in the link frame.
    pub visuals: Vec<Visual>,
    /// Collision geometry in the link frame.
    pub collisions: Vec<Collision>,
}

/// A link's `<inertial>`.
#[derive(Clone, Debug)]
pub struct InertialDesc {
    /// Placement of the inertial frame in the link frame: its origin is the centre of mass (m).
    pub origin: Pose,
    /// Mass (kg).
    pub mass: f64,
    /// Rotational inertia about the centre of mass in the inertial frame (kg·m²):
    /// `[ixx, ixy, ixz, iyy, iyz, izz]`.
    pub inertia: [f64; 6],
}

/// Joint types a description can hold; the unsupported ones keep their name for the error.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum JointType {
    /// Limited rotation.
    Revolute,
    /// Unlimited rotation.
    Continuous,
    /// Translation.
    Prismatic,
    /// No motion (the child is welded to the parent).
    Fixed,
    /// Anything else (floating, planar, spherical…), by name.
    Unsupported(String),
}

/// One joint.
#[derive(Clone, Debug)]
pub struct JointDesc {
    /// Joint name.
    pub name: String,
    /// Joint type.
    pub kind: JointType,
    /// Parent link name.
    pub parent: String,
    /// Child link name.
    pub child: String,
    /// Placement of the joint frame in the parent link frame (m).
    pub origin: Pose,
    /// Axis in the joint frame (any non-zero length).
    pub axis: [f64; 3],
    /// Lower and upper position limits, if given.
    pub limits: Option<(f64, f64)>,
    /// Effort limit, if given (> 0).
    pub effort: Option<f64>,
    /// Velocity limit (rad/s or m/s), if given (> 0).
    pub velocity: Option<f64>,
    /// Viscous damping (0 if not given).
    pub damping: f64,
    /// Coulomb friction at the joint (N·m or N, ≥ 0; 0 if not given): URDF's `<dynamics
    /// friction>`, MJCF's `frictionloss`.
    pub friction: f64,
    /// `<mimic>`: this joint follows another, q = multiplier·q_leader + offset.
    pub mimic: Option<MimicDesc>,
}

/// A `<mimic joint multiplier offset>` element.
#[derive(Clone, Debug, PartialEq)]
pub struct MimicDesc {
    /// The leading joint's name.
    pub joint: String,
    /// m in q = m·q_leader + o (1 if not given).
    pub multiplier: f64,
    /// o in q = m·q_leader + o (0 if not given).
    pub offset: f64,
}

/// Shape of a visual or a collision element.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// Axis-aligned box with the given side lengths (m), centred on the visual origin.
    Box {
        /// Side lengths x, y, z (m).
        size: Vec3,
    },
    /// Cylinder along z, centred on the visual origin.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length (m).
        length: f64,
    },
    /// Capsule along z, centred on the visual origin: a cylinder with a hemisphere on each end
    /// (MJCF's capsule).
    Capsule {
        /// Radius of the cylinder and the hemispheres (m).
        radius: f64,
        /// Length of the cylinder between the hemispheres' centres (m).
        length: f64,
    },
    /// Sphere centred on the visual origin.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A mesh file.
    Mesh {
        /// The reference as written in the file (`package://…`, relative, or absolute).
        uri: String,
        /// The file it resolved to, if it exists.
        path: Option<PathBuf>,
        /// Scale factors x, y, z.
        scale: Vec3,
    },
}

/// A visual: geometry placed in a link frame, with an optional colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Visual {
    /// Placement of the geometry in the link frame.
    pub origin: Pose,
    /// The shape.
    pub geometry: Geometry,
    /// RGBA colour in 0..1, if given.
    pub rgba: Option<[f64; 4]>,
}

/// A collision element: geometry placed in a link frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Collision {
    /// Placement of the geometry in the link frame.
    pub origin: Pose,
    /// The shape.
    pub geometry: Geometry,
}
