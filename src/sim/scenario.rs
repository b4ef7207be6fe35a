//! A validated, ready-to-run experiment, and the builder that makes one: it tunes the
//! controller, checks every input, and returns its warnings as values (it prints nothing).
//!
//! ```no_run
//! use faze4::sim::{Scenario, StopFlag, run};
//! use faze4::traj::{Trajectory, Wave};
//! # fn main() -> faze4::Result<()> {
//! let model = faze4::faze4::model();
//! let wave = Trajectory::Wave(Wave { amplitude: vec![0.3; model.dof()], omega: 0.5, center: vec![0.0; model.dof()] });
//! let scenario = Scenario::builder(model, wave).duration(4.0).payload_kg(0.5).build()?;
//! let summary = run(&scenario, &mut [], &StopFlag::new())?;
//! println!("J2 saturated {} % of the steps", summary.saturation_pct[1]);
//! # Ok(()) }
//! ```

use std::sync::Arc;

use super::check::{count, non_negative, override_per_joint, positive};
use super::drives::{self, Drive, JointDrive};
use super::{MeshSource, SelfContact, Thresholds, Warning, steps_per_record};
use crate::algo::{Data, crba};
use crate::control::{FeedForward, Gains, Motor, Pd, Stability, arithmetic_holds, tune};
use crate::error::{Error, Result, shortest};
use crate::geometry::{ClearanceGeometry, CollisionSet, GeometryModel, PairFilter, PathClearance};
use crate::model::{FrameId, LoadWarning, Model};
use crate::traj::{ShapeRun, Trajectory};

/// Default control and integration period Δt (s): 5 kHz.
pub const DEFAULT_DT: f64 = 2e-4;
/// Default time between two trail samples, where the tool range and path deviation are taken (s).
pub const DEFAULT_RECORD_PERIOD: f64 = 0.02;
/// Default tolerance (m) of the self-clearance ([`ScenarioBuilder::clearance_tolerance`]); how
/// it was chosen: docs/clearance.md, "Speed".
pub const DEFAULT_CLEARANCE_TOLERANCE_M: f64 = 1e-3;
/// Default simulated time (s) of a run built without [`ScenarioBuilder::duration`].
pub const DEFAULT_DURATION: f64 = 8.0;

/// Everything one closed-loop run needs, validated. Runs start at the command's start state,
/// q = q_cmd(0), v = v_cmd(0). Made by [`Scenario::builder`].
#[derive(Clone, Debug)]
pub struct Scenario {
    /// What runs, for people: `wave`, `replay`, `shape circle (240 points)`.
    pub command: String,
    /// The simulated model (payload included; gravity as the run wants it).
    pub model: Model,
    /// Its visuals and collision geometry (empty unless given; no collision geometry when
    /// the run checks no clearance).
    pub geometry: GeometryModel,
    /// The loaded collision geometry whose self-clearance the run measures at every trail
    /// sample: `None` with clearance off ([`ScenarioBuilder::collisions`]`(None)`) or when the
    /// geometry has no collision element. Shared, immutable: clones of the scenario (a sweep's
    /// runs) use the same one.
    pub collision_set: Option<Arc<CollisionSet>>,
    /// The model's collision meshes and where each was found (the summary's `meshes`), listed
    /// before the clearance is turned off or loaded: a run without clearance lists them too.
    pub meshes: Vec<MeshSource>,
    /// How far (m) the self-clearance's minimum may be above the true one (0: exact; see
    /// [`crate::geometry::Clearance::with_tolerance`]).
    pub clearance_tolerance: f64,
    /// The clearance of the commanded path, computed once and shared by the runs of one
    /// command ([`super::commanded_path`]; a sweep's rows): the run's clearance is derived from
    /// it where the run stays near it ([`crate::geometry::Clearance::following`]). `None`:
    /// the run's own, alone (a path of another collision set is not used).
    pub path_clearance: Option<Arc<PathClearance>>,
    /// The frame traced as the tool.
    pub tool_frame: FrameId,
    /// The joint command.
    pub trajectory: Trajectory,
    /// Control and integration period Δt (s).
    pub dt: f64,
    /// Number of steps (duration / Δt, rounded).
    pub steps: usize,
    /// The controller: its gains, the inertias they were tuned from, the torque limits.
    pub controller: Pd,
    /// Speed limit per joint (rad/s or m/s; +∞ where none): not enforced, only counted
    /// (`velocity_limit_pct` in the summary).
    pub speed_limit: Vec<f64>,
    /// Metric sampling period in steps: tool range and path deviation are taken every
    /// `record_every` steps and after the last (the trail's rows).
    pub record_every: usize,
    /// For `shape`: the board, the reference path and the moving target.
    pub shape: Option<ShapeRun>,
    /// The limits within which the arm is judged to follow its command.
    pub thresholds: Thresholds,
    /// What the builder noticed and the user should know before the run.
    pub warnings: Vec<Warning>,
    /// `--self-collisions`: contact between the arm's own collision geometry, if on.
    pub self_contact: Option<SelfContact>,
    /// Per joint the motor whose envelope clips its torque at its speed (`None` for a joint
    /// without one: the constant limit alone), its gear ratio and rotor those of the model's
    /// joint; `None`: no motors, the constant limits of the controller.
    pub motors: Option<Vec<Option<Motor>>>,
    /// What drives each joint (n; [`JointDrive::Pd`] for all under [`Drive::Pd`]), with the
    /// drive's state at the start pose.
    pub drives: Vec<JointDrive>,
    /// Under [`Drive::Stepper`], whether a slip's robustness is found by running again with
    /// the joint's damping changed (the summary's `ringing.slips_below`; on by default;
    /// off in those runs themselves).
    pub slip_margins: bool,
}

