//! The run's text and file outputs, each a [`Recorder`](crate::sim::Recorder): the terminal
//! printer, the trail CSV and the trail kept in memory; and the number formats they share.

mod capture;
pub mod format;
mod sizing;
mod terminal;
mod trail;

pub use capture::Capture;
pub use sizing::{INERTIA_RATIO_RULE, sizing_table};
pub use terminal::{PRINT_PERIOD, Terminal, for_people};
pub use trail::TrailCsv;
