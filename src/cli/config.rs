//! The parsed command line → the library's [`RunConfig`]. Only the mapping lives here: the
//! configuration checks its values, each error naming the field, which [`super::main`] shows
//! as its flag.

use super::args::{Command, JointValues, ReplayArgs, RetimeArgs, RunArgs, ShapeArgs, TrajectoryFileArgs, WaveArgs};
use crate::config::fields::{all_given, parse_center};
use crate::config::{
    ArmConfig, Center, ClearanceConfig, ControlConfig, DriveMode, Motion, Motors, OutputConfig, ReplayConfig,
    RetimeConfig, RunConfig, ShapeConfig, VerdictConfig, WaveConfig,
};
use crate::control::FeedForward;
use crate::error::{Error, Result};
use crate::geometry::{ClearanceGeometry, PairFilter};
use crate::sim::Thresholds;
use crate::traj::shape::Shape;

/// The configuration of a run command (`wave`, `replay`, `shape`, `retime`).
pub fn run_config(command: &Command) -> Result<RunConfig> {
    match command {
        Command::Wave(a) => wave(a),
        Command::Replay(a) => replay(a),
        Command::Shape(a) => shape(a),
        Command::Retime(a) => retime(a),
        Command::Sweep(_) => Err(Error::argument("sweep", "is a sweep of runs, not a run")),
    }
}

fn wave(a: &WaveArgs) -> Result<RunConfig> {
    let center = match &a.center {
        None => Center::Zero,
        Some(text) => parse_center(text)?,
    };
    let motion = Motion::Wave(WaveConfig {
        freq: a.freq,
        amp_deg: a.amp_deg,
        amp_m: a.amp_m,
        center,
    });
    with_run(motion, Some(a.duration), &a.run)
}

fn replay(a: &ReplayArgs) -> Result<RunConfig> {
    let motion = Motion::Replay(file(&a.file));
    with_run(motion, a.duration, &a.run)
}

/// The trajectory file's options.
fn file(a: &TrajectoryFileArgs) -> ReplayConfig {
    ReplayConfig {
        q_traj: a.q_traj.clone(),
        traj_period: a.traj_period,
        message: a.message,
        topic: a.topic.clone(),
    }
}

fn shape(a: &ShapeArgs) -> Result<RunConfig> {
    let shape = Shape::from_name(&a.shape)
        .ok_or_else(|| Error::option("shape", format!("'{}' is not one of sine, circle, tri", a.shape)))?;
    let motion = Motion::Shape(ShapeConfig {
        shape,
        shape_points: a.shape_points,
        save_q: a.save_q.clone().filter(|p| !is_none(p)),
    });
    with_run(motion, Some(a.duration), &a.run)
}

fn retime(a: &RetimeArgs) -> Result<RunConfig> {
    let motion = Motion::Retime(RetimeConfig {
        path: file(&a.file),
        out: Some(a.out.clone()),
        grid: a.grid,
        margin: a.margin,
        attempts: a.attempts,
    });
    with_run(motion, None, &a.run)
}

/// `motion` with the options every run command shares.
fn with_run(motion: Motion, duration: Option<f64>, run: &RunArgs) -> Result<RunConfig> {
    let per_joint = |v: &Option<JointValues>| v.as_ref().map_or(Vec::new(), |v| v.0.clone());
    let path = |p: &Option<std::path::PathBuf>| p.clone().filter(|p| !is_none(p));
    Ok(RunConfig {
        motion,
        arm: ArmConfig {
            urdf: run.urdf.clone(),
            package_path: run.package_path.clone(),
            balance_inertia: run.balance_inertia,
            tool_link: run.tool_link.clone(),
            motors: run.motors.as_deref().map(Motors::named).transpose()?,
            supply_voltage: run.supply_voltage,
            rotor_inertia: per_joint(&run.rotor_inertia),
            gear_ratio: per_joint(&run.gear_ratio),
            payload_kg: run.payload_kg,
            no_gravity: run.no_gravity,
        },
        control: ControlConfig {
            dt: run.dt,
            effort: run.effort.as_ref().map(|e| all_given("effort", &e.0)).transpose()?,
            kp: per_joint(&run.kp),
            kd: per_joint(&run.kd),
            max_speed: per_joint(&run.max_speed),
            no_ff: run.no_ff,
            ff: match run.ff.as_deref() {
                Some("full") => Some(FeedForward::Full),
                Some(_) => Some(FeedForward::Gravity),
                None => None,
            },
            drive: match run.drive.as_deref() {
                Some("stepper") => DriveMode::Stepper,
                _ => DriveMode::Pd,
            },
            microsteps: per_joint(&run.microsteps),
            driver_bandwidth: run.driver_bandwidth,
            rotor_damping: per_joint(&run.rotor_damping),
            reducer_friction: per_joint(&run.reducer_friction),
        },
        duration,
        record_period: run.record_period,
        verdict: VerdictConfig {
            thresholds: Thresholds {
                max_saturation_pct: run.max_saturation_pct,
                max_error: run.max_error,
                max_deviation_mm: run.max_deviation_mm,
            },
            strict: run.strict,
        },
        clearance: ClearanceConfig {
            collision_geometry: match run.collision_geometry.as_str() {
                "hull" => ClearanceGeometry::Hull,
                _ => ClearanceGeometry::Mesh,
            },
            collision_pairs: match run.collision_pairs.as_deref() {
                Some("all") => PairFilter::All,
                _ => PairFilter::NonAdjacent,
            },
            clearance_tolerance: run.clearance_tolerance,
            no_collisions: run.no_collisions,
            self_collisions: run.self_collisions,
            friction: run.friction,
        },
        outputs: OutputConfig {
            trail: Some(run.trail.clone()).filter(|p| !is_none(p)),
            summary: path(&run.summary),
            html: path(&run.html),
            plot: path(&run.plot),
            plot_motors: path(&run.plot_motors),
            view: run.view,
            port: run.port,
            hold: run.hold,
            quiet: run.quiet,
            debug: run.debug,
            print_period: run.print_period,
            sizing: run.sizing,
        },
    })
}

/// Whether an output path means "do not write it".
fn is_none(path: &std::path::Path) -> bool {
    path.as_os_str() == "none"
}
