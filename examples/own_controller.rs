//! A step-by-step loop with your own controller: the library's algorithms on one workspace,
//! no scenario, no recorders. A computed-torque controller (τ = M(q)(q̈_cmd + Kp e + Kd ė) +
//! C v + g + D v, D the joint damping) holds J1–J5 of the Faze4's wave within about 2e-5 rad (the PD of `faze4 wave`: 3e-4),
//! where the motors can give the torque it asks for: the loop reports the largest torque it
//! needed per joint next to the Faze4's limits. (J6 is the exception: its link inertia is so
//! small that the explicit damping term lags the step's implicit damping.)
//!
//!     cargo run --release --example own_controller

use faze4::algo::{Data, State, compute_all_terms, integrate_discrete};
use faze4::traj::Wave;

fn main() -> faze4::Result<()> {
    let model = faze4::faze4::model();
    let n = model.dof();
    let mut data = Data::new(&model);
    let wave = Wave {
        amplitude: vec![25f64.to_radians(); n],
        omega: 0.5,
        center: vec![0.0; n],
    };
    let (dt, steps) = (2e-4, 40_000);
    let (kp, kd) = (400.0, 40.0); // per unit inertia: a critically damped 20 rad/s loop

    let mut state = State::new(&model, dt);
    wave.eval(0.0, &mut state.q, &mut state.v);
    let (mut q_cmd, mut v_cmd) = (vec![0.0; n], vec![0.0; n]);
    let (mut max_error, mut max_tau) = (vec![0.0f64; n], vec![0.0f64; n]);
    for k in 0..steps {
        let t = k as f64 * dt;
        // M, g and C v + g at (q, v) from one kinematics pass
        compute_all_terms(&model, &mut data, &state.q, &state.v);
        let State { q, v, tau, .. } = &mut state;
        wave.eval(t, &mut q_cmd, &mut v_cmd);
        // q̈_cmd = −ω² q_cmd for a sine
        let a: Vec<f64> = (0..n)
            .map(|i| -wave.omega * wave.omega * q_cmd[i] + kp * (q_cmd[i] - q[i]) + kd * (v_cmd[i] - v[i]))
            .collect();
        for i in 0..n {
            tau[i] = (0..n).map(|j| data.m[(i, j)] * a[j]).sum::<f64>() + data.bias[i] + model.joints[i].damping * v[i];
            max_tau[i] = max_tau[i].max(tau[i].abs());
            max_error[i] = max_error[i].max((q_cmd[i] - q[i]).abs());
        }
        integrate_discrete(&model, &mut data, &mut state)?;
    }
    println!("joint  max error (rad)  max |τ| (N·m)  Faze4 limit (N·m)");
    for i in 0..n {
        println!(
            "J{}     {:>13.2e}  {:>13.3}  {:>17}",
            i + 1,
            max_error[i],
            max_tau[i],
            faze4::faze4::EFFORT[i]
        );
    }
    Ok(())
}
