//! The run summary: a stable JSON contract (`--summary F.json`) that CI and other tools read.

use serde::Serialize;

use super::{Scenario, Sizing, SlipMargin, Verdict};
use crate::control::{FeedForward, Gains, Trip};
use crate::error::{Words, in_words};
use crate::geometry::mesh::{Origin, origin};
use crate::geometry::{ClearanceReport, GeometryModel};
use crate::model::{Geometry, JointId, Mapping, ToolChoice};
use crate::traj::Interpolation;

/// What a run simulated: the robot, its degrees of freedom and their units, the tool, and where
/// each collision mesh came from (the summary's first keys), so that summaries of several arms
/// can be read side by side without their command lines.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Simulated {
    /// The robot's name (the URDF's `<robot name>`).
    pub robot: String,
    /// Where the model was read from: the robot file's path, with a xacro file's arguments
    /// (`PATH, NAME:=VALUE, …`, the arguments given), `bundled urdf/faze4_arm.urdf` for the
    /// bundled arm. Its format is [`Simulated::format`].
    pub robot_source: String,
    /// The degrees of freedom in order (J1 … Jn, the order of every per-joint list): the moving
    /// joints that mimic no other.
    pub joints: Vec<DofJoint>,
    /// The link whose origin is the tool (the trail's x, y, z, the tool range, the payload).
    pub tool_link: String,
    /// How the tool link was chosen.
    pub tool_choice: ToolRule,
    /// Every collision mesh of the model, in link order then document order, and where it was
    /// found. Listed whether or not the run checks the self-clearance (`--no-collisions` too):
    /// whether it did, and the links it left out, is `clearance`.
    pub meshes: Vec<MeshSource>,
    /// The robot file's format: `urdf`, `xacro`, `mjcf` (empty for a model built in memory).
    pub format: String,
    /// What reading the file mapped onto faze4's terms or left out (MJCF's `armature` as rotor
    /// inertia, its world geoms left out, its springs not simulated), each with the
    /// elements concerned; empty for a URDF. An option it names is in field words
    /// (`center home`), the summary being every front end's.
    pub mapped: Vec<Mapping>,
}

impl Simulated {
    /// The description of a run of `sc`.
    pub fn of(sc: &Scenario) -> Simulated {
        let model = &sc.model;
        let (default, choice) = model.default_tool();
        Simulated {
            robot: model.name.clone(),
            robot_source: model.source.clone(),
            joints: (model.joints.iter())
                .map(|j| DofJoint {
                    name: j.name.clone(),
                    unit: j.kind.unit(),
                })
                .collect(),
            tool_link: model.frame(sc.tool_frame).name.clone(),
            tool_choice: match choice {
                _ if default != sc.tool_frame => ToolRule::Given,
                ToolChoice::Named => ToolRule::NamedToolLink,
                ToolChoice::LastLink => ToolRule::LastLink,
                ToolChoice::DeepestCommonAncestor => ToolRule::DeepestCommonAncestor,
            },
            meshes: sc.meshes.clone(),
            format: model.format.clone(),
            mapped: (model.mapped.iter())
                .map(|m| Mapping {
                    to: in_words(&m.to, Words::Keywords),
                    ..m.clone()
                })
                .collect(),
        }
    }
}

/// A degree of freedom: its joint and the unit of its position.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DofJoint {
    /// The URDF joint name.
    pub name: String,
    /// `"rad"` (revolute, continuous) or `"m"` (prismatic): the unit of the joint's entries in
    /// the per-joint lists (per second for speeds).
    pub unit: &'static str,
}

/// How the tool link was chosen (the model's default rule, docs/model.md 1.3, or given).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ToolRule {
    /// The model has a link named `tool_link`.
    #[default]
    NamedToolLink,
    /// A chain: its last link.
    LastLink,
    /// A branched tree: the deepest common ancestor of its deepest leaves.
    DeepestCommonAncestor,
    /// `--tool-link` (or [`super::ScenarioBuilder::tool_frame`]) named a link the default rule
    /// does not give.
    Given,
}

/// One collision mesh of the model and where it was found.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct MeshSource {
    /// The link it belongs to.
    pub link: String,
    /// The reference as the URDF writes it (`package://…`, relative or absolute).
    pub uri: String,
    /// The file it resolved to (as faze4 resolved it: relative to the working directory when
    /// `--urdf` or `--package-path` was relative), `"built-in"` for the copy of an official
    /// Faze4 mesh built into the binary, `null` when found nowhere (its link is not checked).
    pub source: Option<String>,
}

