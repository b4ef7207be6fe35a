//! The robot model: an immutable kinematic tree of moving bodies.
//!
//! A URDF describes links joined by joints. faze4 keeps every link as a [`Frame`] (so any link
//! can be asked for its pose), but for dynamics it merges links joined by `fixed` joints into
//! one rigid body: the model has exactly one body per moving joint. Body `i` is moved by the
//! joint `bodies[i]`, its parent is `parent[i]` (`None` for the fixed world), and
//! `parent[i] < i`: bodies are numbered root to tip, so a forward pass is a plain loop over
//! `0..nb` and a backward pass over `(0..nb).rev()`.
//!
//! The degrees of freedom are the moving joints that do not `<mimic>` another (`joints`,
//! `q[i]` is `joints[i]`'s position). A mimic follower's body is driven by its leader's
//! coordinate: `q_body = multiplier·q[coordinate] + offset` ([`Body`]). Without mimic joints
//! body i is moved by joint i (`nb = n`) and the two numberings are the same.
//!
//! Only [`urdf`] knows the URDF format (and the urdf-rs crate), only [`xacro`] xacro, only
//! [`mjcf`] MuJoCo's MJCF; each produces a [`RobotDescription`] (xacro through `urdf`), and
//! [`Model::from_description`] turns any description into a model. [`robot_file`] is the one
//! place that picks a robot file's format and hands it to the file that owns it.

mod build;
pub use build::{LoadOptions, LoadWarning};
mod defaults;
mod description;
pub mod mjcf;
mod package;
pub mod robot_file;
pub mod urdf;
pub mod xacro;

pub use defaults::{ArmDefaults, Board, ShapeIk};
pub use description::{
    Collision, Geometry, InertialDesc, JointDesc, JointType, LinkDesc, Mapping, MimicDesc, RobotDescription,
    TransmissionDesc, Visual,
};
pub use package::{PackagePaths, not_found_advice};
pub use robot_file::{ReadOptions, RobotFormat, describe_file};

pub use crate::id::{FrameId, JointId};

use crate::spatial::{Inertia, Mat3, Motion, Pose, Vec3, rotation_about_axis, skew};

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

impl JointKind {
    /// The SI unit of the joint's position: `"rad"` for a rotation, `"m"` for a translation
    /// (velocities per second, torques N·m or forces N; docs/model.md, 4.1).
    pub fn unit(self) -> &'static str {
        match self {
            JointKind::Revolute | JointKind::Continuous => "rad",
            JointKind::Prismatic => "m",
        }
    }
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
    /// The URDF `velocity` limit (rad/s or m/s), if the URDF gives one (> 0). faze4 does not
    /// enforce it: a run reports how often a joint exceeds it.
    pub velocity: Option<f64>,
    /// Viscous damping coefficient d in τ_damping = −d·v (N·m·s/rad or N·s/m).
    pub damping: f64,
    /// Coulomb friction f (N·m or N, ≥ 0): the step's friction torque is the one that would stop
    /// the joint within the step, within ±f (docs/model.md §2.3); 0 without friction.
    pub friction: f64,
    /// Name of the URDF link this joint moves (the body's frame).
    pub child_link: String,
    /// Inertia of the motor's rotor about its own axis, at the motor shaft (kg·m²); 0 when
    /// the joint has no motor modelled.
    pub rotor_inertia: f64,
    /// Gear ratio r of the motor's reducer: the motor turns r times for one turn of the joint
    /// (1 when the motor drives the joint directly).
    pub gear_ratio: f64,
}

impl Joint {
    /// The joint's own motion: `child_T_jointframe(q)` as a placement of the child frame in the
    /// joint's origin frame (rotation about, or translation along, `axis` by `q`).
    #[inline]
    pub fn motion_pose(&self, q: f64) -> Pose {
        motion_pose(self.kind, &self.axis, q)
    }

    /// The joint's motion subspace `s` in the child frame: `(axis, 0)` for a rotation,
    /// `(0, axis)` for a translation.
    pub fn motion_subspace(&self) -> Motion {
        match self.kind {
            JointKind::Revolute | JointKind::Continuous => Motion::new(self.axis, Vec3::zeros()),
            JointKind::Prismatic => Motion::new(Vec3::zeros(), self.axis),
        }
    }

