//! `faze4 sweep --plot F.svg | F.png`: a sweep's figures against its varied option (per joint:
//! the largest tracking error, the saturated share of the steps; a shape's path deviation;
//! whether the arm follows), or, over two varied options, one heatmap each of the worst joint's
//! tracking error and saturation and of the verdict. Rows that failed to run are left out;
//! those that diverged show their figures up to the divergence.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::{FAMILY, Figure, PALETTE, TITLE_HEIGHT, chart, chart_area, range, titled, write_figure};
use crate::atomic::{Outputs, check_output_path};
use crate::error::{Error, Result};
use crate::sweep::{Grid, Outcome, Row};

const WIDTH: u32 = 1400;
const PANEL_HEIGHT: u32 = 360;
const FOLLOWS: RGBColor = RGBColor(44, 160, 44);
const CANNOT: RGBColor = RGBColor(214, 39, 40);

/// One run's figures, as the plot keeps them.
#[derive(Clone, Debug)]
struct Point {
    /// The run's index in the sweep.
    index: usize,
    values: Vec<f64>,
    /// Largest tracking error per joint (rad or m).
    error: Vec<f64>,
    /// Saturated share per joint (%).
    saturation: Vec<f64>,
    /// Largest path deviation (mm), shapes only.
    deviation: Option<f64>,
    follows: bool,
}

/// Collects a sweep's rows (their figures only) and draws the figure on [`SweepPlot::finish`],
/// written whole or not at all.
#[derive(Debug)]
pub struct SweepPlot {
    path: PathBuf,
    outputs: Outputs,
    svg: bool,
    grid: Grid,
    points: Vec<Point>,
}

impl Figure for SweepPlot {
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> std::result::Result<(), String> {
        self.draw(root)
    }
}

impl SweepPlot {
    /// A plot of a sweep over `grid` (one or two varied options) to `path`, `.svg` or `.png`;
    /// fails at once on another extension, a missing directory, or more than two options.
    pub fn new(path: &Path, grid: &Grid) -> Result<SweepPlot> {
        check_output_path(path, "`plot`")?;
        let svg = match path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .as_deref()
        {
            Some("svg") => true,
            Some("png") => false,
            _ => {
                return Err(Error::argument(
                    "`plot`",
                    format!("{}: the plot is written as .svg or .png", path.display()),
                ));
            }
        };
        if grid.axes.is_empty() || grid.axes.len() > 2 {
            return Err(Error::argument(
                "`plot`",
                format!("draws one or two varied options; this sweep varies {}", grid.axes.len()),
            ));
        }
        Ok(SweepPlot {
            path: path.to_path_buf(),
            outputs: Outputs::immediate(),
            svg,
            grid: grid.clone(),
            points: Vec::new(),
        })
    }

    /// Writes the figure as a file of `outputs` (it appears when they are committed) instead
    /// of on its own.
    pub fn within(mut self, outputs: &Outputs) -> SweepPlot {
        self.outputs = outputs.clone();
        self
    }

    /// Keeps `row`'s figures (a failed run has none).
    pub fn add(&mut self, row: &Row) {
        if let Outcome::Ran(s) = &row.outcome {
            self.points.push(Point {
                index: row.index,
                values: row.values.clone(),
                error: s.max_tracking_error_rad.clone(),
                saturation: s.saturation_pct.clone(),
                deviation: s.path_deviation_mm.as_ref().map(|d| d.max),
                follows: s.verdict.follows,
            });
        }
    }

    /// Draws and writes the figure.
    pub fn finish(self) -> Result<()> {
        let panels = self.panels();
        let size = (WIDTH, TITLE_HEIGHT + PANEL_HEIGHT * panels.div_ceil(2) as u32);
        write_figure(&self, &self.outputs, &self.path, size, self.svg)
    }

    fn has_deviation(&self) -> bool {
        self.points.iter().any(|p| p.deviation.is_some())
    }