/// How a run measures the self-clearance of its collision geometry (see
/// [`CollisionSet`]): the default is the exact meshes and Drake's non-adjacent pairs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Collisions {
    /// Exact triangles (`--collision-geometry mesh`) or convex hulls (`hull`).
    pub geometry: ClearanceGeometry,
    /// Which pairs are checked (`--collision-pairs all` for [`PairFilter::All`]).
    pub pairs: PairFilter,
}

impl Scenario {
    /// A builder for a run of `model` following `trajectory`, with the defaults: Δt 2e-4 s,
    /// 8 s, gravity and its feed-forward on, no payload, the tuned gains, the model's torque
    /// limits ([`default_effort`]), the model's default tool frame.
    pub fn builder(model: Model, trajectory: Trajectory) -> ScenarioBuilder {
        ScenarioBuilder {
            geometry: GeometryModel::default(),
            load_warnings: Vec::new(),
            command_warnings: Vec::new(),
            collisions: Some(Collisions::default()),
            collision_set: None,
            clearance_tolerance: DEFAULT_CLEARANCE_TOLERANCE_M,
            path_clearance: None,
            command: String::from(match trajectory {
                Trajectory::Wave(_) => "wave",
                Trajectory::Interpolated(_) | Trajectory::Spline(_) => "replay",
            }),
            model,
            trajectory,
            dt: DEFAULT_DT,
            duration: DEFAULT_DURATION,
            record_period: DEFAULT_RECORD_PERIOD,
            payload_kg: 0.0,
            gravity: true,
            feedforward: FeedForward::Gravity,
            tool_frame: None,
            effort: None,
            kp: Vec::new(),
            kd: Vec::new(),
            max_speed: Vec::new(),
            shape: None,
            thresholds: Thresholds::default(),
            self_contact: None,
            motors: None,
            drive: Drive::Pd,
        }
    }
}

/// Builds a [`Scenario`]; see [`Scenario::builder`]. Every setter takes the value as given;
/// [`ScenarioBuilder::build`] checks them all, each error naming the option of the same meaning
/// as a field of [`crate::config::RunConfig`] (`` `dt` ``, `` `payload_kg` ``; see
/// [`Error::option`]).
#[derive(Clone, Debug)]
pub struct ScenarioBuilder {
    command: String,
    model: Model,
    geometry: GeometryModel,
    load_warnings: Vec<LoadWarning>,
    command_warnings: Vec<Warning>,
    collisions: Option<Collisions>,
    collision_set: Option<Arc<CollisionSet>>,
    clearance_tolerance: f64,
    path_clearance: Option<Arc<PathClearance>>,
    trajectory: Trajectory,
    dt: f64,
    duration: f64,
    record_period: f64,
    payload_kg: f64,
    gravity: bool,
    feedforward: FeedForward,
    tool_frame: Option<FrameId>,
    effort: Option<Vec<f64>>,
    kp: Vec<Option<f64>>,
    kd: Vec<Option<f64>>,
    max_speed: Vec<Option<f64>>,
    shape: Option<ShapeRun>,
    thresholds: Thresholds,
    self_contact: Option<SelfContact>,
    motors: Option<Vec<Option<Motor>>>,
    drive: Drive,
}

