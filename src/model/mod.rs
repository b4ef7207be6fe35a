//! The robot model: an immutable kinematic tree of moving bodies.
//!
//! A URDF describes links joined by joints. faze4 keeps every link as a [`Frame`] (so any link
//! can be asked for its pose), but for dynamics it merges links joined by `fixed` joints into
//! one rigid body: the model has exactly one body per moving joint (one degree of freedom
//! each). Body `i` is moved by joint `i`, its parent is `parent[i]` (`None` for the fixed
//! world), and `parent[i] < i`: bodies are numbered root to tip, so a forward pass is a plain
//! loop over `0..n` and a backward pass over `(0..n).rev()`.
//!
//! Only [`urdf`] knows the URDF format (and the urdf-rs crate); it produces a
//! [`RobotDescription`], and [`Model::from_description`] turns any description into a model.

mod build;
mod description;
mod package;
pub mod urdf;

pub use description::{Collision, Geometry, InertialDesc, JointDesc, JointType, LinkDesc, RobotDescription, Visual};
pub use package::PackagePaths;

use crate::spatial::{Inertia, Mat3, Motion, Pose, Vec3, Xform, rotation_about_axis, skew};

/// The bundled Faze4 URDF (`urdf/faze4_arm.urdf`), built into the binary so it runs from any
/// directory.
pub const FAZE4_ARM_URDF: &str = include_str!("../../urdf/faze4_arm.urdf");

/// Name under which the bundled model reports its source.
pub const FAZE4_ARM_SOURCE: &str = "bundled urdf/faze4_arm.urdf";

/// Robot names of the bundled Faze4 models, which get the Faze4 torque limits by default.
pub const FAZE4_NAMES: [&str; 2] = ["faze4_arm", "faze4_real"];

/// The bundled Faze4 model (SPEC §1).
pub fn faze4_arm() -> Model {
    faze4_robot().model
}

/// The bundled Faze4 model with its geometry.
pub fn faze4_robot() -> Robot {
    urdf::read_str(FAZE4_ARM_URDF, FAZE4_ARM_SOURCE, None, &PackagePaths::default())
        .expect("the bundled URDF is valid (tested)")
}

/// Standard gravity used by faze4 (m/s²), pointing along world −z.
pub const STANDARD_GRAVITY: f64 = 9.81;

/// How a moving joint moves its child body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about `axis`, limited to `[lower, upper]`.
    Revolute,
    /// Rotation about `axis`, unlimited.
    Continuous,
    /// Translation along `axis`.
    Prismatic,
}

/// One moving joint (one degree of freedom) and the static facts about it.
#[derive(Clone, Debug)]
pub struct Joint {
    /// The URDF joint name.
    pub name: String,
    /// Revolute, continuous or prismatic.
    pub kind: JointKind,
    /// Unit axis in the joint (= child body) frame. The URDF axis, normalised.
    pub axis: Vec3,
    /// Lower position limit (rad or m; −∞ when unlimited).
    pub lower: f64,
    /// Upper position limit (rad or m; +∞ when unlimited).
    pub upper: f64,
    /// The URDF `effort` limit (N·m or N), if the URDF gives one (> 0).
    pub effort: Option<f64>,
    /// Viscous damping coefficient d in τ_damping = −d·v (N·m·s/rad or N·s/m).
    pub damping: f64,
    /// Name of the URDF link this joint moves (the body's frame).
    pub child_link: String,
}

impl Joint {
    /// The joint's own motion: `child_T_jointframe(q)` as a placement of the child frame in the
    /// joint's origin frame (rotation about, or translation along, `axis` by `q`).
    #[inline]
    pub fn motion_pose(&self, q: f64) -> Pose {
        match self.kind {
            JointKind::Revolute | JointKind::Continuous => {
                let (s, c) = q.sin_cos();
                Pose::new(rotation_about_axis(&self.axis, s, c), Vec3::zeros())
            }
            JointKind::Prismatic => Pose::new(Pose::IDENTITY.rot, self.axis * q),
        }
    }

    /// The joint's motion subspace `s` in the child frame: `(axis, 0)` for a rotation,
    /// `(0, axis)` for a translation.
    pub fn motion_subspace(&self) -> Motion {
        match self.kind {
            JointKind::Revolute | JointKind::Continuous => Motion::new(self.axis, Vec3::zeros()),
            JointKind::Prismatic => Motion::new(Vec3::zeros(), self.axis),
        }
    }

    /// Whether `q` lies within the joint's limits.
    pub fn within_limits(&self, q: f64) -> bool {
        q >= self.lower && q <= self.upper
    }
}

/// A revolute joint's tree rotation with Rodrigues' formula folded in, so that the joint's
/// transform at q needs only `sin q` and `cos q` and no matrix product (the 5 kHz loop
/// computes it for every joint at every step):
///
/// ```text
///   E(q) = R(a, q)ᵀ E_T = P + cos q · Q − sin q · S,    P = a aᵀ E_T,  Q = E_T − P,  S = [a]× E_T
/// ```
///
/// from Rodrigues, `R(a, q)ᵀ = R(a, −q) = cos q · 1 − sin q · [a]× + (1 − cos q) a aᵀ`. `a` is the
/// unit axis and `E_T` the tree rotation (parent to joint frame) of [`Model::x_tree`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisSplit {
    /// `P = a aᵀ E_T`: the part of `E_T` along the axis, which the rotation leaves alone.
    pub along: Mat3,
    /// `Q = E_T − P`: the part across the axis, scaled by `cos q`.
    pub across: Mat3,
    /// `S = [a]× E_T`: the part across the axis turned a quarter turn, scaled by `−sin q`.
    pub turned: Mat3,
}

