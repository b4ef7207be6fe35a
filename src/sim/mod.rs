//! Closed-loop runs: a [`Scenario`] (model, command, controller) stepped at Δt by [`run`],
//! reported to recorders, summarised in a [`Summary`].

pub mod check;
mod contact;
mod drives;
mod margin;
mod record;
mod run;
mod scenario;
mod sizing;
pub mod step;
mod stop;
mod summary;
mod tape;
mod timed;
mod verdict;
mod warning;

pub use contact::{ContactStep, HUNT_CROSSLEY_DISSIPATION, MAX_FRICTION, POINT_STIFFNESS, SelfContact};
pub use drives::{
    DEFAULT_GOAL_RATE, Drive, DriveMode, Holding, JointDrive, ServoDrive, ServoOptions, Servos, StepperOptions,
};
pub use margin::{ROBUST_DAMPING_RATIO, SlipMargin};
pub use record::{Recorder, RunInfo, Sample, steps_per_record};
pub use run::{RUNAWAY_SPEED, commanded_path, run};
pub(crate) use scenario::{BadSteps, MAX_STEPS, step_count};
pub use scenario::{
    Collisions, DEFAULT_CLEARANCE_TOLERANCE_M, DEFAULT_DT, DEFAULT_DURATION, DEFAULT_RECORD_PERIOD, Scenario,
    ScenarioBuilder, default_effort, effort_limits, load_collisions, simulated_model,
};
pub use sizing::{Sizing, SizingSums, SupplyCurrent, WindingLoss};
pub use step::{Step, actuation, command, controller, dynamics, integrate, sample, step};
pub use stop::{SIGPIPE, StopFlag, exit_status, stdout_closed};
pub use summary::{
    ContactSummary, Diverged, DofJoint, ENVELOPE_MARGIN, MeshSource, MotorSummary, PathDeviation, Ringing,
    ServoSummary, Simulated, StepLoss, Summary, ToolRange, ToolRule,
};
pub use tape::{TAPE_BUDGET, Tape};
pub use timed::{Play, TimedCommand};
pub use verdict::{Intersection, NearSlip, Reason, Thresholds, Verdict, percent};
pub use warning::{STEPPER_STEPS_PER_RADIAN, Warning};