    fn panels(&self) -> usize {
        3 + usize::from(self.has_deviation())
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> std::result::Result<(), String> {
        let names: Vec<&str> = self.grid.axes.iter().map(|a| a.name.as_str()).collect();
        let follow = self.points.iter().filter(|p| p.follows).count();
        let title = format!(
            "faze4 sweep over {} · {} runs, {follow} follow",
            names.join(" × "),
            self.points.len()
        );
        let body = titled(root, &title)?;
        let areas = body.split_evenly((self.panels().div_ceil(2), 2));
        if self.grid.axes.len() == 1 {
            self.draw_lines(&areas)
        } else {
            self.draw_heatmaps(&areas)
        }
    }

    /// One option: figures against its values.
    fn draw_lines<DB: DrawingBackend>(&self, areas: &[DrawingArea<DB, Shift>]) -> std::result::Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let name = &self.grid.axes[0].name;
        let x = range(self.points.iter().map(|p| p.values[0]));
        let dof = self.points.first().map_or(0, |p| p.error.len());
        type PerJoint = fn(&Point) -> &Vec<f64>;
        let per_joint: [(&str, PerJoint, f64); 2] = [
            ("largest tracking error (mrad)", |p| &p.error, 1e3),
            ("saturated steps (%)", |p| &p.saturation, 1.0),
        ];
        for (area, (caption, figure, unit)) in areas.iter().zip(per_joint) {
            let y = range(self.points.iter().flat_map(|p| figure(p).iter().map(move |v| v * unit)));
            let mut chart = chart(area, caption, name, x.clone(), y)?;
            for j in 0..dof {
                let colour = PALETTE[j % PALETTE.len()];
                let series = self
                    .points
                    .iter()
                    .map(|p| (p.values[0], figure(p)[j] * unit))
                    .filter(|(_, y)| y.is_finite());
                chart
                    .draw_series(LineSeries::new(series, colour.stroke_width(2)))
                    .map_err(e)?
                    .label(format!("J{}", j + 1))
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], colour.stroke_width(2)));
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(180, 180, 180))
                .label_font((FAMILY, 12))
                .draw()
                .map_err(e)?;
        }
        let mut verdicts = chart(
            &areas[2],
            "follows (1, green) or cannot (0, red)",
            name,
            x.clone(),
            -0.2..1.2,
        )?;
        verdicts
            .draw_series(self.points.iter().map(|p| {
                let (level, colour) = if p.follows { (1.0, FOLLOWS) } else { (0.0, CANNOT) };
                Circle::new((p.values[0], level), 4, colour.filled())
            }))
            .map_err(e)?;
        if self.has_deviation() {
            let y = range(self.points.iter().filter_map(|p| p.deviation).chain([0.0]));
            let mut chart = chart(&areas[3], "largest path deviation (mm)", name, x, y)?;
            let series = (self.points.iter())
                .filter_map(|p| p.deviation.map(|d| (p.values[0], d)))
                .filter(|(_, d)| d.is_finite());
            chart
                .draw_series(LineSeries::new(series, PALETTE[0].stroke_width(2)))
                .map_err(e)?;
        }
        Ok(())
    }

    /// Two options: a heatmap per figure, cells in the order of the values (first option
    /// across, second up).
    fn draw_heatmaps<DB: DrawingBackend>(&self, areas: &[DrawingArea<DB, Shift>]) -> std::result::Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let (a, b) = (&self.grid.axes[0], &self.grid.axes[1]);
        type Figure = fn(&Point) -> Option<f64>;
        let mut figures: Vec<(&str, Figure)> = vec![
            ("worst joint's tracking error (mrad)", |p| {
                Some(p.error.iter().copied().fold(0.0, f64::max) * 1e3)
            }),
            ("worst joint's saturated steps (%)", |p| {
                Some(p.saturation.iter().copied().fold(0.0, f64::max))
            }),
            ("follows (green) or cannot (red)", |p| {
                Some(f64::from(u8::from(p.follows)))
            }),
        ];
        if self.has_deviation() {
            figures.push(("largest path deviation (mm)", |p| p.deviation));
        }
        for (area, (caption, figure)) in areas.iter().zip(figures) {
            let verdict = caption.starts_with("follows");
            let cells: Vec<(usize, usize, f64)> = (self.points.iter())
                .filter_map(|p| {
                    figure(p).map(|v| (p.index / b.values.len() % a.values.len(), p.index % b.values.len(), v))
                })
                .collect();
            let finite = cells.iter().map(|c| c.2).filter(|v| v.is_finite());
            let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
            let caption = match verdict || !lo.is_finite() {
                true => caption.to_string(),
                false => format!("{caption}: {lo:.3} (dark) … {hi:.3} (bright)"),
            };
            let x = -0.5..a.values.len() as f64 - 0.5;
            let mut chart = chart_area(area, &caption, x, -0.5..b.values.len() as f64 - 0.5)?;
            let label = |values: &[f64], x: f64| {
                let i = x.round();
                match i >= 0.0 && (i as usize) < values.len() && (x - i).abs() < 1e-9 {
                    true => format!("{}", values[i as usize]),
                    false => String::new(),
                }
            };
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc(a.name.as_str())
                .y_desc(b.name.as_str())
                .x_labels(a.values.len().min(12))
                .y_labels(b.values.len().min(12))
                .x_label_formatter(&|x| label(&a.values, *x))
                .y_label_formatter(&|y| label(&b.values, *y))
                .label_style((FAMILY, 12))
                .draw()
                .map_err(|e| e.to_string())?;
            chart
                .draw_series(cells.iter().map(|&(i, j, v)| {
                    let colour = match (verdict, v.is_finite()) {
                        (true, _) if v > 0.5 => FOLLOWS,
                        (true, _) => CANNOT,
                        (false, false) => RGBColor(0, 0, 0),
                        (false, true) => heat(if hi > lo { (v - lo) / (hi - lo) } else { 0.0 }),
                    };
                    let (x, y) = (i as f64, j as f64);
                    Rectangle::new([(x - 0.5, y - 0.5), (x + 0.5, y + 0.5)], colour.filled())
                }))
                .map_err(e)?;
        }
        Ok(())
    }
}

/// A dark-blue → teal → yellow colour for `s` in [0, 1] (close to viridis).
fn heat(s: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 3] = [(68.0, 1.0, 84.0), (33.0, 145.0, 140.0), (253.0, 231.0, 37.0)];
    let s = s.clamp(0.0, 1.0) * 2.0;
    let k = (s.floor() as usize).min(1);
    let f = s - k as f64;
    let mix = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}
