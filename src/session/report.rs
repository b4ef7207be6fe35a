//! The lines a run prints after its progress: the files it wrote with its speed (`[done]`), and
//! why it diverged. Options are named as fields (`` `dt` ``), shown by each front end in its
//! own words.

use super::{Finished, OUTPUT_FILES, Recorders};
use crate::config::RunConfig;
use crate::error::{quoted, shown_path};
use crate::output::format::number;
use crate::output::sizing_table;
use crate::sim::{Diverged, RUNAWAY_SPEED, Scenario, Summary};

/// What a run prints on stdout before its verdict: the `[done]` line (unless `quiet`), then
/// the `sizing` table; each line ends in a newline. Both front ends print it (the command line
/// always, then the verdict; Python unless `quiet`).
pub fn report_text(finished: &Finished, config: &RunConfig) -> String {
    let summary = &finished.summary;
    let mut text = String::new();
    if !config.outputs.quiet {
        text = format!("{}\n", done_line(&finished.recorders, config, summary));
    }
    if let (true, Some(motors)) = (config.outputs.sizing, &summary.motors) {
        for line in sizing_table(motors) {
            text.push_str(&line);
            text.push('\n');
        }
    }
    text
}

/// The `[done]` line: the files written ([`OUTPUT_FILES`], each `word -> PATH` and its
/// detail) and the run's speed.
pub fn done_line(outputs: &Recorders, config: &RunConfig, summary: &Summary) -> String {
    let mut written: Vec<String> = (OUTPUT_FILES.iter())
        .filter_map(|output| {
            let path = (output.path)(config)?;
            let detail = (output.detail)(outputs).unwrap_or_default();
            Some(format!("{} -> {}{detail}", output.word, shown_path(path)))
        })
        .collect();
    written.push(speed(summary));
    format!("[done] {}", written.join(" · "))
}

/// The `[done]` line's speed: the steps and the loop's wall time, then the dynamics' µs per
/// step and, when the run measures its self-clearance, the clearance's time and share of the
/// loop's: `40000 steps in 1.339 s (dynamics 7.70 µs/step; self-clearance 1.031 s, 77 % of
/// the time)`. The clearance's worker runs beside the dynamics, so the two need not add up.
fn speed(summary: &Summary) -> String {
    let steps = summary.steps.max(1) as f64;
    let total = format!("{} steps in {:.3} s", summary.steps, summary.wall_time_s);
    match summary.clearance_wall_time_s {
        Some(c) => format!(
            "{total} (dynamics {:.2} µs/step; self-clearance {c:.3} s, {:.0} % of the time)",
            summary.dynamics_wall_time_s / steps * 1e6,
            100.0 * c / summary.wall_time_s.max(f64::MIN_POSITIVE),
        ),
        None => format!("{total} ({:.2} µs/step)", summary.dynamics_wall_time_s / steps * 1e6),
    }
}

/// How many of the stiffest joints a divergence message names.
const STIFFEST_NAMED: usize = 3;

/// The line that says where and why `scenario`'s run diverged (`d`): the command, when it
/// asks the joint for more than [`RUNAWAY_SPEED`] over the last step (a trajectory of 10⁹
/// rad in 1 s was blamed on the gains), else the gains.
pub fn divergence_line(scenario: &Scenario, d: &Diverged) -> String {
    let joint = scenario.model.joint(d.joint);
    let n = scenario.model.dof();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    let step = scenario.dt;
    let commanded = [d.t - step, d.t]
        .iter()
        .map(|&t| {
            scenario.trajectory.eval(t.max(0.0), &mut q, &mut v);
            v[d.joint.0].abs()
        })
        .fold(0.0, f64::max);
    if commanded > RUNAWAY_SPEED {
        return format!(
            "diverged at t = {:.4} s on joint {} ({}): the command asks it for {} {}/s there, faster than the {RUNAWAY_SPEED} {}/s a run takes for a runaway (no arm moves so fast): the trajectory's timing, not the gains, is the cause; the outputs keep the steps before it",
            d.t,
            d.joint,
            quoted(&joint.name),
            number(commanded, 0),
            joint.kind.unit(),
            joint.kind.unit(),
        );
    }
    format!(
        "diverged at t = {:.4} s on joint {} ({}): {} (the tuning rule keeps b ≤ 0.4: lower `dt` or `kp`); the outputs keep the steps before it",
        d.t,
        d.joint,
        quoted(&joint.name),
        stiffest_joints(scenario, &d.stiffness_b)
    )
}

/// The divergence message's account of the gains, one line on any arm: the coupled figures,
/// then b = Δt²·kp/I of the [`STIFFEST_NAMED`] largest joints (all of them on a small arm).
fn stiffest_joints(scenario: &Scenario, b: &[f64]) -> String {
    let mut order: Vec<usize> = (0..b.len()).collect();
    order.sort_by(|&x, &y| b[y].total_cmp(&b[x]));
    let named: Vec<String> = order
        .iter()
        .take(STIFFEST_NAMED)
        .map(|&i| {
            format!(
                "J{} ({}) {}",
                i + 1,
                quoted(&scenario.model.joints[i].name),
                number(b[i], 0)
            )
        })
        .collect();
    let more = if b.len() > STIFFEST_NAMED {
        format!(" and {} more", b.len() - STIFFEST_NAMED)
    } else {
        String::new()
    };
    let coupled = match &scenario.controller.gains.stability {
        Some(s) => format!(
            "b_max = {}, spectral radius {}; ",
            number(s.b_max, 0),
            number(s.spectral_radius, 0)
        ),
        None => String::new(),
    };
    format!("{coupled}b = Δt²·kp/I largest at {}{more}", named.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `[done]` line's speed separates the dynamics from the self-clearance (made-up
    /// times: the format is tested, never a timing).
    #[test]
    fn the_speed_separates_dynamics_and_clearance() {
        let mut summary = Summary {
            steps: 40000,
            wall_time_s: 1.339,
            dynamics_wall_time_s: 0.308,
            clearance_wall_time_s: Some(1.031),
            ..Summary::default()
        };
        assert_eq!(
            speed(&summary),
            "40000 steps in 1.339 s (dynamics 7.70 µs/step; self-clearance 1.031 s, 77 % of the time)"
        );
        summary.clearance_wall_time_s = None;
        summary.wall_time_s = 0.03;
        summary.dynamics_wall_time_s = 0.0292;
        assert_eq!(speed(&summary), "40000 steps in 0.030 s (0.73 µs/step)");
    }
}
