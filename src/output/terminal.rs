//! What a run prints: a banner with the model and the gains, a line every print period of
//! simulated time (0.5 s unless the run is long or `--print-period` says otherwise), and the
//! summary.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

use super::format::{joint_header, row, text_row};
use crate::choice::Choice;
use crate::control::FeedForward;
use crate::error::{Words, escape_controls, in_words, quoted, shortest};
use crate::geometry::{ClearanceGeometry, ClearanceReport};
use crate::model::{JointKind, ToolChoice};
use crate::sim::{MotorSummary, Reason, Recorder, Ringing, RunInfo, Sample, Summary, Verdict, percent};
use crate::traj::{Interpolation, Playback};

/// Simulated time between progress lines (s), unless a run asks for another.
pub const PRINT_PERIOD: f64 = 0.5;
/// A run shows a progress bar once it has taken this long (and stderr is a terminal).
const BAR_AFTER: Duration = Duration::from_secs(1);
/// Time between two redraws of the bar.
const BAR_REDRAW: Duration = Duration::from_millis(100);

/// Prints to stdout; for runs longer than a second, also a progress bar on stderr when stderr is
/// a terminal.
pub struct Terminal {
    debug: bool,
    /// How the lines name options (`--tool-link` or `tool_link`).
    words: Words,
    /// Simulated time between progress lines (s).
    print_period: f64,
    dof: usize,
    /// Per joint, whether it is prismatic (its rows are in m, not rad); empty for none.
    prismatic: Vec<bool>,
    steps: usize,
    dt: f64,
    bar: Option<Bar>,
}

/// The progress bar's state.
struct Bar {
    started: Instant,
    drawn: Option<Instant>,
}

impl Terminal {
    /// A row naming each joint's unit: `revolute` for a revolute or continuous joint,
    /// `prismatic` for a prismatic one.
    fn unit_row(&self, label: &str, revolute: &str, prismatic: &str) -> String {
        text_row(
            label,
            self.prismatic
                .iter()
                .map(|&p| if p { prismatic } else { revolute }.to_string()),
        )
    }

    /// A printer with a progress line every `print_period` s of simulated time; `debug` adds τ,
    /// the tracking error, v and g(q) to every progress line; `words`: how its lines name options.
    pub fn new(debug: bool, print_period: f64, words: Words) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| Bar {
            started: Instant::now(),
            drawn: None,
        });
        Self {
            debug,
            words,
            print_period,
            dof: 0,
            prismatic: Vec::new(),
            steps: 0,
            dt: 0.0,
            bar,
        }
    }

    /// Erases the bar (before a line is printed, and at the end).
    fn clear_bar(&mut self) {
        if let Some(bar) = self.bar.as_mut().filter(|b| b.drawn.is_some()) {
            let _ = write!(std::io::stderr().lock(), "\r\x1b[2K");
            bar.drawn = None;
        }
    }

    fn draw_bar(&mut self, step: usize) {
        let Some(bar) = self.bar.as_mut() else { return };
        let now = Instant::now();
        let elapsed = now - bar.started;
        if elapsed < BAR_AFTER || bar.drawn.is_some_and(|d| now - d < BAR_REDRAW) {
            return;
        }
        let done = step as f64 / self.steps.max(1) as f64;
        let width = 30;
        let full = (done * width as f64).round() as usize;
        let left = elapsed.as_secs_f64() * (1.0 - done) / done.max(1e-9);
        let _ = write!(
            std::io::stderr().lock(),
            "\r\x1b[2K[{}{}] {:3.0}%  t = {:.1} / {:.1} s  ~{:.*} s left",
            "#".repeat(full),
            "-".repeat(width - full),
            done * 100.0,
            step as f64 * self.dt,
            self.steps as f64 * self.dt,
            if left < 10.0 { 1 } else { 0 },
            left
        );
        bar.drawn = Some(now);
    }
}

/// Where the banner says the model came from: its format and source (`urdf PATH`,
/// `xacro PATH, NAME:=VALUE`, `mjcf PATH`; the source alone for a model built in memory).
fn origin(m: &crate::model::Model) -> String {
    match m.format.is_empty() {
        true => m.source.clone(),
        false => format!("{} {}", m.format, m.source),
    }
}

