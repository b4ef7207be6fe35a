//! The joint controller: the digital PD with gravity feed-forward, and its auto-tuning.

mod pd;
mod stability;
mod tuning;

pub use pd::Pd;
pub use stability::{Stability, lambda_max, spectral_radius, stabilize};
pub use tuning::{Gains, auto_tune};
