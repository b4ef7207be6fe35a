//! Self-clearance of the Faze4's official meshes over a 12 s circle run's recorded samples
//! (600, one every 0.02 s; the joint samples are the circle's IK samples of
//! `tests/fixtures/shape_circle_q.npy`, 5 s per loop): `cargo bench --bench geometry`.
//! Reads the official description from the repository (`assets/faze4_description`), or from
//! `FAZE4_DESCRIPTION`.
//!
//! * `clearance_hull_600_samples`: forward kinematics and [`Clearance::add`] (then
//!   [`Clearance::finish`]) with
//!   each mesh as its convex hull, for the 600 samples of a run.
//! * `clearance_mesh_600_samples`: the same with the exact triangles.
//!
//! Compare with a 12 s run's wall time (`faze4 shape --shape circle --duration 12`, about 50 ms
//! in release): the target for the exact clearance is at most 20 % of it.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};
use faze4::algo::{Data, forward_kinematics};
use faze4::geometry::{Clearance, ClearanceGeometry, CollisionSet, PairFilter, Robot};
use faze4::model::PackagePaths;
use faze4::traj::npy;

fn description() -> PathBuf {
    if let Some(dir) = std::env::var_os("FAZE4_DESCRIPTION") {
        return PathBuf::from(dir);
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/faze4_description")
}

/// The joint samples of a 12 s circle run's 600 records (t = k·0.02 s, 240 samples per 5 s).
fn run_samples() -> Vec<Vec<f64>> {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let circle = npy::read_samples(&repo.join("tests/fixtures/shape_circle_q.npy")).unwrap();
    (0..600)
        .map(|k| circle[(k * 240 / 250) % circle.len()].clone())
        .collect()
}

fn clearance_pass(robot: &Robot, set: &CollisionSet, samples: &[(f64, &Vec<f64>)]) -> f64 {
    let mut data = Data::new(&robot.model);
    let mut clearance = Clearance::new(set);
    for (t, q) in samples {
        forward_kinematics(&robot.model, &mut data, q);
        clearance.add(&data.frame_pose, *t);
    }
    clearance.finish();
    let report = clearance.into_report();
    report.min_m.unwrap()
}

fn clearance(c: &mut Criterion) {
    let robot = Robot::from_urdf_file(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("urdf/faze4_real.urdf"),
        &PackagePaths::new(vec![description()]),
    )
    .unwrap();
    let q = run_samples();
    let all: Vec<(f64, &Vec<f64>)> = q.iter().enumerate().map(|(k, q)| (k as f64 * 0.02, q)).collect();
    let (hull, _) = CollisionSet::new(
        &robot.model,
        &robot.geometry,
        ClearanceGeometry::Hull,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    let (mesh, _) = CollisionSet::new(
        &robot.model,
        &robot.geometry,
        ClearanceGeometry::Mesh,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    let mut group = c.benchmark_group("geometry");
    group.sample_size(10);
    group.bench_function("clearance_hull_600_samples", |b| {
        b.iter(|| clearance_pass(&robot, &hull, black_box(&all)))
    });
    group.bench_function("clearance_mesh_600_samples", |b| {
        b.iter(|| clearance_pass(&robot, &mesh, black_box(&all)))
    });
    group.finish();
}

criterion_group!(benches, clearance);
criterion_main!(benches);