impl ScenarioBuilder {
    /// The model as given (before the payload, the motors and the gravity setting apply).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The time step `dt` as given (s; checked when the scenario is built).
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// The joint command, replacing the one given to [`Scenario::builder`] (retime's check
    /// plays each timing it tries on the same builder).
    pub fn trajectory(mut self, trajectory: Trajectory) -> Self {
        self.trajectory = trajectory;
        self
    }

    /// What runs, for people (the banner's first word): `wave`, `replay`, `shape circle …`.
    pub fn command(mut self, command: impl Into<String>) -> Self {
        self.command = command.into();
        self
    }

    /// What reading the model skipped or changed (see [`crate::geometry::Robot::warnings`]): the
    /// scenario's warnings start with these.
    pub fn load_warnings(mut self, warnings: Vec<LoadWarning>) -> Self {
        self.load_warnings = warnings;
        self
    }

    /// What building the command noticed (e.g. [`Warning::HeldJoints`]): the scenario's
    /// warnings include these, after the model's.
    pub fn command_warnings(mut self, warnings: impl IntoIterator<Item = Warning>) -> Self {
        self.command_warnings.extend(warnings);
        self
    }

    /// The model's visuals and collision geometry (see [`crate::geometry::Robot`]), for the
    /// views; none by default.
    pub fn geometry(mut self, geometry: GeometryModel) -> Self {
        self.geometry = geometry;
        self
    }

    /// How the self-clearance of the geometry's collision elements is measured, or `None`
    /// (`--no-collisions`) for no clearance at all: the collision elements are dropped and no
    /// mesh is read. Default: [`Collisions::default`] (exact meshes, non-adjacent pairs).
    pub fn collisions(mut self, collisions: Option<Collisions>) -> Self {
        self.collisions = collisions;
        self
    }

    /// A collision set already loaded from the geometry given by
    /// [`ScenarioBuilder::geometry`] (its pairs index that geometry's collision elements), used
    /// instead of loading one: a sweep loads it once and shares it between its runs. Its
    /// reading of meshes and its pairs are its own; [`ScenarioBuilder::collisions`]`(None)`
    /// still turns the clearance off.
    pub fn collision_set(mut self, set: Arc<CollisionSet>) -> Self {
        self.collision_set = Some(set);
        self
    }

    /// How far (m, ≥ 0) the self-clearance's minimum may be above the true minimum over the
    /// samples (`clearance_tolerance`, in mm there): it is the distance of two actual parts,
    /// and the true minimum is at most this much below it; 0 is exact. Intersections are
    /// decided exactly whatever it is. Default [`DEFAULT_CLEARANCE_TOLERANCE_M`].
    pub fn clearance_tolerance(mut self, tolerance: f64) -> Self {
        self.clearance_tolerance = tolerance;
        self
    }

    /// The commanded path's clearance, computed once for the runs of one command
    /// ([`super::commanded_path`]): the run derives its own from it where it stays near it.
    /// Used only with the same collision set ([`ScenarioBuilder::collision_set`]).
    pub fn path_clearance(mut self, path: Arc<PathClearance>) -> Self {
        self.path_clearance = Some(path);
        self
    }

