//! A configuration with what it reads once: the arm, a replay's frames, a shape's plan and the
//! collision set. Each run of it (one, or the many of a sweep, each with its own numbers) is a
//! [`Scenario`] built on them by [`Loaded::scenario`].

use std::borrow::Cow;
use std::path::Path;
use std::sync::Arc;

use super::arm::{Arm, fit_motors, load_arm};
use super::motors::Motors;
use super::{ArmConfig, Center, Motion, ReplayConfig, RetimeConfig, RunConfig};
use crate::atomic::Inputs;
use crate::error::{Error, Result, quoted, shortest};
use crate::geometry::CollisionSet;
use crate::model::{JointKind, Model};
use crate::retime::{PathSpline, hold};
use crate::sim::check::{finite, non_negative, positive};
use crate::sim::{Collisions, Play, Scenario, ScenarioBuilder, SelfContact, TimedCommand, Warning, load_collisions};
use crate::traj::files::{self, Content, Selection};
use crate::traj::{Interpolated, ShapeRun, TimedTrajectory, Trajectory, Wave, Wrap, shape};

/// What a replay plays: a `.npy`'s evenly spaced frames (N×dof), or a time-stamped trajectory.
#[derive(Clone, Debug)]
pub enum Replayed {
    /// Frames played at even spacing over `traj_period`, repeating.
    Samples(Vec<Vec<f64>>),
    /// Points at their own times, played once as ros2_control plays them.
    Timed(TimedTrajectory),
}

/// A run configuration's inputs, read once.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The arm as its file gives it, before the motors (a run that gives other motors or
    /// supply voltage fits them to this).
    bare: Arm,
    /// The arm with the configuration's motors.
    arm: Arm,
    /// The configuration's arm options, as loaded.
    arm_config: ArmConfig,
    /// The collision set every run measures its self-clearance with.
    collision_set: Option<Arc<CollisionSet>>,
    /// What a replay plays.
    replay: Option<Replayed>,
    /// What reading the replayed file said ([`files::Opened`]).
    read: ReadNotes,
    /// A shape's plan and the number of samples it was made with.
    plan: Option<(usize, (Trajectory, ShapeRun))>,
    /// What loading found that changes the result (collision meshes not found): said once,
    /// after the first run's own warnings.
    pub warnings: Vec<Warning>,
    /// The files read, which no output of a run may replace.
    inputs: Inputs,
}

impl Loaded {
    /// Checks `config`'s numbers, then reads its arm (and motors), what a replay plays (its
    /// `q_traj` file, unless `replayed` gives it), a shape's plan and the collision meshes.
    pub fn load(config: &RunConfig, replayed: Option<Replayed>) -> Result<Loaded> {
        check(config)?;
        let bare = load_arm(&ArmConfig {
            motors: None,
            supply_voltage: None,
            gear_ratio: Vec::new(),
            rotor_inertia: Vec::new(),
            ..config.arm.clone()
        })?;
        let arm = fitted(&bare, &config.arm)?;
        let replay_read = replayed.is_none();
        let model = &arm.robot.model;
        let (replay, read) = match (&config.motion, replayed) {
            (Motion::Replay(r) | Motion::Retime(RetimeConfig { path: r, .. }), Some(given)) => {
                let given = match given {
                    // arrays' names are renamed as a file's
                    Replayed::Timed(mut t) => {
                        files::reading::rename(&mut t, &r.rename, &r.q_traj)?;
                        Replayed::Timed(t)
                    }
                    samples => samples,
                };
                (Some(given), ReadNotes::default())
            }
            (Motion::Replay(r), None) => read_replay(r, model).map(|(r, read)| (Some(r), read))?,
            (Motion::Retime(r), None) => read_replay(&r.path, model).map(|(r, read)| (Some(r), read))?,
            _ => (None, ReadNotes::default()),
        };
        let plan = match &config.motion {
            Motion::Shape(s) => Some((s.shape_points, plan(&arm, s.shape, s.shape_points)?)),
            _ => None,
        };
        let mut warnings = Vec::new();
        let (_, collision_set) = load_collisions(
            &arm.robot.model,
            arm.robot.geometry.clone(),
            collisions(config),
            &mut warnings,
        )?;
        let inputs = inputs(config, &arm, replay_read);
        Ok(Loaded {
            bare,
            arm,
            arm_config: config.arm.clone(),
            collision_set,
            replay,
            read,
            plan,
            warnings,
            inputs,
        })
    }

