//! Everything a run writes goes through one interface, [`Recorder`]: the terminal printer,
//! the trail CSV, the live view and the HTML export all receive the same calls.

pub mod atomic;
pub mod format;
mod terminal;
mod trail;

pub use terminal::{PRINT_PERIOD, Terminal};
pub use trail::{TrailCsv, steps_per_record};

use crate::control::Gains;
use crate::model::Model;
use crate::sim::Summary;
use crate::spatial::Vec3;
use crate::traj::shape::Board;

/// What a run is, told to every recorder before the first sample.
#[derive(Clone, Copy, Debug)]
pub struct RunInfo<'a> {
    /// The command name: `wave`, `replay` or `shape`.
    pub command: &'a str,
    /// The simulated model (payload included).
    pub model: &'a Model,
    /// Its visuals and collision geometry.
    pub geometry: &'a crate::geometry::GeometryModel,
    /// The frame whose origin is the tool (trail x, y, z).
    pub tool_frame: usize,
    /// Control and integration period Δt (s).
    pub dt: f64,
    /// Number of steps the run will take.
    pub steps: usize,
    /// Gains and limits in use.
    pub gains: &'a Gains,
    /// Whether g(q) is fed forward.
    pub feedforward: bool,
    /// The start state q (= q_cmd(0)).
    pub start_q: &'a [f64],
    /// For shapes: the drawing board.
    pub board: Option<&'a Board>,
    /// For shapes: the closed reference path the tool should draw (world, m).
    pub reference_path: Option<&'a [Vec3]>,
}

/// The state of the run after `step` steps (t = step·Δt), with the torque computed from it.
#[derive(Clone, Copy, Debug)]
pub struct Sample<'a> {
    /// Steps taken.
    pub step: usize,
    /// Simulated time (s).
    pub t: f64,
    /// Measured joint positions.
    pub q: &'a [f64],
    /// Measured joint velocities.
    pub v: &'a [f64],
    /// Commanded positions at t.
    pub q_cmd: &'a [f64],
    /// Commanded velocities at t.
    pub v_cmd: &'a [f64],
    /// Torque held over the next step (clipped).
    pub tau: &'a [f64],
    /// Gravity forces g(q) at this state.
    pub g: &'a [f64],
    /// Tool frame origin in the world (m).
    pub tool: Vec3,
    /// For shapes: the reference point the tool should be at now (world, m).
    pub target: Option<Vec3>,
}

/// A consumer of a run's output. `begin` once, `record` at every sample its period asks for
/// (see [`Recorder::every`]), `finish` once with the summary (also after a divergence).
pub trait Recorder {
    /// The recording period in steps for a run with step `dt` (the last step is always
    /// recorded too).
    fn every(&self, dt: f64) -> usize;

    /// Called once before the first sample.
    fn begin(&mut self, _run: &RunInfo) -> crate::Result<()> {
        Ok(())
    }

    /// Called at step 0, every [`Recorder::every`] steps, and after the last step.
    fn record(&mut self, sample: &Sample) -> crate::Result<()>;

    /// Called once at the end with the run's summary.
    fn finish(&mut self, _summary: &Summary) -> crate::Result<()> {
        Ok(())
    }
}