    /// Control and integration period Δt (s), > 0.
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = dt;
        self
    }

    /// Simulated time (s), at least one step.
    pub fn duration(mut self, duration: f64) -> Self {
        self.duration = duration;
        self
    }

    /// Time between two trail samples (s), where the tool range and path deviation are taken.
    pub fn record_period(mut self, period: f64) -> Self {
        self.record_period = period;
        self
    }

    /// A point mass (kg, ≥ 0) at the tool frame's origin.
    pub fn payload_kg(mut self, mass: f64) -> Self {
        self.payload_kg = mass;
        self
    }

    /// Whether the gravity field is on (default) or off (`no_gravity`).
    pub fn gravity(mut self, on: bool) -> Self {
        self.gravity = on;
        self
    }

    /// What the controller adds to its PD torque: g(q) (default), the command's inverse
    /// dynamics (`ff` full), or nothing (`no_ff`).
    pub fn feedforward(mut self, feedforward: FeedForward) -> Self {
        self.feedforward = feedforward;
        self
    }

    /// The frame traced as the tool.
    pub fn tool_frame(mut self, frame: FrameId) -> Self {
        self.tool_frame = Some(frame);
        self
    }

    /// Torque limits, one per joint (N·m or N, > 0; +∞ for none).
    pub fn effort(mut self, effort: Vec<f64>) -> Self {
        self.effort = Some(effort);
        self
    }

    /// Proportional gains that replace the tuned ones, one entry per joint (`None` keeps the
    /// tuned value). An empty vector keeps them all.
    pub fn kp(mut self, kp: Vec<Option<f64>>) -> Self {
        self.kp = kp;
        self
    }

    /// Derivative gains that replace the tuned ones, as [`ScenarioBuilder::kp`].
    pub fn kd(mut self, kd: Vec<Option<f64>>) -> Self {
        self.kd = kd;
        self
    }

    /// Speed limits (rad/s or m/s, > 0) that replace the model's, one entry per joint (`None`
    /// keeps the model's). An empty vector keeps them all. The model's are its defaults' where
    /// it has them ([`crate::model::ArmDefaults::speed_limit`]), else the URDF's `velocity`.
    /// Limits are counted (`velocity_limit_pct`), not enforced.
    pub fn max_speed(mut self, limits: Vec<Option<f64>>) -> Self {
        self.max_speed = limits;
        self
    }

    /// The limits within which the arm is judged to follow (see [`Thresholds`]).
    pub fn thresholds(mut self, thresholds: Thresholds) -> Self {
        self.thresholds = thresholds;
        self
    }

    /// The drawing part of a shape run (see [`ShapeRun::plan`]).
    pub fn shape(mut self, shape: ShapeRun) -> Self {
        self.shape = Some(shape);
        self
    }

    /// A motor per joint (`None` for a joint without one), behind the joint's gear ratio and
    /// with its rotor as the model has them (put a motor's ratio and rotor on the model first:
    /// [`crate::config::motors::fit`]); its envelope clips the joint's torque at its speed,
    /// every step; the constant limit E of a motored joint becomes ratio × η × the motor's
    /// largest torque unless [`ScenarioBuilder::effort`] gives it ([`effort_limits`]).
    pub fn motors(mut self, motors: Vec<Option<Motor>>) -> Self {
        self.motors = Some(motors);
        self
    }

    /// How the joints are driven (`drive`; default [`Drive::Pd`]). [`Drive::Stepper`]
    /// needs [`ScenarioBuilder::motors`] with at least one stepper whose rotor is known.
    pub fn drive(mut self, drive: Drive) -> Self {
        self.drive = drive;
        self
    }

    /// Contact forces between the checked pairs of the collision geometry given by
    /// [`ScenarioBuilder::geometry`] (`self_collisions`; off by default).
    pub fn self_contact(mut self, contact: SelfContact) -> Self {
        self.self_contact = Some(contact);
        self
    }

    /// Checks everything, applies gravity and the payload, tunes the controller at the start
    /// pose, and returns the scenario with its warnings.
    pub fn build(self) -> Result<Scenario> {
        self.check_values()?;
        let (n, tool_frame) = self.check_model()?;
        let mut drives = self.drive.joints(self.motors.as_deref(), n)?;
        let steps = steps(self.duration, self.dt)?;
        check_wave_limits(&self.model, &self.trajectory, self.dt, steps)?;
        // the arm without its payload, kept only to say which input overflows
        let bare = (self.payload_kg > 0.0).then(|| simulated_model(&self.model, tool_frame, 0.0, self.gravity));
        let mut model = simulated_model(&self.model, tool_frame, self.payload_kg, self.gravity);

        let mut warnings: Vec<Warning> = self.load_warnings.iter().cloned().map(Warning::Model).collect();
        warnings.extend(self.command_warnings.iter().cloned());
        warnings.extend(self.check_effort(&model)?);
        let effort = effort_limits(&model, self.effort.as_deref(), self.motors.as_deref());
        let q_start = start_pose(&model, &self.trajectory);
        warnings.extend(drives::prepare(
            &mut model,
            self.motors.as_deref(),
            &mut drives,
            &q_start,
            self.effort.is_some(),
        ));
        let gains = self.gains(&model, bare.as_ref(), &q_start, &effort, &mut warnings)?;
        warnings.extend(drives::timing_warnings(&model, &drives, self.dt));
        let speed_limit = speed_limits(&model, &self.max_speed)?;
        let meshes = MeshSource::of(&self.geometry);
        let (geometry, collision_set) = match (self.collisions, self.collision_set) {
            (Some(_), Some(set)) => (self.geometry, Some(set)),
            (collisions, _) => load_collisions(&model, self.geometry, collisions, &mut warnings)?,
        };
        Ok(Scenario {
            command: self.command,
            model,
            geometry,
            collision_set,
            meshes,
            clearance_tolerance: self.clearance_tolerance,
            path_clearance: self.path_clearance,
            tool_frame,
            trajectory: self.trajectory,
            dt: self.dt,
            steps,
            controller: Pd {
                gains,
                feedforward: self.feedforward,
            },
            record_every: steps_per_record(self.record_period, self.dt),
            speed_limit,
            shape: self.shape,
            thresholds: self.thresholds,
            warnings,
            self_contact: self.self_contact,
            motors: self.motors,
            drives,
            slip_margins: true,
        })
    }

    /// The values that stand alone: Δt, the duration, the record period, the thresholds, the
    /// payload, the clearance tolerance and the contact settings (and that contact has the
    /// collision geometry).
    fn check_values(&self) -> Result<()> {
        positive("dt", self.dt)?;
        positive("duration", self.duration)?;
        positive("record_period", self.record_period)?;
        self.thresholds.check()?;
        non_negative("payload_kg", self.payload_kg)?;
        non_negative("clearance_tolerance", self.clearance_tolerance)?;
        if let Some(contact) = &self.self_contact {
            contact.check()?;
            if self.collisions.is_none() {
                return Err(Error::option(
                    "self_collisions",
                    "needs the collision geometry: not with `no_collisions`",
                ));
            }
        }
        Ok(())
    }

    /// The model against the rest: it moves, the command has its joints, the tool frame is one
    /// of its frames and each motor is whole. Its dof n and the tool frame.
    fn check_model(&self) -> Result<(usize, FrameId)> {
        let model = &self.model;
        let n = model.dof();
        if n == 0 {
            return Err(Error::model(
                &model.source,
                format!("robot '{}'", model.name.escape_debug()),
                "has no moving joint: there is nothing to simulate",
            ));
        }
        if self.trajectory.dof() != n {
            return Err(Error::argument(
                "trajectory",
                format!("commands {} joints; the model has {n}", self.trajectory.dof()),
            ));
        }
        let tool_frame = self.tool_frame.unwrap_or_else(|| model.default_tool_frame());
        if tool_frame.0 >= model.frames.len() {
            return Err(Error::option(
                "tool_link",
                format!(
                    "frame index {} out of range ({} frames)",
                    tool_frame.0,
                    model.frames.len()
                ),
            ));
        }
        if let Some(motors) = &self.motors {
            count("motors", motors.len(), n)?;
            for (i, m) in motors.iter().enumerate() {
                if let Some(m) = m {
                    m.check()
                        .map_err(|e| Error::option("motors", format!("J{} {e}", i + 1)))?;
                }
            }
        }
        Ok((n, tool_frame))
    }

    /// The given torque limits, one per joint and each > 0; without them, the warning for the
    /// joints of `model` (the simulated model) that have no limit at all.
    fn check_effort(&self, model: &Model) -> Result<Option<Warning>> {
        if let Some(effort) = &self.effort {
            count("effort", effort.len(), model.dof())?;
            if let Some((i, x)) = effort.iter().enumerate().find(|(_, x)| x.is_nan() || **x <= 0.0) {
                return Err(Error::option(
                    "effort",
                    format!("J{} limit {} must be > 0", i + 1, shortest(*x)),
                ));
            }
            return Ok(None);
        }
        if model.defaults.effort.is_some() {
            return Ok(None);
        }
        let unlimited: Vec<String> = (model.joints.iter())
            .filter(|j| j.effort.is_none())
            .map(|j| j.name.clone())
            .collect();
        Ok((!unlimited.is_empty()).then(|| Warning::UnlimitedEffort {
            source: model.source.clone(),
            joints: unlimited,
        }))
    }

    /// The gains at the start pose `q_start` of `model` (the simulated model, `bare` without its
    /// payload) within the limits `effort`: tuned, `kp` and `kd` over them (their stability
    /// assessed again), or the error of an arithmetic that overflows; an unstable loop's
    /// warning appended to `warnings`.
    fn gains(
        &self,
        model: &Model,
        bare: Option<&Model>,
        q_start: &[f64],
        effort: &[f64],
        warnings: &mut Vec<Warning>,
    ) -> Result<Gains> {
        let (mut gains, m) = tune(model, q_start, effort, self.dt);
        override_gains("kp", &mut gains.kp, &self.kp)?;
        override_gains("kd", &mut gains.kd, &self.kd)?;
        let given = self.kp.iter().chain(&self.kd).any(Option::is_some);
        if given {
            // the given gains' own figures; `scaled` still says whether the rule's were scaled
            let damping: Vec<f64> = model.damping().collect();
            gains.stability = Some(Stability {
                scaled: gains.stability.is_some_and(|s| s.scaled),
                ..Stability::assess(&m, &damping, &gains.kp, &gains.kd, self.dt)
            });
        }
        if !arithmetic_holds(&m, &gains) {
            return Err(overflow(model, bare, self.payload_kg, q_start, effort, self.dt));
        }
        if let Some(stability) = gains.stability.filter(|s| !s.is_stable()) {
            warnings.push(Warning::UnstableGains { stability, given });
        }
        Ok(gains)
    }
}

