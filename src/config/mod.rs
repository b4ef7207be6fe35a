//! One run's configuration: every option a run takes, typed, with its default written once.
//!
//! Each option is declared once in [`fields::FIELDS`] (its name, kind, default, help, the
//! commands that take it, how it is set and checked): the command line builds its arguments
//! from that table and fills a [`RunConfig`] through it, the Python binding takes its keywords
//! and docstrings from it, and a sweep varies its numeric fields. From a configuration,
//! [`load_arm`] reads the arm once (its URDF, the motors resolved onto its joints, the
//! payload and gravity applied) and [`Loaded`] builds the [`crate::sim::Scenario`] of each
//! run on it.
//!
//! Errors name the field the user set, as [`crate::error::Error::option`] does: the library's
//! message writes it `` `dt` ``, the command line shows it as `--dt` and Python as `dt`
//! ([`crate::error::in_words`]).

mod arm;
pub mod fields;
mod loaded;
pub mod motors;
mod motors_file;
pub mod object;

use std::path::PathBuf;

use crate::control::FeedForward;
use crate::error::Words;
use crate::geometry::{ClearanceGeometry, PairFilter};
pub use crate::sim::DriveMode;
use crate::sim::{Drive, ServoOptions, StepperOptions, Thresholds};
use crate::traj::files::lerobot::Units;
use crate::traj::shape::Shape;

pub use arm::{Arm, load_arm, tool_frame};
pub use fields::{Commands, DefaultValue, Field, Kind, Value};
pub use loaded::{Loaded, Replayed, check_samples, wave_amplitudes, wave_center};
pub use motors::{MotorEntry, Motors, PRESET_SETS, PRESETS, Preset};

/// Default control and integration period Δt (s): 5 kHz.
pub const DEFAULT_DT: f64 = crate::sim::DEFAULT_DT;
/// Default time between two trail samples (s).
pub const DEFAULT_RECORD_PERIOD: f64 = crate::sim::DEFAULT_RECORD_PERIOD;
/// Default self-clearance tolerance (mm; docs/clearance.md, "Speed").
pub const DEFAULT_CLEARANCE_TOLERANCE_MM: f64 = crate::sim::DEFAULT_CLEARANCE_TOLERANCE_M * 1e3;
/// Default simulated time of `wave` and `replay` (s).
pub const DEFAULT_DURATION: f64 = crate::sim::DEFAULT_DURATION;
/// Default simulated time of `shape` (s): the original's 12 s.
pub const DEFAULT_SHAPE_DURATION: f64 = 12.0;
/// Default angular frequency of `wave` (rad/s, the original's convention).
pub const DEFAULT_FREQ: f64 = 0.5;
/// Default amplitude of `wave`'s revolute and continuous joints (degrees).
pub const DEFAULT_AMP_DEG: f64 = 25.0;
/// Default time the frames of a `.npy` replay span (s).
pub const DEFAULT_TRAJ_PERIOD: f64 = 5.0;
/// Default samples along a shape's path.
pub const DEFAULT_SHAPE_POINTS: usize = 240;
/// Default Coulomb friction of `self_collisions` contacts.
pub const DEFAULT_FRICTION: f64 = 1.0;
/// Default port of the live view (127.0.0.1 only).
pub const DEFAULT_PORT: u16 = 7000;

/// Everything one run takes: what the joints are asked to do, the arm, the controller, the
/// verdict's limits, the clearance, and the outputs.
#[derive(Clone, Debug, PartialEq)]
pub struct RunConfig {
    /// The command: `wave`, `replay` or `shape`, with its own options.
    pub motion: Motion,
    /// The arm and its motors.
    pub arm: ArmConfig,
    /// The controller and the step.
    pub control: ControlConfig,
    /// Simulated time (s); `None`: the command's default ([`Motion::default_duration`]; a
    /// time-stamped trajectory's last time).
    pub duration: Option<f64>,
    /// Time between trail samples (s), where the tool range, path deviation and clearance
    /// are taken.
    pub record_period: f64,
    /// The limits within which the arm is judged to follow, and `strict`.
    pub verdict: VerdictConfig,
    /// Self-clearance and self-contact.
    pub clearance: ClearanceConfig,
    /// The files and lines a run writes.
    pub outputs: OutputConfig,
}

