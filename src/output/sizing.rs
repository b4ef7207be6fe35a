//! `--sizing`: the motors' sizing report for people, one column per joint, at the motor shaft
//! (the figures are the summary's `motors[].sizing`, computed by the run; docs/motors.md,
//! "Sizing").

use super::format::{joint_header, text_row};
use super::terminal::per_motor;
use crate::sim::MotorSummary;

/// The inertia ratio (reflected load over rotor) sizing notes keep a stepper at or below.
pub const INERTIA_RATIO_RULE: f64 = 10.0;

/// The report's lines: a header, then per joint (`-` where a joint has no motor or a figure is
/// not known) peak and RMS torque, peak speed, inertia ratio, peak power, braking energy,
/// supply current, and the heating check that applies: RMS torque against a continuous rating,
/// or a stepper's winding loss under its constant-current driver against its rated loss.
pub fn sizing_table(motors: &[Option<MotorSummary>]) -> Vec<String> {
    let cell = |f: &dyn Fn(&MotorSummary) -> Option<String>| per_motor(motors, f);
    let mut lines = vec![
        format!("[sizing at the motor]{}", &joint_header(motors.len())[21..]),
        text_row(
            "peak torque (N·m)",
            cell(&|m| Some(format!("{:.4}", m.sizing.peak_torque))),
        ),
        text_row("RMS torque (N·m)", cell(&|m| Some(format!("{:.4}", m.rms_torque)))),
        text_row(
            "peak speed (rad/s)",
            cell(&|m| Some(format!("{:.1}", m.max_motor_speed))),
        ),
        text_row(
            "inertia ratio",
            cell(&|m| {
                m.sizing.inertia_ratio.map(|r| {
                    let flag = if r > INERTIA_RATIO_RULE { " !" } else { "" };
                    format!("{r:.1}{flag}")
                })
            }),
        ),
        text_row(
            "peak power (W)",
            cell(&|m| Some(format!("{:.2}", m.sizing.peak_power_w))),
        ),
        text_row(
            "braking energy (J)",
            cell(&|m| Some(format!("{:.2}", m.sizing.braking_energy_j))),
        ),
        text_row(
            "supply A peak",
            cell(&|m| m.sizing.supply_current_a.map(|c| format!("{:.3}", c.peak))),
        ),
        text_row(
            "supply A mean",
            cell(&|m| m.sizing.supply_current_a.map(|c| format!("{:.3}", c.mean))),
        ),
        text_row(
            "heating",
            cell(&|m| match (m.sizing.winding_loss_w, m.continuous_torque) {
                (Some(w), _) => Some(format!("{:.0} % loss", 100.0 * w.at_drive / w.at_rating)),
                (None, Some(c)) => Some(format!("{:.0} % RMS", 100.0 * m.rms_torque / c)),
                (None, None) => None,
            }),
        ),
    ];
    lines.push(format!(
        "inertia ratio: reflected load over rotor at the run's heaviest pose (! above the {INERTIA_RATIO_RULE}:1 rule of thumb)"
    ));
    for (i, w) in (motors.iter().enumerate())
        .filter_map(|(i, m)| Some((i, m.as_ref()?.sizing.winding_loss_w?)))
        .filter(|(_, w)| w.above_rating)
    {
        lines.push(format!(
            "J{}: driven at {} A, above its rating (both phases at {} A, {:.2} A): its torque is taken at its holding torque, the most its datasheet supports; its winding loss at {} A",
            i + 1,
            w.current,
            w.rated_current,
            std::f64::consts::SQRT_2 * w.rated_current,
            w.current
        ));
    }
    lines.push(
        "heating: a stepper's chopper holds its current at any torque, so its winding loss R·I² is the driver's, shown against 2·R·I_r² at its rating; a DC motor's RMS torque against its continuous rating".into(),
    );
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Sizing, WindingLoss};

    #[test]
    fn the_report_flags_a_heavy_load_and_says_how_a_stepper_heats() {
        let stepper = MotorSummary {
            rms_torque: 0.1,
            max_motor_speed: 12.0,
            sizing: Sizing {
                peak_torque: 0.3,
                inertia_ratio: Some(44.0),
                winding_loss_w: Some(WindingLoss {
                    at_drive: 4.4,
                    at_rating: 8.8,
                    current: 2.7,
                    rated_current: 1.5,
                    above_rating: true,
                }),
                ..Sizing::default()
            },
            ..MotorSummary::default()
        };
        let dc = MotorSummary {
            rms_torque: 0.2,
            continuous_torque: Some(0.4),
            sizing: Sizing {
                inertia_ratio: Some(3.0),
                ..Sizing::default()
            },
            ..MotorSummary::default()
        };
        let lines = sizing_table(&[Some(stepper), None, Some(dc)]);
        let line = |label: &str| lines.iter().find(|l| l.starts_with(label)).unwrap().clone();
        assert!(
            lines[0].starts_with("[sizing at the motor]") && lines[0].ends_with("J3"),
            "{}",
            lines[0]
        );
        let ratio_line = line("inertia ratio");
        let ratio: Vec<&str> = ratio_line.split_whitespace().skip(2).collect();
        assert_eq!(ratio, ["44.0", "!", "-", "3.0"]);
        assert!(line("heating").contains("50 % loss") && line("heating").contains("50 % RMS"));
        assert!(line("supply A peak").ends_with('-'));
        // a drive above its motor's rating is named, and so is what the model does with it
        let above = line("J1: driven at 2.7 A");
        assert!(
            above.contains("1.5 A, 2.12 A") && above.contains("holding torque"),
            "{above}"
        );
        assert!(!lines.iter().any(|l| l.starts_with("J3:")));
    }
}