    /// The banner's name of `command` (`replay`), with what its file is where its name does not
    /// say (`replay of a ROS 1 bag, topic /joint_states`).
    fn command(&self, command: &str) -> String {
        match &self.read.what {
            Some(what) => format!("{command} of {what}"),
            None => command.to_string(),
        }
    }

    /// `error` with the read's limit hint when it is a joint-limit refusal.
    fn with_limit_hint(&self, error: Error) -> Error {
        match (error, &self.read.limit_hint) {
            (Error::InvalidData { path, message }, Some(hint)) if message.contains("beyond its limits") => {
                Error::InvalidData {
                    path,
                    message: format!("{message}{hint}"),
                }
            }
            (error, _) => error,
        }
    }

    /// The arm, with the loaded configuration's motors.
    pub fn arm(&self) -> &Arm {
        &self.arm
    }

    /// The points of a retime's path (or a replay's frames) over `model`'s joints, in its
    /// order: a `.npy`'s rows, or a time-stamped trajectory's positions (its joints matched by
    /// name, a joint it does not name held as replay holds it), its times ignored.
    pub fn path_points(&self, model: &Model, source: &Path) -> Result<Vec<Vec<f64>>> {
        match &self.replay {
            Some(Replayed::Samples(frames)) => Ok(frames.clone()),
            Some(Replayed::Timed(timed)) => {
                let names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
                let hold: Vec<f64> = model.joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)).collect();
                let (ordered, _) = timed.in_joint_order(&names, &hold, source)?;
                Ok(ordered.points.into_iter().map(|p| p.positions).collect())
            }
            None => Err(Error::option("q_traj", "no trajectory was loaded")),
        }
    }

    /// The own timing of what a replay or retime read (s): a time-stamped trajectory's last
    /// time, a `.npy`'s `traj_period`.
    pub fn own_duration(&self, traj_period: f64) -> Option<f64> {
        match &self.replay {
            Some(Replayed::Timed(timed)) => Some(timed.duration()),
            Some(Replayed::Samples(_)) => Some(traj_period),
            None => None,
        }
    }

    /// The files loading read (the URDF, its meshes, the motors file, the replayed
    /// trajectory), which no output of a run of this configuration may replace.
    pub fn inputs(&self) -> &Inputs {
        &self.inputs
    }

    /// The scenario of `config` on what was loaded: `config` is the loaded one, or the same
    /// with other numbers (a sweep's point: durations, periods, the payload, limits, a shape's
    /// samples, the motors' supply voltage); another arm file is refused.
    pub fn scenario(&self, config: &RunConfig) -> Result<Scenario> {
        self.builder(config)?.build()
    }

    /// The builder of [`Loaded::scenario`], for a command that builds several runs on it
    /// (`retime` plays each timing it tries on it): the arm for `config`
    /// (`arm_for`), its command (`command_of`), then every setting.
    pub fn builder(&self, config: &RunConfig) -> Result<ScenarioBuilder> {
        check(config)?;
        let arm = self.arm_for(config)?;
        let Command {
            trajectory,
            name,
            shape,
            duration,
            warnings,
        } = self.command_of(config, &arm)?;
        let control = &config.control;
        let clearance = &config.clearance;
        let mut builder = Scenario::builder(arm.robot.model.clone(), trajectory)
            .command(name)
            .geometry(arm.robot.geometry.clone())
            .load_warnings(arm.robot.warnings.clone())
            .tool_frame(arm.tool)
            .command_warnings(warnings)
            .dt(control.dt)
            .duration(duration.unwrap_or(config.motion.default_duration()))
            .record_period(config.record_period)
            .payload_kg(config.arm.payload_kg)
            .gravity(!config.arm.no_gravity)
            .feedforward(config.feedforward()?)
            .drive(config.drive(arm.robot.model.dof())?)
            .collisions(collisions(config))
            .clearance_tolerance(clearance.clearance_tolerance * 1e-3)
            .thresholds(config.verdict.thresholds)
            .kp(control.kp.clone())
            .kd(control.kd.clone())
            .max_speed(control.max_speed.clone());
        if let Some(set) = &self.collision_set {
            builder = builder.collision_set(set.clone());
        }
        if clearance.self_collisions {
            builder = builder.self_contact(SelfContact {
                friction: clearance.friction,
                ..SelfContact::default()
            });
        }
        if let Some(effort) = &control.effort {
            builder = builder.effort(effort.clone());
        }
        if let Some(motors) = &arm.motors {
            builder = builder.motors(motors.clone());
        }
        if let Some(run) = shape {
            builder = builder.shape(run);
        }
        Ok(builder)
    }

    /// The arm a run of `config` uses: the loaded one, or, for other motors, ratios, rotors or
    /// supply voltage, the bare arm fitted with them; another arm file or tool link is
    /// refused.
    fn arm_for(&self, config: &RunConfig) -> Result<Cow<'_, Arm>> {
        if config.arm == self.arm_config {
            return Ok(Cow::Borrowed(&self.arm));
        }
        let file = |a: &ArmConfig| {
            (
                a.robot.clone(),
                a.xacro_arg.clone(),
                a.package_path.clone(),
                a.balance_inertia,
                a.tool_link.clone(),
            )
        };
        if file(&config.arm) != file(&self.arm_config) {
            return Err(Error::option(
                "robot",
                "the arm was loaded from another file or tool link",
            ));
        }
        Ok(Cow::Owned(fitted(&self.bare, &config.arm)?))
    }

    /// What `config`'s motion commands on `arm`: a wave, a replay (its frames, or its
    /// time-stamped trajectory: [`Loaded::timed_replay`]), a retime's held start, or a shape's
    /// plan (the loaded one when its samples are the same).
    fn command_of(&self, config: &RunConfig, arm: &Arm) -> Result<Command> {
        let model = &arm.robot.model;
        let command = |trajectory, name: &str| Command {
            trajectory,
            name: name.to_string(),
            shape: None,
            duration: config.duration,
            warnings: Vec::new(),
        };
        Ok(match &config.motion {
            Motion::Wave(w) => command(
                Trajectory::Wave(Wave {
                    amplitude: wave_amplitudes(model, w.amp_deg, w.amp_m),
                    omega: w.freq,
                    center: wave_center(model, &w.center)?,
                }),
                "wave",
            ),
            Motion::Replay(r) => match &self.replay {
                Some(Replayed::Timed(timed)) => self.timed_replay(config, r, model, timed)?,
                Some(Replayed::Samples(frames)) => {
                    check_samples(model, frames, &r.q_traj)?;
                    let trajectory = Trajectory::Interpolated(Interpolated::new(frames, r.traj_period, Wrap::Repeat));
                    command(trajectory, &self.command("replay"))
                }
                None => unreachable!("a replay's trajectory is loaded"),
            },
            Motion::Retime(r) => {
                // retime plays its timings on this scenario; until then it holds the start
                let path = PathSpline::through(&self.path_points(model, &r.path.q_traj)?)?;
                command(hold(&path), "retime")
            }
            Motion::Shape(s) => {
                let (trajectory, run) = match &self.plan {
                    Some((points, planned)) if *points == s.shape_points => planned.clone(),
                    _ => plan(arm, s.shape, s.shape_points)?,
                };
                Command {
                    shape: Some(run),
                    ..command(
                        trajectory,
                        &format!("shape {} ({} points)", s.shape.name(), s.shape_points),
                    )
                }
            }
        })
    }

    /// A replay of the loaded time-stamped trajectory `timed` (`r`'s file) on `model`, played
    /// as `r` says, with what reading it said; its duration its own unless `config` gives
    /// one (a trajectory of 0 s, or one a run cannot take, then refused).
    fn timed_replay(
        &self,
        config: &RunConfig,
        r: &ReplayConfig,
        model: &Model,
        timed: &TimedTrajectory,
    ) -> Result<Command> {
        let play = Play {
            start: r.start.clone(),
            interpolation: r.interpolation,
        };
        let timed = TimedCommand::new(model, timed, &r.q_traj, &play).map_err(|e| self.with_limit_hint(e))?;
        let mut warnings = self.read.warnings.clone();
        warnings.extend(timed.warning(&r.q_traj));
        if config.duration.is_none() && timed.duration == 0.0 {
            return Err(Error::option(
                "duration",
                format!(
                    "{} lasts 0 s (one point at t = 0): give how long to hold it",
                    r.q_traj.display()
                ),
            ));
        }
        if config.duration.is_none() {
            own_duration(timed.duration, config.control.dt, &r.q_traj)?;
        }
        Ok(Command {
            trajectory: timed.trajectory,
            name: self.command("replay"),
            shape: None,
            duration: config.duration.or(Some(timed.duration)),
            warnings,
        })
    }
}

