//! The Faze4 arm's facts, in one place: the bundled model and its names, the torque limits of
//! its motors, and the original experiment's drawing board, IK seed, free joints and shape
//! period. Everything else in faze4 works on any URDF arm; these are what the original program
//! knew about its one arm.

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

/// Robot names (`<robot name>`) of the Faze4 models in this repository: a 6-dof model with one
/// of these names gets the Faze4's torque limits and shape task by default.
pub const ROBOT_NAMES: [&str; 2] = ["faze4_arm", "faze4_real"];

/// Torque limits of the Faze4's joints (N·m), J1..J6: 0.315 N·m at each NEMA17 stepper (70 % of
/// a 0.45 N·m motor's holding torque) times the joint's reduction ratio (25, 27, 15, 11.846, 11,
/// 19.19), rounded as the original program gave them. Not the URDF effort values.
pub const EFFORT: [f64; 6] = [7.9, 8.5, 4.7, 3.7, 3.5, 6.0];

/// The original's drawing board: plane y = −0.48 m, centred at x = 0.08, z = 0.55, 0.50 × 0.44 m.
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

/// Time for one loop of a shape (s).
pub const SHAPE_PERIOD: f64 = 5.0;

/// The bundled Faze4 model (`urdf/faze4_arm.urdf`), with its [`defaults`].
pub fn model() -> Model {
    let mut model =
        urdf::read_str(URDF, SOURCE, None, &PackagePaths::default()).expect("the bundled URDF is valid (tested)");
    model.defaults = defaults();
    model
}

/// Whether `model` is one of the Faze4 models (by robot name and degrees of freedom).
pub fn is_faze4(model: &Model) -> bool {
    ROBOT_NAMES.contains(&model.name.as_str()) && model.dof() == 6
}

/// What the Faze4's makers know beyond its URDF: its motors' torque limits ([`EFFORT`]), no
/// speed limits (its URDF gives every joint the same `velocity="3.0"`, a placeholder rather
/// than a motor's figure), and the shapes' IK ([`SHAPE_FREE_JOINTS`] from [`Q_SEED`]).
pub fn defaults() -> ArmDefaults {
    ArmDefaults {
        effort: Some(EFFORT.to_vec()),
        speed_limit: Some(vec![f64::INFINITY; 6]),
        shape_ik: Some(ShapeIk {
            free_joints: SHAPE_FREE_JOINTS.to_vec(),
            seed: Q_SEED.to_vec(),
        }),
    }
}

/// The defaults of a model read from a file: the Faze4's ([`defaults`]) for one of the Faze4
/// models ([`is_faze4`]), none for any other arm.
pub fn defaults_for(model: &Model) -> ArmDefaults {
    match is_faze4(model) {
        true => defaults(),
        false => ArmDefaults::default(),
    }
}

/// The shapes' IK task on a Faze4 model: its tool frame ([`Model::default_tool_frame`]) with
/// [`SHAPE_FREE_JOINTS`] free.
pub fn shape_ik_task(model: &Model) -> Result<IkTask> {
    IkTask::new(model, model.default_tool_frame(), &SHAPE_FREE_JOINTS)
}
