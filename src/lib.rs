//! faze4: fast, exact rigid-body dynamics of robot arms, and the closed-loop experiments
//! built on them (a 5 kHz digital PD controller, torque limits, trajectories).
//!
//! Layers, bottom up: [`spatial`] (6D algebra), [`model`] (URDF → immutable model),
//! [`algo`] (kinematics and dynamics on a preallocated workspace).

pub mod algo;
pub mod error;
pub mod model;
pub mod spatial;

pub use error::{Error, Result};
