//! Command-line arguments → a validated [`Scenario`]. Every check names the option and says
//! what is wrong, before anything runs or is written.

use std::path::Path;

use super::args::{JointValues, ReplayArgs, RunArgs, ShapeArgs, WaveArgs};
use crate::algo::{Data, crba};
use crate::control::{FAZE4_EFFORT, Gains, Pd, auto_tune};
use crate::error::{Error, Result};
use crate::geometry::GeometryModel;
use crate::ik::{IkTask, SHAPE_FREE_JOINTS, solve_path};
use crate::model::{self, Model, PackagePaths, Robot};
use crate::output::steps_per_record;
use crate::sim::{Scenario, ShapeRun};
use crate::traj::shape::{BOARD, Q_SEED, SHAPE_PERIOD, Shape};
use crate::traj::{Interpolated, Trajectory, Wave, Wrap, npy};

/// `faze4 wave` → scenario.
pub fn wave(args: &WaveArgs) -> Result<Scenario> {
    positive("--duration", args.duration)?;
    finite("--freq", args.freq)?;
    non_negative("--amp-deg", args.amp_deg)?;
    let Robot { model, geometry } = load_model(&args.run)?;
    let trajectory = Trajectory::Wave(Wave {
        amplitude: args.amp_deg.to_radians(),
        omega: args.freq,
        dof: model.dof(),
    });
    let steps = steps("--duration", args.duration, args.run.dt)?;
    check_wave_limits(&model, &trajectory, args.run.dt, steps)?;
    assemble("wave", model, geometry, trajectory, steps, &args.run, None)
}

/// `faze4 replay` → scenario.
pub fn replay(args: &ReplayArgs) -> Result<Scenario> {
    positive("--duration", args.duration)?;
    positive("--traj-period", args.traj_period)?;
    let Robot { model, geometry } = load_model(&args.run)?;
    let frames = npy::read_samples(&args.q_traj)?;
    check_samples(&model, &frames, &args.q_traj)?;
    let trajectory = Trajectory::Interpolated(Interpolated::new(&frames, args.traj_period, Wrap::Repeat));
    let steps = steps("--duration", args.duration, args.run.dt)?;
    assemble("replay", model, geometry, trajectory, steps, &args.run, None)
}

/// `faze4 shape` → scenario: the board targets, their exact IK, and the joint samples played as a closed loop every [`SHAPE_PERIOD`].
///
/// On the Faze4 the IK moves J1, J2, J3 and J5 from [`Q_SEED`] (J4 = J6 = 0, SPEC §4); on
/// any other arm every joint is free, from the zero pose clamped into the limits.
pub fn shape(args: &ShapeArgs) -> Result<Scenario> {
    positive("--duration", args.duration)?;
    let shape = Shape::from_name(&args.shape)
        .ok_or_else(|| Error::argument("--shape", format!("'{}' is not one of sine, circle, tri", args.shape)))?;
    if args.shape_points < 3 {
        return Err(Error::argument(
            "--shape-points",
            format!("{} samples cannot make a closed path: at least 3", args.shape_points),
        ));
    }
    let Robot { model, geometry } = load_model(&args.run)?;
    let tool = tool_frame(&model, args.run.tool_link.as_deref())?;
    let (free, seed): (Vec<usize>, Vec<f64>) = if model.is_faze4() {
        (SHAPE_FREE_JOINTS.to_vec(), Q_SEED.to_vec())
    } else {
        let seed = model.joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)).collect();
        ((0..model.dof()).collect(), seed)
    };
    let task = IkTask::new(&model, tool, &free)?;
    let targets = shape.targets(args.shape_points, &BOARD);
    let ik = solve_path(&model, &task, &targets, &seed)?;
    let rows: Vec<Vec<f64>> = targets.iter().map(|p| vec![p.x, p.y, p.z]).collect();
    let run = ShapeRun {
        board: BOARD,
        target: Interpolated::new(&rows, SHAPE_PERIOD, Wrap::Closed),
        reference: targets,
        ik_max_residual_m: ik.max_residual_m,
    };
    let trajectory = Trajectory::Interpolated(Interpolated::new(&ik.q, SHAPE_PERIOD, Wrap::Closed));
    let steps = steps("--duration", args.duration, args.run.dt)?;
    let command = format!("shape {} ({} points)", shape.name(), args.shape_points);
    assemble(&command, model, geometry, trajectory, steps, &args.run, Some(run))
}

/// The model a run uses: the URDF (or the bundled arm), gravity, tool frame, payload; and its
/// geometry.
pub fn load_model(run: &RunArgs) -> Result<Robot> {
    positive("--dt", run.dt)?;
    positive("--record-period", run.record_period)?;
    non_negative("--payload-kg", run.payload_kg)?;
    let Robot { mut model, geometry } = match &run.urdf {
        Some(path) => model::urdf::read_file(path, &PackagePaths::with_ros_package_path(run.package_path.clone()))?,
        None => model::faze4_robot(),
    };
    if run.no_gravity {
        model.gravity = Default::default();
    }
    let tool = tool_frame(&model, run.tool_link.as_deref())?;
    if run.payload_kg > 0.0 {
        model = model.with_point_mass(tool, run.payload_kg);
    }
    Ok(Robot { model, geometry })
}

