//! The Faze4 arm's facts, in one place: the bundled model and its names, the torque limits of
//! its motors, and the original experiment's drawing board, IK seed, free joints and shape
//! period. Everything else in faze4 works on any URDF arm; these are what the original program
//! knew about its one arm.
//!
//! They belong to the descriptions faze4 bundles ([`BUNDLED`]), not to a name: the bundled arm
//! has them, and so does a robot file that is a byte-for-byte copy of one of those descriptions
//! ([`is_bundled`]); any other file has none, whatever its robot is called, and one that looks
//! like the Faze4 (its name or joint names) is told what it gets instead ([`not_bundled`]).

pub mod meshes;
pub mod motors;

use crate::error::Result;
use crate::ik::IkTask;
use crate::model::{ArmDefaults, JointId, Model, PackagePaths, ShapeIk, urdf};
use crate::spatial::Vec3;
use crate::traj::shape::Board;

/// The bundled Faze4 URDF (`urdf/faze4_arm.urdf`), built into the binary so it runs from any
/// directory.
pub const URDF: &str = include_str!("../../urdf/faze4_arm.urdf");

/// Name under which the bundled model reports its source.
pub const SOURCE: &str = "bundled urdf/faze4_arm.urdf";

/// `urdf/faze4_real.urdf`, built into the binary: the bundled model's visuals (the official
/// meshes, themselves built in: [`meshes`]).
pub const REAL_URDF: &str = include_str!("../../urdf/faze4_real.urdf");

/// The descriptions faze4 bundles (`urdf/faze4_arm.urdf`, `urdf/faze4_real.urdf`): a robot
/// text byte for byte equal to one of them is the Faze4, with its [`defaults`] and the built-in
/// [`meshes`].
pub const BUNDLED: [&str; 2] = [URDF, REAL_URDF];

/// Robot names (`<robot name>`) of the Faze4 models in this repository. A name alone gives no
/// fact: a model so named that is not a bundled description is told so ([`not_bundled`]).
pub const ROBOT_NAMES: [&str; 2] = ["faze4_arm", "faze4_real"];

/// The Faze4's moving joints, J1..J6, as its URDFs (ours and the official one) name them.
pub const JOINT_NAMES: [&str; 6] = ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"];

/// Torque limits of the Faze4's joints (N·m), J1..J6: 0.315 N·m at each NEMA17 stepper (70 % of
/// a 0.45 N·m motor's holding torque) times the joint's reduction ratio (25, 27, 15, 11.846, 11,
/// 19.19), rounded as the original program gave them. Not the URDF effort values.
pub const EFFORT: [f64; 6] = [7.9, 8.5, 4.7, 3.7, 3.5, 6.0];

/// The original's drawing board: plane y = −0.48 m, centred at x = 0.08, z = 0.55, 0.50 × 0.44 m
/// (the width the shapes' sizes are given for, [`crate::traj::shape::SHAPES_WIDTH`]).
pub const BOARD: Board = Board {
    center: Vec3::new(0.08, -0.48, 0.55),
    width: 0.50,
    height: 0.44,
};

/// The joint configuration the shapes' IK starts from for the first sample (rad), the
/// original's seed.
pub const Q_SEED: [f64; 6] = [0.0104, 0.1795, -0.5049, 0.0, -0.0938, 0.0];

/// The joints the shapes' IK moves: J1, J2, J3 and J5 (J4 = J6 = 0 held).
pub const SHAPE_FREE_JOINTS: [JointId; 4] = [JointId(0), JointId(1), JointId(2), JointId(4)];

/// Time for one loop of a shape (s): the original's, every arm's
/// ([`crate::traj::shape::PERIOD`]).
pub const SHAPE_PERIOD: f64 = crate::traj::shape::PERIOD;

/// The bundled Faze4 model (`urdf/faze4_arm.urdf`), with its [`defaults`].
pub fn model() -> Model {
    let mut model =
        urdf::read_str(URDF, SOURCE, None, &PackagePaths::default()).expect("the bundled URDF is valid (tested)");
    model.defaults = defaults();
    model
}

/// Whether robot text `text` is one of the bundled descriptions ([`BUNDLED`]), byte for byte.
pub fn is_bundled(text: &[u8]) -> bool {
    BUNDLED.iter().any(|bundled| bundled.as_bytes() == text)
}

/// Whether the robot file at `path` is a byte-for-byte copy of a bundled description: read only
/// when its length is one of theirs; a file that cannot be read is not.
pub fn is_bundled_file(path: &std::path::Path) -> bool {
    let length = std::fs::metadata(path).map(|m| m.len());
    (BUNDLED.iter()).any(|b| length.as_ref().is_ok_and(|&l| l == b.len() as u64))
        && std::fs::read(path).is_ok_and(|bytes| is_bundled(&bytes))
}

/// For a model that is not a bundled description but looks like the Faze4 (a robot name of
/// [`ROBOT_NAMES`], or the Faze4's joint names, [`JOINT_NAMES`]): what it looks like, and what it
/// gets instead of the Faze4's facts. `None` for any other model.
pub fn not_bundled(model: &Model) -> Option<(String, &'static str)> {
    let joints: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    let like = match (ROBOT_NAMES.contains(&model.name.as_str()), joints == JOINT_NAMES) {
        (true, _) => format!("robot '{}' is named like the Faze4", model.name),
        (false, true) => format!("robot '{}' has the Faze4's joint names", model.name),
        (false, false) => return None,
    };
    Some((
        like,
        "its own file's effort and velocity limits, the shapes' IK on every joint from the zero pose, a board from its reach, and no built-in meshes",
    ))
}

/// What the Faze4's makers know beyond its URDF: its motors' torque limits ([`EFFORT`]), no
/// speed limits (its URDF gives every joint the same `velocity="3.0"`, a placeholder rather
/// than a motor's figure), the shapes' IK ([`SHAPE_FREE_JOINTS`] from [`Q_SEED`]) and the
/// original's board ([`BOARD`]).
pub fn defaults() -> ArmDefaults {
    ArmDefaults {
        effort: Some(EFFORT.to_vec()),
        speed_limit: Some(vec![f64::INFINITY; 6]),
        shape_ik: Some(ShapeIk {
            free_joints: SHAPE_FREE_JOINTS.to_vec(),
            seed: Q_SEED.to_vec(),
        }),
        board: Some(BOARD),
    }
}

/// The shapes' IK task on a Faze4 model: its tool frame ([`Model::default_tool_frame`]) with
/// [`SHAPE_FREE_JOINTS`] free.
pub fn shape_ik_task(model: &Model) -> Result<IkTask> {
    IkTask::new(model, model.default_tool_frame(), &SHAPE_FREE_JOINTS)
}
