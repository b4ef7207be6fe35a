//! Stopping a run from outside (Ctrl-C, SIGTERM, SIGHUP), cleanly: the loop polls a flag,
//! finishes its recorders, and every file is complete.

use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A shared "please stop" flag, which remembers the signal that raised it; optionally with a
/// [`StopFlag::with_poll`] question asked at every look at it.
#[derive(Clone, Default)]
pub struct StopFlag(Arc<AtomicUsize>, Option<Poll>);

/// A question asked at every look at a flag: should it be raised now?
type Poll = Arc<dyn Fn() -> bool + Send + Sync>;

impl std::fmt::Debug for StopFlag {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("StopFlag")
            .field(&self.0)
            .field(&self.1.is_some())
            .finish()
    }
}

/// SIGINT's number, what [`StopFlag::raise`] records.
const SIGINT: usize = 2;

impl StopFlag {
    /// A flag nobody has raised.
    pub fn new() -> Self {
        Self::default()
    }

    /// The process-wide flag raised by Ctrl-C (SIGINT), SIGTERM (what `timeout`, Slurm and
    /// Kubernetes send) and SIGHUP (a closed terminal). The handlers are installed on the first
    /// call; later calls return the same flag.
    pub fn ctrl_c() -> StopFlag {
        static FLAG: OnceLock<StopFlag> = OnceLock::new();
        FLAG.get_or_init(|| {
            let flag = StopFlag::new();
            // the handler only stores the signal's number (async-signal-safe); if one cannot
            // be installed, that signal keeps its default behaviour
            for signal in signals() {
                let _ = signal_hook::flag::register_usize(signal, flag.0.clone(), signal as usize);
            }
            flag
        })
        .clone()
    }

    /// Asks whoever polls the flag to stop (as Ctrl-C does).
    pub fn raise(&self) {
        let _ = self.0.compare_exchange(0, SIGINT, Ordering::Relaxed, Ordering::Relaxed);
    }

    /// A flag that also asks `poll` at every [`StopFlag::is_raised`] and is raised when it
    /// says so (the Python binding looks for Ctrl-C there, on the thread that may see it).
    pub fn with_poll(poll: impl Fn() -> bool + Send + Sync + 'static) -> StopFlag {
        StopFlag(Arc::default(), Some(Arc::new(poll)))
    }

    /// Whether a stop was asked for.
    pub fn is_raised(&self) -> bool {
        if self.0.load(Ordering::Relaxed) != 0 {
            return true;
        }
        match &self.1 {
            Some(poll) if poll() => {
                self.raise();
                true
            }
            _ => false,
        }
    }

    /// The signal that raised the flag (SIGINT for [`StopFlag::raise`]), if raised.
    pub fn signal(&self) -> Option<i32> {
        match self.0.load(Ordering::Relaxed) {
            0 => None,
            s => Some(s as i32),
        }
    }
}

#[cfg(unix)]
fn signals() -> [i32; 3] {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    [SIGINT, SIGTERM, SIGHUP]
}

#[cfg(not(unix))]
fn signals() -> [i32; 2] {
    use signal_hook::consts::{SIGINT, SIGTERM};
    [SIGINT, SIGTERM]
}

/// The exit status of a process stopped by `signal`, as shells report it: 128 + its number
/// (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP).
pub fn exit_status(signal: i32) -> u8 {
    (128 + signal).clamp(0, 255) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_raised_flag_remembers_its_signal() {
        let flag = StopFlag::new();
        assert_eq!(flag.signal(), None);
        flag.raise();
        assert!(flag.is_raised());
        assert_eq!(flag.signal(), Some(2));
        assert_eq!(exit_status(2), 130);
        assert_eq!(exit_status(15), 143);
        assert_eq!(exit_status(1), 129);
    }
}