impl RunConfig {
    /// The defaults of every option for `motion`.
    pub fn new(motion: Motion) -> RunConfig {
        RunConfig {
            motion,
            arm: ArmConfig::default(),
            control: ControlConfig::default(),
            duration: None,
            record_period: DEFAULT_RECORD_PERIOD,
            verdict: VerdictConfig::default(),
            clearance: ClearanceConfig::default(),
            outputs: OutputConfig::default(),
        }
    }

    /// The simulated time: `duration`, else the command's default.
    pub fn duration(&self) -> f64 {
        self.duration.unwrap_or(self.motion.default_duration())
    }

    /// What the controller feeds forward: nothing under `no_ff`, else `ff` (default: g(q)).
    pub fn feedforward(&self) -> crate::Result<FeedForward> {
        match (self.control.no_ff, self.control.ff) {
            (true, Some(_)) => Err(crate::Error::option(
                "ff",
                "and `no_ff` both say what is fed forward: give one",
            )),
            (true, None) => Ok(FeedForward::None),
            (false, ff) => Ok(ff.unwrap_or_default()),
        }
    }

    /// How the `n` joints are driven: `drive` with its `microsteps` (whole numbers ≥ 1; one
    /// value is every joint's), `driver_bandwidth`, `rotor_damping` and `reducer_friction`
    /// (one value is every joint's) for stepper, `servo_rate` for servo. Each with another
    /// `drive` is an error.
    pub fn drive(&self, n: usize) -> crate::Result<Drive> {
        let control = &self.control;
        let given = &control.microsteps;
        if control.drive != DriveMode::Servo && control.servo_rate.is_some() {
            return Err(crate::Error::option("servo_rate", "is for `drive` servo"));
        }
        if control.drive != DriveMode::Stepper {
            for (field, set) in [
                ("microsteps", !given.is_empty()),
                ("driver_bandwidth", control.driver_bandwidth.is_some()),
                ("rotor_damping", !control.rotor_damping.is_empty()),
                ("reducer_friction", !control.reducer_friction.is_empty()),
            ] {
                if set {
                    return Err(crate::Error::option(field, "is for `drive` stepper"));
                }
            }
        }
        match control.drive {
            DriveMode::Pd => return Ok(Drive::Pd),
            DriveMode::Servo => {
                return Ok(Drive::Servo(ServoOptions {
                    rate: control.servo_rate,
                }));
            }
            DriveMode::Stepper => {}
        }
        let every = |values: &[Option<f64>]| match values {
            [one] => vec![*one; n],
            _ => values.to_vec(),
        };
        let microsteps = (given.iter().enumerate())
            .map(|(i, v)| match v {
                None => Ok(None),
                Some(x) if x.fract() == 0.0 && *x >= 1.0 && *x <= f64::from(u32::MAX) => Ok(Some(*x as u32)),
                Some(x) => Err(crate::Error::option(
                    "microsteps",
                    format!("J{} {} is not a whole number ≥ 1", i + 1, crate::error::shortest(*x)),
                )),
            })
            .collect::<crate::Result<Vec<_>>>()?;
        Ok(Drive::Stepper(StepperOptions {
            microsteps: match microsteps.as_slice() {
                [one] => vec![*one; n],
                _ => microsteps,
            },
            driver_bandwidth: control.driver_bandwidth,
            rotor_damping: every(&control.rotor_damping),
            reducer_friction: every(&control.reducer_friction),
        }))
    }
}

/// What the joints are asked to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// Every joint follows A·sin(ω t + i·π/3) about a centre (docs/model.md).
    Wave(WaveConfig),
    /// Joint positions from a file (or arrays), played as a command.
    Replay(ReplayConfig),
    /// The tool draws a shape on the board: exact IK, then the samples as a loop.
    Shape(ShapeConfig),
    /// The fastest timing of a path (a trajectory file's points, its times ignored) that the
    /// motors follow, checked in the closed loop ([`crate::retime`]).
    Retime(RetimeConfig),
}