/// The error of a scenario whose arithmetic overflows: the payload's (`payload_kg`) when the
/// arm without it (`bare`) holds, else `dt`'s when a time step shorter than the default
/// overflows (the tuned gains grow as 1/dt²) and the default's holds, else the model's joint
/// of largest inertia.
fn overflow(model: &Model, bare: Option<&Model>, payload_kg: f64, q_start: &[f64], effort: &[f64], dt: f64) -> Error {
    let holds_at = |m: &Model, dt: f64| {
        let (gains, mass) = tune(m, q_start, effort, dt);
        arithmetic_holds(&mass, &gains)
    };
    let holds = |m: &Model| holds_at(m, dt);
    if dt < DEFAULT_DT && holds_at(model, DEFAULT_DT) {
        return Error::option(
            "dt",
            format!(
                "{} s: too short to simulate this arm (the gains tuned for it grow as 1/dt² and overflow; {} s holds)",
                shortest(dt),
                shortest(DEFAULT_DT)
            ),
        );
    }
    if bare.is_some_and(holds) {
        return Error::option(
            "payload_kg",
            format!(
                "{} kg: too heavy to simulate (the mass matrix and the gains tuned for it overflow)",
                shortest(payload_kg)
            ),
        );
    }
    let model = bare.unwrap_or(model);
    let n = model.dof();
    let m = crba(model, &mut Data::new(model), q_start).clone();
    let joint = (0..n)
        .max_by(|&a, &b| m[(a, a)].abs().total_cmp(&m[(b, b)].abs()))
        .map_or(String::new(), |i| {
            format!("joint {}", crate::error::quoted(&model.joints[i].name))
        });
    Error::model(
        &model.source,
        joint,
        "its masses, lengths (joint and inertial origins), rotor inertia or gear ratio are too large to simulate: the mass matrix and the gains tuned for it overflow (check the URDF's masses and origins, `rotor_inertia`, `gear_ratio`)",
    )
}

