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

use std::fmt;
use std::sync::Arc;

use nalgebra::DMatrix;

use super::{MeshSource, SelfContact};
use crate::algo::{Data, crba};
use crate::control::{Gains, JointMotor, Motor, Pd, Stability, auto_tune, stabilize};
use crate::error::{Error, Result, shortest};
use crate::faze4;
use crate::geometry::{self, ClearanceGeometry, CollisionSet, GeometryModel, PairFilter};
use crate::ik::{IkTask, solve_path};
use crate::model::{FrameId, JointId, LoadWarning, Model};
use crate::spatial::Vec3;
use crate::traj::shape::{Board, Shape};
use crate::traj::{Interpolated, Trajectory, Wrap};

use super::{Thresholds, steps_per_record};

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
    /// `--motors`: per joint the motor whose envelope clips its torque at its speed (`None`
    /// for a joint without one: the constant limit alone); `None`: no motors, the constant
    /// limits of the controller.
    pub motors: Option<Vec<Option<Motor>>>,
}

/// Something a scenario runs with that the user should know about; the builder returns these
/// instead of printing them.
#[derive(Clone, Debug, PartialEq)]
pub enum Warning {
    /// The model gives no torque limit for these joints (by name): their torque is not clipped.
    UnlimitedEffort {
        /// The model's source (file).
        source: String,
        /// The joints without a limit.
        joints: Vec<String>,
    },
    /// The gains make the linearised loop unstable about the start pose (ρ not below 1); the
    /// run goes ahead.
    UnstableGains {
        /// The loop's figures with these gains.
        stability: Stability,
        /// Whether the gains were given (`--kp`/`--kd`) rather than tuned.
        given: bool,
    },
    /// Part of the collision geometry is left out of the clearance (a mesh not found).
    Clearance(geometry::Warning),
    /// Reading the model skipped or changed something (a transmission, an inertia).
    Model(LoadWarning),
}

impl Warning {
    /// Whether the run's result differs from what the input says because of it (a mesh left
    /// out, a transmission skipped, an inertia balanced): such a warning is printed even under
    /// `-q`.
    pub fn changes_result(&self) -> bool {
        matches!(self, Warning::Clearance(_) | Warning::Model(_))
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::UnlimitedEffort { source, joints } => write!(
                f,
                "{source} gives no effort limit for {}: their torque is not clipped (set --effort)",
                joints
                    .iter()
                    .map(|j| crate::error::quoted(j))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Warning::UnstableGains { stability: s, given } => write!(
                f,
                "warning: with the {} gains the linearised loop's spectral radius is {:.3} (not below 1: unstable about the start pose; b_max = {:.3}, b_kd = {:.3}); running anyway",
                if *given { "given --kp/--kd" } else { "tuned" },
                s.spectral_radius,
                s.b_max,
                s.b_kd
            ),
            Warning::Clearance(w) => write!(f, "warning: {w}"),
            Warning::Model(w) => write!(f, "warning: {w}"),
        }
    }
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

impl ShapeRun {
    /// Plans a shape on the Faze4's board: `points` targets along `shape`, their exact IK for
    /// the origin of frame `tool`, and the joint samples as a closed loop every
    /// [`faze4::SHAPE_PERIOD`]. On a Faze4 model the IK moves J1, J2, J3 and J5 from
    /// [`faze4::Q_SEED`] (J4 = J6 = 0); on any other arm every joint is free, from the zero pose
    /// clamped into the limits. Returns the joint command and the drawing part of the run.
    pub fn plan(model: &Model, tool: FrameId, shape: Shape, points: usize) -> Result<(Trajectory, ShapeRun)> {
        if points < 3 {
            return Err(Error::argument(
                "--shape-points",
                format!("{points} samples cannot make a closed path: at least 3"),
            ));
        }
        let (free, seed): (Vec<JointId>, Vec<f64>) = if faze4::is_faze4(model) {
            (faze4::SHAPE_FREE_JOINTS.to_vec(), faze4::Q_SEED.to_vec())
        } else {
            let seed = model.joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)).collect();
            (JointId::all(model.dof()).collect(), seed)
        };
        let task = IkTask::new(model, tool, &free)?;
        let targets = shape.targets(points, &faze4::BOARD);
        let ik = solve_path(model, &task, &targets, &seed)?;
        let rows: Vec<Vec<f64>> = targets.iter().map(|p| vec![p.x, p.y, p.z]).collect();
        let run = ShapeRun {
            board: faze4::BOARD,
            target: Interpolated::new(&rows, faze4::SHAPE_PERIOD, Wrap::Closed),
            reference: targets,
            ik_max_residual_m: ik.max_residual_m,
        };
        let trajectory = Trajectory::Interpolated(Interpolated::new(&ik.q, faze4::SHAPE_PERIOD, Wrap::Closed));
        Ok((trajectory, run))
    }
}

