//! `--view`: the run in the browser as it happens, served by [`super::server`] at
//! `http://127.0.0.1:PORT`. This recorder paces the run to the wall clock and hands each
//! sample to the server; the simulation never touches a socket.

use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::json;

use super::scene::{SampleEncoder, Scene};
use super::server::Server;
use super::util::f32_bytes;
use super::{DEFAULT_PERIOD, page};
use crate::error::Result;
use crate::sim::{Recorder, RunInfo, Sample, Summary};

/// The live view: a [`Recorder`] that serves the run at `http://127.0.0.1:PORT`.
///
/// The server runs from [`LiveView::start`] until the last of this value and its
/// [`LiveHandle`]s is dropped, or forever under [`LiveView::hold`].
pub struct LiveView {
    server: Arc<Server>,
    period: f64,
    realtime: bool,
    encoder: Option<SampleEncoder>,
    /// Wall-clock instant of simulated time 0.
    start: Option<Instant>,
    scratch: Vec<f32>,
}

/// A handle on a running live view's server (cheap to clone, `Send`): its address, and
/// [`LiveHandle::hold`] after the run. Keeps the server running while it exists.
#[derive(Clone)]
pub struct LiveHandle {
    server: Arc<Server>,
}

impl LiveView {
    /// Starts serving on `127.0.0.1:port` (0: any free port) and prints the address on stderr.
    /// A port already in use is an [`Error::InvalidArgument`](crate::Error::InvalidArgument) for `--port`.
    pub fn start(port: u16) -> Result<LiveView> {
        let server = Server::start(port, page::render("faze4 · live view", &json!({"mode": "live"})))?;
        let view = LiveView {
            server: Arc::new(server),
            period: DEFAULT_PERIOD,
            realtime: true,
            encoder: None,
            start: None,
            scratch: Vec::new(),
        };
        crate::error::to_stderr(&format!("viz: live view at {}", view.url()));
        Ok(view)
    }

    /// Whether [`Recorder::record`] waits for the wall clock (default: yes, sample t is
    /// published t seconds after the first sample). Off, samples go out as fast as the
    /// simulation makes them.
    pub fn with_realtime(mut self, realtime: bool) -> LiveView {
        self.realtime = realtime;
        self
    }

    /// Publishes a sample every `period` seconds of simulated time (default
    /// [`DEFAULT_PERIOD`]).
    pub fn with_period(mut self, period: f64) -> LiveView {
        self.period = period;
        self
    }

    /// `http://127.0.0.1:PORT`.
    pub fn url(&self) -> String {
        format!("http://{}", self.server.addr())
    }

    /// The port served.
    pub fn port(&self) -> u16 {
        self.server.addr().port()
    }

    /// A handle that keeps the server running and can [`LiveHandle::hold`] it, e.g. when
    /// this recorder is boxed into a list of recorders.
    pub fn handle(&self) -> LiveHandle {
        LiveHandle {
            server: self.server.clone(),
        }
    }

    /// Keeps serving until the process is interrupted (Ctrl-C with its default action).
    /// Returns only if the server stopped by itself. See [`LiveHandle::hold_until`] when a
    /// Ctrl-C handler is installed.
    pub fn hold(&self) {
        self.handle().hold()
    }

    /// Keeps serving until `stop()` returns true (polled 10 times a second; e.g. the
    /// command line's Ctrl-C flag) or the server stopped by itself.
    pub fn hold_until(&self, stop: impl Fn() -> bool) {
        self.handle().hold_until(stop)
    }

    /// [`LiveHandle::hold_line`].
    pub fn hold_line(&self) -> String {
        self.handle().hold_line()
    }

    /// [`LiveHandle::serve_until`].
    pub fn serve_until(&self, stop: impl Fn() -> bool) {
        self.handle().serve_until(stop)
    }
}

impl LiveHandle {
    /// `http://127.0.0.1:PORT`.
    pub fn url(&self) -> String {
        format!("http://{}", self.server.addr())
    }

    /// Keeps serving until the process is interrupted (Ctrl-C with its default action: the
    /// run's files are already written). Returns only if the server stopped by itself.
    pub fn hold(&self) {
        self.hold_until(|| false)
    }

    /// Keeps serving until `stop()` returns true (polled 10 times a second; e.g. the
    /// command line's Ctrl-C flag, since a Ctrl-C handler keeps Ctrl-C from ending the
    /// process) or the server stopped by itself.
    pub fn hold_until(&self, stop: impl Fn() -> bool) {
        crate::error::to_stderr(&self.hold_line());
        self.serve_until(stop)
    }

    /// What [`LiveHandle::hold_until`] prints first: `viz: serving http://127.0.0.1:PORT until
    /// Ctrl-C`. The command line prints it before its verdict and then calls
    /// [`LiveHandle::serve_until`], so that the verdict stays the last line.
    pub fn hold_line(&self) -> String {
        format!("viz: serving {} until Ctrl-C", self.url())
    }

    /// [`LiveHandle::hold_until`] without its line.
    pub fn serve_until(&self, stop: impl Fn() -> bool) {
        while !stop() {
            if self.server.is_finished() {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Recorder for LiveView {
    fn period(&self) -> f64 {
        self.period
    }

    fn begin(&mut self, run: &RunInfo) -> Result<()> {
        let scene = Scene::for_run(run, self.period);
        scene.warn_fallbacks();
        let encoder = SampleEncoder::new(run.model, &scene.slots).collision_pairs(run.collision_pairs);
        self.server.publish_run(encoder.stride(), scene.encode());
        self.encoder = Some(encoder);
        self.start = None;
        Ok(())
    }

    fn reads_intersections(&self) -> bool {
        true
    }

    fn record(&mut self, sample: &Sample) -> Result<()> {
        let Some(encoder) = &mut self.encoder else {
            return Ok(());
        };
        if self.realtime {
            let now = Instant::now();
            let start = *self.start.get_or_insert_with(|| {
                now.checked_sub(Duration::from_secs_f64(sample.t.max(0.0)))
                    .unwrap_or(now)
            });
            if let Some(due) = start.checked_add(Duration::from_secs_f64(sample.t.max(0.0)))
                && due > now
            {
                std::thread::sleep(due - now);
            }
        }
        self.scratch.clear();
        encoder.push(sample, &mut self.scratch);
        self.server.publish_samples(&f32_bytes(&self.scratch));
        Ok(())
    }

    fn finish(&mut self, summary: &Summary) -> Result<()> {
        let json = serde_json::to_string(summary).expect("summary JSON");
        self.server.publish_end(json);
        Ok(())
    }
}