/// `model` as a run simulates it: with a point mass of `payload_kg` at the origin of frame
/// `tool` (none for 0), and without the gravity field unless `gravity`.
pub fn simulated_model(model: &Model, tool: FrameId, payload_kg: f64, gravity: bool) -> Model {
    let mut model = match payload_kg > 0.0 {
        true => model.with_point_mass(tool, payload_kg),
        false => model.clone(),
    };
    if !gravity {
        model.gravity = Default::default();
    }
    model
}

/// The geometry a run of `model` keeps and its loaded collision set, as
/// [`ScenarioBuilder::collisions`] says: none, and no collision elements, when `collisions` is
/// `None`; none when the geometry has no collision element. Meshes not found become warnings
/// (appended to `warnings`); a mesh that cannot be read is an error. What the builder does; a
/// sweep calls it once for all its runs.
pub fn load_collisions(
    model: &Model,
    geometry: GeometryModel,
    collisions: Option<Collisions>,
    warnings: &mut Vec<Warning>,
) -> Result<(GeometryModel, Option<Arc<CollisionSet>>)> {
    let Some(Collisions { geometry: kind, pairs }) = collisions else {
        return Ok((geometry.without_collisions(), None));
    };
    if geometry.collisions.is_empty() {
        return Ok((geometry, None));
    }
    let (set, missing) = CollisionSet::new(model, &geometry, kind, pairs)?;
    warnings.extend(missing.into_iter().map(Warning::Clearance));
    Ok((geometry, Some(Arc::new(set))))
}

