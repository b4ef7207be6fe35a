//! faze4: fast, exact rigid-body dynamics of robot arms, and the closed-loop experiments
//! built on them (a 5 kHz digital PD controller, torque limits, trajectories).
//!
//! Layers, bottom up (each uses only those below it; `ARCHITECTURE.md` has the table):
//! [`spatial`] (6D algebra), [`error`], [`choice`] (the words of a configuration enum),
//! [`atomic`] (files written whole or not at all),
//! [`input`] (files read whole under a cap),
//! [`model`] (URDF → immutable model), [`algo`] (kinematics and dynamics on a preallocated
//! workspace), [`control`] (PD, tuning, motors), [`ik`] (inverse kinematics), [`traj`]
//! (commands), [`faze4`] (the Faze4 arm's facts and its built-in meshes), [`geometry`] (visuals
//! and collision shapes beside the model, self-clearance), [`sim`] (scenarios, the closed loop,
//! the recorder interface, the summary and verdict), [`retime`] (the fastest timing of a path
//! that the motors follow), [`config`] (one run's configuration, read
//! once into scenarios), [`output`] (terminal and trail recorders), [`sweep`] (many runs of one
//! configuration), [`viz`] (the 3D view, live and exported, and the plots), [`session`] (a run
//! with its output files, as every front end runs it). The command line is the `faze4` binary's
//! (`src/main.rs`, `src/cli/`: clap only there), built from the options [`config::fields`]
//! declares, as the Python binding's keywords are.
//!
//! A run from the library, without the command line:
//!
//! ```no_run
//! use faze4::sim::{Scenario, StopFlag, run};
//! use faze4::traj::{Trajectory, Wave};
//! # fn main() -> faze4::Result<()> {
//! let model = faze4::faze4::model();
//! let wave = Trajectory::Wave(Wave { amplitude: vec![0.4; model.dof()], omega: 0.5, center: vec![0.0; model.dof()] });
//! let scenario = Scenario::builder(model, wave).payload_kg(1.0).build()?;
//! let summary = run(&scenario, &mut [], &StopFlag::new())?;
//! println!("{}", summary.verdict);
//! # Ok(()) }
//! ```

#![warn(missing_docs)]
// No `unsafe` in faze4's own code. PyO3's macros expand to `unsafe` blocks marked
// `#[allow(unsafe_code)]`, which `forbid` would refuse, so the Python build denies instead (an
// `unsafe` written by hand still fails it).
#![cfg_attr(not(feature = "python"), forbid(unsafe_code))]
#![cfg_attr(feature = "python", deny(unsafe_code))]

pub mod algo;
pub mod atomic;
pub mod choice;
pub mod config;
pub mod control;
pub mod error;
pub mod faze4;
#[doc(hidden)]
pub mod fuzzing;
pub mod geometry;
pub mod id;
pub mod ik;
pub mod input;
pub mod model;
pub mod output;
#[cfg(feature = "python")]
mod python;
pub mod retime;
pub mod session;
pub mod sim;
pub mod spatial;
pub mod sweep;
pub mod traj;
pub mod viz;

pub use error::{Error, Result};
