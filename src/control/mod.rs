//! The joint controller: the digital PD with gravity feed-forward, and its auto-tuning.

mod pd;
mod tuning;

pub use pd::Pd;
pub use tuning::{Gains, auto_tune};
