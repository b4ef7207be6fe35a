//! The run summary: a stable JSON contract (`--summary F.json`) that CI and other tools read.

use serde::Serialize;

use crate::control::Stability;

/// Per-axis [lo, hi] of the tool origin over the trail samples (m).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ToolRange {
    /// World x range.
    pub x: [f64; 2],
    /// World y range.
    pub y: [f64; 2],
    /// World z range.
    pub z: [f64; 2],
}

/// Where and how a run went unstable.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Diverged {
    /// Simulated time of the step that went bad (s).
    pub t: f64,
    /// The joint that went bad, 1-based (J1..Jn).
    pub joint: usize,
    /// b = Δt²·kp/I per joint.
    pub stiffness_b: Vec<f64>,
}

/// Distance from the tool to the closed reference path over the trail samples (mm).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PathDeviation {
    /// Largest distance (mm).
    pub max: f64,
    /// Mean distance (mm).
    pub mean: f64,
}

/// What a run did. Field names and units are the contract.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Summary {
    /// Degrees of freedom.
    pub dof: usize,
    /// Step Δt (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// Effective inertia per joint, M_ii(q_start).
    pub effective_inertia: Vec<f64>,
    /// Proportional gains.
    pub kp: Vec<f64>,
    /// Derivative gains.
    pub kd: Vec<f64>,
    /// Torque limits (null in JSON where unlimited).
    pub effort: Vec<f64>,
    /// The coupled loop's figures at the start pose (b_max, b_kd, spectral radius, whether the
    /// tuning scaled the gains); null if the gains were never assessed.
    pub stability: Option<Stability>,
    /// max over steps of |q_cmd − q| per joint (rad or m).
    pub max_tracking_error_rad: Vec<f64>,
    /// Share of steps with |τ_raw| ≥ E per joint (%).
    pub saturation_pct: Vec<f64>,
    /// max over steps of |v| per joint (rad/s or m/s).
    pub max_speed: Vec<f64>,
    /// Speed limit per joint (rad/s or m/s; null in JSON where none).
    pub velocity_limit: Vec<f64>,
    /// Share of steps with |v| above the joint's speed limit (%); null where it has none. A
    /// joint whose share is above 0 exceeded its limit.
    pub velocity_limit_pct: Vec<Option<f64>>,
    /// Tool range over the trail samples.
    pub tool_range_m: ToolRange,
    /// `null`, or where the run went unstable.
    pub diverged: Option<Diverged>,
    /// Wall-clock time of the simulation loop (s).
    pub wall_time_s: f64,
    /// Shapes only: tool distance to the reference path.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_deviation_mm: Option<PathDeviation>,
    /// Shapes only: the largest IK position residual over the samples (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ik_max_residual_m: Option<f64>,
    /// Only when the run was stopped by Ctrl-C: the simulated time it stopped at (s); the
    /// metrics cover the steps before it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interrupted_at_s: Option<f64>,
}
