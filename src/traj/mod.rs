//! Commanded trajectories: what the joints are asked to do at each instant (docs/model.md).
//!
//! A [`Trajectory`] is a closed set of kinds (an enum, so evaluating one inside the 5 kHz loop
//! is a `match`, not a virtual call).

pub mod files;
mod linear;
pub mod npy;
pub mod shape;
mod shape_plan;
mod spline;
pub mod timed;
mod wave;

pub use linear::{Interpolated, Wrap};
pub use shape_plan::ShapeRun;
pub use spline::{Playback, Spline};
pub use timed::{HeldJoint, Interpolation, TimedTrajectory, TrajectoryPoint};
pub use wave::Wave;

/// A joint-space command q_cmd(t), v_cmd(t), and its acceleration a_cmd(t) for the full
/// feed-forward.
#[derive(Clone, Debug)]
pub enum Trajectory {
    /// Phase-shifted sines on every joint (`faze4 wave`).
    Wave(Wave),
    /// Linear interpolation of samples (`faze4 replay`, `faze4 shape`).
    Interpolated(Interpolated),
    /// A time-stamped trajectory played once as `joint_trajectory_controller` plays it
    /// (`faze4 replay` of a `.yaml`, `.json`, `.mcap` or `.csv` file).
    Spline(Spline),
}

impl Trajectory {
    /// Writes q_cmd(t) into `q` and v_cmd(t) into `v` (one entry per joint).
    #[inline]
    pub fn eval(&self, t: f64, q: &mut [f64], v: &mut [f64]) {
        match self {
            Trajectory::Wave(w) => w.eval(t, q, v),
            Trajectory::Interpolated(p) => p.eval(t, q, v),
            Trajectory::Spline(s) => s.eval(t, q, v),
        }
    }

    /// [`Trajectory::eval`], and a_cmd(t) into `a`: the wave's
    /// `−A_i ω² sin(ω t + i π/3)`, 0 for linearly interpolated samples (their slope is constant
    /// between samples), the spline's second derivative. q and v are those of
    /// [`Trajectory::eval`], bit for bit.
    #[inline]
    pub fn eval_with_acceleration(&self, t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) {
        match self {
            Trajectory::Wave(w) => w.eval_with_acceleration(t, q, v, a),
            Trajectory::Interpolated(p) => {
                p.eval(t, q, v);
                a.fill(0.0);
            }
            Trajectory::Spline(s) => s.eval_with_acceleration(t, q, v, a),
        }
    }

    /// The sample a sampled command holds at time `t` (s): the index of the last sample at or
    /// before `t` and that sample's time (s); `None` for a wave, which has no samples. A smart
    /// servo is sent its goal at these times (`drive` servo).
    pub fn frame(&self, t: f64) -> Option<(u64, f64)> {
        match self {
            Trajectory::Wave(_) => None,
            Trajectory::Interpolated(p) => Some(p.frame(t)),
            Trajectory::Spline(s) => Some(s.frame(t)),
        }
    }

    /// The state a run of it starts in: the command's at t = 0, or for a message played from
    /// a start, at rest there ([`Spline::start_state`]).
    pub fn start_state(&self, q: &mut [f64], v: &mut [f64]) {
        match self {
            Trajectory::Spline(s) => s.start_state(q, v),
            _ => self.eval(0.0, q, v),
        }
    }

    /// Number of joints commanded.
    pub fn dof(&self) -> usize {
        match self {
            Trajectory::Wave(w) => w.center.len(),
            Trajectory::Interpolated(p) => p.columns(),
            Trajectory::Spline(s) => s.columns(),
        }
    }
}