impl MeshSource {
    /// The collision meshes of `geometry` and where each is loaded from (see
    /// [`crate::geometry::mesh::load`]); reads no file.
    pub fn of(geometry: &GeometryModel) -> Vec<MeshSource> {
        (geometry.collisions.iter())
            .filter_map(|g| match &g.geometry {
                Geometry::Mesh { uri, path, .. } => Some(MeshSource {
                    link: g.link.clone(),
                    uri: uri.clone(),
                    source: match origin(uri, path.as_deref(), geometry.built_in_meshes) {
                        Origin::File(path) => Some(path.to_string_lossy().into_owned()),
                        Origin::BuiltIn => Some("built-in".into()),
                        Origin::NotFound => None,
                    },
                }),
                _ => None,
            })
            .collect()
    }
}

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
    /// The joint that went bad (1-based, J1..Jn, in the JSON).
    #[serde(serialize_with = "one_based")]
    pub joint: JointId,
    /// b = Δt²·kp/I per joint.
    pub stiffness_b: Vec<f64>,
}

fn one_based<S: serde::Serializer>(joint: &JointId, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_u64(joint.0 as u64 + 1)
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
    /// What was simulated (`robot`, `joints`, `tool_link`, `tool_choice`, `meshes` in the
    /// JSON).
    #[serde(flatten)]
    pub simulated: Simulated,
    /// Degrees of freedom.
    pub dof: usize,
    /// Step Δt (s).
    pub dt: f64,
    /// Steps taken: the run's steps, or those before it diverged or was interrupted.
    pub steps: usize,
    /// The gains and limits the run used, and the effective inertias they were tuned from
    /// (`effective_inertia`, `kp`, `kd`, `effort` in the JSON, an unlimited effort `null`; and
    /// `stability`, the coupled loop's figures at the start pose).
    #[serde(flatten)]
    pub gains: Gains,
    /// What the controller fed forward: `"gravity"` (g(q), the default), `"full"` (the
    /// command's inverse dynamics, `--ff full`) or `"none"` (`--no-ff`).
    pub feed_forward: FeedForward,
    /// A time-stamped trajectory's interpolation between its points (`"linear"`, `"cubic"`,
    /// `"quintic"`); absent for the other commands.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interpolation: Option<Interpolation>,
    /// A time-stamped trajectory's playback (`"playback": {"start": [rad or m…], "start_given",
    /// "approach_s", "interpolation_forced", "points"}`): where the arm started, and the time
    /// it had to reach the first point; absent for the other commands and for a trajectory
    /// built without one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub playback: Option<crate::traj::Playback>,
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
    /// Whether the arm follows its command, and if not, why (see [`Verdict`]).
    pub verdict: Verdict,
    /// Wall-clock time of the simulation loop (s), the self-clearance included.
    pub wall_time_s: f64,
    /// Of `wall_time_s`, the loop's own time (s): the dynamics, controller and recorders, without
    /// the time the loop spent on the self-clearance (measuring it on the loop's thread, or
    /// waiting to hand a sample to the clearance's worker) and without waiting for the worker
    /// to finish after the last step.
    pub dynamics_wall_time_s: f64,
    /// Of `wall_time_s`, the time spent measuring the self-clearance (s), on whichever thread
    /// measured it (a worker's time overlaps the dynamics'); absent when the run checks none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance_wall_time_s: Option<f64>,
    /// Shapes only: tool distance to the reference path.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_deviation_mm: Option<PathDeviation>,
    /// Shapes only: the largest IK position residual over the samples (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ik_max_residual_m: Option<f64>,
    /// The self-clearance of the collision geometry over the trail samples: per checked pair
    /// its smallest distance and when, the closest pair, the links not checked. Absent when
    /// the run checks none (`--no-collisions`, or a model without collision geometry).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance: Option<ClearanceReport>,
    /// Only when the run was stopped by Ctrl-C: the simulated time it stopped at (s); the
    /// metrics cover the steps before it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interrupted_at_s: Option<f64>,
    /// Only under `--self-collisions`: what the contacts did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub self_contact: Option<ContactSummary>,
    /// Only under `--motors`: per joint what its motor did (`null` for a joint without one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motors: Option<Vec<Option<MotorSummary>>>,
}

