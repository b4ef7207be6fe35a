//! Stopping a run from outside (Ctrl-C, SIGTERM, SIGHUP), cleanly: the loop polls a flag,
//! finishes its recorders, and every file is complete. Before anything watches the process's
//! flag (while a command reads and parses its inputs, loads its model, retimes a path: nothing
//! is written yet, and nothing would look at the flag), a signal ends the process at once, with
//! one line on stderr and the signal's status ([`StopFlag::ctrl_c`], [`StopFlag::watch`]). A
//! closed stdout (`faze4 … | head`) raises the flag as SIGPIPE would ([`stdout_closed`]).

use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

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
/// SIGPIPE's number, what [`stdout_closed`] records.
pub const SIGPIPE: i32 = 13;

/// The process's flag ([`StopFlag::ctrl_c`]), once its handlers are installed.
static PROCESS: OnceLock<StopFlag> = OnceLock::new();
/// Whether something watches the process's flag: until then a signal ends the process.
static WATCHED: AtomicBool = AtomicBool::new(false);

impl StopFlag {
    /// A flag nobody has raised.
    pub fn new() -> Self {
        Self::default()
    }

    /// The process-wide flag raised by Ctrl-C (SIGINT), SIGTERM (what `timeout`, Slurm and
    /// Kubernetes send) and SIGHUP (a closed terminal). The handlers are installed on the first
    /// call; later calls return the same flag. Until the flag is watched ([`StopFlag::watch`],
    /// [`StopFlag::is_raised`]), a signal ends the process at once: `faze4: stopped by SIGTERM
    /// before the run began; nothing is written` on stderr and 128 + its number (a parse, a
    /// load or a retime has nothing to finish, and would not look at the flag until it ends).
    pub fn ctrl_c() -> StopFlag {
        PROCESS
            .get_or_init(|| {
                let flag = StopFlag::new();
                // the handlers store the signal's number in the flag; a thread of signal_hook's
                // (its iterator: the handler only wakes it) ends the process if nothing watches
                // the flag yet. If a handler cannot be installed, that signal keeps its default
                // behaviour
                for signal in signals() {
                    let _ = signal_hook::flag::register_usize(signal, flag.0.clone(), signal as usize);
                }
                if let Ok(mut arrived) = signal_hook::iterator::Signals::new(signals()) {
                    std::thread::spawn(move || {
                        for signal in arrived.forever() {
                            if !WATCHED.load(Ordering::SeqCst) {
                                let _ = std::io::Write::write_all(&mut std::io::stderr(), unwatched_line(signal));
                                std::process::exit(exit_status(signal).into());
                            }
                        }
                    });
                }
                flag
            })
            .clone()
    }

    /// Says that the flag is watched from now on: a signal raises it instead of ending the
    /// process ([`StopFlag::ctrl_c`]). Called before anything exists that a stop must finish
    /// (a temporary output file, a run's first step); [`StopFlag::is_raised`] calls it too.
    pub fn watch(&self) {
        if PROCESS.get().is_some_and(|p| Arc::ptr_eq(&p.0, &self.0)) {
            WATCHED.store(true, Ordering::SeqCst);
        }
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

    /// Whether a stop was asked for (the flag is watched from now on: [`StopFlag::watch`]).
    pub fn is_raised(&self) -> bool {
        self.watch();
        self.asked()
    }

    /// Whether a stop was asked for, the flag left unwatched: a look from work that has nothing
    /// to finish (a retime's timing), which a signal on the command line ends at once instead
    /// ([`StopFlag::ctrl_c`]); a flag raised by hand or by its poll (Python's Ctrl-C) stops it.
    pub fn asked(&self) -> bool {
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

/// The process's stdout is closed (a write failed with a broken pipe: `faze4 … | head` once
/// `head` has its lines): the process's flag, if installed, is raised as SIGPIPE would, so that
/// the run ends at its next look, quietly, with SIGPIPE's status (141).
pub fn stdout_closed() {
    if let Some(flag) = PROCESS.get() {
        let _ = flag
            .0
            .compare_exchange(0, SIGPIPE as usize, Ordering::Relaxed, Ordering::Relaxed);
    }
}

/// The line a signal writes when it ends the process before anything watched the flag.
fn unwatched_line(signal: i32) -> &'static [u8] {
    match signal {
        2 => b"faze4: interrupted before the run began; nothing is written\n",
        15 => b"faze4: stopped by SIGTERM before the run began; nothing is written\n",
        1 => b"faze4: stopped by SIGHUP before the run began; nothing is written\n",
        _ => b"faze4: stopped by a signal before the run began; nothing is written\n",
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
