//! What an arm's maker knows beyond its URDF: the torque limits of its motors, whether the
//! URDF's speed limits are real, how its shapes' IK is posed and the board it draws them on.
//! Generic code reads these as data; they come with a description faze4 bundles (the Faze4's
//! are `crate::faze4::defaults`, given to the bundled arm and to a byte-for-byte copy of its
//! files), never from a robot's name: any other model has none.

use crate::id::JointId;
use crate::spatial::Vec3;

/// Defaults of one arm beyond its URDF; every field `None`: the URDF says it all.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ArmDefaults {
    /// Torque limits per joint (N·m or N) used when none are given, instead of the URDF's
    /// `effort` values.
    pub effort: Option<Vec<f64>>,
    /// Speed limits per joint (rad/s or m/s, +∞ for none) used instead of the URDF's
    /// `velocity` values when those are placeholders rather than a motor's figures.
    pub speed_limit: Option<Vec<f64>>,
    /// The shapes' IK: which joints it moves and the pose it starts from (one value per
    /// joint). `None`: every joint, from the zero pose clamped into the limits.
    pub shape_ik: Option<ShapeIk>,
    /// The board the shapes are drawn on. `None`: one from the arm's reach
    /// (`crate::traj::shape::Board::of`).
    pub board: Option<Board>,
}

/// A vertical drawing board in the world plane `y = center.y`, facing the arm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Board {
    /// Centre of the board face (world, m).
    pub center: Vec3,
    /// Extent along world x (m).
    pub width: f64,
    /// Extent along world z (m).
    pub height: f64,
}

/// How a shape's IK is posed on an arm.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeIk {
    /// The joints the IK moves (the others hold their seed value).
    pub free_joints: Vec<JointId>,
    /// The first sample's start pose, one value per joint (rad or m).
    pub seed: Vec<f64>,
}