    /// The rotor's inertia reflected through the reducer, `r²·I_rotor` (kg·m², or kg for a
    /// prismatic joint): a rotor spinning r times faster stores r² times the energy, so the
    /// joint sees it as this much more inertia on its own diagonal entry of M, coupled to no
    /// other joint (Drake's reflected inertia, MuJoCo's and Pinocchio's armature).
    #[inline]
    pub fn reflected_inertia(&self) -> f64 {
        self.gear_ratio * self.gear_ratio * self.rotor_inertia
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
/// unit axis and `E_T` the tree rotation (parent to joint frame), `tree_pose[i].rot`ᵀ.
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

/// The joint motion of a body: a rotation by `q` about `axis` or a translation by `q` along it,
/// as a placement of the child frame in the joint's origin frame.
#[inline]
fn motion_pose(kind: JointKind, axis: &Vec3, q: f64) -> Pose {
    match kind {
        JointKind::Revolute | JointKind::Continuous => {
            let (s, c) = q.sin_cos();
            Pose::new(rotation_about_axis(axis, s, c), Vec3::zeros())
        }
        JointKind::Prismatic => Pose::new(Pose::IDENTITY.rot, axis * q),
    }
}

/// One moving body of the tree and the coordinate that drives it. A body moved by one of the
/// model's [`Joint`]s has `multiplier` 1 and `offset` 0 exactly; a body moved by a `<mimic>`
/// follower has its leader's coordinate and the follower's multiplier and offset.
#[derive(Clone, Debug)]
pub struct Body {
    /// The URDF joint that moves the body (a follower's own name).
    pub joint: String,
    /// How that joint moves the body.
    pub kind: JointKind,
    /// Unit axis of that joint in the body's frame.
    pub axis: Vec3,
    /// The coordinate (index into `q` and [`Model::joints`]) that drives the body.
    pub coordinate: usize,
    /// m in `q_body = m·q[coordinate] + o`.
    pub multiplier: f64,
    /// o in `q_body = m·q[coordinate] + o`.
    pub offset: f64,
    /// Whether the body's joint mimics another (it is then no degree of freedom).
    pub follower: bool,
}

impl Body {
    /// The body's joint motion at the body's own position `q_body`.
    #[inline]
    pub fn motion_pose(&self, q_body: f64) -> Pose {
        motion_pose(self.kind, &self.axis, q_body)
    }

    /// The body's joint position at the coordinates `q`.
    #[inline]
    pub fn position(&self, q: &[f64]) -> f64 {
        match self.follower {
            false => q[self.coordinate],
            true => self.multiplier * q[self.coordinate] + self.offset,
        }
    }
}

/// A named frame: one per URDF link, fixed to a body (or to the world).
#[derive(Clone, Debug)]
pub struct Frame {
    /// The URDF link name.
    pub name: String,
    /// The body it is fixed to (body i is moved by `Model::bodies[i]`); `None` for frames welded to the
    /// world.
    pub body: Option<JointId>,
    /// Its placement `body_T_frame` in that body's frame (or in the world).
    pub placement: Pose,
    /// The frame of its parent link in the URDF tree (`None` for the root link).
    pub parent: Option<FrameId>,
}

/// How [`Model::default_tool`] chose the tool frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolChoice {
    /// The model has a link named `tool_link`.
    Named,
    /// A chain: its last link.
    LastLink,
    /// A branched tree: the deepest common ancestor of its deepest leaves (e.g. a hand, not
    /// one of its fingers).
    DeepestCommonAncestor,
}

/// The immutable model: kinematic tree, inertias, limits and frames. The shapes attached to
/// the frames (visuals, collision geometry) are in [`crate::geometry::GeometryModel`].
#[derive(Clone, Debug)]
pub struct Model {
    /// The robot's name (URDF `<robot name>`).
    pub name: String,
    /// Where the model came from (a file path, with a xacro file's arguments, or the name of a
    /// bundled model).
    pub source: String,
    /// The n degrees of freedom: the moving joints that mimic no other, in generalised-coordinate
    /// order (`q[i]` is joint i's position). A leader's limits are its own intersected with each
    /// follower's mapped through the mimic map, its damping includes m²·d of each follower.
    pub joints: Vec<Joint>,
    /// The nb moving bodies, one per moving joint (mimic followers included), root to tip, and
    /// the coordinate that drives each. `nb = n` and body i is joint i without mimic joints.
    pub bodies: Vec<Body>,
    /// `parent[i]`: the body that carries body i (`None`: the world). Always `< i`. nb entries.
    pub parent: Vec<Option<usize>>,
    /// `tree_pose[i]`: the placement `λ_T_joint` of joint i's frame in its parent body's frame
    /// at q = 0 (the URDF joint origin, fixed joints on the way folded in); its Plücker
    /// transform `X_T(i)` is `tree_pose[i].to_xform()`. nb entries (bodies).
    pub tree_pose: Vec<Pose>,
    /// `axis_split[i]`: `X_T(i)`'s rotation split about joint i's axis, derived from
    /// `tree_pose[i]` when the model is built (the 5 kHz loop's form of it; see [`AxisSplit`]).
    /// nb entries.
    pub(crate) axis_split: Vec<AxisSplit>,
    /// `s[i]`: motion subspace of body i's joint in body i's frame (6-vector). nb entries.
    pub s: Vec<Motion>,
    /// `inertia[i]`: spatial inertia of body i (its link and every link welded to it) about
    /// body i's origin, in body i's frame. nb entries.
    pub inertia: Vec<Inertia>,
    /// Gravitational acceleration in the world frame (m/s²), `(0, 0, −9.81)` by default.
    pub gravity: Vec3,
    /// Every URDF link as a frame, root first, in depth-first order.
    pub frames: Vec<Frame>,
    /// What the arm's maker knows beyond the URDF (default limits, the shapes' IK pose and
    /// board): none for a model read from a file, unless the file is a byte-for-byte copy of a
    /// description faze4 bundles (`crate::geometry::Robot::from_file_with`).
    pub defaults: ArmDefaults,
    /// The format of the file it was read from (`urdf`, `xacro`, `mjcf`; empty for a description built
    /// in memory without one).
    pub format: String,
    /// What reading that format mapped onto faze4's terms or left out (MJCF's armature as
    /// rotor inertia, its world geoms left out); empty for a URDF.
    pub mapped: Vec<Mapping>,
    /// The start pose the file offers (MJCF's `home` keyframe), one position per coordinate
    /// (rad or m), if it offers one.
    pub home: Option<Vec<f64>>,
}

impl Model {
    /// Number of degrees of freedom n (the moving joints that mimic no other).
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// Number of moving bodies nb (= moving joints, mimic followers included; ≥ n).
    pub fn num_bodies(&self) -> usize {
        self.bodies.len()
    }

