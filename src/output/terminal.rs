//! What a run prints (SPEC §5): a banner with the model and the gains, a line every 0.5 s of
//! simulated time, and the summary.

use std::io::Write;

use super::format::{joint_header, row};
use super::{Recorder, RunInfo, Sample};
use crate::sim::Summary;

/// Simulated time between progress lines (s).
pub const PRINT_PERIOD: f64 = 0.5;

/// Prints to stdout.
pub struct Terminal {
    debug: bool,
    dof: usize,
}

impl Terminal {
    /// A printer; `debug` adds τ, the tracking error, v and g(q) to every progress line.
    pub fn new(debug: bool) -> Self {
        Self { debug, dof: 0 }
    }
}

/// A control rate for people: "5 kHz", "1 kHz", "250 Hz".
fn rate(hz: f64) -> String {
    if hz >= 1e3 {
        format!("{} kHz", (hz / 1e3 * 1e3).round() / 1e3)
    } else {
        format!("{} Hz", (hz * 1e3).round() / 1e3)
    }
}

fn out(line: &str) -> crate::Result<()> {
    // a closed stdout (`faze4 … | head`) is not the run's failure
    let _ = writeln!(std::io::stdout().lock(), "{line}");
    Ok(())
}

impl Recorder for Terminal {
    fn every(&self, dt: f64) -> usize {
        (PRINT_PERIOD / dt).round() as usize
    }

    fn begin(&mut self, run: &RunInfo) -> crate::Result<()> {
        let m = run.model;
        self.dof = m.dof();
        let g = m.gravity.z;
        out(&format!(
            "[faze4] {} · {} ({}) · {} dof · gravity {} · Δt {} ms ({}) · {} s = {} steps",
            run.command,
            m.name,
            m.source,
            m.dof(),
            if g == 0.0 {
                "off".to_string()
            } else {
                format!("{g} m/s²")
            },
            run.dt * 1e3,
            rate(1.0 / run.dt),
            run.steps as f64 * run.dt,
            run.steps
        ))?;
        out(&format!(
            "[faze4] tool {} · gravity feed-forward {}",
            m.frames[run.tool_frame].name,
            if run.feedforward { "on" } else { "off" }
        ))?;
        let gains = run.gains;
        out(&joint_header(m.dof()))?;
        out(&row("torque limit (N·m)", gains.effort.iter().copied()))?;
        out(&row("eff. inertia (kg·m²)", gains.effective_inertia.iter().copied()))?;
        out(&row("kp", gains.kp.iter().copied()))?;
        out(&row("kd", gains.kd.iter().copied()))?;
        out(&row("b = Δt²·kp/I", gains.stiffness_b(run.dt)))?;
        // degrees to 0.01: a −8e-15 from sin(π) is 0
        out(&row(
            "start pose (deg)",
            run.start_q
                .iter()
                .map(|q| (q.to_degrees() * 100.0).round() / 100.0 + 0.0),
        ))
    }

    fn record(&mut self, s: &Sample) -> crate::Result<()> {
        let list = |v: &mut dyn Iterator<Item = f64>| v.map(|x| format!("{x:7.3}")).collect::<Vec<_>>().join("");
        out(&format!(
            "t={:6.2}s  q(rad){}  tool xyz(m){}",
            s.t,
            list(&mut s.q.iter().copied()),
            list(&mut s.tool.iter().copied())
        ))?;
        if self.debug {
            out(&row("    τ command (N·m)", s.tau.iter().copied()))?;
            out(&row("    error (rad)", s.q_cmd.iter().zip(s.q).map(|(c, q)| c - q)))?;
            out(&row("    velocity (rad/s)", s.v.iter().copied()))?;
            out(&row("    g(q) (N·m)", s.g.iter().copied()))?;
        }
        Ok(())
    }

    fn finish(&mut self, s: &Summary) -> crate::Result<()> {
        out(&format!("[summary]{}", &joint_header(self.dof)[9..]))?;
        out(&row("max track. err (rad)", s.max_tracking_error_rad.iter().copied()))?;
        out(&row("saturation (%)", s.saturation_pct.iter().copied()))?;
        let r = &s.tool_range_m;
        out(&format!(
            "tool range (m)        x [{:.3}, {:.3}]  y [{:.3}, {:.3}]  z [{:.3}, {:.3}]",
            r.x[0], r.x[1], r.y[0], r.y[1], r.z[0], r.z[1]
        ))?;
        if let Some(d) = &s.path_deviation_mm {
            out(&format!("path deviation (mm)   max {:.2}  mean {:.2}", d.max, d.mean))?;
        }
        if let Some(res) = s.ik_max_residual_m {
            out(&format!("IK residual (m)       max {res:.1e}"))?;
        }
        Ok(())
    }
}
