//! The arm a configuration names, read once: its robot file (or the bundled Faze4), the motors put on
//! its joints, its tool frame.

use super::ArmConfig;
use super::motors::{fit, resolve};
use crate::control::Motor;
use crate::error::{Error, Result};
use crate::geometry::Robot;
use crate::model::{FrameId, LoadOptions, Model, PackagePaths, ReadOptions};

/// An arm as a run uses it: the robot (its model with the motors' ratios and rotors on its
/// joints, its geometry, what reading it changed), the motors' envelopes, and the tool frame.
#[derive(Clone, Debug)]
pub struct Arm {
    /// The model, geometry and load warnings.
    pub robot: Robot,
    /// Per joint the motor behind it (`None`: no motors given).
    pub motors: Option<Vec<Option<Motor>>>,
    /// The frame traced as the tool.
    pub tool: FrameId,
}

/// Reads the arm `arm` names: `robot` (else the bundled Faze4), with `motors`, `gear_ratio` and
/// `rotor_inertia` resolved onto its joints once ([`fit`]), and its tool frame.
pub fn load_arm(arm: &ArmConfig) -> Result<Arm> {
    let options = LoadOptions {
        balance_inertia: arm.balance_inertia,
    };
    let read = ReadOptions {
        packages: PackagePaths::with_ros_package_path(arm.package_path.clone()),
        xacro_args: arm.xacro_arg.clone(),
    };
    let mut robot = match &arm.robot {
        Some(path) => Robot::from_file_with(path, &read, &options)?,
        None if !arm.xacro_arg.is_empty() => {
            return Err(Error::option("xacro_arg", "is for a xacro file given as `robot`"));
        }
        None => Robot::faze4(),
    };
    let motors = fit_motors(&mut robot.model, arm)?;
    let tool = tool_frame(&robot.model, arm.tool_link.as_deref())?;
    Ok(Arm { robot, motors, tool })
}

/// The motors of `arm` (`motors`, `supply_voltage`) resolved onto `model`'s joints and fitted
/// with `gear_ratio` and `rotor_inertia` ([`resolve`], then [`fit`]): the one place both
/// happen, for [`load_arm`] and for a loaded arm's runs.
pub(super) fn fit_motors(model: &mut Model, arm: &ArmConfig) -> Result<Option<Vec<Option<Motor>>>> {
    let motors = resolve(arm.motors.as_ref(), arm.supply_voltage, model)?;
    fit(model, motors, &arm.gear_ratio, &arm.rotor_inertia)
}

/// The tool frame: the link `name`, or the model's default.
pub fn tool_frame(model: &Model, name: Option<&str>) -> Result<FrameId> {
    match name {
        None => Ok(model.default_tool_frame()),
        Some(name) => model.frame_index(name).ok_or_else(|| {
            let names: Vec<&str> = model.frames.iter().map(|f| f.name.as_str()).collect();
            Error::option(
                "tool_link",
                format!("no link '{name}' in {} (links: {})", model.source, names.join(", ")),
            )
        }),
    }
}
