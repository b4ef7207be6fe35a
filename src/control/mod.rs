//! The joint controller: the digital PD with its feed-forward (gravity or computed torque), and
//! its auto-tuning (at a start pose of a model, `tune`); the motors behind it, their
//! torque–speed envelopes (`motor.rs`, each kind's in `kinds/`), the open-loop stepper drive (`stepper.rs`), the smart servos' own loop and protection (`servo.rs`) and the
//! published figures of the presets' motors (`catalog.rs`).

pub mod catalog;
mod kinds;
mod motor;
mod pd;
mod servo;
mod stability;
mod stepper;
mod tuning;

pub use kinds::{KINDS, Kind, kind};
pub use motor::{Electrics, Envelope, JointMotor, Motor, StepperLosses, StepperWinding, Stepping};
pub use pd::{FeedForward, Pd};
pub use servo::{Protection, ServoSpec, ServoState, Trip, TripKind};
pub use stability::{Stability, lambda_max, spectral_radius, stabilize};
pub use stepper::{DEFAULT_MICROSTEPS, OpenLoopStepper, STEPS_PER_CYCLE, Slips, StepperDamping, detent, torque_angle};
pub use tuning::{Gains, arithmetic_holds, auto_tune, tune};
