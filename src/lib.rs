//! faze4: fast, exact rigid-body dynamics of robot arms, and the closed-loop experiments
//! built on them (a 5 kHz digital PD controller, torque limits, trajectories).
//!
//! Layers, bottom up: [`spatial`] (6D algebra), [`model`] (URDF → immutable model),
//! [`algo`] (kinematics and dynamics on a preallocated workspace), [`control`] (PD + tuning),
//! [`traj`] (commands), [`sim`] (closed-loop runs), [`output`] (the recorder interface).

pub mod algo;
pub mod cli;
pub mod control;
pub mod error;
#[doc(hidden)]
pub mod fuzzing;
pub mod model;
pub mod output;
pub mod sim;
pub mod spatial;
pub mod traj;

pub use error::{Error, Result};