impl Scenario {
    /// A builder for a run of `model` following `trajectory`, with the defaults: Δt 2e-4 s,
    /// 8 s, gravity and its feed-forward on, no payload, the tuned gains, the model's torque
    /// limits (the Faze4's motor limits for a Faze4 model), the model's default tool frame.
    pub fn builder(model: Model, trajectory: Trajectory) -> ScenarioBuilder {
        ScenarioBuilder {
            geometry: GeometryModel::default(),
            load_warnings: Vec::new(),
            collisions: Some(Collisions::default()),
            collision_set: None,
            clearance_tolerance: DEFAULT_CLEARANCE_TOLERANCE_M,
            command: String::from(match trajectory {
                Trajectory::Wave(_) => "wave",
                Trajectory::Interpolated(_) => "replay",
            }),
            model,
            trajectory,
            dt: DEFAULT_DT,
            duration: DEFAULT_DURATION,
            record_period: DEFAULT_RECORD_PERIOD,
            payload_kg: 0.0,
            gravity: true,
            feedforward: true,
            tool_frame: None,
            effort: None,
            kp: Vec::new(),
            kd: Vec::new(),
            max_speed: Vec::new(),
            shape: None,
            thresholds: Thresholds::default(),
            self_contact: None,
            motors: None,
        }
    }
}

/// Builds a [`Scenario`]; see [`Scenario::builder`]. Every setter takes the value as given;
/// [`ScenarioBuilder::build`] checks them all, each error naming the command-line option of the
/// same meaning (`--dt`, `--payload-kg`, …).
#[derive(Clone, Debug)]
pub struct ScenarioBuilder {
    command: String,
    model: Model,
    geometry: GeometryModel,
    load_warnings: Vec<LoadWarning>,
    collisions: Option<Collisions>,
    collision_set: Option<Arc<CollisionSet>>,
    clearance_tolerance: f64,
    trajectory: Trajectory,
    dt: f64,
    duration: f64,
    record_period: f64,
    payload_kg: f64,
    gravity: bool,
    feedforward: bool,
    tool_frame: Option<FrameId>,
    effort: Option<Vec<f64>>,
    kp: Vec<Option<f64>>,
    kd: Vec<Option<f64>>,
    max_speed: Vec<Option<f64>>,
    shape: Option<ShapeRun>,
    thresholds: Thresholds,
    self_contact: Option<SelfContact>,
    motors: Option<Vec<Option<JointMotor>>>,
}