/// The banner's line of what reading the model mapped onto faze4's terms or left out, each with
/// the number of elements concerned (`None` when nothing was: a URDF, a xacro file), the
/// options it names in `words`.
fn mapped_line(m: &crate::model::Model, words: Words) -> Option<String> {
    if m.mapped.is_empty() {
        return None;
    }
    let mapped: Vec<String> = (m.mapped.iter())
        .map(|x| format!("{} → {} ({})", x.from, in_words(&x.to, words), x.items.len()))
        .collect();
    Some(format!("[faze4] mapped from {}: {}", m.format, mapped.join(" · ")))
}

/// A figure of the banner for people: `x` to 9 significant digits, written as short as that
/// allows (a duration of 9894 steps of 0.2 ms reads `1.9788`, not its sum's
/// `1.9788000000000001`).
pub fn for_people(x: f64) -> String {
    let rounded: f64 = format!("{x:.8e}").parse().unwrap_or(x);
    format!("{rounded}")
}

/// A control rate for people: "5 kHz", "1 kHz", "250 Hz".
fn rate(hz: f64) -> String {
    if hz >= 1e3 {
        format!("{} kHz", (hz / 1e3 * 1e3).round() / 1e3)
    } else {
        format!("{} Hz", (hz * 1e3).round() / 1e3)
    }
}

/// The banner's line on a time-stamped trajectory: its points, their interpolation and why,
/// where the arm starts and how it reaches the first point (options named in `words`).
fn playback_line(p: &Playback, words: Words) -> String {
    let why = match (p.interpolation_forced, p.interpolation) {
        (true, _) => "`interpolation`",
        (false, Interpolation::Linear) => "its points give positions",
        (false, Interpolation::Cubic) => "its points give velocities",
        (false, Interpolation::Quintic) => "its points give accelerations",
    };
    let approach = shortest(p.approach_s);
    let start = match (p.start_given, p.approach_s > 0.0) {
        (false, false) => "from the first point".to_string(),
        (false, true) => format!("from the first point's positions, held {approach} s until its time"),
        (true, true) => format!("from `start`, reaching the first point at {approach} s"),
        (true, false) => "from `start`, the first point commanded at once (t = 0)".to_string(),
    };
    let line = format!(
        "[faze4] trajectory: {} point{}, {} ({why}) · {start}",
        p.points,
        if p.points == 1 { "" } else { "s" },
        p.interpolation.word()
    );
    in_words(&line, words)
}

/// Prints `line` on stdout, its control and bidirectional characters escaped: a name read
/// from a file (robot, link, joint, path) can neither start a new line nor reorder this one.
fn out(line: &str) -> crate::Result<()> {
    // a closed stdout (`faze4 … | head`) is not the run's failure: it ends the run at its next
    // look at the stop flag, quietly (sim::stdout_closed); a full one is said by the last lines
    if let Err(e) = writeln!(std::io::stdout().lock(), "{}", escape_controls(line))
        && e.kind() == std::io::ErrorKind::BrokenPipe
    {
        crate::sim::stdout_closed();
    }
    Ok(())
}

/// The banner's line naming the joints a drive of their own moves (a stepper, a servo), on
/// which the PD's gains and feed-forward printed above do not act; `None` when the PD drives
/// every joint.
fn drives_line(drives: &[crate::sim::JointDrive]) -> Option<String> {
    let mut by_drive: Vec<(&str, Vec<String>)> = Vec::new();
    for (i, drive) in drives.iter().enumerate() {
        let word = drive.word();
        if word == crate::sim::DriveMode::Pd.word() {
            continue;
        }
        match by_drive.iter_mut().find(|(w, _)| *w == word) {
            Some((_, joints)) => joints.push(format!("J{}", i + 1)),
            None => by_drive.push((word, vec![format!("J{}", i + 1)])),
        }
    }
    (!by_drive.is_empty()).then(|| {
        let named: Vec<String> = (by_drive.iter())
            .map(|(word, joints)| format!("{} driven by the {word}", joints.join(", ")))
            .collect();
        format!(
            "own drive             {}, not the PD: its kp, kd and feed-forward above do not act on them",
            named.join("; ")
        )
    })
}

