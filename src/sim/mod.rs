//! Closed-loop runs: a scenario (model, command, controller) stepped at Δt, reported to
//! recorders, summarised.

mod summary;

pub use summary::{Diverged, PathDeviation, Summary, ToolRange};
