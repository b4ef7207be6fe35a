//! Inverse kinematics of the original's shapes: `cargo bench --bench ik`.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use faze4::faze4::{BOARD, Q_SEED, shape_ik_task};
use faze4::ik::{IkWorkspace, solve_path, solve_position};
use faze4::model::{Model, PackagePaths};
use faze4::traj::shape::Shape;

fn faze4() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("urdf/faze4_arm.urdf");
    Model::from_urdf_file(&path, &PackagePaths::default()).unwrap()
}

fn ik(c: &mut Criterion) {
    let model = faze4();
    let task = shape_ik_task(&model).unwrap();
    // the whole circle: 240 targets, each from the previous solution (sample 0 from Q_SEED)
    c.bench_function("ik_circle_240", |b| {
        b.iter(|| {
            let targets = Shape::Circle.targets(240, &BOARD);
            solve_path(&model, &task, black_box(&targets), &Q_SEED)
                .unwrap()
                .max_residual_m
        })
    });
    // one sample of it: the step from one circle point to the next
    let targets = Shape::Circle.targets(240, &BOARD);
    let path = solve_path(&model, &task, &targets, &Q_SEED).unwrap();
    let mut ws = IkWorkspace::new(&model);
    c.bench_function("ik_circle_one_sample", |b| {
        b.iter(|| {
            solve_position(&model, &mut ws, &task, black_box(&targets[100]), &path.q[99])
                .unwrap()
                .residual_m
        })
    });
}

criterion_group!(benches, ik);
criterion_main!(benches);
