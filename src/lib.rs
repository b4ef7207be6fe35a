//! faze4: fast, exact rigid-body dynamics of robot arms, and the closed-loop experiments
//! built on them (a 5 kHz digital PD controller, torque limits, trajectories).
//!
//! Layers, bottom up: [`spatial`] (6D algebra), [`model`] (URDF → immutable model),
//! [`algo`] (kinematics and dynamics on a preallocated workspace), [`geometry`] (visuals and
//! collision shapes beside the model, self-clearance), [`control`] (PD + tuning),
//! [`traj`] (commands), [`sim`] (closed-loop runs), [`output`] (the recorder interface),
//! [`viz`] (the 3D view, live and exported, and the plot: recorders).

pub mod algo;
pub mod cli;
pub mod control;
pub mod error;
#[doc(hidden)]
pub mod fuzzing;
pub mod geometry;
pub mod ik;
pub mod model;
pub mod output;
pub mod sim;
pub mod spatial;
pub mod traj;
pub mod viz;

pub use error::{Error, Result};