impl Recorder for Terminal {
    fn period(&self) -> f64 {
        self.print_period
    }

    fn begin(&mut self, run: &RunInfo) -> crate::Result<()> {
        let m = run.model;
        self.dof = m.dof();
        self.prismatic = match m.joints.iter().any(|j| j.kind == JointKind::Prismatic) {
            true => m.joints.iter().map(|j| j.kind == JointKind::Prismatic).collect(),
            false => Vec::new(),
        };
        self.steps = run.steps;
        self.dt = run.dt;
        let g = m.gravity.z;
        out(&format!(
            "[faze4] {} · {} ({}) · {} dof · gravity {} · Δt {} ms ({}) · {} s = {} steps",
            run.command,
            m.name,
            origin(m),
            m.dof(),
            if g == 0.0 {
                "off".to_string()
            } else {
                format!("{} m/s²", for_people(g))
            },
            for_people(run.dt * 1e3),
            rate(1.0 / run.dt),
            for_people(run.steps as f64 * run.dt),
            run.steps
        ))?;
        if let Some(line) = mapped_line(m, self.words) {
            out(&line)?;
        }
        // how a default tool was chosen, said only where it is not the chain's obvious one
        let how = match m.default_tool() {
            (f, ToolChoice::DeepestCommonAncestor) if f == run.tool_frame => in_words(
                " (deepest common ancestor of the deepest leaves; `tool_link` to choose)",
                self.words,
            ),
            _ => String::new(),
        };
        out(&format!(
            "[faze4] tool {}{how} · {}",
            m.frame(run.tool_frame).name,
            match run.feedforward {
                FeedForward::None => "gravity feed-forward off",
                FeedForward::Gravity => "gravity feed-forward on",
                FeedForward::Full => "full feed-forward (the command's inverse dynamics)",
            }
        ))?;
        if let Some(p) = run.playback {
            out(&playback_line(p, self.words))?;
        }
        let gains = run.gains;
        out(&joint_header(m.dof()))?;
        out(&row("torque limit (N·m)", gains.effort.iter().copied()))?;
        out(&row("eff. inertia (kg·m²)", gains.effective_inertia.iter().copied()))?;
        out(&row("kp", gains.kp.iter().copied()))?;
        out(&row("kd", gains.kd.iter().copied()))?;
        out(&format!(
            "{}   (the rule keeps b ≤ 0.4; one joint alone diverges near 4 − 2·Δt·kd/I)",
            row("b = Δt²·kp/I", gains.stiffness_b(run.dt))
        ))?;
        if let Some(s) = &gains.stability {
            out(&format!(
                "coupled loop          b_max = Δt²·λmax(M⁻¹Kp) {:.3} · b_kd = Δt·λmax(M⁻¹Kd) {:.3} · spectral radius {:.3}{}",
                s.b_max,
                s.b_kd,
                s.spectral_radius,
                if s.scaled {
                    " · gains scaled down for the coupled arm"
                } else {
                    ""
                }
            ))?;
        }
        if let Some(line) = drives_line(run.drives) {
            out(&line)?;
        }
        if self.prismatic.is_empty() {
            // degrees to 0.01: a −8e-15 from sin(π) is 0
            return out(&row(
                "start pose (deg)",
                run.start_q
                    .iter()
                    .map(|q| (q.to_degrees() * 100.0).round() / 100.0 + 0.0),
            ));
        }
        // with a prismatic joint, each joint's unit is said: degrees and millimetres to 0.01
        out(&self.unit_row("start pose unit", "deg", "mm"))?;
        out(&row(
            "start pose (deg | mm)",
            (run.start_q.iter().zip(&self.prismatic))
                .map(|(&q, &p)| (if p { q * 1e3 } else { q.to_degrees() } * 100.0).round() / 100.0 + 0.0),
        ))?;
        out(&self.unit_row("unit of rad rows", "rad", "m"))
    }

    fn record(&mut self, s: &Sample) -> crate::Result<()> {
        self.clear_bar();
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
        self.draw_bar(s.step);
        Ok(())
    }

