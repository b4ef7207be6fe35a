//! `--plot F.svg | F.png`: one figure of the run (plotters). Per joint: angle against command,
//! torque against its limit; then the tracking error of every joint, and for shapes the tool's
//! distance to the reference path (otherwise the tool position).
//!
//! Text is laid out with DejaVu Sans, embedded in the binary (`assets/fonts/`, its licence
//! beside it), so neither format needs a system font or library: SVG names the font family
//! for the viewer, PNG is rasterised here and encoded with the `png` crate.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::{Chart, FAMILY, Figure, PALETTE, TITLE_HEIGHT, chart, err, range, titled, write_figure};
use crate::atomic::{Outputs, check_output_path};
use crate::control::{FeedForward, Motor};
use crate::error::{Error, Result};
use crate::sim::Summary;
use crate::sim::{Recorder, RunInfo, Sample};
use crate::spatial::Vec3;
use crate::traj::shape::distance_to_closed_path;

/// Recording period of the plot (s).
const PERIOD: f64 = 0.01;
const WIDTH: u32 = 1400;
const ROW_HEIGHT: u32 = 220;

/// Whether a figure to `path` is an SVG (`.svg`) rather than a PNG (`.png`); another
/// extension is an error naming `option`.
pub(crate) fn is_svg(path: &std::path::Path, option: &str) -> Result<bool> {
    match path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .as_deref()
    {
        Some("svg") => Ok(true),
        Some("png") => Ok(false),
        _ => Err(Error::argument(
            option,
            format!("{}: the plot is written as .svg or .png", path.display()),
        )),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Svg,
    Png,
}

/// Collects the run and draws the figure on [`Recorder::finish`], written whole or not at all.
#[derive(Debug)]
pub struct PlotRecorder {
    path: PathBuf,
    outputs: Outputs,
    format: Format,
    /// Sampling period (s of simulated time).
    period: f64,
    title: String,
    joints: Vec<String>,
    effort: Vec<f64>,
    reference: Option<Vec<Vec3>>,
    t: Vec<f64>,
    /// Per sample: q, q_cmd, τ (dof each).
    q: Vec<Vec<f64>>,
    q_cmd: Vec<Vec<f64>>,
    tau: Vec<Vec<f64>>,
    tool: Vec<Vec3>,
    /// `--motors`: per joint its motor and ratio, and per sample v (its envelope's speed).
    motors: Vec<Option<(Motor, f64)>>,
    v: Vec<Vec<f64>>,
}

impl PlotRecorder {
    /// A plot to `path`, an `.svg` or `.png` file. Fails at once (before the run) on another
    /// extension or a missing directory.
    pub fn new(path: impl Into<PathBuf>) -> Result<PlotRecorder> {
        let path = path.into();
        check_output_path(&path, "`plot`")?;
        let format = if is_svg(&path, "`plot`")? {
            Format::Svg
        } else {
            Format::Png
        };
        Ok(PlotRecorder {
            path,
            outputs: Outputs::immediate(),
            format,
            period: PERIOD,
            title: String::new(),
            joints: Vec::new(),
            effort: Vec::new(),
            reference: None,
            t: Vec::new(),
            q: Vec::new(),
            q_cmd: Vec::new(),
            tau: Vec::new(),
            tool: Vec::new(),
            motors: Vec::new(),
            v: Vec::new(),
        })
    }

    /// Samples every `period` seconds of simulated time instead of every 0.01 s (the command
    /// line passes `--record-period`, so the figure's path deviation is the summary's).
    pub fn with_period(mut self, period: f64) -> PlotRecorder {
        self.period = period;
        self
    }

    /// Writes the figure as a file of `outputs` (it appears when they are committed) instead
    /// of on its own.
    pub fn within(mut self, outputs: &Outputs) -> PlotRecorder {
        self.outputs = outputs.clone();
        self
    }

    /// The file this recorder writes.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Recorder for PlotRecorder {
    fn period(&self) -> f64 {
        self.period
    }

    fn begin(&mut self, run: &RunInfo) -> Result<()> {
        self.title = format!(
            "faze4 · {} · {} · Δt = {} s{}",
            run.model.name,
            run.command,
            run.dt,
            match run.feedforward {
                FeedForward::Gravity => "",
                FeedForward::None => " · no feed-forward",
                FeedForward::Full => " · full feed-forward",
            }
        );
        self.joints = run.model.joints.iter().map(|j| j.name.clone()).collect();
        self.effort = run.gains.effort.clone();
        self.reference = run.reference_path.map(|p| p.to_vec());
        self.motors = (run.motors.into_iter().flatten().zip(&run.model.joints))
            .map(|(m, j)| m.clone().map(|m| (m, j.gear_ratio)))
            .collect();
        Ok(())
    }

    fn record(&mut self, s: &Sample) -> Result<()> {
        self.t.push(s.t);
        self.q.push(s.q.to_vec());
        self.q_cmd.push(s.q_cmd.to_vec());
        self.tau.push(s.tau.to_vec());
        if !self.motors.is_empty() {
            self.v.push(s.v.to_vec());
        }
        self.tool.push(s.tool);
        Ok(())
    }

    fn finish(&mut self, _summary: &Summary) -> Result<()> {
        let rows = self.joints.len() as u32 + 1;
        let size = (WIDTH, TITLE_HEIGHT + rows * ROW_HEIGHT);
        write_figure(self, &self.outputs, &self.path, size, self.format == Format::Svg)
    }
}

const COMMAND: RGBColor = RGBColor(255, 175, 95);
const MEASURED: RGBColor = RGBColor(31, 90, 180);
const LIMIT: RGBColor = RGBColor(110, 110, 110);

type Area<'a, DB> = DrawingArea<DB, Shift>;

impl Figure for PlotRecorder {
    fn draw_on<DB: DrawingBackend>(&self, root: &Area<DB>) -> std::result::Result<(), String> {
        self.draw(root)
    }
}

impl PlotRecorder {
    /// The whole figure: a title, then per joint its angle and its torque, then the tracking
    /// error of every joint and the path deviation (or the tool position).
    fn draw<DB: DrawingBackend>(&self, root: &Area<DB>) -> std::result::Result<(), String> {
        let body = titled(root, &self.title)?;
        let n = self.joints.len();
        let panels = body.split_evenly((n + 1, 2));
        let t_end = self.t.last().copied().unwrap_or(1.0).max(1e-6);
        for j in 0..n {
            self.draw_angle(&panels[2 * j], j, t_end)?;
            self.draw_torque(&panels[2 * j + 1], j, t_end)?;
        }
        self.draw_tracking_error(&panels[2 * n], t_end)?;
        match &self.reference {
            Some(path) => self.draw_path_deviation(&panels[2 * n + 1], path, t_end),
            None => self.draw_tool_position(&panels[2 * n + 1], t_end),
        }
    }

    /// Joint j's values of `of` over the samples.
    fn column(&self, j: usize, of: &[Vec<f64>]) -> Vec<f64> {
        of.iter().map(|v| v[j]).collect()
    }

    fn joint_name(&self, j: usize) -> String {
        format!("J{} {}", j + 1, self.joints[j])
    }

    /// Joint j's angle against its command.
    fn draw_angle<DB: DrawingBackend>(&self, area: &Area<DB>, j: usize, t_end: f64) -> std::result::Result<(), String> {
        let (q, q_cmd) = (self.column(j, &self.q), self.column(j, &self.q_cmd));
        let y = range(q.iter().chain(&q_cmd).copied());
        let caption = format!("{}: q (blue), q_cmd (orange), rad", self.joint_name(j));
        let mut chart = new_chart(area, &caption, t_end, y)?;
        for (series, colour, width) in [(&q_cmd, COMMAND, 3), (&q, MEASURED, 1)] {
            chart
                .draw_series(LineSeries::new(
                    self.t.iter().copied().zip(series.iter().copied()),
                    colour.stroke_width(width),
                ))
                .map_err(err)?;
        }
        Ok(())
    }

    /// Joint j's torque against its limit.
    fn draw_torque<DB: DrawingBackend>(
        &self,
        area: &Area<DB>,
        j: usize,
        t_end: f64,
    ) -> std::result::Result<(), String> {
        let tau = self.column(j, &self.tau);
        let limit = self.effort.get(j).copied().filter(|x| x.is_finite());
        // under --motors: the envelope at the joint's speed, r·η·bounds(r·q̇), within ±E
        let envelope: Option<Vec<(f64, f64)>> = self.motors.get(j).and_then(Option::as_ref).map(|(m, ratio)| {
            let e = limit.unwrap_or(f64::INFINITY);
            (self.v.iter())
                .map(|v| {
                    let (lo, hi) = m.joint_bounds(*ratio, v[j]);
                    (lo.max(-e), hi.min(e))
                })
                .collect()
        });
        let y = range(tau.iter().copied().chain(limit.into_iter().flat_map(|l| [l, -l])));
        let caption = match (&envelope, limit) {
            (Some(_), _) => format!("{}: τ (N·m), its motor's envelope at q̇ (grey)", self.joint_name(j)),
            (None, Some(l)) => format!("{}: τ (N·m), limit ±{l} (grey)", self.joint_name(j)),
            (None, None) => format!("{}: τ (N·m), unlimited", self.joint_name(j)),
        };
        let mut chart = new_chart(area, &caption, t_end, y)?;
        if let Some(bounds) = &envelope {
            for side in [0, 1] {
                let line = self
                    .t
                    .iter()
                    .zip(bounds)
                    .map(|(&t, b)| (t, if side == 0 { b.0 } else { b.1 }));
                chart
                    .draw_series(LineSeries::new(line, LIMIT.stroke_width(1)))
                    .map_err(err)?;
            }
        } else if let Some(l) = limit {
            for level in [l, -l] {
                chart
                    .draw_series(LineSeries::new([(0.0, level), (t_end, level)], LIMIT.stroke_width(1)))
                    .map_err(err)?;
            }
        }
        chart
            .draw_series(LineSeries::new(
                self.t.iter().copied().zip(tau.iter().copied()),
                PALETTE[j % 6].stroke_width(1),
            ))
            .map_err(err)?;
        Ok(())
    }

    /// The tracking error of every joint, in one panel.
    fn draw_tracking_error<DB: DrawingBackend>(&self, area: &Area<DB>, t_end: f64) -> std::result::Result<(), String> {
        let errors: Vec<Vec<f64>> = (0..self.joints.len())
            .map(|j| {
                (self.q.iter().zip(&self.q_cmd))
                    .map(|(q, c)| (c[j] - q[j]) * 1e3)
                    .collect()
            })
            .collect();
        let y = range(errors.iter().flatten().copied());
        let mut chart = new_chart(area, "tracking error q_cmd − q (mrad)", t_end, y)?;
        for (j, e) in errors.iter().enumerate() {
            chart
                .draw_series(LineSeries::new(
                    self.t.iter().copied().zip(e.iter().copied()),
                    PALETTE[j % 6].stroke_width(1),
                ))
                .map_err(err)?
                .label(format!("J{}", j + 1))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], PALETTE[j % 6].stroke_width(2)));
        }
        legend(&mut chart).map_err(err)
    }

    /// A shape's tool distance to its reference path.
    fn draw_path_deviation<DB: DrawingBackend>(
        &self,
        area: &Area<DB>,
        path: &[Vec3],
        t_end: f64,
    ) -> std::result::Result<(), String> {
        let dev: Vec<f64> = self
            .tool
            .iter()
            .map(|p| distance_to_closed_path(p, path) * 1e3)
            .collect();
        let max = dev.iter().copied().fold(0.0, f64::max);
        let mean = dev.iter().sum::<f64>() / dev.len().max(1) as f64;
        let y = range(dev.iter().copied().chain([0.0]));
        let caption = format!("tool distance to the reference path (mm): max {max:.2}, mean {mean:.2}");
        let mut chart = new_chart(area, &caption, t_end, y)?;
        chart
            .draw_series(LineSeries::new(
                self.t.iter().copied().zip(dev.iter().copied()),
                MEASURED.stroke_width(1),
            ))
            .map_err(err)?;
        Ok(())
    }

    /// The tool position, when there is no reference path.
    fn draw_tool_position<DB: DrawingBackend>(&self, area: &Area<DB>, t_end: f64) -> std::result::Result<(), String> {
        let y = range(self.tool.iter().flat_map(|p| [p.x, p.y, p.z]));
        let mut chart = new_chart(area, "tool position (m)", t_end, y)?;
        for (a, label) in ["x", "y", "z"].into_iter().enumerate() {
            chart
                .draw_series(LineSeries::new(
                    self.t.iter().copied().zip(self.tool.iter().map(|p| p[a])),
                    PALETTE[a].stroke_width(1),
                ))
                .map_err(err)?
                .label(label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], PALETTE[a].stroke_width(2)));
        }
        legend(&mut chart).map_err(err)
    }
}

/// A chart over the run's time, 0 to `t_end` (s).
fn new_chart<'a, DB: DrawingBackend>(
    area: &'a Area<DB>,
    caption: &str,
    t_end: f64,
    y: std::ops::Range<f64>,
) -> std::result::Result<Chart<'a, DB>, String> {
    chart(area, caption, "t (s)", 0.0..t_end, y)
}

fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .label_font((FAMILY, 12))
        .draw()
}
