//! Writing a plotters figure as `.svg` or `.png`, whole or not at all: shared by the run's plot
//! and the sweep's.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::plot::register_font;
use crate::atomic::{AtomicFile, write_atomically};
use crate::error::{Error, Result};

/// Something drawn on a plotters drawing area of any backend.
pub(super) trait Figure {
    /// Draws the whole figure on `root`.
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> std::result::Result<(), String>;
}

/// Draws `figure` at `size` (pixels) and writes it to `path`: SVG when `svg`, else an RGB PNG.
pub(super) fn write_figure(figure: &impl Figure, path: &Path, size: (u32, u32), svg: bool) -> Result<()> {
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
        return write_atomically(path, text.as_bytes());
    }
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        figure.draw_on(&root).map_err(failed)?;
        root.present().map_err(|e| failed(e.to_string()))?;
    }
    let mut file = AtomicFile::create(path)?;
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
