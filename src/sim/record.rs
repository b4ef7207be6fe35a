//! The one interface every output of a run implements ([`Recorder`]), and what the run tells
//! it: [`RunInfo`] once, a [`Sample`] at every recording step, the [`Summary`] at the end. It
//! sits in `sim`, below every recorder (the terminal, the trail, the 3D views, the plot), so
//! the recorders import the run and never the other way round.

use super::Summary;
use crate::control::Gains;
use crate::geometry::GeometryModel;
use crate::model::{FrameId, Model};
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
    pub geometry: &'a GeometryModel,
    /// The frame whose origin is the tool (trail x, y, z).
    pub tool_frame: FrameId,
    /// Control and integration period Δt (s).
    pub dt: f64,
    /// Number of steps the run will take.
    pub steps: usize,
    /// Gains and limits in use.
    pub gains: &'a Gains,
    /// What the controller feeds forward.
    pub feedforward: crate::control::FeedForward,
    /// The start state q (q_cmd(0), or a time-stamped trajectory's start).
    pub start_q: &'a [f64],
    /// For shapes: the drawing board.
    pub board: Option<&'a Board>,
    /// For shapes: the closed reference path the tool should draw (world, m).
    pub reference_path: Option<&'a [Vec3]>,
    /// The link frames of each pair whose self-clearance is checked, in the order of
    /// [`Sample::intersecting`] (empty when the run checks none).
    pub collision_pairs: &'a [[FrameId; 2]],
    /// `--motors`: per joint its motor (`None` without one); `None`: no motors.
    pub motors: Option<&'a [Option<crate::control::Motor>]>,
    /// A time-stamped trajectory's playback: its start and approach.
    pub playback: Option<&'a crate::traj::Playback>,
    /// Per joint, what drives it (size dof): the PD, or a drive of its own that the PD's
    /// gains and feed-forward do not act on.
    pub drives: &'a [super::JointDrive],
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
    /// The controller's torque before actuation, τ_raw (under `--drive stepper` a stepper's
    /// joint's is its τ: an open-loop stepper asks for nothing else).
    pub tau_raw: &'a [f64],
    /// Gravity forces g(q) at this state.
    pub g: &'a [f64],
    /// Tool frame origin in the world (m).
    pub tool: Vec3,
    /// For shapes: the reference point the tool should be at now (world, m).
    pub target: Option<Vec3>,
    /// Per checked pair ([`RunInfo::collision_pairs`]), whether its collision geometry
    /// intersects at the latest trail sample (this one when it is a trail sample); empty when
    /// the run checks no clearance, or when no recorder [`Recorder::reads_intersections`].
    pub intersecting: &'a [bool],
}

/// A consumer of a run's output. `begin` once, `record` at every sample its period asks for
/// (see [`Recorder::period`]), `finish` once with the summary (also after a divergence).
pub trait Recorder {
    /// Simulated time between two recorded samples (s). The run records at step 0, every
    /// [`steps_per_record`]`(period, Δt)` steps, and after the last step.
    fn period(&self) -> f64;

    /// Whether it reads [`Sample::intersecting`] (the 3D views, which draw the links of
    /// intersecting pairs red): the run then measures the self-clearance at each sample
    /// before handing it over. Otherwise the self-clearance is measured on a worker thread
    /// beside the dynamics, and `intersecting` is empty.
    fn reads_intersections(&self) -> bool {
        false
    }

    /// Called once before the first sample.
    fn begin(&mut self, _run: &RunInfo) -> crate::Result<()> {
        Ok(())
    }

    /// Called at step 0, every [`Recorder::period`], and after the last step.
    fn record(&mut self, sample: &Sample) -> crate::Result<()>;

    /// Called once at the end with the run's summary.
    fn finish(&mut self, _summary: &Summary) -> crate::Result<()> {
        Ok(())
    }
}

/// The recording period in steps for `period` seconds at step `dt` (at least one step).
pub fn steps_per_record(period: f64, dt: f64) -> usize {
    ((period / dt).round() as usize).max(1)
}
