//! retime's `--plot F.svg | F.png`: the phase plane (plotters) as TOPP users know it: ṡ
//! against s, the speed-limit curve, each joint's torque-limit curve, the controllable sets'
//! upper edge, the chosen profile, and a mark on the profile wherever a limit binds, in the
//! colour of its joint (docs/retime.md).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::{FAMILY, Figure, PALETTE, TITLE_HEIGHT, chart_area, err, titled, write_figure};
use crate::atomic::{Outputs, check_output_path};
use crate::error::Result;
use crate::retime::{Limit, Retimed};

const SIZE: (u32, u32) = (1200, 700 + TITLE_HEIGHT);
const PROFILE: RGBColor = RGBColor(0, 0, 0);
const SPEED_LIMIT: RGBColor = RGBColor(200, 30, 30);
const CONTROLLABLE: RGBColor = RGBColor(150, 150, 150);
/// The y axis reaches this multiple of the profile's top speed (the limit curves above it are
/// cut).
const HEADROOM: f64 = 1.6;

/// The phase-plane figure of one retimed path.
#[derive(Debug)]
pub struct PhasePlot {
    path: PathBuf,
    outputs: Outputs,
    svg: bool,
}

impl PhasePlot {
    /// A figure to `path` (`.svg` or `.png`); fails at once on another extension or a missing
    /// directory.
    pub fn new(path: impl Into<PathBuf>) -> Result<PhasePlot> {
        let path = path.into();
        check_output_path(&path, "`plot`")?;
        let svg = super::plot::is_svg(&path, "`plot`")?;
        Ok(PhasePlot {
            path,
            outputs: Outputs::immediate(),
            svg,
        })
    }

    /// Writes the figure as a file of `outputs`.
    pub fn within(mut self, outputs: &Outputs) -> PhasePlot {
        self.outputs = outputs.clone();
        self
    }

    /// The file this figure writes.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Draws `retimed` (the robot `robot`, its joints `joints`, with `margin` left for the
    /// feedback) and writes the file.
    pub fn write(&self, retimed: &Retimed, robot: &str, joints: &[String], margin: f64) -> Result<()> {
        let figure = Drawing {
            retimed,
            joints,
            title: format!(
                "faze4 · {robot} · retime · {:.3} s · margin {} % · phase plane",
                retimed.profile.duration(),
                margin * 100.0
            ),
        };
        write_figure(&figure, &self.outputs, &self.path, SIZE, self.svg)
    }
}

struct Drawing<'a> {
    retimed: &'a Retimed,
    joints: &'a [String],
    title: String,
}

impl Figure for Drawing<'_> {
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> std::result::Result<(), String> {
        let body = titled(root, &self.title)?;
        let plane = &self.retimed.phase_plane();
        let top = plane.profile.iter().copied().fold(0.0, f64::max).max(1e-9) * HEADROOM;
        let length = plane.s.last().copied().unwrap_or(1.0).max(1e-9);
        let caption = "ṡ (path units/s) against s: profile (black), speed limit (red, dashed), torque limit per joint (colour), controllable (grey); marks where a limit binds (● torque, ■ speed)";
        let mut chart = chart_area(&body, caption, 0.0..length, 0.0..top)?;
        chart
            .configure_mesh()
            .x_desc("s (path length, rad or m)")
            .y_desc("ṡ")
            .label_style((FAMILY, 12))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(|e| e.to_string())?;
        let below = |v: &f64| v.is_finite() && *v <= top;
        // a curve cut where it leaves the chart
        let mut curve = |values: &[f64],
                         style: ShapeStyle,
                         dashed: bool,
                         label: Option<String>|
         -> std::result::Result<(), String> {
            let mut first = true;
            let mut run: Vec<(f64, f64)> = Vec::new();
            let points = plane.s.iter().copied().zip(values.iter().copied());
            for (s, v) in points.chain([(f64::NAN, f64::NAN)]) {
                if below(&v) {
                    run.push((s, v));
                    continue;
                }
                if run.len() > 1 {
                    let series = match dashed {
                        true => chart.draw_series(DashedLineSeries::new(std::mem::take(&mut run), 8, 5, style)),
                        false => chart.draw_series(LineSeries::new(std::mem::take(&mut run), style)),
                    }
                    .map_err(err)?;
                    if let (true, Some(label)) = (first, &label) {
                        series
                            .label(label.clone())
                            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], style));
                        first = false;
                    }
                }
                run.clear();
            }
            Ok(())
        };
        curve(
            &plane.controllable,
            CONTROLLABLE.stroke_width(1),
            false,
            Some("controllable".into()),
        )?;
        for (j, values) in plane.torque_limit.iter().enumerate() {
            let name = self.joints.get(j).map_or(String::new(), |n| format!(" {n}"));
            curve(
                values,
                PALETTE[j % 6].stroke_width(1),
                false,
                Some(format!("J{}{name} torque", j + 1)),
            )?;
        }
        curve(&plane.profile, PROFILE.stroke_width(2), false, Some("profile".into()))?;
        curve(
            &plane.speed_limit,
            SPEED_LIMIT.stroke_width(2),
            true,
            Some("speed limit".into()),
        )?;
        // a mark at each segment's start where its limit binds
        for (i, b) in self.retimed.bindings.iter().enumerate() {
            if !b.binds() {
                continue;
            }
            let at = (plane.s[i], plane.profile[i]);
            let colour = b.joint.map_or(SPEED_LIMIT, |j| PALETTE[j.0 % 6]);
            match b.limit {
                Limit::TorqueUpper | Limit::TorqueLower => {
                    chart.draw_series([Circle::new(at, 3, colour.filled())]).map_err(err)?;
                }
                _ => {
                    chart
                        .draw_series([EmptyElement::at(at) + Rectangle::new([(-3, -3), (3, 3)], colour.filled())])
                        .map_err(err)?;
                }
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .label_font((FAMILY, 12))
            .draw()
            .map_err(err)
    }
}