/// What a run's motion commands ([`Loaded::command_of`]).
struct Command {
    /// The joints' command.
    trajectory: Trajectory,
    /// The banner's name of it (`wave`, `replay of a ROS 1 bag, …`, `shape circle (240 points)`).
    name: String,
    /// A shape's plan, for its path deviation and views.
    shape: Option<ShapeRun>,
    /// How long the run lasts (`None`: the motion's default).
    duration: Option<f64>,
    /// What the command said before the run (a replay's reading notes).
    warnings: Vec<Warning>,
}

/// What a replay's file holds ([`files::open`]: a time-stamped trajectory, a bag, a rosbag2
/// folder, a LeRobot dataset, a `.npy`'s frames; `message`, `topic`, `episode` and the
/// LeRobot options pick from it, `rename` renames its joints, a recorded stream keeps
/// `model`'s joints), and what reading said.
fn read_replay(r: &ReplayConfig, model: &Model) -> Result<(Replayed, ReadNotes)> {
    let selection = Selection {
        message: r.message,
        topic: r.topic.clone(),
        episode: r.episode,
        lerobot_key: r.lerobot_key.clone(),
        units: r.units,
        calibration: r.calibration.clone(),
        rename: r.rename.clone(),
        joints: Some(model.joints.iter().map(|j| j.name.clone()).collect()),
        interpolation: r.interpolation,
    };
    let opened = files::open(&r.q_traj, &selection)?;
    let replayed = match opened.content {
        Content::Timed(timed) => Replayed::Timed(timed),
        Content::Samples(frames) => {
            let timed_only = [
                (!r.rename.is_empty(), "rename"),
                (r.start.is_some(), "start"),
                (r.interpolation.is_some(), "interpolation"),
            ];
            if let Some((_, field)) = timed_only.iter().find(|(given, _)| *given) {
                return Err(Error::option(
                    field,
                    "is for a time-stamped trajectory (.yaml, .json, .csv, a bag), not a .npy's frames",
                ));
            }
            Replayed::Samples(frames)
        }
    };
    let source = r.q_traj.display().to_string();
    let notes = (opened.notes.into_iter()).map(|note| Warning::Read {
        source: source.clone(),
        note,
    });
    let read = ReadNotes {
        what: opened.what,
        warnings: (opened.warnings.into_iter().map(Warning::Trajectory))
            .chain(notes)
            .collect(),
        limit_hint: opened.limit_hint,
    };
    Ok((replayed, read))
}

