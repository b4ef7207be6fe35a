//! One bench per core algorithm on the Faze4 at a generic state:
//! `cargo bench --bench core`.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use faze4::algo::{Data, compute_all_terms, crba, discrete_step, forward_kinematics, gravity, rnea};
use faze4::model::{Model, PackagePaths};

fn faze4() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("urdf/faze4_arm.urdf");
    Model::from_urdf_file(&path, &PackagePaths::default()).unwrap()
}

fn core(c: &mut Criterion) {
    let model = faze4();
    let mut data = Data::new(&model);
    let q = [0.1, 0.4, -0.3, 0.2, -0.5, 0.3];
    let v = [0.2, -0.1, 0.3, 0.5, -0.4, 0.6];
    let a = [1.0, -0.5, 0.3, 2.0, -1.0, 0.7];
    let tau = [0.1, 3.0, 1.5, 0.0, 0.02, 0.0];

    c.bench_function("fk", |b| {
        b.iter(|| forward_kinematics(&model, &mut data, black_box(&q)))
    });
    c.bench_function("rnea", |b| b.iter(|| rnea(&model, &mut data, black_box(&q), &v, &a)[0]));
    c.bench_function("crba", |b| b.iter(|| crba(&model, &mut data, black_box(&q))[(0, 0)]));
    c.bench_function("gravity", |b| b.iter(|| gravity(&model, &mut data, black_box(&q))[0]));
    c.bench_function("all_terms", |b| {
        b.iter(|| compute_all_terms(&model, &mut data, black_box(&q), &v))
    });
    c.bench_function("step", |b| {
        let (mut qs, mut vs) = (q, v);
        b.iter(|| {
            // restart from the same state so the bench measures a fixed workload
            qs = q;
            vs = v;
            discrete_step(&model, &mut data, &mut qs, &mut vs, black_box(&tau), 2e-4).unwrap();
        })
    });
}

criterion_group!(benches, core);
criterion_main!(benches);