    /// Whether some body follows a `<mimic>`: then `nb > n` and the algorithms expand the
    /// coordinates to the bodies' positions (`q_b = G q + o`) and reduce their results
    /// (`M_r = Gᵀ M G`, `τ_r = Gᵀ τ`). Without, both are the identity and skipped.
    #[inline]
    pub fn has_mimic(&self) -> bool {
        self.bodies.len() != self.joints.len()
    }

    /// The bodies' joint positions `q_b = G q + o` (nb) from the coordinates `q` (n).
    pub fn expand_positions(&self, q: &[f64], q_body: &mut [f64]) {
        for (x, body) in q_body.iter_mut().zip(&self.bodies) {
            *x = body.position(q);
        }
    }

    /// The bodies' joint velocities (or accelerations) `v_b = G v` (nb) from the coordinates'.
    pub fn expand_velocities(&self, v: &[f64], v_body: &mut [f64]) {
        for (x, body) in v_body.iter_mut().zip(&self.bodies) {
            *x = body.multiplier * v[body.coordinate];
        }
    }

    /// Joint forces on the bodies (nb) → generalised forces on the coordinates, `τ = Gᵀ τ_b`
    /// (the virtual work of each body's force through `q_b = m q_c + o`).
    pub fn reduce_forces(&self, tau_body: &[f64], tau: &mut [f64]) {
        tau.fill(0.0);
        for (x, body) in tau_body.iter().zip(&self.bodies) {
            tau[body.coordinate] += body.multiplier * x;
        }
    }

