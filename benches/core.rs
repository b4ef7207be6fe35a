//! One bench per core algorithm on the Faze4 at a generic state:
//! `cargo bench --bench core`.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use faze4::algo::{
    Data, State, compute_all_terms, crba, discrete_step, forward_kinematics, gravity, integrate_discrete, rnea,
};
use faze4::model::{Model, PackagePaths};
use faze4::sim::Scenario;
use faze4::traj::{Trajectory, Wave};

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
        let mut state = State::at(&q, &v, black_box(&tau), 2e-4);
        b.iter(|| {
            // restart from the same state so the bench measures a fixed workload
            state.q.copy_from_slice(&q);
            state.v.copy_from_slice(&v);
            discrete_step(&model, &mut data, &mut state).unwrap();
        })
    });
}

/// One step of the 5 kHz closed loop as `faze4 wave` runs it: all terms, the wave command,
/// the PD torque, the discrete step.
fn closed_loop_step(c: &mut Criterion) {
    let model = faze4();
    let mut data = Data::new(&model);
    let dt = 2e-4;
    let wave = Wave {
        amplitude: vec![25f64.to_radians(); 6],
        omega: 0.5,
        center: vec![0.0; 6],
    };
    let (mut q0, mut v0) = ([0.0; 6], [0.0; 6]);
    wave.eval(0.0, &mut q0, &mut v0);
    let pd = Scenario::builder(model.clone(), Trajectory::Wave(wave.clone()))
        .dt(dt)
        .build()
        .unwrap()
        .controller;
    let mut state = State::at(&q0, &v0, &[0.0; 6], dt);
    let (mut q_cmd, mut v_cmd, mut tau_raw) = ([0.0; 6], [0.0; 6], [0.0; 6]);
    let mut k = 0usize;
    c.bench_function("closed_loop_step", |b| {
        b.iter(|| {
            let t = k as f64 * dt;
            compute_all_terms(&model, &mut data, &state.q, &state.v);
            wave.eval(t, &mut q_cmd, &mut v_cmd);
            pd.torque(&state.q, &state.v, &q_cmd, &v_cmd, data.g.as_slice(), &mut tau_raw);
            pd.clip(&tau_raw, &mut state.tau);
            integrate_discrete(&model, &mut data, &mut state).unwrap();
            // the wave is periodic; restart every 8 s so the state stays on the trajectory
            k = (k + 1) % 40_000;
            if k == 0 {
                state.q.copy_from_slice(&q0);
                state.v.copy_from_slice(&v0);
            }
        })
    });
}

criterion_group!(benches, core, closed_loop_step);
criterion_main!(benches);
