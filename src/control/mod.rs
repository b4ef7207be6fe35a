//! The joint controller: SPEC §3's digital PD with gravity feed-forward, and its auto-tuning.

mod pd;
mod stability;
mod tuning;

pub use pd::Pd;
pub use stability::{Stability, lambda_max, spectral_radius, stabilize};
pub use tuning::{FAZE4_EFFORT, Gains, auto_tune};