impl Motion {
    /// The command: wave, replay, shape or retime.
    pub fn command(&self) -> Command {
        match self {
            Motion::Wave(_) => Command::Wave,
            Motion::Replay(_) => Command::Replay,
            Motion::Shape(_) => Command::Shape,
            Motion::Retime(_) => Command::Retime,
        }
    }

    /// The command's name: `wave`, `replay`, `shape`, `retime`.
    pub fn name(&self) -> &'static str {
        self.command().name()
    }

    /// Simulated time when none is given (s).
    pub fn default_duration(&self) -> f64 {
        match self {
            Motion::Shape(_) => DEFAULT_SHAPE_DURATION,
            _ => DEFAULT_DURATION,
        }
    }
}

/// A command of the configuration: what [`Motion`] a run is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// [`Motion::Wave`].
    Wave,
    /// [`Motion::Replay`].
    Replay,
    /// [`Motion::Shape`].
    Shape,
    /// [`Motion::Retime`].
    Retime,
}

crate::choice::choice_words!(Command { Wave => "wave", Replay => "replay", Shape => "shape", Retime => "retime" });

impl Command {
    /// Its name: `wave`, `replay`, `shape`, `retime`.
    pub fn name(self) -> &'static str {
        crate::choice::Choice::word(self)
    }

    /// The command's motion with every option at its default. The options the command
    /// requires (`Field::required`: `q_traj`, `shape`) hold a placeholder (the path
    /// `q_traj`, the circle) until they are set.
    pub fn motion(self) -> Motion {
        match self {
            Command::Wave => Motion::Wave(WaveConfig::default()),
            Command::Replay => Motion::Replay(ReplayConfig::new("q_traj")),
            Command::Shape => Motion::Shape(ShapeConfig::new(Shape::Circle)),
            Command::Retime => Motion::Retime(RetimeConfig::new("q_traj")),
        }
    }
}

/// `wave`'s options.
#[derive(Clone, Debug, PartialEq)]
pub struct WaveConfig {
    /// Angular frequency ω (rad/s).
    pub freq: f64,
    /// Amplitude of the revolute and continuous joints (degrees).
    pub amp_deg: f64,
    /// Amplitude of the prismatic joints (m); `None`: a quarter of each limited range, else
    /// [`DEFAULT_AMP_M`].
    pub amp_m: Option<f64>,
    /// The pose waved about.
    pub center: Center,
}

impl Default for WaveConfig {
    fn default() -> Self {
        WaveConfig {
            freq: DEFAULT_FREQ,
            amp_deg: DEFAULT_AMP_DEG,
            amp_m: None,
            center: Center::Zero,
        }
    }
}

/// Default amplitude of a prismatic joint without `amp_m` and without limits (m).
pub const DEFAULT_AMP_M: f64 = 0.05;

/// The pose a wave is centred on.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Center {
    /// Every joint at zero.
    #[default]
    Zero,
    /// The middle of each limited joint's range (0 for an unlimited one).
    Mid,
    /// The start pose the robot file offers (MJCF's `home` keyframe).
    Home,
    /// One value per joint (rad or m).
    Given(Vec<f64>),
}

/// `replay`'s options.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayConfig {
    /// The trajectory file: time-stamped (`.yaml`, `.json`, `.mcap`, `.csv`; played once), or
    /// an N×dof `.npy` (evenly spaced, repeating); or the name arrays given in memory are
    /// reported by.
    pub q_traj: PathBuf,
    /// A `.npy`'s period: the time its frames span (s); the trajectory then repeats.
    pub traj_period: f64,
    /// Which message of a `.yaml`, `.json` or `.mcap` file, counted from 1 (`None`: the first).
    pub message: Option<usize>,
    /// The topic of an `.mcap` file (`None`: its one JointTrajectory topic, else its one
    /// JointState topic).
    pub topic: Option<String>,
    /// The file's joint-name prefixes renamed (`FROM=TO`, the first that fits a name).
    pub rename: Vec<crate::traj::files::Rename>,
    /// Where the arm starts a time-stamped trajectory, at rest (rad or m per degree of
    /// freedom); `None`: the first point's positions.
    pub start: Option<Vec<f64>>,
    /// How a time-stamped trajectory's points are joined; `None`: by what they give.
    pub interpolation: Option<crate::traj::Interpolation>,
    /// A LeRobot dataset's episode, from 0 (`None`: 0).
    pub episode: Option<usize>,
    /// A LeRobot dataset's column of joint values (`None`: `action`).
    pub lerobot_key: Option<String>,
    /// What a LeRobot dataset's values are: `deg` or `rad` (`None`: normalised, turned into
    /// radians by `calibration`, else taken as radians).
    pub units: Option<Units>,
    /// LeRobot's calibration file of the arm (JSON: per motor `drive_mode`, `range_min`,
    /// `range_max`), for a dataset's normalised values.
    pub calibration: Option<PathBuf>,
}