impl ScenarioBuilder {
    /// The model as given (before the payload, the motors and the gravity setting apply).
    pub fn model(&self) -> &Model {
        &self.model
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
    /// samples (`--clearance-tolerance`, in mm there): it is the distance of two actual parts,
    /// and the true minimum is at most this much below it; 0 is exact. Intersections are
    /// decided exactly whatever it is. Default [`DEFAULT_CLEARANCE_TOLERANCE_M`].
    pub fn clearance_tolerance(mut self, tolerance: f64) -> Self {
        self.clearance_tolerance = tolerance;
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

    /// Whether the gravity field is on (default) or off (`--no-gravity`).
    pub fn gravity(mut self, on: bool) -> Self {
        self.gravity = on;
        self
    }

    /// Whether the controller adds g(q) to its torque (default) or not (`--no-ff`).
    pub fn feedforward(mut self, on: bool) -> Self {
        self.feedforward = on;
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
    /// keeps the model's). An empty vector keeps them all. The model's are the URDF's
    /// `velocity`, except on the bundled Faze4, whose URDF gives every joint a placeholder 3.0:
    /// it has none unless given. Limits are counted (`velocity_limit_pct`), not enforced.
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

    /// A motor per joint (`--motors`; `None` for a joint without one): its ratio and rotor
    /// inertia, where given, replace the model's; its envelope clips the joint's torque at the
    /// joint's speed, every step; the constant limit E of a motored joint becomes
    /// ratio × η × the motor's largest torque unless [`ScenarioBuilder::effort`] gives it.
    pub fn motors(mut self, motors: Vec<Option<JointMotor>>) -> Self {
        self.motors = Some(motors);
        self
    }

    /// Contact forces between the checked pairs of the collision geometry given by
    /// [`ScenarioBuilder::geometry`] (`--self-collisions`; off by default).
    pub fn self_contact(mut self, contact: SelfContact) -> Self {
        self.self_contact = Some(contact);
        self
    }

    /// Checks everything, applies gravity and the payload, tunes the controller at the start
    /// pose, and returns the scenario with its warnings.
    pub fn build(self) -> Result<Scenario> {
        positive("--dt", self.dt)?;
        positive("--duration", self.duration)?;
        positive("--record-period", self.record_period)?;
        non_negative("--max-saturation-pct", self.thresholds.max_saturation_pct)?;
        non_negative("--max-error", self.thresholds.max_error)?;
        non_negative("--max-deviation-mm", self.thresholds.max_deviation_mm)?;
        non_negative("--payload-kg", self.payload_kg)?;
        non_negative("--clearance-tolerance", self.clearance_tolerance)?;
        if let Some(contact) = &self.self_contact {
            non_negative("--friction", contact.friction)?;
            if contact.friction > MAX_FRICTION {
                return Err(Error::argument(
                    "--friction",
                    format!(
                        "{}: at most {MAX_FRICTION:e}: beyond it the contact solver's arithmetic overflows (any μ above about 1e10 already sticks)",
                        shortest(contact.friction)
                    ),
                ));
            }
            positive("--self-collisions: stiffness", contact.stiffness)?;
            non_negative("--self-collisions: dissipation", contact.dissipation)?;
            if self.collisions.is_none() {
                return Err(Error::argument(
                    "--self-collisions",
                    "needs the collision geometry: not with --no-collisions",
                ));
            }
        }
        let mut model = self.model;
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
            return Err(Error::argument(
                "--tool-link",
                format!(
                    "frame index {} out of range ({} frames)",
                    tool_frame.0,
                    model.frames.len()
                ),
            ));
        }
        let motors = match self.motors {
            Some(motors) => Some(fit_motors(&mut model, motors)?),
            None => None,
        };
        let steps = steps(self.duration, self.dt)?;
        check_wave_limits(&model, &self.trajectory, self.dt, steps)?;
        if !self.gravity {
            model.gravity = Default::default();
        }
        // the arm without its payload, kept only to say which input overflows
        let bare = (self.payload_kg > 0.0).then(|| model.clone());
        if self.payload_kg > 0.0 {
            model = model.with_point_mass(tool_frame, self.payload_kg);
        }

        let mut warnings: Vec<Warning> = self.load_warnings.iter().cloned().map(Warning::Model).collect();
        let explicit_effort = self.effort.is_some();
        let effort = match self.effort {
            Some(effort) => {
                count("--effort", effort.len(), n)?;
                if let Some((i, x)) = effort.iter().enumerate().find(|(_, x)| x.is_nan() || **x <= 0.0) {
                    return Err(Error::argument(
                        "--effort",
                        format!("J{} limit {} must be > 0", i + 1, shortest(*x)),
                    ));
                }
                effort
            }
            None if faze4::is_faze4(&model) => default_effort(&model),
            None => {
                let unlimited: Vec<String> = (model.joints.iter())
                    .filter(|j| j.effort.is_none())
                    .map(|j| j.name.clone())
                    .collect();
                if !unlimited.is_empty() {
                    warnings.push(Warning::UnlimitedEffort {
                        source: model.source.clone(),
                        joints: unlimited,
                    });
                }
                default_effort(&model)
            }
        };

        let effort = match (&motors, explicit_effort) {
            (Some(motors), false) => (effort.iter().zip(motors).zip(&model.joints))
                .map(|((&e, m), j)| m.as_ref().map_or(e, |m| m.joint_limit(j.gear_ratio)))
                .collect(),
            _ => effort,
        };
        let (mut gains, m) = tune(&model, &self.trajectory, &effort, self.dt);
        override_gains("--kp", &mut gains.kp, &self.kp)?;
        override_gains("--kd", &mut gains.kd, &self.kd)?;
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
            return Err(overflow(
                &model,
                bare.as_ref(),
                self.payload_kg,
                &self.trajectory,
                &effort,
                self.dt,
            ));
        }
        if let Some(stability) = gains.stability.filter(|s| !s.is_stable()) {
            warnings.push(Warning::UnstableGains { stability, given });
        }
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
            motors,
        })
    }
}

