//! Command-line arguments → the library's [`Scenario`] builder. Only the mapping lives here:
//! the builder checks and tunes; what only a command line has (files, link names) is checked
//! here, each error naming its option, before anything runs or is written.

use std::path::Path;
use std::sync::Arc;

use super::args::{JointValues, ReplayArgs, RunArgs, ShapeArgs, WaveArgs};
use crate::control::JointMotor;
use crate::error::{Error, Result, shortest};
use crate::geometry::{ClearanceGeometry, CollisionSet, PairFilter, Robot};
use crate::model::{FrameId, Joint, JointKind, LoadOptions, Model, PackagePaths};
use crate::sim::scenario::{count, default_effort, finite, non_negative, override_per_joint, positive};
use crate::sim::{Collisions, Scenario, ScenarioBuilder, SelfContact, ShapeRun, Thresholds};
use crate::traj::shape::Shape;
use crate::traj::{Interpolated, Trajectory, Wave, Wrap, npy};

/// `faze4 wave` → scenario.
pub fn wave(args: &WaveArgs) -> Result<Scenario> {
    check_wave(args)?;
    wave_with(args, load_model(&args.run)?, None)
}

/// `faze4 wave` → scenario, on a model already loaded (a sweep loads it once, and its
/// collision set: `set`).
pub fn wave_with(
    args: &WaveArgs,
    Robot {
        model,
        geometry,
        warnings,
    }: Robot,
    set: Option<Arc<CollisionSet>>,
) -> Result<Scenario> {
    check_wave(args)?;
    let trajectory = Trajectory::Wave(Wave {
        amplitude: wave_amplitudes(&model, args.amp_deg, args.amp_m),
        omega: args.freq,
        center: wave_center(&model, args.center.as_deref())?,
    });
    builder(model, trajectory, &args.run, set)?
        .geometry(geometry)
        .load_warnings(warnings)
        .command("wave")
        .duration(args.duration)
        .build()
}

fn check_wave(args: &WaveArgs) -> Result<()> {
    positive("--duration", args.duration)?;
    finite("--freq", args.freq)?;
    if let Some(a) = args.amp_m {
        non_negative("--amp-m", a)?;
    }
    non_negative("--amp-deg", args.amp_deg)
}

/// Default amplitude of a prismatic joint without `--amp-m` and without limits (m).
pub const DEFAULT_AMP_M: f64 = 0.05;

/// Each joint's wave amplitude in its own unit: `amp_deg` in radians for a revolute or
/// continuous joint; for a prismatic one `amp_m`, else a quarter of its range where both
/// limits are finite, else [`DEFAULT_AMP_M`] (docs/model.md, 4.1).
pub fn wave_amplitudes(model: &Model, amp_deg: f64, amp_m: Option<f64>) -> Vec<f64> {
    (model.joints.iter())
        .map(|j| match j.kind {
            JointKind::Prismatic => amp_m.unwrap_or(match (j.lower.is_finite(), j.upper.is_finite()) {
                (true, true) => 0.25 * (j.upper - j.lower),
                _ => DEFAULT_AMP_M,
            }),
            _ => amp_deg.to_radians(),
        })
        .collect()
}

/// `faze4 replay` → scenario.
pub fn replay(args: &ReplayArgs) -> Result<Scenario> {
    positive("--duration", args.duration)?;
    positive("--traj-period", args.traj_period)?;
    let model = load_model(&args.run)?;
    let frames = npy::read_samples(&args.q_traj)?;
    replay_with(args, model, &frames, None)
}

/// `faze4 replay` → scenario, on a model and frames (`--q-traj`) already read (and a
/// collision set, as [`wave_with`]).
pub fn replay_with(
    args: &ReplayArgs,
    Robot {
        model,
        geometry,
        warnings,
    }: Robot,
    frames: &[Vec<f64>],
    set: Option<Arc<CollisionSet>>,
) -> Result<Scenario> {
    positive("--duration", args.duration)?;
    positive("--traj-period", args.traj_period)?;
    check_samples(&model, frames, &args.q_traj)?;
    let trajectory = Trajectory::Interpolated(Interpolated::new(frames, args.traj_period, Wrap::Repeat));
    builder(model, trajectory, &args.run, set)?
        .geometry(geometry)
        .load_warnings(warnings)
        .command("replay")
        .duration(args.duration)
        .build()
}

/// `faze4 shape` → scenario: the board targets, their exact IK, and the joint samples played
/// as a closed loop (see [`ShapeRun::plan`]).
pub fn shape(args: &ShapeArgs) -> Result<Scenario> {
    positive("--duration", args.duration)?;
    shape_of(args)?;
    let robot = load_model(&args.run)?;
    let plan = shape_plan(args, &robot.model)?;
    shape_with(args, robot, plan, None)
}