/// The tool frame: `--tool-link`, or the model's default.
pub fn tool_frame(model: &Model, name: Option<&str>) -> Result<usize> {
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

/// Gains, controller and the rest of the scenario, common to every command.
pub fn assemble(
    command: &str,
    model: Model,
    geometry: GeometryModel,
    trajectory: Trajectory,
    steps: usize,
    run: &RunArgs,
    shape: Option<ShapeRun>,
) -> Result<Scenario> {
    let n = model.dof();
    let tool_frame = tool_frame(&model, run.tool_link.as_deref())?;
    let effort = match &run.effort {
        Some(values) => {
            let e = all_given("--effort", values, n)?;
            for (i, &x) in e.iter().enumerate() {
                if x.is_nan() || x <= 0.0 {
                    return Err(Error::argument("--effort", format!("J{} limit {x} must be > 0", i + 1)));
                }
            }
            e
        }
        None if model.is_faze4() => FAZE4_EFFORT.to_vec(),
        None => {
            let unlimited: Vec<&str> = model
                .joints
                .iter()
                .filter(|j| j.effort.is_none())
                .map(|j| j.name.as_str())
                .collect();
            if !unlimited.is_empty() {
                eprintln!(
                    "faze4: {} gives no effort limit for {}: their torque is not clipped (set --effort)",
                    model.source,
                    unlimited.join(", ")
                );
            }
            model.joints.iter().map(|j| j.effort.unwrap_or(f64::INFINITY)).collect()
        }
    };
    let dt = run.dt;

    // auto-tuning from the effective inertia at the start state, then the overrides
    let (mut q0, mut v0) = (vec![0.0; n], vec![0.0; n]);
    trajectory.eval(0.0, &mut q0, &mut v0);
    let mut data = Data::new(&model);
    let inertia: Vec<f64> = crba(&model, &mut data, &q0).diagonal().iter().copied().collect();
    let mut gains = auto_tune(&inertia, &effort, dt);
    override_gains("--kp", &mut gains.kp, run.kp.as_ref(), n)?;
    override_gains("--kd", &mut gains.kd, run.kd.as_ref(), n)?;
    let pd = pd(&gains, !run.no_ff);
    Ok(Scenario {
        command: command.to_string(),
        model,
        geometry,
        tool_frame,
        trajectory,
        dt,
        steps,
        gains,
        pd,
        record_every: steps_per_record(run.record_period, dt),
        shape,
    })
}

fn pd(gains: &Gains, feedforward: bool) -> Pd {
    Pd {
        kp: gains.kp.clone(),
        kd: gains.kd.clone(),
        effort: gains.effort.clone(),
        feedforward,
    }
}

fn override_gains(option: &str, gains: &mut [f64], values: Option<&JointValues>, n: usize) -> Result<()> {
    let Some(values) = values else { return Ok(()) };
    count(option, values, n)?;
    for (i, v) in values.0.iter().enumerate() {
        if let Some(v) = *v {
            if !v.is_finite() || v < 0.0 {
                return Err(Error::argument(
                    option,
                    format!("J{} value {v} must be finite and ≥ 0", i + 1),
                ));
            }
            gains[i] = v;
        }
    }
    Ok(())
}

fn count(option: &str, values: &JointValues, n: usize) -> Result<()> {
    if values.0.len() != n {
        return Err(Error::argument(
            option,
            format!("{} values given; the model has {n} joints", values.0.len()),
        ));
    }
    Ok(())
}

fn all_given(option: &str, values: &JointValues, n: usize) -> Result<Vec<f64>> {
    count(option, values, n)?;
    values
        .0
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v.ok_or_else(|| Error::argument(option, format!("J{} has no value ('auto' is for gains)", i + 1)))
        })
        .collect()
}

/// Number of steps for `duration` at `dt` (at least one).
pub fn steps(option: &str, duration: f64, dt: f64) -> Result<usize> {
    let steps = (duration / dt).round();
    if steps < 1.0 {
        return Err(Error::argument(
            option,
            format!("{duration} s is shorter than one step of --dt {dt} s"),
        ));
    }
    if steps > 1e12 {
        return Err(Error::argument(
            option,
            format!("{duration} s at --dt {dt} s is {steps:e} steps: too many"),
        ));
    }
    Ok(steps as usize)
}

/// Joint samples (replay frames, shape samples) must fit the model and its limits.
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
                    frame[i],
                    joint.lower,
                    joint.upper
                )));
            }
        }
    }
    Ok(())
}

/// The wave's command must stay inside the joint limits: where the amplitude could cross a
/// limit, the command is scanned at every step to report the first crossing.
fn check_wave_limits(model: &Model, trajectory: &Trajectory, dt: f64, steps: usize) -> Result<()> {
    let Trajectory::Wave(wave) = trajectory else {
        return Ok(());
    };
    if model
        .joints
        .iter()
        .all(|j| j.within_limits(wave.amplitude) && j.within_limits(-wave.amplitude))
    {
        return Ok(());
    }
    let n = model.dof();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    for k in 0..=steps {
        let t = k as f64 * dt;
        trajectory.eval(t, &mut q, &mut v);
        if let Some(i) = (0..n).find(|&i| !model.joints[i].within_limits(q[i])) {
            let j = &model.joints[i];
            return Err(Error::argument(
                "--amp-deg",
                format!(
                    "joint J{} ({}) would be commanded to {:.4} rad at t = {t:.4} s, beyond its limits [{:.4}, {:.4}]",
                    i + 1,
                    j.name,
                    q[i],
                    j.lower,
                    j.upper
                ),
            ));
        }
    }
    Ok(())
}

fn finite(option: &str, x: f64) -> Result<()> {
    if !x.is_finite() {
        return Err(Error::argument(option, format!("{x} is not a finite number")));
    }
    Ok(())
}

fn positive(option: &str, x: f64) -> Result<()> {
    finite(option, x)?;
    if x <= 0.0 {
        return Err(Error::argument(option, format!("{x} must be > 0")));
    }
    Ok(())
}

fn non_negative(option: &str, x: f64) -> Result<()> {
    finite(option, x)?;
    if x < 0.0 {
        return Err(Error::argument(option, format!("{x} must be ≥ 0")));
    }
    Ok(())
}
