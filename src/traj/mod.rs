//! Commanded trajectories: what the joints are asked to do at each instant (docs/model.md).
//!
//! A [`Trajectory`] is a closed set of kinds (an enum, so evaluating one inside the 5 kHz loop
//! is a `match`, not a virtual call).

mod linear;
pub mod npy;
pub mod shape;
mod shape_plan;
pub mod timed;
mod wave;

pub use linear::{Interpolated, Wrap};
pub use shape_plan::ShapeRun;
pub use timed::{TimedTrajectory, TrajectoryPoint};
pub use wave::Wave;

/// A joint-space command q_cmd(t), v_cmd(t).
#[derive(Clone, Debug)]
pub enum Trajectory {
    /// Phase-shifted sines on every joint (`faze4 wave`).
    Wave(Wave),
    /// Linear interpolation of samples (`faze4 replay`, `faze4 shape`).
    Interpolated(Interpolated),
}

impl Trajectory {
    /// Writes q_cmd(t) into `q` and v_cmd(t) into `v` (one entry per joint).
    #[inline]
    pub fn eval(&self, t: f64, q: &mut [f64], v: &mut [f64]) {
        match self {
            Trajectory::Wave(w) => w.eval(t, q, v),
            Trajectory::Interpolated(p) => p.eval(t, q, v),
        }
    }

    /// Number of joints commanded.
    pub fn dof(&self) -> usize {
        match self {
            Trajectory::Wave(w) => w.center.len(),
            Trajectory::Interpolated(p) => p.columns(),
        }
    }
}