/// The joint command and drawing part of `faze4 shape` on `model` (the IK; see
/// [`ShapeRun::plan`]).
pub fn shape_plan(args: &ShapeArgs, model: &Model) -> Result<(Trajectory, ShapeRun)> {
    let tool = tool_frame(model, args.run.tool_link.as_deref())?;
    ShapeRun::plan(model, tool, shape_of(args)?, args.shape_points)
}

/// `faze4 shape` → scenario, on a model already loaded and its [`shape_plan`] (a sweep plans
/// once unless it varies `shape-points`), and a collision set as [`wave_with`].
pub fn shape_with(
    args: &ShapeArgs,
    Robot {
        model,
        geometry,
        warnings,
    }: Robot,
    (trajectory, run): (Trajectory, ShapeRun),
    set: Option<Arc<CollisionSet>>,
) -> Result<Scenario> {
    positive("--duration", args.duration)?;
    let shape = shape_of(args)?;
    builder(model, trajectory, &args.run, set)?
        .geometry(geometry)
        .load_warnings(warnings)
        .command(format!("shape {} ({} points)", shape.name(), args.shape_points))
        .duration(args.duration)
        .shape(run)
        .build()
}

fn shape_of(args: &ShapeArgs) -> Result<Shape> {
    Shape::from_name(&args.shape)
        .ok_or_else(|| Error::argument("--shape", format!("'{}' is not one of sine, circle, tri", args.shape)))
}

/// The arm a run uses, its model and geometry: `--urdf`, or the bundled Faze4; with
/// `--motors`, `--rotor-inertia` and `--gear-ratio` applied.
pub fn load_model(run: &RunArgs) -> Result<Robot> {
    // the run's own numbers first: a bad one is reported before a URDF is read
    positive("--dt", run.dt)?;
    positive("--record-period", run.record_period)?;
    non_negative("--payload-kg", run.payload_kg)?;
    non_negative("--clearance-tolerance", run.clearance_tolerance)?;
    let options = LoadOptions {
        balance_inertia: run.balance_inertia,
    };
    let Robot {
        mut model,
        geometry,
        warnings,
    } = match &run.urdf {
        Some(path) => Robot::from_urdf_file_with(
            path,
            &PackagePaths::with_ros_package_path(run.package_path.clone()),
            &options,
        )?,
        None => Robot::faze4(),
    };
    // the motors' ratios and rotors, then the command line's overrides of them
    if let Some(motors) = super::motors::motors(run, &model)? {
        for (joint, m) in model.joints.iter_mut().zip(motors.iter().flatten()) {
            joint.gear_ratio = m.gear_ratio.unwrap_or(joint.gear_ratio);
            joint.rotor_inertia = m.rotor_inertia.unwrap_or(joint.rotor_inertia);
        }
    }
    set_rotors("--rotor-inertia", &mut model, run.rotor_inertia.as_ref(), |j| {
        &mut j.rotor_inertia
    })?;
    set_rotors("--gear-ratio", &mut model, run.gear_ratio.as_ref(), |j| {
        &mut j.gear_ratio
    })?;
    Ok(Robot {
        model,
        geometry,
        warnings,
    })
}

/// Sets each joint's motor value that `values` gives (> 0; 'auto' keeps the model's).
fn set_rotors(
    option: &str,
    model: &mut Model,
    values: Option<&JointValues>,
    field: fn(&mut Joint) -> &mut f64,
) -> Result<()> {
    let Some(values) = values else { return Ok(()) };
    let mut current: Vec<f64> = model.joints.iter_mut().map(|j| *field(j)).collect();
    override_per_joint(option, &mut current, &values.0, |v| v.is_finite() && v > 0.0, "> 0")?;
    for (joint, x) in model.joints.iter_mut().zip(current) {
        *field(joint) = x;
    }
    Ok(())
}

/// The pose `--center` names: zero when not given; `mid`, the middle of each limited joint's
/// range (0 for an unlimited one); else one value per joint, each inside its joint's limits.
pub fn wave_center(model: &Model, center: Option<&str>) -> Result<Vec<f64>> {
    let n = model.dof();
    let center: Vec<f64> = match center.map(str::trim) {
        None => return Ok(vec![0.0; n]),
        Some("mid") => (model.joints.iter())
            .map(|j| match (j.lower.is_finite(), j.upper.is_finite()) {
                (true, true) => 0.5 * (j.lower + j.upper),
                (true, false) => j.lower,
                (false, true) => j.upper,
                (false, false) => 0.0,
            })
            .collect(),
        Some(list) => (list.split(',').enumerate())
            .map(|(i, x)| {
                x.trim().parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                    Error::argument(
                        "--center",
                        format!("J{} value '{}' is not a finite number (or use 'mid')", i + 1, x.trim()),
                    )
                })
            })
            .collect::<Result<_>>()?,
    };
    if center.len() != n {
        return Err(Error::argument(
            "--center",
            format!("{} values given; the model has {n} joints", center.len()),
        ));
    }
    for (i, (j, &c)) in model.joints.iter().zip(&center).enumerate() {
        if !j.within_limits(c) {
            return Err(Error::argument(
                "--center",
                format!(
                    "J{} ({}) {c} is outside its limits [{}, {}]{}",
                    i + 1,
                    j.name,
                    j.lower,
                    j.upper,
                    model.mimic_note(i)
                ),
            ));
        }
    }
    Ok(center)
}

