//! The visual side of a run: the 3D view in the browser (live and exported), and the plot.
//! Each output is a [`Recorder`](crate::sim::Recorder); the simulation knows nothing else
//! about them.
//!
//! # API for the command line
//!
//! ```no_run
//! use faze4::sim::Recorder;
//! use faze4::viz::{DEFAULT_PORT, HtmlExport, LiveView, PlotRecorder};
//! # fn main() -> faze4::Result<()> {
//! # let stop = std::sync::atomic::AtomicBool::new(false);
//! // --view [--port P]: serves http://127.0.0.1:P at once and prints the address; a port in
//! // use is an Error::InvalidArgument for --port
//! let mut live = LiveView::start(DEFAULT_PORT)?;
//! // --html F (--html none: skip it): checks F's directory before the run
//! let mut html = HtmlExport::new("faze4_run.html")?;
//! // --plot F.svg | F.png: checks the extension and the directory before the run
//! let mut plot = PlotRecorder::new("faze4_plot.svg")?;
//! let mut recorders: Vec<&mut dyn Recorder> = vec![&mut live, &mut html, &mut plot];
//! // … run the simulation with `recorders` (begin, record, finish) …
//! drop(recorders);
//! // --hold: keep serving until Ctrl-C (with a Ctrl-C handler installed, poll its flag;
//! // without one, `live.hold()`)
//! live.hold_until(|| stop.load(std::sync::atomic::Ordering::Relaxed));
//! # Ok(()) }
//! ```
//!
//! The live view paces [`Recorder::record`](crate::sim::Recorder::record) to the wall
//! clock (sample t is shown t seconds after the first), so a run with `--view` takes its
//! simulated duration in real time. Recorders that are boxed away can leave a
//! [`LiveHandle`] (`live.handle()`) to hold the server with.
//!
//! Meshes come with the model: load it with the `--package-path` directories
//! (`Model::from_urdf_file(path, &PackagePaths::with_ros_package_path(dirs))`), which resolves
//! every `package://` mesh. The official Faze4 meshes are built into the binary
//! ([`crate::faze4::meshes`]): in a description faze4 bundles (or a byte-for-byte copy of
//! one), a reference to one of them that is not found on disk is drawn from the built-in copy.
//! Any other mesh that was not found (or cannot be read) is drawn as a
//! box, and one line on stderr says so.
//!
//! | file | what |
//! |---|---|
//! | `mesh.rs` | STL (binary, ASCII) → indexed mesh with crease-aware normals; primitives; the compact form (u16 positions, oct-encoded normals) |
//! | `scene.rs` | model (+ board, reference path) → scene blob; samples → f32 records (world pose per visual frame) |
//! | `page.rs`, `web/` | the viewer page: `index.html` + `viewer.js` (WebGL2, orbit camera, timeline player), inlined |
//! | `html.rs` | [`HtmlExport`]: one self-contained HTML file, written on `finish`, whole or not at all (`output::atomic`) |
//! | `live.rs` | [`LiveView`]: the recorder, paced to the wall clock |
//! | `server.rs` | the live view's std::net HTTP server on 127.0.0.1: page + scene + Server-Sent Events |
//! | `plot.rs` | [`PlotRecorder`]: one SVG/PNG figure (plotters, embedded DejaVu Sans) |
//! | `phase_plot.rs` | [`PhasePlot`]: retime's phase plane (ṡ against s: limits, profile, where they bind) |
//! | `sweep_plot.rs` | [`SweepPlot`]: a sweep's figures against the varied option, or heatmaps over two |

mod figure;
mod html;
mod live;
pub mod mesh;
mod motor_plot;
mod page;
mod phase_plot;
mod plot;
pub mod scene;
mod server;
mod sweep_plot;
mod util;

pub use html::HtmlExport;
pub use live::{LiveHandle, LiveView};
pub use motor_plot::MotorPlot;
pub use phase_plot::PhasePlot;
pub use plot::PlotRecorder;
pub use sweep_plot::SweepPlot;
pub use util::base64;

pub use crate::config::DEFAULT_PORT;

/// Recording period of the 3D views (s): 50 samples per simulated second, the original's
/// publishing period.
pub const DEFAULT_PERIOD: f64 = 0.02;