impl ReplayConfig {
    /// A replay of `q_traj` with the default period.
    pub fn new(q_traj: impl Into<PathBuf>) -> ReplayConfig {
        ReplayConfig {
            q_traj: q_traj.into(),
            traj_period: DEFAULT_TRAJ_PERIOD,
            message: None,
            topic: None,
            rename: Vec::new(),
            start: None,
            interpolation: None,
            episode: None,
            lerobot_key: None,
            units: None,
            calibration: None,
        }
    }
}

/// `retime`'s options.
#[derive(Clone, Debug, PartialEq)]
pub struct RetimeConfig {
    /// The path: a trajectory file read as `replay` reads it (its `q_traj`, `message`,
    /// `topic`), its points in order; `traj_period` is a `.npy`'s own timing, which the
    /// speed-up is reported against.
    pub path: ReplayConfig,
    /// Where the timing is written: `.yaml`, `.json`, `.mcap` or `.csv` (positions,
    /// velocities, accelerations, time from start), which `replay` plays (`None`: nowhere; the
    /// command line asks for one).
    pub out: Option<PathBuf>,
    /// Grid intervals in s (1 to 100,000, `input::MAX_RETIME_INTERVALS`).
    pub grid: usize,
    /// The share of every torque limit left for the feedback, in [0, 1).
    pub margin: f64,
    /// Most closed-loop checks (≥ 1), the first timing's included.
    pub attempts: usize,
    /// Whether `out` is written when the checked timing does not follow (it is not
    /// otherwise).
    pub force: bool,
    /// Whether to skip the closed-loop check: the timing is written unchecked (it keeps every
    /// limit as a controller plays it, but whether the loop follows it is not known), and no
    /// output of a run (summary, trail, …) can be asked for.
    pub no_check: bool,
    /// Acceleration limits per joint (rad/s² or m/s²; empty or `None`: none).
    pub max_accel: Vec<Option<f64>>,
    /// Jerk limits per joint (rad/s³ or m/s³; empty or `None`: none).
    pub max_jerk: Vec<Option<f64>>,
    /// The joint velocity the timing starts at (rad/s or m/s per joint; empty or `None`: 0),
    /// along the path's tangent (docs/retime.md, "Chaining segments").
    pub start_velocity: Vec<Option<f64>>,
    /// The joint velocity the timing ends at, likewise.
    pub end_velocity: Vec<Option<f64>>,
}

impl RetimeConfig {
    /// A retime of the path in `q_traj`, written nowhere, with the default grid, margin and
    /// checks.
    pub fn new(q_traj: impl Into<PathBuf>) -> RetimeConfig {
        RetimeConfig {
            path: ReplayConfig::new(q_traj),
            out: None,
            grid: DEFAULT_GRID,
            margin: DEFAULT_MARGIN,
            attempts: DEFAULT_ATTEMPTS,
            force: false,
            no_check: false,
            max_accel: Vec::new(),
            max_jerk: Vec::new(),
            start_velocity: Vec::new(),
            end_velocity: Vec::new(),
        }
    }

    /// The library's options (Ctrl-C stops a check through `stop`).
    pub fn options(&self, stop: crate::sim::StopFlag) -> crate::retime::RetimeOptions {
        crate::retime::RetimeOptions {
            intervals: self.grid,
            margin: self.margin,
            check: !self.no_check,
            attempts: self.attempts,
            max_acceleration: self.max_accel.clone(),
            max_jerk: self.max_jerk.clone(),
            start_velocity: self.start_velocity.clone(),
            end_velocity: self.end_velocity.clone(),
            tape: None,
            stop,
        }
    }
}

