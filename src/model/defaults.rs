//! What an arm's maker knows beyond its URDF: the torque limits of its motors, whether the
//! URDF's speed limits are real, and how its shapes' IK is posed. Generic code reads these as
//! data; a model read from a file has none unless its loader knows the arm (the bundled Faze4's
//! are `crate::faze4::defaults`).

use crate::id::JointId;

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
}

/// How a shape's IK is posed on an arm.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeIk {
    /// The joints the IK moves (the others hold their seed value).
    pub free_joints: Vec<JointId>,
    /// The first sample's start pose, one value per joint (rad or m).
    pub seed: Vec<f64>,
}