/// The tool frame: `--tool-link`, or the model's default.
pub fn tool_frame(model: &Model, name: Option<&str>) -> Result<FrameId> {
    match name {
        None => Ok(model.default_tool_frame()),
        Some(name) => model.frame_index(name).ok_or_else(|| {
            let names: Vec<&str> = model.frames.iter().map(|f| f.name.as_str()).collect();
            Error::argument(
                "--tool-link",
                format!("no link '{name}' in {} (links: {})", model.source, names.join(", ")),
            )
        }),
    }
}

/// The options every command shares, on the builder (with `set`, a collision set already
/// loaded).
fn builder(
    model: Model,
    trajectory: Trajectory,
    run: &RunArgs,
    set: Option<Arc<CollisionSet>>,
) -> Result<ScenarioBuilder> {
    let n = model.dof();
    // the motors' ratios and rotors are on the model already (load_model, with the overrides)
    let motors = super::motors::motors(run, &model)?.map(|motors| {
        (motors.into_iter())
            .map(|m| {
                m.map(|m| JointMotor {
                    gear_ratio: None,
                    rotor_inertia: None,
                    ..m
                })
            })
            .collect::<Vec<_>>()
    });
    let tool = tool_frame(&model, run.tool_link.as_deref())?;
    let mut builder = Scenario::builder(model, trajectory)
        .tool_frame(tool)
        .dt(run.dt)
        .record_period(run.record_period)
        .payload_kg(run.payload_kg)
        .gravity(!run.no_gravity)
        .feedforward(!run.no_ff)
        .collisions(collisions(run))
        .clearance_tolerance(run.clearance_tolerance * 1e-3)
        .thresholds(Thresholds {
            max_saturation_pct: run.max_saturation_pct,
            max_error: run.max_error,
            max_deviation_mm: run.max_deviation_mm,
        });
    if let Some(set) = set {
        builder = builder.collision_set(set);
    }
    if run.self_collisions {
        builder = builder.self_contact(SelfContact {
            friction: run.friction,
            ..SelfContact::default()
        });
    }
    if let Some(effort) = &run.effort {
        builder = builder.effort(all_given("--effort", effort, n)?);
    }
    if let Some(motors) = motors {
        builder = builder.motors(motors);
    }
    if let Some(limits) = &run.max_speed {
        builder = builder.max_speed(limits.0.clone());
    }
    if let Some(kp) = &run.kp {
        builder = builder.kp(kp.0.clone());
    }
    if let Some(kd) = &run.kd {
        builder = builder.kd(kd.0.clone());
    }
    Ok(builder)
}

/// `--collision-geometry`, `--collision-pairs`, `--no-collisions` → the run's clearance
/// settings (`None`: no clearance).
pub fn collisions(run: &RunArgs) -> Option<Collisions> {
    (!run.no_collisions).then_some(Collisions {
        geometry: match run.collision_geometry.as_str() {
            "hull" => ClearanceGeometry::Hull,
            _ => ClearanceGeometry::Mesh,
        },
        pairs: match run.collision_pairs.as_deref() {
            Some("all") => PairFilter::All,
            _ => PairFilter::NonAdjacent,
        },
    })
}

/// The torque limits a run of `run` on `model` uses: `--effort`, else the motors' under
/// `--motors`, else the model's default ([`default_effort`]).
pub fn effort_limits(model: &Model, run: &RunArgs) -> Result<Vec<f64>> {
    match (&run.effort, &run.motors) {
        (Some(effort), _) => all_given("--effort", effort, model.dof()),
        (None, Some(_)) => {
            let motors = super::motors::motors(run, model)?.unwrap_or_default();
            Ok((default_effort(model).into_iter().zip(&model.joints).enumerate())
                .map(|(i, (e, joint))| match motors.get(i) {
                    Some(Some(m)) => m.motor.joint_limit(joint.gear_ratio),
                    _ => e,
                })
                .collect())
        }
        (None, None) => Ok(default_effort(model)),
    }
}

/// Every joint's value, `auto` refused (it is for gains).
fn all_given(option: &str, values: &JointValues, n: usize) -> Result<Vec<f64>> {
    count(option, values.0.len(), n)?;
    values
        .0
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v.ok_or_else(|| Error::argument(option, format!("J{} has no value ('auto' is for gains)", i + 1)))
        })
        .collect()
}

/// Joint samples (replay frames) must fit the model and its limits.
pub fn check_samples(model: &Model, frames: &[Vec<f64>], path: &Path) -> Result<()> {
    let bad = |message: String| Error::InvalidData {
        path: path.to_path_buf(),
        message,
    };
    let n = model.dof();
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