/// Default grid intervals of `retime`.
pub const DEFAULT_GRID: usize = crate::retime::DEFAULT_INTERVALS;
/// Default margin of `retime` (docs/retime.md, "The margin").
pub const DEFAULT_MARGIN: f64 = crate::retime::DEFAULT_MARGIN;
/// Default closed-loop checks of `retime`.
pub const DEFAULT_ATTEMPTS: usize = crate::retime::DEFAULT_ATTEMPTS;

/// `shape`'s options.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeConfig {
    /// The path the tool draws.
    pub shape: Shape,
    /// Samples along the path (IK targets).
    pub shape_points: usize,
    /// Where to write the IK joint samples (`.npy`), if anywhere.
    pub save_q: Option<PathBuf>,
}

impl ShapeConfig {
    /// `shape` with the default samples.
    pub fn new(shape: Shape) -> ShapeConfig {
        ShapeConfig {
            shape,
            shape_points: DEFAULT_SHAPE_POINTS,
            save_q: None,
        }
    }
}

/// The arm: its file, its motors, and what is added to it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ArmConfig {
    /// The robot file, URDF or xacro (`None`: the bundled Faze4).
    pub robot: Option<PathBuf>,
    /// A xacro file's arguments, `NAME:=VALUE`, in order.
    pub xacro_arg: Vec<String>,
    /// Where `package://` meshes and `$(find …)` packages are looked for (before ROS_PACKAGE_PATH).
    pub package_path: Vec<PathBuf>,
    /// Balance a body's inertia that no rigid body has instead of refusing the model.
    pub balance_inertia: bool,
    /// The link traced as the tool (`None`: the model's default).
    pub tool_link: Option<String>,
    /// The motors behind the joints.
    pub motors: Option<Motors>,
    /// Supply voltage of the presets' drives (V; `None`: the preset's).
    pub supply_voltage: Option<f64>,
    /// Rotor inertia per joint (kg·m² at the motor; `None` keeps the model's or the motor's;
    /// empty: none given).
    pub rotor_inertia: Vec<Option<f64>>,
    /// Gear ratio per joint (motor turns per joint turn; as `rotor_inertia`).
    pub gear_ratio: Vec<Option<f64>>,
    /// A point mass at the tool link (kg).
    pub payload_kg: f64,
    /// No gravity field.
    pub no_gravity: bool,
}

/// The controller and the step.
#[derive(Clone, Debug, PartialEq)]
pub struct ControlConfig {
    /// Control and integration period Δt (s).
    pub dt: f64,
    /// Torque limits per joint (N·m or N; `None`: the motors', else the arm's default).
    pub effort: Option<Vec<f64>>,
    /// Proportional gains per joint (`None` keeps the tuned value; empty: all tuned).
    pub kp: Vec<Option<f64>>,
    /// Derivative gains per joint, as `kp`.
    pub kd: Vec<Option<f64>>,
    /// Speed limits per joint (rad/s or m/s; `None` keeps the arm's; empty: all the arm's).
    pub max_speed: Vec<Option<f64>>,
    /// No gravity feed-forward.
    pub no_ff: bool,
    /// What the controller feeds forward (`None`: g(q), the default; `Full`: the command's
    /// inverse dynamics).
    pub ff: Option<FeedForward>,
    /// How the joints with a stepper are driven: the PD's torque clipped to the envelope, or
    /// open loop (docs/motors.md).
    pub drive: DriveMode,
    /// Microsteps per full step of the steppers' drivers under [`DriveMode::Stepper`]: one
    /// value for every joint or one per joint (`None` keeps the motor's; empty: all the
    /// motors').
    pub microsteps: Vec<Option<f64>>,
    /// Under [`DriveMode::Stepper`], every stepper driver's current-loop bandwidth (Hz; `None`:
    /// the motor's, 5 kHz for the presets).
    pub driver_bandwidth: Option<f64>,
    /// Under [`DriveMode::Stepper`], each rotor's viscous damping (N·m·s/rad at the shaft;
    /// `None` keeps the motor's; empty: all the motors').
    pub rotor_damping: Vec<Option<f64>>,
    /// Under [`DriveMode::Stepper`], each reducer's Coulomb friction (N·m at the motor shaft;
    /// as `rotor_damping`).
    pub reducer_friction: Vec<Option<f64>>,
    /// Under [`DriveMode::Servo`], how often each servo is sent its goal (Hz; `None`: at the
    /// trajectory's own sample times, else [`crate::sim::DEFAULT_GOAL_RATE`]).
    pub servo_rate: Option<f64>,
}

