//! `--plot-motors F.svg | F.png`: the sizing plot (plotters). Per joint with a motor, the run's
//! operating points (|ω_m|, |τ_m|) at the motor shaft over its torque–speed envelope, the
//! continuous torque line where the motor has a rating, and the RMS point (RMS speed, RMS
//! torque), as motor sizing application notes draw them (docs/motors.md).

use std::path::PathBuf;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::{FAMILY, Figure, PALETTE, TITLE_HEIGHT, chart, err, titled, write_figure};
use crate::atomic::{Outputs, check_output_path};
use crate::control::Motor;
use crate::error::{Error, Result};
use crate::sim::{Recorder, RunInfo, Sample, Summary};

/// Sampling period of the operating points (s).
const PERIOD: f64 = 0.04;
const PANEL: (u32, u32) = (700, 340);
/// Points along a drawn envelope.
const ENVELOPE_POINTS: usize = 200;
const ENVELOPE: RGBColor = RGBColor(60, 60, 60);
const CONTINUOUS: RGBColor = RGBColor(200, 40, 40);

/// Collects the operating points and draws the sizing plot on [`Recorder::finish`].
#[derive(Debug)]
pub struct MotorPlot {
    path: PathBuf,
    outputs: Outputs,
    svg: bool,
    title: String,
    /// Per motored joint: its index, name, motor and ratio.
    joints: Vec<(usize, String, Motor, f64)>,
    /// Per motored joint, the samples' (|ω_m|, |τ_m|).
    points: Vec<Vec<(f64, f64)>>,
    /// Per motored joint, (RMS speed, RMS torque) once the run is over.
    rms: Vec<(f64, f64)>,
    /// Per motored joint, its continuous rating.
    continuous: Vec<Option<f64>>,
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
            continuous: Vec::new(),
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
            points.push(((ratio * s.v[*i]).abs(), (s.tau[*i] / k).abs()));
        }
        Ok(())
    }

    fn finish(&mut self, summary: &Summary) -> Result<()> {
        let motors = summary.motors.as_deref().unwrap_or(&[]);
        self.rms = (self.joints.iter().zip(&self.points))
            .map(|((i, ..), points)| {
                let speed = points.iter().map(|p| p.0 * p.0).sum::<f64>() / points.len().max(1) as f64;
                let torque = motors.get(*i).and_then(Option::as_ref).map_or(0.0, |m| m.rms_torque);
                (speed.sqrt(), torque)
            })
            .collect();
        self.continuous = (self.joints.iter()).map(|(_, _, m, _)| m.continuous_torque).collect();
        let rows = self.joints.len().div_ceil(2).max(1) as u32;
        let size = (2 * PANEL.0, TITLE_HEIGHT + rows * PANEL.1);
        write_figure(self, &self.outputs, &self.path, size, self.svg)
    }
}

impl Figure for MotorPlot {
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> std::result::Result<(), String> {
        let body = titled(root, &self.title)?;
        let rows = self.joints.len().div_ceil(2).max(1);
        let panels = body.split_evenly((rows, 2));
        for (k, (panel, ((i, name, m, _), points))) in
            panels.iter().zip(self.joints.iter().zip(&self.points)).enumerate()
        {
            // x to past the fastest point and where the envelope has halved; y to the largest
            // torque
            let fastest = points.iter().map(|p| p.0).fold(0.0, f64::max);
            let reach = match &m.envelope {
                crate::control::Envelope::Dc { no_load_speed, .. } => *no_load_speed,
                crate::control::Envelope::Stepper { curve } => curve.last().map_or(0.0, |p| p[0]),
            };
            let top = m.envelope.max_torque();
            let halved = (0..=ENVELOPE_POINTS)
                .map(|s| reach * s as f64 / ENVELOPE_POINTS as f64)
                .find(|&w| m.envelope.bounds(w).1 <= 0.5 * top)
                .unwrap_or(reach);
            let x_end = 1.1 * fastest.max(halved).max(1e-6);
            let strongest = points.iter().map(|p| p.1).fold(m.envelope.max_torque(), f64::max);
            let y_end = 1.1 * strongest.max(self.continuous[k].unwrap_or(0.0)).max(1e-9);
            let caption = format!("J{} {name}: {} (|τ_m| N·m against |ω_m| rad/s)", i + 1, m.label);
            let mut chart = chart(panel, &caption, "|ω_m| (rad/s)", 0.0..x_end, 0.0..y_end)?;
            let envelope = (0..=ENVELOPE_POINTS).map(|s| {
                let w = x_end * s as f64 / ENVELOPE_POINTS as f64;
                (w, m.envelope.bounds(w).1.max(0.0))
            });
            chart
                .draw_series(LineSeries::new(envelope, ENVELOPE.stroke_width(2)))
                .map_err(err)?
                .label("envelope")
                .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], ENVELOPE.stroke_width(2)));
            let colour = PALETTE[i % 6];
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 2, colour.mix(0.5).filled())))
                .map_err(err)?
                .label("operating points")
                .legend(move |(x, y)| Circle::new((x + 8, y), 3, colour.filled()));
            if let Some(c) = self.continuous[k] {
                chart
                    .draw_series(LineSeries::new([(0.0, c), (x_end, c)], CONTINUOUS.stroke_width(1)))
                    .map_err(err)?
                    .label(format!("continuous {c} N·m"))
                    .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], CONTINUOUS.stroke_width(1)));
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
                .label_font((FAMILY, 12))
                .draw()
                .map_err(err)?;
        }
        Ok(())
    }
}