    fn finish(&mut self, s: &Summary) -> crate::Result<()> {
        self.clear_bar();
        out(&format!("[summary]{}", &joint_header(self.dof)[9..]))?;
        if !self.prismatic.is_empty() {
            out(&self.unit_row("unit of rad rows", "rad", "m"))?;
        }
        out(&row("max track. err (rad)", s.max_tracking_error_rad.iter().copied()))?;
        out(&text_row(
            "saturation (% steps)",
            s.saturation_pct.iter().map(|&p| percent(p)),
        ))?;
        out(&row("max speed (rad/s)", s.max_speed.iter().copied()))?;
        if s.velocity_limit_pct.iter().any(Option::is_some) {
            out(&row("speed limit (rad/s)", s.velocity_limit.iter().copied()))?;
            // a joint without a limit shows "-"
            out(&text_row(
                "over speed limit",
                (s.velocity_limit_pct.iter()).map(|p| p.map_or("-".to_string(), percent)),
            ))?;
        }
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
        if let Some(c) = &s.clearance {
            out(&clearance_line(c, &s.verdict))?;
        }
        if let Some(motors) = &s.motors {
            for line in motor_table(motors) {
                out(&line)?;
            }
        }
        Ok(())
    }
}

/// The `--motors` table, one column per joint (`-` where a joint has no motor or a figure does
/// not apply): kind and drive, share of steps beyond the envelope (under `--drive stepper`: past
/// the torque–angle curve's peak), fastest shaft speed, RMS torque against the continuous
/// rating, when a stepper first lost steps, under `--drive stepper` the full steps it ends
/// off its command and its ringing, under `--drive servo` the largest duty each servo's loop
/// asked and when its protection first acted. Torques and speeds at the motor shaft.
pub fn motor_table(motors: &[Option<MotorSummary>]) -> Vec<String> {
    let cell = |f: &dyn Fn(&MotorSummary) -> Option<String>| per_motor(motors, f);
    let mut lines = vec![
        text_row("motor", cell(&|m| Some(m.kind.to_string()))),
        text_row("driven by", cell(&|m| Some(m.drive.to_string()))),
        text_row("beyond envelope", cell(&|m| Some(percent(m.envelope_pct)))),
        text_row(
            "max motor speed rad/s",
            cell(&|m| Some(format!("{:.1}", m.max_motor_speed))),
        ),
        text_row("RMS torque (N·m)", cell(&|m| Some(format!("{:.4}", m.rms_torque)))),
        text_row(
            "continuous (N·m)",
            cell(&|m| m.continuous_torque.map(|c| format!("{c:.4}"))),
        ),
        text_row(
            "loses steps at (s)",
            cell(&|m| {
                m.loses_steps_at
                    .map(|t| t.map_or("never".into(), |t| format!("{t:.3}")))
            }),
        ),
    ];
    if motors.iter().flatten().any(|m| m.steps_lost.is_some()) {
        lines.push(text_row(
            "full steps lost",
            cell(&|m| m.steps_lost.map(|n| n.to_string())),
        ));
    }
    if motors.iter().flatten().any(|m| m.ringing.is_some()) {
        let ringing = |f: fn(&Ringing) -> String| cell(&move |m: &MotorSummary| m.ringing.as_ref().map(f));
        lines.push(text_row("rings at (Hz)", ringing(|r| format!("{:.0}", r.natural_hz))));
        lines.push(text_row(
            "damping ratio",
            ringing(|r| format!("{:.3}", r.damping_ratio)),
        ));
        lines.push(text_row(
            "max lag (full steps)",
            ringing(|r| format!("{:.2}", r.max_lag_steps)),
        ));
    }
    if motors.iter().flatten().any(|m| m.servo.is_some()) {
        lines.push(text_row(
            "servo max duty",
            cell(&|m| m.servo.map(|s| percent(100.0 * s.max_duty))),
        ));
        lines.push(text_row(
            "servo trips at (s)",
            cell(&|m| {
                m.servo
                    .map(|s| s.trip.map_or("never".into(), |t| format!("{:.3}", t.t)))
            }),
        ));
    }
    lines
}

