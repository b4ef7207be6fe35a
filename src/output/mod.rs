//! The run's text and file outputs, each a [`Recorder`](crate::sim::Recorder): the terminal
//! printer and the trail CSV; and the number formats they share.

pub mod format;
mod terminal;
mod trail;

pub use terminal::{PRINT_PERIOD, Terminal};
pub use trail::TrailCsv;
