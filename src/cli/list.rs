//! `faze4 list robots|motors|drives`: what `--robot`, `--motors` and `--drive` take, with each
//! one's figures and sources, read from where they are defined (the bundled arm's module,
//! [`PRESET_SETS`], [`DriveMode`]'s words and [`RobotFormat::ALL`]): a preset or a drive added
//! there appears here.

use faze4::choice::Choice;
use faze4::config::{DriveMode, PRESET_SETS, Preset};
use faze4::control::JointMotor;
use faze4::model::RobotFormat;

/// What `faze4 list` lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Listed {
    /// The bundled arm and the files `--robot` reads.
    Robots,
    /// Every `--motors` preset: per joint its motor, ratio, torque and speed, and the sources.
    Motors,
    /// Every `--drive`.
    Drives,
}

/// The lines `faze4 list what` prints, each ending in a newline.
pub fn text(what: Listed) -> String {
    let lines = match what {
        Listed::Robots => robots(),
        Listed::Motors => PRESET_SETS.iter().flat_map(preset).collect(),
        Listed::Drives => (DriveMode::VALUES.iter())
            .map(|d| format!("{:<8} {}", d.word(), d.about()))
            .collect(),
    };
    lines.iter().map(|l| format!("{l}\n")).collect()
}

/// The bundled Faze4 (`faze4::faze4`), then the formats `--robot` reads.
fn robots() -> Vec<String> {
    let model = faze4::faze4::model();
    let mass: f64 = model.inertia.iter().map(|i| i.mass).sum();
    let joints: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    let effort: Vec<String> = faze4::faze4::EFFORT.iter().map(|e| e.to_string()).collect();
    let mut lines = vec![
        format!(
            "faze4 (the default, built in: {}): {} joints ({}), {mass:.3} kg of links",
            faze4::faze4::SOURCE.trim_start_matches("bundled "),
            model.dof(),
            joints.join(", "),
        ),
        format!(
            "  torque limits {} N·m: 0.315 N·m at a NEMA17 × each reducer's ratio, the original program's \
             (the arm as built: --motors faze4-bom)",
            effort.join(", ")
        ),
        "--robot FILE reads (told apart by the file's root element):".to_string(),
    ];
    for format in RobotFormat::ALL {
        lines.push(format!("  {:<6} {}", format.name(), format.told_by()));
    }
    lines
}

/// One preset: its name and sources, then a row per joint (one for every joint of any arm).
fn preset(p: &Preset) -> Vec<String> {
    let motors = (p.motors)(None);
    let mut lines = vec![format!("{}: {}", p.name, p.sources)];
    for (k, m) in motors.iter().enumerate() {
        let joint = match p.every_joint {
            true => "every joint".to_string(),
            false => format!("J{}", k + 1),
        };
        lines.push(match m {
            Some(m) => format!("  {joint:<11} {}", figures(m)),
            None => format!("  {joint:<11} no motor"),
        });
    }
    lines
}

/// A joint motor's figures: its label, the ratio, the most torque it gives the joint and the
/// fastest joint speed at which it still gives torque.
fn figures(m: &JointMotor) -> String {
    // a preset without a ratio keeps the model's (its URDF transmission's): the motor's own figures
    let (ratio, shown) = match m.gear_ratio {
        Some(r) => (r, format!("ratio {r}")),
        None => (1.0, "the model's ratio (figures at the motor)".to_string()),
    };
    format!(
        "{} · {shown} · up to {:.2} N·m, torque to {:.2} rad/s at the joint ({})",
        m.motor.label,
        m.motor.joint_limit(ratio),
        m.motor.envelope.top_speed() / ratio,
        m.motor.envelope.kind(),
    )
}