/// What one joint's motor did over the steps (the summary's `"motors"`); torques and speeds
/// at the motor shaft.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MotorSummary {
    /// The motor, for people.
    pub label: String,
    /// `"dc"` or `"stepper"`.
    pub kind: &'static str,
    /// What drove the joint: `"pd"` (the controller, clipped to the envelope), `"stepper"`
    /// (`--drive stepper`: the stepper open loop) or `"servo"` (`--drive servo`: the servo's
    /// own loop).
    pub drive: &'static str,
    /// Under the PD: the share of the steps where the controller asked for more than the
    /// envelope gave at the joint's speed (beyond it by more than [`ENVELOPE_MARGIN`]). Under
    /// `--drive stepper`: the share of the steps with the rotor's lag past the torque–angle
    /// curve's peak; under `--drive servo`: the share with the duty asked at the servo's torque
    /// limit (%).
    pub envelope_pct: f64,
    /// max over steps of |ω_m| = |ratio · q̇| (rad/s).
    pub max_motor_speed: f64,
    /// √(mean over steps of τ_m²), τ_m = τ / (ratio · η) the torque the motor gave (N·m).
    pub rms_torque: f64,
    /// The motor's continuous rating (N·m RMS), `null` when unknown.
    pub continuous_torque: Option<f64>,
    /// Steppers only: under the PD the first time the controller asked for more than the
    /// pull-out torque, under `--drive stepper` the first slip (s), or `null`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loses_steps_at: Option<Option<f64>>,
    /// Steppers under the PD that lose steps: what it needed, at what speed, and what the
    /// curve gave.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_loss: Option<StepLoss>,
    /// Steppers under `--drive stepper`: the full steps the rotor ends off its command, a
    /// multiple of 4 (each slip is one electrical cycle).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps_lost: Option<u64>,
    /// Steppers under `--drive stepper`: the offset the slips left at the joint, actual −
    /// commanded (rad or m; negative: behind).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position_lost: Option<f64>,
    /// Steppers under `--drive stepper`: how the rotor rang about its microstep, and whether a
    /// slip survives the damping's uncertainty.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ringing: Option<Ringing>,
    /// Smart servos under `--drive servo`: whether their protection acted, and what their own
    /// loop asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub servo: Option<ServoSummary>,
    /// The sizing report (`--sizing` prints it).
    pub sizing: Sizing,
}

/// A smart servo over a run (`--drive servo`; docs/motors.md, "Smart servos").
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ServoSummary {
    /// The first time its protection acted: `kind` (`"overload"`, `"over_current"`,
    /// `"shutdown"`), `t` (s), `torque` (the largest at the output over the time that tripped
    /// it, N·m) and `duration` (that time, s); `null` when it never did.
    pub trip: Option<Trip>,
    /// The largest duty its loop asked for (a share of the supply; its torque limit at most).
    pub max_duty: f64,
    /// A Feetech servo's protective torque: the duty it is held to once its overload
    /// protection acts (share); `null` for a Dynamixel, which shuts down instead.
    pub protective: Option<f64>,
    /// How often it was sent its goal (Hz; `servo_rate`); `null`: at the trajectory's own
    /// sample times, or 30 Hz for a wave.
    pub goal_rate: Option<f64>,
    /// That its protection registers are assumed defaults, not published figures.
    pub note: &'static str,
}

/// How an open-loop stepper's rotor rang about its microstep (docs/motors.md, "The stepper's
/// damping"), at the motor shaft where not said.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Ringing {
    /// Its natural frequency at the start pose (Hz).
    pub natural_hz: f64,
    /// Its damping ratio ζ at the start pose: the joint's own damping and the drive's.
    pub damping_ratio: f64,
    /// Of the drive's damping, the driver's current loop on the winding (N·m·s/rad).
    pub electrical_damping: f64,
    /// The rotor's own viscous damping (N·m·s/rad).
    pub rotor_damping: f64,
    /// The reducer's viscous damping (N·m·s/rad).
    pub reducer_damping: f64,
    /// The reducer's Coulomb friction (N·m).
    pub reducer_friction: f64,
    /// The largest lag of the rotor from its nearest stable point (full steps: 1 is the
    /// torque–angle curve's peak, 2 its unstable top, where it slips).
    pub max_lag_steps: f64,
    /// For a rotor that slipped, or came within a full step of it: the damping ratio below
    /// which it slips (found by running again with the joint's damping changed), `"robust"`
    /// when it slips even at [`crate::sim::ROBUST_DAMPING_RATIO`]; absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slips_below: Option<SlipMargin>,
}

/// How far (relative) a demand must exceed the envelope to count as beyond it under the PD
/// (`envelope_pct`, and a stepper's `step_loss`): the demand and the envelope are each a few
/// floating-point operations from the same figures, so a demand equal to the envelope
/// differs from it by about 1e-15 relative; 1e-9 is far above that round-off and far below
/// any excess that matters (1e-9 of 0.3 N·m is 0.3 nN·m).
pub const ENVELOPE_MARGIN: f64 = 1e-9;

/// The first step at which a stepper was asked for more than its pull-out torque.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct StepLoss {
    /// Simulated time (s).
    pub t: f64,
    /// The torque the controller asked of the motor, |τ_raw| / (ratio · η) (N·m).
    pub needs: f64,
    /// The motor's speed |ω_m| (rad/s).
    pub speed: f64,
    /// The curve's torque at that speed (N·m).
    pub gives: f64,
}

/// The contacts of a `--self-collisions` run (the summary's `"self_contact"`).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ContactSummary {
    /// Coulomb friction μ.
    pub friction: f64,
    /// How meshes were read: `"hull"` or `"mesh"`.
    pub geometry: crate::geometry::ClearanceGeometry,
    /// Share of the steps with at least one contact (%).
    pub steps_in_contact_pct: f64,
    /// Deepest penetration (m).
    pub max_depth_m: f64,
    /// Mean Newton iterations per step in contact.
    pub newton_iterations_per_step: f64,
    /// Pair queries of the geometry (the other pairs at the other steps were pruned or
    /// followed).
    pub geometry_queries: u64,
}