/// The motors' ratios and rotors onto `model`, each checked; the motors themselves, checked.
fn fit_motors(model: &mut Model, motors: Vec<Option<JointMotor>>) -> Result<Vec<Option<Motor>>> {
    count("--motors", motors.len(), model.dof())?;
    let bad = |i: usize, what: String| Error::argument("--motors", format!("J{} {what}", i + 1));
    let mut out = Vec::with_capacity(motors.len());
    for (i, (m, joint)) in motors.into_iter().zip(model.joints.iter_mut()).enumerate() {
        let Some(m) = m else {
            out.push(None);
            continue;
        };
        if let Some(r) = m.gear_ratio {
            if !(r.is_finite() && r > 0.0) {
                return Err(bad(i, format!("gear_ratio {r} must be > 0")));
            }
            joint.gear_ratio = r;
        }
        if let Some(inertia) = m.rotor_inertia {
            if !(inertia.is_finite() && inertia >= 0.0) {
                return Err(bad(i, format!("rotor_inertia {inertia} must be ≥ 0")));
            }
            joint.rotor_inertia = inertia;
        }
        m.motor.check().map_err(|e| bad(i, e))?;
        out.push(Some(m.motor));
    }
    Ok(out)
}

/// Largest Coulomb friction `--friction` takes. The contact step's products of μ overflow
/// between 1e150 and 1e200 (μ = 1e200 gave the frictionless result); every μ from about 1e10
/// gave the same sticking run as 1e100 (the circle shape with `--self-collisions`).
pub const MAX_FRICTION: f64 = 1e100;

/// Whether the mass matrix at the start pose, the gains and their stability figures are all
/// finite: inputs too large for f64 (a payload of 1e300 kg, a gear ratio of 1e160) make one of
/// them overflow, and the run would end as "diverged" with a NaN spectral radius.
pub fn arithmetic_holds(m: &DMatrix<f64>, gains: &Gains) -> bool {
    m.iter().chain(&gains.kp).chain(&gains.kd).all(|x| x.is_finite())
        && gains
            .stability
            .is_none_or(|s| s.b_max.is_finite() && s.spectral_radius.is_finite())
}

