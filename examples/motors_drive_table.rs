//! docs/motors.md's comparison of `--drive pd` and `--drive stepper`: the original's shapes
//! and waves under `--motors faze4` and `--motors faze4-bom`, each run by the release binary
//! with the PD (the original's controller, clipped to the envelopes), with the open-loop
//! stepper drive at the 2020 firmware's microsteps, the same at 20 kHz (`--dt 5e-5`: how much a
//! result near a slip depends on the step), and at 16 microsteps. Prints Markdown rows.
//!
//!     cargo build --release && cargo run --release --example motors_drive_table [-- path/to/faze4]

use std::process::Command;

use serde_json::Value;

/// The runs: name and command words.
const RUNS: [(&str, &[&str]); 7] = [
    ("shape sine", &["shape", "--shape", "sine"]),
    ("shape circle", &["shape", "--shape", "circle"]),
    ("shape tri", &["shape", "--shape", "tri"]),
    ("wave", &["wave"]),
    ("wave --freq 2", &["wave", "--freq", "2"]),
    ("wave --freq 4", &["wave", "--freq", "4"]),
    ("wave --freq 12.566", &["wave", "--freq", "12.566"]),
];

/// The drives: name and options.
const DRIVES: [(&str, &[&str]); 4] = [
    ("pd", &["--drive", "pd"]),
    ("stepper", &["--drive", "stepper"]),
    ("stepper, 20 kHz", &["--drive", "stepper", "--dt", "5e-5"]),
    ("stepper, 16 µsteps", &["--drive", "stepper", "--microsteps", "16"]),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let binary = std::env::args().nth(1).unwrap_or_else(|| "target/release/faze4".into());
    let dir = std::env::temp_dir().join(format!("faze4-drive-table-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let summary = dir.join("s.json");
    println!("| run | motors | drive | follows | full steps lost (J1…J6) | first slip (s) | the verdict's reasons |");
    println!("|---|---|---|---|---|---|---|");
    for (run, words) in RUNS {
        for motors in ["faze4", "faze4-bom"] {
            for (drive, options) in DRIVES {
                let out = Command::new(&binary)
                    .args(words)
                    .args(["--motors", motors])
                    .args(options)
                    .args(["--no-collisions", "--trail", "none", "--quiet", "--summary"])
                    .arg(&summary)
                    .output()?;
                if !matches!(out.status.code(), Some(0 | 1)) {
                    return Err(format!("{run} {motors} {drive}: {}", String::from_utf8_lossy(&out.stderr)).into());
                }
                let s: Value = serde_json::from_str(&std::fs::read_to_string(&summary)?)?;
                let m = s["motors"].as_array().ok_or("no motors")?;
                let lost: Vec<String> = (m.iter())
                    .map(|m| m["steps_lost"].as_u64().map_or("-".into(), |n| n.to_string()))
                    .collect();
                let first = (m.iter())
                    .filter_map(|m| m["steps_lost"].as_u64().and(m["loses_steps_at"].as_f64()))
                    .fold(None, |a: Option<f64>, t| Some(a.map_or(t, |a| a.min(t))));
                println!(
                    "| {run} | {motors} | {drive} | {} | {} | {} | {} |",
                    if s["verdict"]["follows"] == true { "yes" } else { "no" },
                    lost.join(" "),
                    first.map_or("-".into(), |t| format!("{t:.3}")),
                    reasons(&s)
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// The verdict's reasons, short: per joint what it names (saturation, tracking error, envelope,
/// a PD demand beyond a stepper's curve, a slip), then the path deviation.
fn reasons(s: &Value) -> String {
    let mut out = Vec::new();
    for reason in s["verdict"]["reasons"].as_array().into_iter().flatten() {
        let r = reason.as_str().unwrap_or_default();
        let joint = r.split([' ', '\'']).next().unwrap_or_default();
        let what = if r.contains("saturates") {
            "saturates"
        } else if r.contains("tracking error") {
            "tracking error"
        } else if r.contains("torque–speed envelope") {
            "beyond its envelope"
        } else if r.contains("loses steps") {
            "asks past its pull-out"
        } else if r.contains("slips") {
            "slips"
        } else if r.starts_with("path deviation") {
            out.push("path deviation".to_string());
            continue;
        } else {
            r
        };
        out.push(format!("{joint} {what}"));
    }
    if out.is_empty() { "-".into() } else { out.join(", ") }
}
