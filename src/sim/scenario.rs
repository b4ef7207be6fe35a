//! A validated, ready-to-run experiment.

use crate::control::{Gains, Pd};
use crate::geometry::GeometryModel;
use crate::model::Model;
use crate::spatial::Vec3;
use crate::traj::shape::Board;
use crate::traj::{Interpolated, Trajectory};

/// Everything one closed-loop run needs; built (and validated) by the command line or by a
/// library user. Runs start at the command's start state, q = q_cmd(0), v = v_cmd(0).
#[derive(Clone, Debug)]
pub struct Scenario {
    /// What runs, for people: `wave`, `replay`, `shape circle (240 points)`.
    pub command: String,
    /// The simulated model (payload included; gravity as the run wants it).
    pub model: Model,
    /// Its visuals and collision geometry.
    pub geometry: GeometryModel,
    /// The frame traced as the tool.
    pub tool_frame: usize,
    /// The joint command.
    pub trajectory: Trajectory,
    /// Control and integration period Δt (s).
    pub dt: f64,
    /// Number of steps (duration / Δt, rounded).
    pub steps: usize,
    /// Gains and limits (and the inertias they were tuned from).
    pub gains: Gains,
    /// The controller built from `gains`.
    pub pd: Pd,
    /// Metric sampling period in steps: tool range and path deviation are taken every
    /// `record_every` steps and after the last (the trail's rows).
    pub record_every: usize,
    /// For `shape`: the board, the reference path and the moving target.
    pub shape: Option<ShapeRun>,
}

/// The drawing part of a `shape` run.
#[derive(Clone, Debug)]
pub struct ShapeRun {
    /// The board drawn on.
    pub board: Board,
    /// The closed reference path (the IK targets, world, m).
    pub reference: Vec<Vec3>,
    /// The target point over time: the reference samples played like the joint samples.
    pub target: Interpolated,
    /// Largest IK position residual over the samples (m).
    pub ik_max_residual_m: f64,
}