/// The error of a scenario whose arithmetic overflows: the payload's (`--payload-kg`) when the
/// arm without it (`bare`) holds, else the model's joint of largest inertia.
fn overflow(
    model: &Model,
    bare: Option<&Model>,
    payload_kg: f64,
    trajectory: &Trajectory,
    effort: &[f64],
    dt: f64,
) -> Error {
    let holds = |m: &Model| {
        let (gains, mass) = tune(m, trajectory, effort, dt);
        arithmetic_holds(&mass, &gains)
    };
    if bare.is_some_and(holds) {
        return Error::argument(
            "--payload-kg",
            format!(
                "{} kg: too heavy to simulate (the mass matrix and the gains tuned for it overflow)",
                shortest(payload_kg)
            ),
        );
    }
    let model = bare.unwrap_or(model);
    let n = model.dof();
    let mut q = vec![0.0; n];
    trajectory.eval(0.0, &mut q, &mut vec![0.0; n]);
    let m = crba(model, &mut Data::new(model), &q).clone();
    let joint = (0..n)
        .max_by(|&a, &b| m[(a, a)].abs().total_cmp(&m[(b, b)].abs()))
        .map_or(String::new(), |i| {
            format!("joint {}", crate::error::quoted(&model.joints[i].name))
        });
    Error::model(
        &model.source,
        joint,
        "its masses, rotor inertia or gear ratio are too large to simulate: the mass matrix and the gains tuned for it overflow (check the URDF, --rotor-inertia, --gear-ratio)",
    )
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

/// The tuning recipe: the effective inertia I_i = M_ii at the command's start pose, then
/// The torque limits a run on `model` has when none are given: the Faze4 motors' for the
/// bundled arm, else each joint's URDF effort (infinite where it has none).
pub fn default_effort(model: &Model) -> Vec<f64> {
    match faze4::is_faze4(model) {
        true => faze4::EFFORT.to_vec(),
        false => model.joints.iter().map(|j| j.effort.unwrap_or(f64::INFINITY)).collect(),
    }
}

/// [`auto_tune`] with the torque limits `effort` at step `dt`, then [`stabilize`] for the
/// coupled arm (the gains then carry their `stability`). Returns the gains and M(q_start).
pub fn tune(model: &Model, trajectory: &Trajectory, effort: &[f64], dt: f64) -> (Gains, DMatrix<f64>) {
    let n = model.dof();
    let (mut q0, mut v0) = (vec![0.0; n], vec![0.0; n]);
    trajectory.eval(0.0, &mut q0, &mut v0);
    let mut data = Data::new(model);
    let m = crba(model, &mut data, &q0).clone();
    let inertia: Vec<f64> = m.diagonal().iter().copied().collect();
    let damping: Vec<f64> = model.damping().collect();
    let mut gains = auto_tune(&inertia, effort, dt);
    stabilize(&mut gains, &m, &damping, dt);
    (gains, m)
}

/// Speed limits: `given` where it has a value (> 0); elsewhere the URDF's `velocity`, except on
/// the Faze4, whose URDF gives every joint the same `velocity="3.0"`, a placeholder rather than
/// a motor's figure: it has none unless given.
fn speed_limits(model: &Model, given: &[Option<f64>]) -> Result<Vec<f64>> {
    let mut limits: Vec<f64> = match faze4::is_faze4(model) {
        true => vec![f64::INFINITY; model.dof()],
        false => (model.joints.iter())
            .map(|j| j.velocity.unwrap_or(f64::INFINITY))
            .collect(),
    };
    override_per_joint("--max-speed", &mut limits, given, |v| v > 0.0, "> 0")?;
    Ok(limits)
}

/// Gains given per joint (finite and ≥ 0) over the tuned ones.
fn override_gains(option: &str, gains: &mut [f64], values: &[Option<f64>]) -> Result<()> {
    override_per_joint(option, gains, values, |v| v.is_finite() && v >= 0.0, "finite and ≥ 0")
}

/// Each joint's value that `values` gives replaces its entry of `target` (`None` keeps it; an
/// empty `values` keeps them all), if `valid`; otherwise an error for `option` saying the value
/// must be `rule`. `values` must have one entry per entry of `target`.
pub(crate) fn override_per_joint(
    option: &str,
    target: &mut [f64],
    values: &[Option<f64>],
    valid: impl Fn(f64) -> bool,
    rule: &str,
) -> Result<()> {
    if values.is_empty() {
        return Ok(());
    }
    count(option, values.len(), target.len())?;
    for (i, v) in values.iter().enumerate() {
        if let Some(v) = *v {
            if !valid(v) {
                return Err(Error::argument(option, format!("J{} value {v} must be {rule}", i + 1)));
            }
            target[i] = v;
        }
    }
    Ok(())
}

/// `given` values for a model of `n` joints, else an error for `option`.
pub(crate) fn count(option: &str, given: usize, n: usize) -> Result<()> {
    if given != n {
        return Err(Error::argument(
            option,
            format!("{given} values given; the model has {n} joints"),
        ));
    }
    Ok(())
}

/// Number of steps for `duration` at `dt` (at least one).
fn steps(duration: f64, dt: f64) -> Result<usize> {
    let steps = (duration / dt).round();
    if steps < 1.0 {
        return Err(Error::argument(
            "--duration",
            format!("{duration} s is shorter than one step of --dt {dt} s"),
        ));
    }
    if steps > 1e12 {
        return Err(Error::argument(
            "--duration",
            format!("{duration} s at --dt {dt} s is {steps:e} steps: too many"),
        ));
    }
    Ok(steps as usize)
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
    let (option, unit, to_option) = match prismatic {
        true => ("--amp-m", "m", 1.0),
        false => ("--amp-deg", "deg", 180.0 / std::f64::consts::PI),
    };
    let joint_unit = if prismatic { "m" } else { "rad" };
    let room = (j.upper - c).min(c - j.lower);
    let fits = match room >= 0.0 {
        true => format!(
            "an amplitude of at most {} {unit} fits about its centre {c} {joint_unit}",
            room * to_option
        ),
        false => format!("its centre {c} {joint_unit} is itself outside them"),
    };
    let half_range = 0.5 * (j.upper - j.lower);
    let mid = match c == 0.0 && half_range.is_finite() && half_range >= a {
        true => "; the zero pose is the cause: --center mid waves about the middle of each range",
        false => "",
    };
    Error::argument(
        option,
        format!(
            "joint J{} ({}) would be commanded to {q} {joint_unit} at t = {t} s, beyond its limits [{}, {}] {joint_unit}{} (amplitude {} {unit}): {fits}{mid}",
            i + 1,
            j.name,
            j.lower,
            j.upper,
            model.mimic_note(i),
            a * to_option,
        ),
    )
}

/// `x` is a finite number, else an error for `option`.
pub(crate) fn finite(option: &str, x: f64) -> Result<()> {
    if !x.is_finite() {
        return Err(Error::argument(
            option,
            format!("{} is not a finite number", shortest(x)),
        ));
    }
    Ok(())
}

/// `x` is finite and > 0, else an error for `option`.
pub(crate) fn positive(option: &str, x: f64) -> Result<()> {
    finite(option, x)?;
    if x <= 0.0 {
        return Err(Error::argument(option, format!("{} must be > 0", shortest(x))));
    }
    Ok(())
}

/// `x` is finite and ≥ 0, else an error for `option`.
pub(crate) fn non_negative(option: &str, x: f64) -> Result<()> {
    finite(option, x)?;
    if x < 0.0 {
        return Err(Error::argument(option, format!("{} must be ≥ 0", shortest(x))));
    }
    Ok(())
}