impl AxisSplit {
    /// The split of `E_T` (`e_tree`) about the unit axis `axis`.
    pub fn new(axis: &Vec3, e_tree: &Mat3) -> Self {
        let along = axis * (axis.transpose() * e_tree);
        Self {
            along,
            across: e_tree - along,
            turned: skew(axis) * e_tree,
        }
    }

    /// `E(q) = R(a, q)ᵀ E_T`, given `sin q` and `cos q`.
    #[inline]
    pub fn rotation(&self, sin: f64, cos: f64) -> Mat3 {
        self.along + self.across * cos - self.turned * sin
    }
}

/// A named frame: one per URDF link, fixed to a body (or to the world).
#[derive(Clone, Debug)]
pub struct Frame {
    /// The URDF link name.
    pub name: String,
    /// The body it is fixed to; `None` for frames welded to the world.
    pub body: Option<usize>,
    /// Its placement `body_T_frame` in that body's frame (or in the world).
    pub placement: Pose,
}

/// The immutable model: kinematic tree, inertias, limits and frames. The shapes attached to
/// the frames (visuals, collision geometry) are in [`crate::geometry::GeometryModel`].
#[derive(Clone, Debug)]
pub struct Model {
    /// The robot's name (URDF `<robot name>`).
    pub name: String,
    /// Where the model came from (a file path, or the name of a bundled model).
    pub source: String,
    /// The n moving joints, in generalised-coordinate order (`q[i]` is joint i's position).
    pub joints: Vec<Joint>,
    /// `parent[i]`: the body that carries joint i (`None`: the world). Always `< i`.
    pub parent: Vec<Option<usize>>,
    /// `x_tree[i]`: Plücker transform from the parent body's frame to joint i's frame at
    /// q = 0 (the URDF joint origin, fixed joints on the way folded in). n entries.
    pub x_tree: Vec<Xform>,
    /// `axis_split[i]`: `x_tree[i]`'s rotation split about joint i's axis (used for revolute
    /// and continuous joints; see [`AxisSplit`]). n entries.
    pub axis_split: Vec<AxisSplit>,
    /// `tree_pose[i]`: the same placement as a pose `λ_T_joint` (parent frame → joint frame).
    pub tree_pose: Vec<Pose>,
    /// `s[i]`: motion subspace of joint i in body i's frame (6-vector). n entries.
    pub s: Vec<Motion>,
    /// `inertia[i]`: spatial inertia of body i (its link and every link welded to it) about
    /// body i's origin, in body i's frame. n entries.
    pub inertia: Vec<Inertia>,
    /// Gravitational acceleration in the world frame (m/s²), `(0, 0, −9.81)` by default.
    pub gravity: Vec3,
    /// Every URDF link as a frame, root first, in depth-first order.
    pub frames: Vec<Frame>,
}

/// A robot as read from a file: the dynamics [`Model`] and, beside it, the shapes attached to
/// its frames.
#[derive(Clone, Debug)]
pub struct Robot {
    /// Kinematics and dynamics.
    pub model: Model,
    /// Visuals and collision geometry, by frame.
    pub geometry: crate::geometry::GeometryModel,
}

impl Model {
    /// Number of degrees of freedom (= moving joints = bodies).
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// Index of the frame named `name`.
    pub fn frame_index(&self, name: &str) -> Option<usize> {
        self.frames.iter().position(|f| f.name == name)
    }

    /// Index of the joint named `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The frame a tool is taken at by default: `tool_link` if the model has one, otherwise
    /// the last link of the chain (the last frame in depth-first order).
    pub fn default_tool_frame(&self) -> usize {
        self.frame_index("tool_link").unwrap_or(self.frames.len() - 1)
    }

    /// Joint damping coefficients, one per joint.
    pub fn damping(&self) -> impl Iterator<Item = f64> + '_ {
        self.joints.iter().map(|j| j.damping)
    }

    /// Whether this is one of the bundled Faze4 models (by robot name).
    pub fn is_faze4(&self) -> bool {
        FAZE4_NAMES.contains(&self.name.as_str()) && self.dof() == 6
    }

    /// Total mass of the moving bodies (kg); links welded to the world are not counted.
    pub fn moving_mass(&self) -> f64 {
        self.inertia.iter().map(|i| i.mass).sum()
    }

    /// This model with a point mass `mass` (kg) fixed at the origin of frame `frame` (e.g. a
    /// payload at the tool).
    pub fn with_point_mass(&self, frame: usize, mass: f64) -> Model {
        self.with_added_inertia(frame, Inertia::point_mass(mass, Vec3::zeros()))
    }

    /// This model with a rigid body of inertia `inertia` (given about frame `frame`'s origin,
    /// in its coordinates) welded to that frame. A frame welded to the world changes nothing.
    pub fn with_added_inertia(&self, frame: usize, inertia: Inertia) -> Model {
        let mut model = self.clone();
        let f = &self.frames[frame];
        if let Some(b) = f.body {
            model.inertia[b] += inertia.transform_to_source(&f.placement.to_xform());
        }
        model
    }

    /// Builds a model from a format-free description (see [`urdf`] for files).
    pub fn from_description(desc: &RobotDescription) -> crate::Result<Model> {
        build::build(desc)
    }

    /// Reads a URDF file's dynamics alone (see [`urdf::read_file`] for the geometry too);
    /// `packages` resolves `package://` mesh references.
    pub fn from_urdf_file(path: &std::path::Path, packages: &PackagePaths) -> crate::Result<Model> {
        urdf::read_file(path, packages).map(|robot| robot.model)
    }
}