/// The torque limits a run on `model` has when none are given and no joint has a motor: the
/// arm's defaults ([`crate::model::ArmDefaults::effort`]; the Faze4's motor limits), else each
/// joint's URDF effort (infinite where it has none).
pub fn default_effort(model: &Model) -> Vec<f64> {
    match &model.defaults.effort {
        Some(effort) => effort.clone(),
        None => model.joints.iter().map(|j| j.effort.unwrap_or(f64::INFINITY)).collect(),
    }
}

/// The torque limits E a run of `model` uses (N·m or N): `given` where given; otherwise, for a
/// joint with a motor (`motors`), ratio × η × the motor's largest torque at the joint's gear
/// ratio; else the arm's [`default_effort`]. The one rule; `motors` has one entry per joint.
pub fn effort_limits(model: &Model, given: Option<&[f64]>, motors: Option<&[Option<Motor>]>) -> Vec<f64> {
    if let Some(given) = given {
        return given.to_vec();
    }
    let defaults = default_effort(model);
    match motors {
        None => defaults,
        Some(motors) => (defaults.iter().zip(motors).zip(&model.joints))
            .map(|((&e, m), j)| m.as_ref().map_or(e, |m| m.joint_limit(j.gear_ratio)))
            .collect(),
    }
}

/// The command's start pose (q_cmd(0), or a message's start), where the run starts and the
/// gains are tuned.
fn start_pose(model: &Model, trajectory: &Trajectory) -> Vec<f64> {
    let n = model.dof();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    trajectory.start_state(&mut q, &mut v);
    q
}

/// Speed limits: `given` where it has a value (> 0); elsewhere the arm's defaults
/// ([`crate::model::ArmDefaults::speed_limit`]: none on the Faze4, whose URDF gives every joint
/// the same placeholder `velocity="3.0"`), else the URDF's `velocity`.
fn speed_limits(model: &Model, given: &[Option<f64>]) -> Result<Vec<f64>> {
    let mut limits: Vec<f64> = match &model.defaults.speed_limit {
        Some(limits) => limits.clone(),
        None => (model.joints.iter())
            .map(|j| j.velocity.unwrap_or(f64::INFINITY))
            .collect(),
    };
    override_per_joint("max_speed", &mut limits, given, |v| v > 0.0, "> 0")?;
    Ok(limits)
}

/// Gains given per joint (finite and ≥ 0) over the tuned ones.
fn override_gains(field: &str, gains: &mut [f64], values: &[Option<f64>]) -> Result<()> {
    override_per_joint(field, gains, values, |v| v.is_finite() && v >= 0.0, "finite and ≥ 0")
}

