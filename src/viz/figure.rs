//! What the run's plot and the sweep's share: writing a plotters figure as `.svg` or `.png`,
//! whole or not at all; the embedded font, the joint colours, axis ranges.

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::atomic::Outputs;
use crate::error::{Error, Result, escape_controls};

/// Something drawn on a plotters drawing area of any backend.
pub(super) trait Figure {
    /// Draws the whole figure on `root`.
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> std::result::Result<(), String>;
}

/// Draws `figure` at `size` (pixels) and writes it to `path`, a file of `outputs`: SVG when
/// `svg`, else an RGB PNG.
pub(super) fn write_figure(
    figure: &impl Figure,
    outputs: &Outputs,
    path: &Path,
    size: (u32, u32),
    svg: bool,
) -> Result<()> {
    register_font();
    let failed = |e: String| Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(format!("drawing the plot: {e}")),
    };
    if svg {
        let mut text = String::new();
        {
            let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
            figure.draw_on(&root).map_err(failed)?;
            root.present().map_err(|e| failed(e.to_string()))?;
        }
        return outputs.write(path, text.as_bytes());
    }
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        figure.draw_on(&root).map_err(failed)?;
        root.present().map_err(|e| failed(e.to_string()))?;
    }
    let mut file = outputs.create(path)?;
    let encoded = (|| {
        let mut encoder = png::Encoder::new(file.writer(), size.0, size.1);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&rgb)?;
        writer.finish()
    })();
    encoded.map_err(|e| file.error(std::io::Error::other(e)))?;
    file.commit()
}

/// The embedded font every figure is drawn with (DejaVu Sans).
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
/// The family name it is registered under.
pub(super) const FAMILY: &str = "sans-serif";

/// Registers the embedded font under [`FAMILY`], once per process.
fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_err() {
            panic!("the embedded DejaVu Sans font does not load");
        }
    });
}

/// Joint colours (J1..J6, then repeating).
pub(super) const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// `[lo, hi]` of `values` with a margin, never empty.
pub(super) fn range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return -1.0..1.0;
    }
    let pad = ((hi - lo) * 0.08).max(0.005);
    (lo - pad)..(hi + pad)
}

/// Height of every figure's title band (px).
pub(super) const TITLE_HEIGHT: u32 = 44;

/// A drawing error as text.
pub(super) fn err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> String {
    e.to_string()
}

/// Clears `root` to white and writes `title` in the band of [`TITLE_HEIGHT`] at its top, its
/// control and bidirectional characters escaped (it quotes names read from files); the area
/// below it.
pub(super) fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> std::result::Result<DrawingArea<DB, Shift>, String> {
    root.fill(&WHITE).map_err(err)?;
    let (top, body) = root.split_vertically(TITLE_HEIGHT);
    let title = escape_controls(title);
    top.draw(&Text::new(title, (16, 12), (FAMILY, 20).into_font().color(&BLACK)))
        .map_err(err)?;
    Ok(body)
}

/// A chart with f64 axes.
pub(super) type Chart<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>;

/// A captioned chart on `area` over `x` × `y`, its x axis named `x_name`, with the figures'
/// font and light grid.
pub(super) fn chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    x_name: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
) -> std::result::Result<Chart<'a, DB>, String> {
    let mut chart = chart_area(area, caption, x, y)?;
    chart
        .configure_mesh()
        .x_desc(x_name)
        .label_style((FAMILY, 12))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(chart)
}

/// The figures' captioned chart area on `area` over `x` × `y`, margins and label room included,
/// before its grid is drawn; the caption's control and bidirectional characters escaped.
pub(super) fn chart_area<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
) -> std::result::Result<Chart<'a, DB>, String> {
    ChartBuilder::on(area)
        .caption(escape_controls(caption), (FAMILY, 15))
        .margin(8)
        .margin_right(20)
        .x_label_area_size(40)
        .y_label_area_size(64)
        .build_cartesian_2d(x, y)
        .map_err(|e| e.to_string())
}
