//! Stopping a run from outside (Ctrl-C), cleanly: the loop polls a flag, finishes its
//! recorders, and every file is complete.

use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

/// A shared "please stop" flag.
#[derive(Clone, Debug, Default)]
pub struct StopFlag(Arc<AtomicBool>);

impl StopFlag {
    /// A flag nobody has raised.
    pub fn new() -> Self {
        Self::default()
    }

    /// The process-wide flag raised by Ctrl-C (SIGINT/SIGTERM). The handler is installed on the
    /// first call; later calls return the same flag.
    pub fn ctrl_c() -> StopFlag {
        static FLAG: OnceLock<StopFlag> = OnceLock::new();
        FLAG.get_or_init(|| {
            let flag = StopFlag::new();
            let raised = flag.clone();
            // if a handler cannot be installed, Ctrl-C keeps its default behaviour
            let _ = ctrlc::set_handler(move || raised.raise());
            flag
        })
        .clone()
    }

    /// Asks whoever polls the flag to stop.
    pub fn raise(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether a stop was asked for.
    pub fn is_raised(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}