    /// A symmetric bodies' matrix (nb×nb) → the coordinates', `M_r = Gᵀ M G` (n×n), exactly
    /// symmetric: the upper triangle is summed, the lower copied from it.
    pub fn reduce_matrix(&self, m_body: &nalgebra::DMatrix<f64>, m: &mut nalgebra::DMatrix<f64>) {
        m.fill(0.0);
        for (a, ba) in self.bodies.iter().enumerate() {
            for (b, bb) in self.bodies.iter().enumerate() {
                let (i, j) = (ba.coordinate, bb.coordinate);
                if i <= j {
                    m[(i, j)] += ba.multiplier * bb.multiplier * m_body[(a, b)];
                }
            }
        }
        for j in 0..m.ncols() {
            for i in j + 1..m.nrows() {
                m[(i, j)] = m[(j, i)];
            }
        }
    }

    /// The joints that mimic coordinate i, for messages about its limits: empty, or
    /// `" (which include those of its mimic follower(s) F, …)"`.
    pub fn mimic_note(&self, i: usize) -> String {
        let followers: Vec<&str> = (self.bodies.iter())
            .filter(|b| b.follower && b.coordinate == i)
            .map(|b| b.joint.as_str())
            .collect();
        match followers.as_slice() {
            [] => String::new(),
            names => format!(" (which include those of its mimic followers: {})", names.join(", ")),
        }
    }

    /// The motor's reflected inertia on body i's diagonal of the bodies' M: its coordinate's
    /// motor on the body its joint moves, 0 on a follower (a follower carries no motor).
    #[inline]
    pub fn body_reflected_inertia(&self, i: usize) -> f64 {
        let body = &self.bodies[i];
        match body.follower {
            false => self.joints[body.coordinate].reflected_inertia(),
            true => 0.0,
        }
    }

    /// The frame named `name`.
    pub fn frame_index(&self, name: &str) -> Option<FrameId> {
        self.frames.iter().position(|f| f.name == name).map(FrameId)
    }

    /// The joint named `name`.
    pub fn joint_index(&self, name: &str) -> Option<JointId> {
        self.joints.iter().position(|j| j.name == name).map(JointId)
    }

    /// Frame `id`.
    pub fn frame(&self, id: FrameId) -> &Frame {
        &self.frames[id.0]
    }

    /// Joint `id`.
    pub fn joint(&self, id: JointId) -> &Joint {
        &self.joints[id.0]
    }

    /// The frame a tool is taken at by default (see [`Model::default_tool`]).
    pub fn default_tool_frame(&self) -> FrameId {
        self.default_tool().0
    }

    /// The frame a tool is taken at by default, and how it was chosen: `tool_link` if the
    /// model has one; otherwise on a chain its last link (the last frame in depth-first
    /// order), on a branched tree the deepest common ancestor of its deepest leaves (depth:
    /// the number of joints, fixed ones included, from the root link).
    pub fn default_tool(&self) -> (FrameId, ToolChoice) {
        if let Some(f) = self.frame_index("tool_link") {
            return (f, ToolChoice::Named);
        }
        let n = self.frames.len();
        let mut children = vec![0usize; n];
        let mut depth = vec![0usize; n];
        // frames are in depth-first order: a parent comes before its children
        for (i, f) in self.frames.iter().enumerate() {
            if let Some(FrameId(p)) = f.parent {
                children[p] += 1;
                depth[i] = depth[p] + 1;
            }
        }
        if children.iter().all(|&c| c <= 1) {
            return (FrameId(n - 1), ToolChoice::LastLink);
        }
        let deepest = (0..n).filter(|&i| children[i] == 0).map(|i| depth[i]).max();
        let mut leaves = (0..n).filter(|&i| children[i] == 0 && Some(depth[i]) == deepest);
        let Some(first) = leaves.next() else {
            return (FrameId(n - 1), ToolChoice::LastLink);
        };
        // the ancestors of the first deepest leaf, root first; each further leaf cuts the
        // common path at the last ancestor it shares
        let mut path = vec![first];
        while let Some(FrameId(p)) = self.frames[*path.last().unwrap_or(&0)].parent {
            path.push(p);
        }
        path.reverse();
        let mut common = path.len();
        for leaf in leaves {
            let mut up = vec![leaf];
            while let Some(FrameId(p)) = self.frames[*up.last().unwrap_or(&0)].parent {
                up.push(p);
            }
            up.reverse();
            common = common.min(path.iter().zip(&up).take_while(|(a, b)| a == b).count());
        }
        let ancestor = path[common.max(1) - 1];
        (FrameId(ancestor), ToolChoice::DeepestCommonAncestor)
    }

