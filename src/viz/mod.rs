//! The visual side of a run: the 3D view in the browser (live and exported), and the plot.
//! Each output is a [`Recorder`](crate::output::Recorder); the simulation knows nothing else
//! about them.
//!
//! # API for the command line
//!
//! ```no_run
//! use faze4::viz::{HtmlExport, LiveView, PlotRecorder, DEFAULT_PORT};
//! # fn main() -> faze4::Result<()> {
//! // --view [--port P]: serve http://127.0.0.1:P (prints the address); a port in use is an
//! // Error::InvalidArgument for --port
//! let live = LiveView::start(DEFAULT_PORT)?;
//! let hold = live.handle(); // for --hold, if the recorder is boxed away below
//! // --html F (default on; --html none skips it): checks F's directory at once
//! let html = HtmlExport::new("faze4_run.html")?;
//! // --plot F.svg | F.png: checks the extension and directory at once
//! let plot = PlotRecorder::new("faze4_plot.svg")?;
//! let recorders: Vec<Box<dyn faze4::output::Recorder>> = vec![Box::new(live), Box::new(html), Box::new(plot)];
//! // … run the simulation with `recorders` (begin, record, finish) …
//! drop(recorders);
//! hold.hold(); // --hold: keep serving until Ctrl-C
//! # Ok(()) }
//! ```
//!
//! Meshes come with the model: load it with the `--package-path` directories
//! (`Model::from_urdf_file(path, &PackagePaths::with_ros_package_path(dirs))`), which resolves
//! every `package://` mesh. A mesh that was not found (or cannot be read) is drawn as a box,
//! and one line on stderr says so.
//!
//! | file | what |
//! |---|---|
//! | `mesh.rs` | STL (binary, ASCII) → indexed mesh with crease-aware normals; primitives; the compact form (u16 positions, oct-encoded normals) |
//! | `scene.rs` | model (+ board, reference path) → scene blob; samples → f32 records (world pose per visual frame) |
//! | `page.rs`, `web/` | the viewer page: `index.html` + `viewer.js` (WebGL2, orbit camera, timeline player), inlined |
//! | `html.rs` | [`HtmlExport`]: one self-contained HTML file, written on `finish`, whole or not at all |
//! | `live.rs` | [`LiveView`]: std::net HTTP server, page + scene + Server-Sent Events, paced to the wall clock |
//! | `plot.rs` | [`PlotRecorder`]: one SVG/PNG figure (plotters, embedded DejaVu Sans) |

mod html;
mod live;
pub mod mesh;
mod page;
mod plot;
pub mod scene;
mod util;

pub use html::HtmlExport;
pub use live::{LiveHandle, LiveView};
pub use plot::PlotRecorder;
pub use util::base64;

/// The live view's port unless `--port` says otherwise (the original's).
pub const DEFAULT_PORT: u16 = 7000;

/// Recording period of the 3D views (s): 50 samples per simulated second, the original's
/// publishing period.
pub const DEFAULT_PERIOD: f64 = 0.02;

/// Steps between records for a recording `period` and a step `dt` (at least 1).
fn steps_per_record(period: f64, dt: f64) -> usize {
    if dt > 0.0 && period > 0.0 {
        ((period / dt).round() as usize).max(1)
    } else {
        1
    }
}