/// What reading a replay's file said besides its content ([`files::Opened`]).
#[derive(Clone, Debug, Default)]
struct ReadNotes {
    /// What the file is, where its name does not say.
    what: Option<String>,
    /// What reading noticed, said with each run's command warnings.
    warnings: Vec<Warning>,
    /// Said after a joint-limit refusal.
    limit_hint: Option<String>,
}

/// The files a run of `config` on `arm` reads: the URDF, the meshes its geometry found, a
/// motors file, and the trajectory file of a replay or a retime when it was read
/// (`replay_read`; Python may give the frames in memory), each named by the field that gives it.
fn inputs(config: &RunConfig, arm: &Arm, replay_read: bool) -> Inputs {
    let mut inputs = Inputs::new();
    if let Some(robot) = &config.arm.robot {
        inputs.add(robot, "`robot`");
    }
    if let Some(Motors::File(path)) = &config.arm.motors {
        inputs.add(path, "`motors`");
    }
    match (&config.motion, replay_read) {
        (Motion::Replay(r), true) => {
            inputs.add(&r.q_traj, "`q_traj`");
            if let Some(calibration) = &r.calibration {
                inputs.add(calibration, "`calibration`");
            }
        }
        (Motion::Retime(r), true) => inputs.add(&r.path.q_traj, "`q_traj`"),
        _ => {}
    }
    for (link, path) in arm.robot.geometry.mesh_files() {
        inputs.add(path, format!("the mesh of link {}", quoted(link)));
    }
    inputs
}