    /// Joint damping coefficients, one per joint.
    pub fn damping(&self) -> impl Iterator<Item = f64> + '_ {
        self.joints.iter().map(|j| j.damping)
    }

    /// This model with a point mass `mass` (kg) fixed at the origin of frame `frame` (e.g. a
    /// payload at the tool).
    pub fn with_point_mass(&self, frame: FrameId, mass: f64) -> Model {
        self.with_added_inertia(frame, Inertia::point_mass(mass, Vec3::zeros()))
    }

    /// This model with a rigid body of inertia `inertia` (given about frame `frame`'s origin,
    /// in its coordinates) welded to that frame. A frame welded to the world changes nothing.
    pub fn with_added_inertia(&self, frame: FrameId, inertia: Inertia) -> Model {
        let mut model = self.clone();
        let f = self.frame(frame);
        if let Some(JointId(b)) = f.body {
            model.inertia[b] += inertia.transform_to_source(&f.placement.to_xform());
        }
        model
    }

    /// Builds a model from a format-free description (see [`urdf`] for files).
    pub fn from_description(desc: &RobotDescription) -> crate::Result<Model> {
        build::build(desc, &LoadOptions::default()).map(|(model, _)| model)
    }

    /// [`Model::from_description`] with `options`, and what the reading skipped or changed.
    pub fn from_description_with(
        desc: &RobotDescription,
        options: &LoadOptions,
    ) -> crate::Result<(Model, Vec<LoadWarning>)> {
        build::build(desc, options)
    }

    /// Reads a URDF file's dynamics (`crate::geometry::Robot::from_urdf_file` reads its
    /// geometry too); `packages` resolves `package://` mesh references.
    pub fn from_urdf_file(path: &std::path::Path, packages: &PackagePaths) -> crate::Result<Model> {
        urdf::read_file(path, packages)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(file: &str) -> Model {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
        Model::from_urdf_file(&path, &PackagePaths::default()).unwrap()
    }

    #[test]
    fn a_branched_tree_defaults_to_the_deepest_common_ancestor_of_its_deepest_leaves() {
        // tree_arm: the deepest leaves are r_tool and l_forearm (6 joints from the root, fixed
        // ones included); the head (4) is shallower; their deepest common ancestor is the chest
        let model = load("tests/urdf/tree_arm.urdf");
        let (tool, how) = model.default_tool();
        assert_eq!(model.frame(tool).name, "chest");
        assert_eq!(how, ToolChoice::DeepestCommonAncestor);
        assert_eq!(model.default_tool_frame(), tool);
    }

    #[test]
    fn a_chain_keeps_its_tool_link_or_last_link() {
        let faze4 = crate::faze4::model();
        assert_eq!(
            faze4.default_tool(),
            (faze4.frame_index("tool_link").unwrap(), ToolChoice::Named)
        );
        let model = load("tests/urdf/arm_prismatic.urdf");
        let (tool, how) = model.default_tool();
        assert_eq!((tool, how), (FrameId(model.frames.len() - 1), ToolChoice::LastLink));
    }
}
