//! Retime a path from the library: the fastest timing of an N×dof `.npy` path (its rows the
//! points, any times ignored) that the motors follow in faze4's loop, and the time retime took.
//! `tools/bench/retime_vs_toppra.py` runs it beside toppra.
//!
//!     cargo run --release --example retime -- PATH.npy [--urdf F.urdf] [--motors faze4]
//!         [--margin 0.2] [--grid 200] [--attempts 8] [--max-speed V] [--effort E] [--no-check]
//!         [--zero-damping] [--repeat N] [--plot F.svg] [--segments] [--clearance]
//!
//! `--clearance` (the bundled Faze4 only): the check runs measure the self-clearance of the
//! real meshes, their collision set loaded once before the runs (outside `wall_ms`), so
//! `wall_ms` is the retime and its checks with clearance on, the loading apart.
//!
//! Prints one line per run: `duration_s <T> wall_ms <ms> follows <bool> attempts <n> …`; on
//! stderr the check's verdict and, with `--segments`, what binds on each grid interval.

use std::path::PathBuf;
use std::time::Instant;

use faze4::config::motors::fit;
use faze4::model::{PackagePaths, urdf};
use faze4::retime::{PathSpline, RetimeOptions, hold, retime};
use faze4::sim::Scenario;
use faze4::traj::npy::read_samples;
use faze4::viz::PhasePlot;

fn main() -> faze4::Result<()> {
    let mut args = std::env::args().skip(1);
    let mut path = None;
    let mut urdf_file: Option<PathBuf> = None;
    let mut motors = false;
    let mut options = RetimeOptions::default();
    let mut max_speed: Option<f64> = None;
    let mut effort: Option<f64> = None;
    let mut zero_damping = false;
    let mut repeat = 1;
    let mut plot: Option<PathBuf> = None;
    let mut segments = false;
    let mut clearance = false;
    let number = |v: Option<String>, name: &str| -> f64 {
        v.and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{name} takes a number"))
    };
    while let Some(a) = args.next() {
        match a.as_str() {
            "--urdf" => urdf_file = args.next().map(PathBuf::from),
            "--motors" => motors = args.next().as_deref() == Some("faze4"),
            "--margin" => options.margin = number(args.next(), "--margin"),
            "--grid" => options.intervals = number(args.next(), "--grid") as usize,
            "--max-speed" => max_speed = Some(number(args.next(), "--max-speed")),
            "--effort" => effort = Some(number(args.next(), "--effort")),
            "--no-check" => options.check = false,
            "--attempts" => options.attempts = number(args.next(), "--attempts") as usize,
            "--zero-damping" => zero_damping = true,
            "--repeat" => repeat = number(args.next(), "--repeat") as usize,
            "--plot" => plot = args.next().map(PathBuf::from),
            "--segments" => segments = true,
            "--clearance" => clearance = true,
            _ => path = Some(PathBuf::from(a)),
        }
    }
    let points = read_samples(&path.expect("a path .npy"))?;
    let mut model = match &urdf_file {
        Some(f) => urdf::read_file(f, &PackagePaths::default())?,
        None => faze4::faze4::model(),
    };
    if zero_damping {
        model.joints.iter_mut().for_each(|j| j.damping = 0.0);
    }
    let dof = model.dof();
    // the real meshes' collision set, loaded once (its BVHs built on loader threads meanwhile)
    let collisions = match clearance {
        true => {
            let robot = faze4::geometry::Robot::faze4();
            let collisions = faze4::sim::Collisions::default();
            let (set, _) =
                faze4::geometry::CollisionSet::new(&model, &robot.geometry, collisions.geometry, collisions.pairs)?;
            Some((robot.geometry, std::sync::Arc::new(set)))
        }
        false => None,
    };
    for _ in 0..repeat {
        let started = Instant::now();
        let spline = PathSpline::through(&points)?;
        let mut motored = model.clone();
        let fitted = match motors {
            true => fit(&mut motored, Some(faze4::faze4::motors::faze4(None)), &[], &[])?,
            false => None,
        };
        let mut base = Scenario::builder(motored, hold(&spline));
        base = match &collisions {
            Some((geometry, set)) => base.geometry(geometry.clone()).collision_set(set.clone()),
            None => base.collisions(None),
        };
        if let Some(fitted) = fitted {
            base = base.motors(fitted);
        }
        if let Some(v) = max_speed {
            base = base.max_speed(vec![Some(v); dof]);
        }
        if let Some(e) = effort {
            base = base.effort(vec![e; dof]);
        }
        let timed = retime(&base, &spline, &options)?;
        let wall = started.elapsed().as_secs_f64();
        let check = timed.check.as_ref();
        println!(
            "duration_s {} wall_ms {:.3} follows {} attempts {} iterations {} relaxed_s {}",
            timed.profile.duration(),
            wall * 1e3,
            check.is_some_and(|c| c.summary.verdict.follows),
            check.map_or(0, |c| c.attempts),
            timed.iterations,
            timed.relaxed_duration,
        );
        if let Some(c) = check {
            eprintln!("{}", c.summary.verdict);
        }
        if segments {
            for (i, b) in timed.bindings.iter().enumerate() {
                eprintln!("segment {i}: {b} (slack {:.1e})", b.slack);
            }
        }
        if let Some(plot) = &plot {
            let names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
            PhasePlot::new(plot)?.write(&timed, &model.name, &names, options.margin)?;
        }
    }
    Ok(())
}