/// `bare` with the motors, ratios and rotors of `config` fitted to its joints.
fn fitted(bare: &Arm, config: &ArmConfig) -> Result<Arm> {
    let mut arm = bare.clone();
    arm.motors = fit_motors(&mut arm.robot.model, config)?;
    Ok(arm)
}

/// The shape's plan on the arm's board ([`shape::board`]: its maker's, else one from its
/// reach), a loop every [`shape::PERIOD`].
fn plan(arm: &Arm, which: shape::Shape, points: usize) -> Result<(Trajectory, ShapeRun)> {
    let model = &arm.robot.model;
    ShapeRun::plan(
        model,
        arm.tool,
        which,
        points,
        shape::board(model, arm.tool),
        shape::PERIOD,
    )
}

/// The clearance settings of `config` (`None`: no clearance).
fn collisions(config: &RunConfig) -> Option<Collisions> {
    let c = &config.clearance;
    (!c.no_collisions).then_some(Collisions {
        geometry: c.collision_geometry,
        pairs: c.collision_pairs,
    })
}

/// A time-stamped trajectory's last time as a run's duration (no `duration` given): one a run
/// cannot take is refused naming the file and its time, not `duration`, which was not given.
fn own_duration(last: f64, dt: f64, path: &Path) -> Result<()> {
    let Err(bad) = crate::sim::step_count(last, dt) else {
        return Ok(());
    };
    let why = match bad {
        crate::sim::BadSteps::TooFew => format!(
            "shorter than one step of `dt` ({} s): give `duration` to hold its last point longer",
            shortest(dt)
        ),
        crate::sim::BadSteps::TooMany => format!(
            "more than the 10^12 steps of `dt` ({} s) a run may take: are its times seconds from its start? (`duration` runs a part of it)",
            shortest(dt)
        ),
    };
    Err(Error::InvalidData {
        path: path.to_path_buf(),
        message: format!("its points end {} s after it starts, {why}", shortest(last)),
    })
}

/// The numbers of `config` that need no model, each checked naming its field: a bad one is
/// reported before any file is read.
fn check(config: &RunConfig) -> Result<()> {
    positive("dt", config.control.dt)?;
    positive("record_period", config.record_period)?;
    if let Some(d) = config.duration {
        positive("duration", d)?;
    }
    non_negative("payload_kg", config.arm.payload_kg)?;
    non_negative("clearance_tolerance", config.clearance.clearance_tolerance)?;
    config.verdict.thresholds.check()?;
    if let Some(p) = config.outputs.print_period {
        positive("print_period", p)?;
    }
    SelfContact {
        friction: config.clearance.friction,
        ..SelfContact::default()
    }
    .check()?;
    match &config.motion {
        Motion::Wave(w) => {
            finite("freq", w.freq)?;
            // the step must sample the wave: less than half a turn per step (ω·Δt ≤ π)
            if w.freq.abs() * config.control.dt > std::f64::consts::PI {
                return Err(Error::option(
                    "freq",
                    format!(
                        "{} rad/s turns the wave more than half a period per step of `dt` {} s (ω·Δt > π): the steps cannot sample it; lower `freq` or `dt`",
                        shortest(w.freq),
                        shortest(config.control.dt)
                    ),
                ));
            }
            if let Some(a) = w.amp_m {
                non_negative("amp_m", a)?;
            }
            non_negative("amp_deg", w.amp_deg)
        }
        Motion::Replay(r) => {
            positive("traj_period", r.traj_period)?;
            // a period shorter than a step plays frames between the steps, never at them
            match r.traj_period < config.control.dt {
                true => Err(Error::option(
                    "traj_period",
                    format!(
                        "{} s is shorter than one step of `dt` {} s: the steps cannot play the frames",
                        shortest(r.traj_period),
                        shortest(config.control.dt)
                    ),
                )),
                false => Ok(()),
            }
        }
        Motion::Shape(_) => Ok(()),
        Motion::Retime(r) => {
            positive("traj_period", r.path.traj_period)?;
            r.options(crate::sim::StopFlag::new()).check()
        }
    }
}

