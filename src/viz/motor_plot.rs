//! `--plot-motors F.svg | F.png`: the sizing plot (plotters). Per joint with a motor, the run's
//! operating points at the motor shaft over its torque–speed envelope, as motor sizing notes
//! draw them (docs/motors.md): speed |ω_m| across, the torque along the motion τ_m·sgn(ω_m)
//! up, so motoring (> 0) and braking (< 0) stay apart, each with its own envelope limit; the
//! torque the motor gave, and apart from it, where the controller asked for more, the demand
//! before the clip with a line to what it got; the continuous torque where the motor has a
//! rating (a stepper has none: its constant-current driver heats it the same at any torque);
//! the RMS point (RMS speed, RMS torque).

use std::path::PathBuf;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::{FAMILY, Figure, PALETTE, TITLE_HEIGHT, chart_area, err, titled, write_figure};
use crate::atomic::{Outputs, check_output_path};
use crate::control::Motor;
use crate::error::{Error, Result};
use crate::sim::{ENVELOPE_MARGIN, Recorder, RunInfo, Sample, Summary};

/// Sampling period of the operating points (s).
const PERIOD: f64 = 0.04;
const PANEL: (u32, u32) = (700, 380);
/// Points along a drawn envelope.
const ENVELOPE_POINTS: usize = 200;
const ENVELOPE: RGBColor = RGBColor(60, 60, 60);
const CONTINUOUS: RGBColor = RGBColor(200, 40, 40);
const DEMAND: RGBColor = RGBColor(200, 40, 40);

/// One operating point at the shaft: |ω_m| (rad/s), the torque given along the motion and the
/// torque asked for along it (N·m).
#[derive(Clone, Copy, Debug)]
struct Point {
    speed: f64,
    given: f64,
    asked: f64,
}

/// Collects the operating points and draws the sizing plot on [`Recorder::finish`].
#[derive(Debug)]
pub struct MotorPlot {
    path: PathBuf,
    outputs: Outputs,
    svg: bool,
    title: String,
    /// Per motored joint: its index, name, motor and ratio.
    joints: Vec<(usize, String, Motor, f64)>,
    /// Per motored joint, the samples' operating points.
    points: Vec<Vec<Point>>,
    /// Per motored joint, (RMS speed, RMS torque) once the run is over.
    rms: Vec<(f64, f64)>,
}

impl MotorPlot {
    /// A sizing plot to `path` (`.svg` or `.png`); fails at once on another extension or a
    /// missing directory.
    pub fn new(path: impl Into<PathBuf>) -> Result<MotorPlot> {
        let path = path.into();
        check_output_path(&path, "`plot_motors`")?;
        let svg = super::plot::is_svg(&path, "`plot_motors`")?;
        Ok(MotorPlot {
            path,
            outputs: Outputs::immediate(),
            svg,
            title: String::new(),
            joints: Vec::new(),
            points: Vec::new(),
            rms: Vec::new(),
        })
    }

    /// Writes the figure as a file of `outputs`.
    pub fn within(mut self, outputs: &Outputs) -> MotorPlot {
        self.outputs = outputs.clone();
        self
    }
}

impl Recorder for MotorPlot {
    fn period(&self) -> f64 {
        PERIOD
    }

    fn begin(&mut self, run: &RunInfo) -> Result<()> {
        let Some(motors) = run.motors else {
            return Err(Error::option("plot_motors", "draws the motors: add `motors`"));
        };
        self.title = format!("faze4 · {} · {} · motor operating points", run.model.name, run.command);
        self.joints = (motors.iter().enumerate())
            .filter_map(|(i, m)| {
                let joint = &run.model.joints[i];
                m.clone().map(|m| (i, joint.name.clone(), m, joint.gear_ratio))
            })
            .collect();
        self.points = vec![Vec::new(); self.joints.len()];
        Ok(())
    }

    fn record(&mut self, s: &Sample) -> Result<()> {
        for ((i, _, m, ratio), points) in self.joints.iter().zip(&mut self.points) {
            let k = ratio * m.efficiency;
            let omega = ratio * s.v[*i];
            // along the motion: the sign of the speed (at standstill, as given)
            let along = if omega < 0.0 { -1.0 } else { 1.0 };
            points.push(Point {
                speed: omega.abs(),
                given: along * s.tau[*i] / k,
                asked: along * s.tau_raw[*i] / k,
            });
        }
        Ok(())
    }

    fn finish(&mut self, summary: &Summary) -> Result<()> {
        let motors = summary.motors.as_deref().unwrap_or(&[]);
        self.rms = (self.joints.iter().zip(&self.points))
            .map(|((i, ..), points)| {
                let speed = points.iter().map(|p| p.speed * p.speed).sum::<f64>() / points.len().max(1) as f64;
                let torque = motors.get(*i).and_then(Option::as_ref).map_or(0.0, |m| m.rms_torque);
                (speed.sqrt(), torque)
            })
            .collect();
        let rows = self.joints.len().div_ceil(2).max(1) as u32;
        let size = (2 * PANEL.0, TITLE_HEIGHT + rows * PANEL.1);
        write_figure(self, &self.outputs, &self.path, size, self.svg)
    }
}