/// The most steps a run may take (10^12: 6.3 years at 0.2 ms).
pub(crate) const MAX_STEPS: f64 = 1e12;

/// Why a duration at a time step is no run's length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BadSteps {
    /// Shorter than one step.
    TooFew,
    /// More than [`MAX_STEPS`].
    TooMany,
}

/// Number of steps for `duration` at `dt` (at least one, at most [`MAX_STEPS`]), or why not:
/// each caller words the fault for the option or file it comes from.
pub(crate) fn step_count(duration: f64, dt: f64) -> std::result::Result<usize, BadSteps> {
    let steps = (duration / dt).round();
    if steps < 1.0 {
        return Err(BadSteps::TooFew);
    }
    if steps > MAX_STEPS {
        return Err(BadSteps::TooMany);
    }
    Ok(steps as usize)
}

/// Number of steps for `duration` at `dt` ([`step_count`]), or the error naming `duration`.
pub(crate) fn steps(duration: f64, dt: f64) -> Result<usize> {
    step_count(duration, dt).map_err(|bad| {
        Error::option(
            "duration",
            match bad {
                BadSteps::TooFew => format!(
                    "{} s is shorter than one step of `dt` {} s",
                    shortest(duration),
                    shortest(dt)
                ),
                BadSteps::TooMany => format!(
                    "{} s at `dt` {} s is more than the 10^12 steps a run may take",
                    shortest(duration),
                    shortest(dt)
                ),
            },
        )
    })
}

/// A wave's command must stay inside the joint limits: where the amplitude could cross a
/// limit, the command is scanned at every step to report the first crossing.
fn check_wave_limits(model: &Model, trajectory: &Trajectory, dt: f64, steps: usize) -> Result<()> {
    let Trajectory::Wave(wave) = trajectory else {
        return Ok(());
    };
    if (model.joints.iter().zip(&wave.center).zip(&wave.amplitude))
        .all(|((j, &c), &a)| j.within_limits(c + a) && j.within_limits(c - a))
    {
        return Ok(());
    }
    let n = model.dof();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    for k in 0..=steps {
        let t = k as f64 * dt;
        trajectory.eval(t, &mut q, &mut v);
        if let Some(i) = (0..n).find(|&i| !model.joints[i].within_limits(q[i])) {
            return Err(wave_limit_error(model, wave, i, q[i], t));
        }
    }
    Ok(())
}

/// The one line for a wave that leaves joint `i`'s limits (commanded to `q` at `t`): the joint,
/// its unit, the values with every digit (shortest round-trip), the amplitude that would fit
/// about its centre, and `--center mid` where the zero pose is the cause.
fn wave_limit_error(model: &Model, wave: &crate::traj::Wave, i: usize, q: f64, t: f64) -> Error {
    let j = &model.joints[i];
    let (c, a) = (wave.center[i], wave.amplitude[i]);
    let prismatic = j.kind == crate::model::JointKind::Prismatic;
    let (field, unit, to_option) = match prismatic {
        true => ("amp_m", "m", 1.0),
        false => ("amp_deg", "deg", 180.0 / std::f64::consts::PI),
    };
    let joint_unit = if prismatic { "m" } else { "rad" };
    let room = (j.upper - c).min(c - j.lower);
    let fits = match room >= 0.0 {
        true => format!(
            "an amplitude of at most {} {unit} fits about its centre {} {joint_unit}",
            shortest(room * to_option),
            shortest(c)
        ),
        false => format!("its centre {} {joint_unit} is itself outside them", shortest(c)),
    };
    let half_range = 0.5 * (j.upper - j.lower);
    let mid = match c == 0.0 && half_range.is_finite() && half_range >= a {
        true => "; the zero pose is the cause: `center` mid waves about the middle of each range",
        false => "",
    };
    Error::option(
        field,
        format!(
            "joint J{} ({}) would be commanded to {} {joint_unit} at t = {} s, beyond its limits [{}, {}] {joint_unit}{} (amplitude {} {unit}): {fits}{mid}",
            i + 1,
            j.name,
            shortest(q),
            shortest(t),
            shortest(j.lower),
            shortest(j.upper),
            model.mimic_note(i),
            shortest(a * to_option),
        ),
    )
}