/// One text per joint: `f` of its motor's summary, `-` where it has no motor or `f` gives none.
pub(super) fn per_motor(motors: &[Option<MotorSummary>], f: &dyn Fn(&MotorSummary) -> Option<String>) -> Vec<String> {
    (motors.iter())
        .map(|m| m.as_ref().and_then(f).unwrap_or_else(|| "-".into()))
        .collect()
}

/// What a tolerance says about the true minimum over the samples, given the reported minimum
/// `min_m` (m): `true minimum ≥ 17.85 mm`; `intersecting` when the pair intersects there
/// (`min_m` ≤ 0: the exact meshes' 0, or the hulls' negative signed distance), where a bound
/// below zero would say nothing; and never below 0 otherwise, since intersections are decided
/// exactly whatever the tolerance (a pair that does not intersect is more than 0 apart).
pub(crate) fn true_minimum_bound(min_m: f64, tolerance_m: f64) -> String {
    if min_m <= 0.0 {
        "intersecting".into()
    } else {
        format!("true minimum ≥ {:.2} mm", (min_m - tolerance_m).max(0.0) * 1e3)
    }
}

/// The self-clearance for people, one line: the closest pair, its distance (mm; negative: the
/// hulls' penetration depth) and when; the pairs that intersect and from when (from the
/// verdict's [`Reason::Collides`]); the links not checked. E.g. `self-clearance (exact
/// meshes): 'podlaktica'–'hvataljka' 18.85 mm at t = 4.56 s`. With a tolerance, the reading
/// says it and the line ends with the bound it gives the true minimum: `self-clearance (meshes,
/// tolerance 1.00 mm): 'podlaktica'–'hvataljka' 18.85 mm at t = 4.56 s (true minimum ≥ 17.85
/// mm)`, or `(intersecting)` ([`true_minimum_bound`]).
pub fn clearance_line(c: &ClearanceReport, verdict: &Verdict) -> String {
    let what = match (c.geometry, c.tolerance_m > 0.0) {
        (ClearanceGeometry::Mesh, false) => "exact meshes".to_string(),
        (ClearanceGeometry::Hull, false) => "convex hulls".to_string(),
        (ClearanceGeometry::Mesh, true) => format!("meshes, tolerance {:.2} mm", c.tolerance_m * 1e3),
        (ClearanceGeometry::Hull, true) => format!("convex hulls, tolerance {:.2} mm", c.tolerance_m * 1e3),
    };
    let mut line = match (&c.links, c.min_m, c.t) {
        (Some([a, b]), Some(m), Some(t)) if c.tolerance_m > 0.0 => format!(
            "self-clearance ({what}): {}–{} {:.2} mm at t = {t:.2} s ({})",
            quoted(a),
            quoted(b),
            m * 1e3,
            true_minimum_bound(m, c.tolerance_m)
        ),
        (Some([a, b]), Some(m), Some(t)) => {
            format!(
                "self-clearance ({what}): {}–{} {:.2} mm at t = {t:.2} s",
                quoted(a),
                quoted(b),
                m * 1e3
            )
        }
        _ => format!("self-clearance ({what}): no pair checked"),
    };
    for reason in &verdict.reasons {
        if let Reason::Collides { pairs } = reason {
            let named: Vec<String> = (pairs.iter())
                .map(|p| {
                    format!(
                        "{}–{} from t = {:.2} s",
                        quoted(&p.links[0]),
                        quoted(&p.links[1]),
                        p.from_t
                    )
                })
                .collect();
            line += &format!(" · intersecting: {}", named.join(", "));
        }
    }
    if !c.unchecked.is_empty() {
        line += &format!(" · not checked: {}", c.unchecked.join(", "));
    }
    line
}

#[cfg(test)]
mod tests {
    #[test]
    fn banner_figures_are_rounded_for_people() {
        assert_eq!(super::for_people(9894.0 * 2e-4), "1.9788");
        assert_eq!(super::for_people(40000.0 * 2e-4), "8");
        assert_eq!(super::for_people(2e-4 * 1e3), "0.2");
        assert_eq!(super::for_people(-9.81), "-9.81");
        // figures that need their digits keep them
        assert_eq!(super::for_people(1.23456789), "1.23456789");
        assert_eq!(super::for_people(5e-5 * 1e3), "0.05");
    }
}
