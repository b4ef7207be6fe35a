//! MuJoCo's MJCF models → [`RobotDescription`] → [`Model`]. The only place that knows MJCF.
//!
//! Every MJCF body is a link (the world body is the link `world`), its joint the joint that
//! moves it (a body without one is welded to its parent), every named site a link welded to its
//! body (a frame to take as the tool). What MJCF says in other terms than faze4's is mapped and
//! listed in the description's `mapped` (the banner and the summary show it; docs/robots.md has
//! the table): `armature` is the joint's rotor inertia at gear ratio 1 (MuJoCo adds it to M's
//! diagonal, as faze4 adds r²·I_rotor), an actuator's `forcerange` (or a motor's `ctrlrange`)
//! times its `gear` the joint's effort limit, `<equality joint>` a mimic, the `home` keyframe the
//! start pose `center home`, `frictionloss` the joint's Coulomb friction; world geoms (a floor)
//! are left out; springs, tendons and gravity compensation are listed as not simulated (a
//! [`LoadWarning`]).
//!
//! | file | holds |
//! |---|---|
//! | `xml.rs` | the XML as an owned element tree, `<include>`s expanded |
//! | `classes.rs` | `<default>` classes and `childclass` |
//! | `frames.rs` | attribute numbers, the five orientations, primitive geoms' inertia |
//! | `context.rs` | what one reading shares: compiler settings, assets, the mapped list, attributes |
//! | `body.rs` | the body tree: links, joints, inertials, geoms, sites |
//! | `model.rs` | the model's sections around the body tree: compiler, assets, actuators, equalities, keyframes |
//!
//! [`LoadWarning`]: super::LoadWarning

mod body;
mod classes;
mod context;
mod frames;
mod model;
mod xml;

use std::path::Path;

use super::{LoadOptions, Model, RobotDescription};
use crate::error::Result;

/// Reads the MJCF model at `path` and the files it includes: its description, mesh files
/// located (relative to the compiler's `meshdir`), not read.
pub fn describe_file(path: &Path) -> Result<RobotDescription> {
    let root = xml::read_model(path)?;
    model::describe(&root, &path.display().to_string(), path.parent())
}

/// Reads MJCF model `text`; `file` names it in messages, `base_dir` anchors its includes and
/// mesh files.
pub fn describe_str(text: &str, file: &str, base_dir: Option<&Path>) -> Result<RobotDescription> {
    let root = xml::parse_model(text, file, base_dir)?;
    model::describe(&root, file, base_dir)
}

/// Reads and validates the MJCF model at `path`: its dynamics model.
pub fn read_file(path: &Path) -> Result<Model> {
    Model::from_description_with(&describe_file(path)?, &LoadOptions::default()).map(|(model, _)| model)
}