/// Whether the demand went beyond what was given (by more than round-off).
fn clipped(p: &Point) -> bool {
    (p.asked - p.given).abs() > ENVELOPE_MARGIN * p.given.abs().max(1e-12)
}

impl Figure for MotorPlot {
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> std::result::Result<(), String> {
        let body = titled(root, &self.title)?;
        let rows = self.joints.len().div_ceil(2).max(1);
        let panels = body.split_evenly((rows, 2));
        for (k, (panel, ((i, name, m, _), points))) in
            panels.iter().zip(self.joints.iter().zip(&self.points)).enumerate()
        {
            // x to past the fastest point and where the envelope has halved; y over both
            // envelope limits and every point, given or asked
            let fastest = points.iter().map(|p| p.speed).fold(0.0, f64::max);
            let reach = m.envelope.top_speed();
            let top = m.envelope.max_torque();
            let halved = (0..=ENVELOPE_POINTS)
                .map(|s| reach * s as f64 / ENVELOPE_POINTS as f64)
                .find(|&w| m.envelope.bounds(w).1 <= 0.5 * top)
                .unwrap_or(reach);
            let x_end = 1.1 * fastest.max(halved).max(1e-6);
            let (lo, hi) = (points.iter().flat_map(|p| [p.given, p.asked]))
                .chain((0..=ENVELOPE_POINTS).flat_map(|s| {
                    let (lo, hi) = m.envelope.bounds(x_end * s as f64 / ENVELOPE_POINTS as f64);
                    [lo, hi]
                }))
                .chain(m.continuous_torque.into_iter().flat_map(|c| [c, -c]))
                .fold((0.0f64, 0.0f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
            let pad = 0.08 * (hi - lo).max(1e-9);
            let caption = format!("J{} {name}: {}", i + 1, m.label);
            let mut chart = chart_area(panel, &caption, 0.0..x_end, (lo - pad)..(hi + pad))?;
            chart
                .configure_mesh()
                .x_desc("motor speed |ω_m| (rad/s)")
                .y_desc("torque along the motion τ_m·sgn(ω_m) (N·m)")
                .label_style((FAMILY, 12))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()
                .map_err(|e| e.to_string())?;
            // the zero line: motoring above, braking below
            chart
                .draw_series(LineSeries::new(
                    [(0.0, 0.0), (x_end, 0.0)],
                    BLACK.mix(0.4).stroke_width(1),
                ))
                .map_err(err)?;
            let limit = |upper: bool| {
                (0..=ENVELOPE_POINTS).map(move |s| {
                    let w = x_end * s as f64 / ENVELOPE_POINTS as f64;
                    let (lo, hi) = m.envelope.bounds(w);
                    (w, if upper { hi } else { lo })
                })
            };
            chart
                .draw_series(LineSeries::new(limit(true), ENVELOPE.stroke_width(2)))
                .map_err(err)?
                .label("envelope: motoring (above), braking (below)")
                .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], ENVELOPE.stroke_width(2)));
            chart
                .draw_series(LineSeries::new(limit(false), ENVELOPE.stroke_width(2)))
                .map_err(err)?;
            let colour = PALETTE[i % 6];
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|p| Circle::new((p.speed, p.given), 2, colour.mix(0.5).filled())),
                )
                .map_err(err)?
                .label("given (after the clip)")
                .legend(move |(x, y)| Circle::new((x + 8, y), 3, colour.filled()));
            let asked: Vec<&Point> = points.iter().filter(|p| clipped(p)).collect();
            if !asked.is_empty() {
                chart
                    .draw_series(
                        asked
                            .iter()
                            .map(|p| PathElement::new([(p.speed, p.given), (p.speed, p.asked)], DEMAND.mix(0.5))),
                    )
                    .map_err(err)?;
                chart
                    .draw_series(
                        asked
                            .iter()
                            .map(|p| Circle::new((p.speed, p.asked), 3, DEMAND.stroke_width(1))),
                    )
                    .map_err(err)?
                    .label("asked (before the clip)")
                    .legend(|(x, y)| Circle::new((x + 8, y), 3, DEMAND.stroke_width(1)));
            }
            match m.continuous_torque {
                Some(c) => {
                    for level in [c, -c] {
                        chart
                            .draw_series(LineSeries::new(
                                [(0.0, level), (x_end, level)],
                                CONTINUOUS.stroke_width(1),
                            ))
                            .map_err(err)?;
                    }
                    chart
                        .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                        .map_err(err)?
                        .label(format!("continuous ±{c} N·m"))
                        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], CONTINUOUS.stroke_width(1)));
                }
                None => {
                    if let Some(note) = m.envelope.no_continuous_note() {
                        chart
                            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                            .map_err(err)?
                            .label(note)
                            .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], WHITE));
                    }
                }
            }
            let (ws, ts) = self.rms[k];
            chart
                .draw_series([Cross::new((ws, ts), 7, BLACK.stroke_width(3))])
                .map_err(err)?
                .label(format!("RMS ({ws:.1} rad/s, {ts:.3} N·m)"))
                .legend(|(x, y)| Cross::new((x + 8, y), 5, BLACK.stroke_width(2)));
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(200, 200, 200))
                .label_font((FAMILY, 11))
                .draw()
                .map_err(err)?;
        }
        Ok(())
    }
}