impl Default for ControlConfig {
    fn default() -> Self {
        ControlConfig {
            dt: DEFAULT_DT,
            effort: None,
            kp: Vec::new(),
            kd: Vec::new(),
            max_speed: Vec::new(),
            no_ff: false,
            ff: None,
            drive: DriveMode::Pd,
            microsteps: Vec::new(),
            driver_bandwidth: None,
            rotor_damping: Vec::new(),
            reducer_friction: Vec::new(),
            servo_rate: None,
        }
    }
}

/// The verdict's limits, and whether "cannot follow" fails the command (`strict`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VerdictConfig {
    /// The limits of "follows".
    pub thresholds: Thresholds,
    /// Exit with status 3 (Python: raise) when the verdict is not "follows".
    pub strict: bool,
}

/// Self-clearance and self-contact.
#[derive(Clone, Debug, PartialEq)]
pub struct ClearanceConfig {
    /// Exact triangles or convex hulls.
    pub collision_geometry: ClearanceGeometry,
    /// Which pairs are checked.
    pub collision_pairs: PairFilter,
    /// How far (mm) the reported clearance may be above the true minimum.
    pub clearance_tolerance: f64,
    /// No self-clearance at all (no mesh read).
    pub no_collisions: bool,
    /// Contact forces between the checked pairs.
    pub self_collisions: bool,
    /// Coulomb friction of those contacts.
    pub friction: f64,
}

impl Default for ClearanceConfig {
    fn default() -> Self {
        ClearanceConfig {
            collision_geometry: ClearanceGeometry::default(),
            collision_pairs: PairFilter::default(),
            clearance_tolerance: DEFAULT_CLEARANCE_TOLERANCE_MM,
            no_collisions: false,
            self_collisions: false,
            friction: DEFAULT_FRICTION,
        }
    }
}

/// The files and lines a run writes. A path `None` writes nothing, the default of every one (a
/// front end that writes a file unasked chooses it itself).
#[derive(Clone, Debug, PartialEq)]
pub struct OutputConfig {
    /// Trail CSV.
    pub trail: Option<PathBuf>,
    /// Summary JSON.
    pub summary: Option<PathBuf>,
    /// One self-contained HTML playback.
    pub html: Option<PathBuf>,
    /// The figure (.svg or .png).
    pub plot: Option<PathBuf>,
    /// The motors' sizing plot (.svg or .png).
    pub plot_motors: Option<PathBuf>,
    /// Show the run live in the browser.
    pub view: bool,
    /// The live view's port (0 picks a free one).
    pub port: u16,
    /// Keep the live view serving after the run.
    pub hold: bool,
    /// Print only the verdict, errors, and the warnings that change the result.
    pub quiet: bool,
    /// Add τ, error, velocity and g(q) to the progress lines and the trail.
    pub debug: bool,
    /// Simulated time between progress lines (s; `None`: 0.5 s, or longer for long runs).
    pub print_period: Option<f64>,
    /// Print the motors' sizing report (needs `motors`).
    pub sizing: bool,
    /// How the lines a run prints name the options they refer to (`--tool-link` or
    /// `tool_link`): the front end's words, not an option.
    pub words: Words,
}

impl Default for OutputConfig {
    fn default() -> Self {
        OutputConfig {
            trail: None,
            summary: None,
            html: None,
            plot: None,
            plot_motors: None,
            view: false,
            port: DEFAULT_PORT,
            hold: false,
            quiet: false,
            debug: false,
            print_period: None,
            sizing: false,
            words: Words::Keywords,
        }
    }
}