/// Each joint's wave amplitude in its own unit: `amp_deg` in radians for a revolute or
/// continuous joint; for a prismatic one `amp_m`, else a quarter of its range where both
/// limits are finite, else [`super::DEFAULT_AMP_M`] (docs/model.md, 4.1).
pub fn wave_amplitudes(model: &Model, amp_deg: f64, amp_m: Option<f64>) -> Vec<f64> {
    (model.joints.iter())
        .map(|j| match j.kind {
            JointKind::Prismatic => amp_m.unwrap_or(match (j.lower.is_finite(), j.upper.is_finite()) {
                (true, true) => 0.25 * (j.upper - j.lower),
                _ => super::DEFAULT_AMP_M,
            }),
            _ => amp_deg.to_radians(),
        })
        .collect()
}

/// The pose `center` names on `model`, each value inside its joint's limits.
pub fn wave_center(model: &Model, center: &Center) -> Result<Vec<f64>> {
    let n = model.dof();
    let center: Vec<f64> = match center {
        Center::Zero => return Ok(vec![0.0; n]),
        Center::Mid => (model.joints.iter())
            .map(|j| match (j.lower.is_finite(), j.upper.is_finite()) {
                (true, true) => 0.5 * (j.lower + j.upper),
                (true, false) => j.lower,
                (false, true) => j.upper,
                (false, false) => 0.0,
            })
            .collect(),
        Center::Given(values) => values.clone(),
        Center::Home => model.home.clone().ok_or_else(|| {
            Error::option(
                "center",
                format!(
                    "'home': {} offers no start pose (an MJCF model's keyframe named home)",
                    model.source
                ),
            )
        })?,
    };
    if center.len() != n {
        return Err(Error::option(
            "center",
            format!("{} values given; the model has {n} joints", center.len()),
        ));
    }
    for (i, (j, &c)) in model.joints.iter().zip(&center).enumerate() {
        if !c.is_finite() {
            return Err(Error::option(
                "center",
                format!("J{} value {} is not a finite number (or use 'mid')", i + 1, shortest(c)),
            ));
        }
        if !j.within_limits(c) {
            return Err(Error::option(
                "center",
                format!(
                    "J{} ({}) {} is outside its limits [{}, {}]{}",
                    i + 1,
                    j.name,
                    shortest(c),
                    shortest(j.lower),
                    shortest(j.upper),
                    model.mimic_note(i)
                ),
            ));
        }
    }
    Ok(center)
}

/// Joint samples (replay frames) must fit the model and its limits.
pub fn check_samples(model: &Model, frames: &[Vec<f64>], path: &Path) -> Result<()> {
    let bad = |message: String| Error::InvalidData {
        path: path.to_path_buf(),
        message,
    };
    let n = model.dof();
    if frames.len() < 2 {
        return Err(bad(format!(
            "has {} frames; a trajectory needs at least 2",
            frames.len()
        )));
    }
    if frames[0].len() != n {
        return Err(bad(format!(
            "has {} columns; the model has {n} joints",
            frames[0].len()
        )));
    }
    for (k, frame) in frames.iter().enumerate() {
        for (i, joint) in model.joints.iter().enumerate() {
            if !joint.within_limits(frame[i]) {
                return Err(bad(format!(
                    "frame {k}: joint J{} ({}) is commanded to {} rad, beyond its limits [{}, {}]",
                    i + 1,
                    joint.name,
                    shortest(frame[i]),
                    shortest(joint.lower),
                    shortest(joint.upper)
                )));
            }
        }
    }
    Ok(())
}
