//! A trajectory of your own, run through the library and judged: the Faze4 lifts its shoulder
//! and elbow through a smooth point-to-point move (a quintic, zero velocity at both ends), with
//! and without a 1.5 kg payload, and the summary is read back as data.
//!
//!     cargo run --release --example custom_trajectory

use faze4::sim::{Scenario, StopFlag, run};
use faze4::traj::{Interpolated, Trajectory, Wrap};

fn main() -> faze4::Result<()> {
    let model = faze4::faze4::model();
    // 201 samples over 2 s from the zero pose to J2 = 0.6 rad, J3 = −0.9 rad, and back
    let (start, goal) = ([0.0; 6], [0.0, 0.6, -0.9, 0.0, 0.3, 0.0]);
    let samples: Vec<Vec<f64>> = (0..=200)
        .map(|k| {
            let s = k as f64 / 100.0; // 0 → 2
            let u = if s <= 1.0 { s } else { 2.0 - s };
            let blend = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u); // 0 → 1 → 0, smooth
            (0..6).map(|i| start[i] + blend * (goal[i] - start[i])).collect()
        })
        .collect();
    let trajectory = Trajectory::Interpolated(Interpolated::new(&samples, 2.0, Wrap::Repeat));

    for payload in [0.0, 1.5] {
        let scenario = Scenario::builder(model.clone(), trajectory.clone())
            .command("lift")
            .duration(4.0)
            .payload_kg(payload)
            .build()?;
        let summary = run(&scenario, &mut [], &StopFlag::new())?;
        let worst = (0..summary.dof)
            .max_by(|&a, &b| summary.max_tracking_error_rad[a].total_cmp(&summary.max_tracking_error_rad[b]))
            .unwrap_or(0);
        println!(
            "payload {payload} kg: worst tracking J{} {:.2e} rad, J2 saturated {:.2} % — {}",
            worst + 1,
            summary.max_tracking_error_rad[worst],
            summary.saturation_pct[1],
            summary.verdict
        );
    }
    Ok(())
}
