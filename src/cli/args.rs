//! The command line, as clap sees it: every option of a run is a field of
//! [`crate::config::RunConfig`] of the same name (with dashes), its default read from there;
//! [`super::config`] maps the parsed arguments onto a configuration, which checks them.

use std::path::PathBuf;
use std::str::FromStr;

use clap::{Args, Parser, Subcommand};

use crate::config::{
    DEFAULT_AMP_DEG, DEFAULT_ATTEMPTS, DEFAULT_CLEARANCE_TOLERANCE_MM, DEFAULT_DT, DEFAULT_DURATION, DEFAULT_FREQ,
    DEFAULT_FRICTION, DEFAULT_GRID, DEFAULT_MARGIN, DEFAULT_PORT, DEFAULT_RECORD_PERIOD, DEFAULT_SHAPE_DURATION,
    DEFAULT_SHAPE_POINTS, DEFAULT_TRAIL, DEFAULT_TRAJ_PERIOD,
};
use crate::sim::Thresholds;

/// faze4: can the motors of a real arm follow this trajectory? A fast, exact dynamics
/// simulator of the Faze4 six-axis arm (or any URDF arm) under a 5 kHz digital PD controller.
#[derive(Debug, Parser)]
#[command(name = "faze4", version, about, long_about = None)]
pub struct Cli {
    /// What to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The experiments.
#[derive(Clone, Debug, Subcommand)]
pub enum Command {
    /// Every joint follows A·sin(ω t + i·π/3) (docs/model.md).
    Wave(WaveArgs),
    /// Replay a joint trajectory: time-stamped (.yaml, .json, .mcap, .csv; played once as ros2_control plays it), or an N×dof .npy repeating every --traj-period.
    Replay(ReplayArgs),
    /// Draw a sine, circle or triangle on the board: exact IK, then the samples as a loop (docs/model.md).
    Shape(ShapeArgs),
    /// The fastest timing of a path that the motors follow (TOPP-RA on the motors' torque–speed envelopes, checked in the closed loop; docs/retime.md): the path is --q-traj's points (times ignored), the timing goes to --out (replay plays it); --plot draws the phase plane.
    Retime(RetimeArgs),
    /// Many runs at once: vary options over a grid (--vary), or find the largest value that
    /// still follows (--find); after `--`, the command to run: sweep --vary payload-kg=0:2:0.5 -- shape --shape circle.
    Sweep(SweepArgs),
}

/// `faze4 wave`.
#[derive(Clone, Debug, Args)]
pub struct WaveArgs {
    /// Simulated time (s).
    #[arg(long, default_value_t = DEFAULT_DURATION, allow_hyphen_values = true)]
    pub duration: f64,
    /// Angular frequency ω of the wave (rad/s, as the original).
    #[arg(long, default_value_t = DEFAULT_FREQ, allow_hyphen_values = true)]
    pub freq: f64,
    /// Amplitude A of the revolute and continuous joints (degrees).
    #[arg(long = "amp-deg", default_value_t = DEFAULT_AMP_DEG, allow_hyphen_values = true)]
    pub amp_deg: f64,
    /// Amplitude A of the prismatic joints (m). Default: a quarter of each one's range where it
    /// has limits, else 0.05 m.
    #[arg(long = "amp-m", allow_hyphen_values = true)]
    pub amp_m: Option<f64>,
    /// The pose to wave about: one value per joint (rad or m), or 'mid' (the middle of each limited joint's range, 0 for an unlimited one). Default: zero.
    #[arg(long, value_name = "Q1,Q2,…|mid", allow_hyphen_values = true)]
    pub center: Option<String>,
    /// Options every run command shares.
    #[command(flatten)]
    pub run: RunArgs,
}

/// `faze4 replay`.
#[derive(Clone, Debug, Args)]
pub struct ReplayArgs {
    /// The trajectory file.
    #[command(flatten)]
    pub file: TrajectoryFileArgs,
    /// Simulated time (s); default: a time-stamped trajectory's last time, 8 s for a .npy.
    #[arg(long, allow_hyphen_values = true)]
    pub duration: Option<f64>,
    /// Options every run command shares.
    #[command(flatten)]
    pub run: RunArgs,
}

/// The trajectory file `replay` plays and `retime` reads the path of.
#[derive(Clone, Debug, Args)]
pub struct TrajectoryFileArgs {
    /// The trajectory: a time-stamped trajectory_msgs/JointTrajectory as .yaml (ros2 topic echo) or .json, a rosbag2 .mcap (a JointTrajectory or JointState topic), a .csv (a time column t, time or time_from_start and one column per joint by name), played once; or an N×dof float64/float32 .npy array of joint positions (rad), N ≥ 2, evenly spaced and repeating (docs/trajectories.md). retime takes its points as the path, times ignored.
    #[arg(long = "q-traj", value_name = "F.yaml|F.json|F.mcap|F.csv|F.npy")]
    pub q_traj: PathBuf,
    /// .npy: the time the N frames span (s); frame k is at k·T/(N−1), then the trajectory repeats (retime: the input's own timing it reports its speed-up against).
    #[arg(long = "traj-period", default_value_t = DEFAULT_TRAJ_PERIOD, allow_hyphen_values = true)]
    pub traj_period: f64,
    /// Which JointTrajectory message of a .yaml, .json or .mcap file to play, counted from 1 (default: the first).
    #[arg(long, value_name = "K")]
    pub message: Option<usize>,
    /// The topic of an .mcap file (default: its one JointTrajectory topic, else its one JointState topic).
    #[arg(long, value_name = "NAME")]
    pub topic: Option<String>,
}

/// `faze4 shape`.
#[derive(Clone, Debug, Args)]
pub struct ShapeArgs {
    /// The path the tool draws on the board.
    #[arg(long, value_parser = ["sine", "circle", "tri"])]
    pub shape: String,
    /// Samples along the path (IK targets), played one loop every 5 s.
    #[arg(
        long = "shape-points",
        default_value_t = DEFAULT_SHAPE_POINTS,
        value_name = "N",
        allow_hyphen_values = true
    )]
    pub shape_points: usize,
    /// Simulated time (s).
    #[arg(long, default_value_t = DEFAULT_SHAPE_DURATION, allow_hyphen_values = true)]
    pub duration: f64,
    /// Write the IK joint samples as an N×dof float64 .npy (numpy loads it; `faze4 replay` plays it).
    #[arg(long = "save-q", value_name = "F.npy")]
    pub save_q: Option<PathBuf>,
    /// Options every run command shares.
    #[command(flatten)]
    pub run: RunArgs,
}

/// `faze4 retime`.
#[derive(Clone, Debug, Args)]
pub struct RetimeArgs {
    /// The path: the trajectory file's points in order, times ignored, joined by a C² cubic spline over their cumulative joint-space distance.
    #[command(flatten)]
    pub file: TrajectoryFileArgs,
    /// Where the timing is written, by extension: a JointTrajectory as .yaml or .json, a rosbag2 .mcap, or a .csv (positions, velocities, accelerations, time from start); `faze4 replay --q-traj` plays it.
    #[arg(long, value_name = "F.yaml|F.json|F.mcap|F.csv")]
    pub out: PathBuf,
    /// Grid intervals in s (at most 100,000): the limits are kept at the grid's points.
    #[arg(long, default_value_t = DEFAULT_GRID, value_name = "N", allow_hyphen_values = true)]
    pub grid: usize,
    /// The share of every torque limit (each motor's envelope at its speed, or the constant limit) left for the feedback, in [0, 1).
    #[arg(long, default_value_t = DEFAULT_MARGIN, value_name = "SHARE", allow_hyphen_values = true)]
    pub margin: f64,
    /// Most closed-loop checks: the first timing's, then one per slowed timing.
    #[arg(long, default_value_t = DEFAULT_ATTEMPTS, value_name = "N", allow_hyphen_values = true)]
    pub attempts: usize,
    /// Options every run command shares.
    #[command(flatten)]
    pub run: RunArgs,
}

/// Options every run command shares: model, controller, outputs.
#[derive(Clone, Debug, Args)]
pub struct RunArgs {
    /// The arm (default: the bundled Faze4, urdf/faze4_arm.urdf).
    #[arg(long, value_name = "F.urdf")]
    pub urdf: Option<PathBuf>,
    /// Where `package://` meshes are looked for (repeatable; ROS_PACKAGE_PATH is searched after).
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_path: Vec<PathBuf>,
    /// A moving body whose inertia no rigid body has (not positive definite, or its principal
    /// moments break the triangle inequality) gets its principal moments set to their mean, as
    /// MuJoCo's balanceinertia does (a warning per body), instead of the model being refused.
    #[arg(long = "balance-inertia")]
    pub balance_inertia: bool,
    /// The link traced as the tool (default: tool_link, else the last link of a chain; on a
    /// branched tree the deepest common ancestor of the deepest leaves, e.g. a hand).
    #[arg(long = "tool-link", value_name = "NAME")]
    pub tool_link: Option<String>,
    /// Torque limits per joint, N·m (default: the Faze4 motors' for the bundled arm, else the URDF's effort values).
    #[arg(long, value_name = "E1,E2,…", allow_hyphen_values = true)]
    pub effort: Option<JointValues>,
    /// Proportional gains per joint ('auto' keeps the tuned value), e.g. auto,auto,auto,auto,auto,30.
    #[arg(long, value_name = "KP1,KP2,…", allow_hyphen_values = true)]
    pub kp: Option<JointValues>,
    /// Derivative gains per joint ('auto' keeps the tuned value).
    #[arg(long, value_name = "KD1,KD2,…", allow_hyphen_values = true)]
    pub kd: Option<JointValues>,
    /// Motors behind the joints, whose torque–speed envelope clips each joint's torque at its speed: a preset (faze4: 17HS16-2004S1 steppers and the Faze4's reducers; faze4-bom: the motors the Faze4 is built with; sts3215: Feetech STS3215 servos, the SO-100's; xm540-w270: Dynamixel XM540-W270) or a FILE.toml (docs/motors.md).
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub motors: Option<String>,
    /// Supply voltage of the --motors presets' drives, V (default: the preset's, 24 V for the Faze4's steppers).
    #[arg(long = "supply-voltage", value_name = "V")]
    pub supply_voltage: Option<f64>,
    /// How the joints with a stepper are driven: 'pd', the controller's torque clipped to the envelope (the original's; the default), or 'stepper', open loop: the driver's microstep through the torque–angle curve, slips and all (with --motors; docs/motors.md).
    #[arg(long, value_name = "pd|stepper", value_parser = ["pd", "stepper"])]
    pub drive: Option<String>,
    /// Microsteps per full step of the steppers' drivers under --drive stepper: one value for every joint or one per joint ('auto' keeps the motor's: the Faze4 presets' firmware 8,8,4,2,2,2; else 16).
    #[arg(long, value_name = "N|N1,N2,…", allow_hyphen_values = true)]
    pub microsteps: Option<JointValues>,
    /// Under --drive stepper, every stepper driver's current-loop bandwidth, Hz (default: the motor's; 5000 for the presets' TB6600-class choppers, a stated assumption; docs/motors.md, "The stepper's damping").
    #[arg(long = "driver-bandwidth", value_name = "HZ")]
    pub driver_bandwidth: Option<f64>,
    /// Under --drive stepper, each rotor's viscous damping (iron losses, bearings), N·m·s/rad at the motor shaft: one value for every joint or one per joint ('auto' keeps the motor's; the presets' 0: not published).
    #[arg(long = "rotor-damping", value_name = "B|B1,B2,…", allow_hyphen_values = true)]
    pub rotor_damping: Option<JointValues>,
    /// Under --drive stepper, each reducer's Coulomb friction, N·m at the motor shaft: one value for every joint or one per joint ('auto' keeps the motor's; the presets' 0: not published).
    #[arg(long = "reducer-friction", value_name = "T|T1,T2,…", allow_hyphen_values = true)]
    pub reducer_friction: Option<JointValues>,
    /// Print the motors' sizing report (with --motors): per joint at the motor peak and RMS torque, peak speed, inertia ratio, peak power, braking energy, supply current, heating.
    #[arg(long)]
    pub sizing: bool,
    /// Rotor inertia per joint, kg·m² at the motor shaft ('auto' keeps the URDF's or --motors'); overrides the URDF.
    #[arg(long = "rotor-inertia", value_name = "I1,I2,…", allow_hyphen_values = true)]
    pub rotor_inertia: Option<JointValues>,
    /// Gear ratio per joint, motor turns per joint turn ('auto' keeps the URDF's or --motors'); overrides the URDF.
    #[arg(long = "gear-ratio", value_name = "R1,R2,…", allow_hyphen_values = true)]
    pub gear_ratio: Option<JointValues>,
    /// Speed limits per joint, rad/s or m/s ('auto' keeps the URDF's velocity; none for the bundled Faze4): counted, not enforced.
    #[arg(long = "max-speed", value_name = "W1,W2,…", allow_hyphen_values = true)]
    pub max_speed: Option<JointValues>,
    /// No gravity feed-forward (PD alone holds the arm up).
    #[arg(long = "no-ff")]
    pub no_ff: bool,
    /// What the controller feeds forward: 'gravity', g(q) at the measured q (the default), or 'full', the inverse dynamics of the commanded q, v, a (computed torque; docs/trajectories.md).
    #[arg(long, value_name = "gravity|full", value_parser = ["gravity", "full"], conflicts_with = "no_ff")]
    pub ff: Option<String>,
    /// No gravity field.
    #[arg(long = "no-gravity")]
    pub no_gravity: bool,
    /// A point mass at the tool link (kg).
    #[arg(
        long = "payload-kg",
        default_value_t = 0.0,
        value_name = "M",
        allow_hyphen_values = true
    )]
    pub payload_kg: f64,
    /// Control and integration period (s); 2e-4 is 5 kHz.
    #[arg(long, default_value_t = DEFAULT_DT, allow_hyphen_values = true)]
    pub dt: f64,
    /// Print τ, error, velocity and g(q) with every progress line and add them to the trail.
    #[arg(long)]
    pub debug: bool,
    /// Print only the verdict, errors, and the warnings that change the result (a mesh not
    /// found, a transmission skipped, an inertia balanced).
    #[arg(long, short)]
    pub quiet: bool,
    /// Simulated time between progress lines (s); default 0.5 s, or longer so that a long run
    /// prints at most about 40 lines.
    #[arg(long = "print-period", value_name = "S", allow_hyphen_values = true)]
    pub print_period: Option<f64>,
    /// The verdict "follows" allows each joint to saturate at most this share of the steps (%).
    #[arg(
        long = "max-saturation-pct",
        default_value_t = Thresholds::DEFAULT.max_saturation_pct,
        value_name = "PCT",
        allow_hyphen_values = true
    )]
    pub max_saturation_pct: f64,
    /// The verdict "follows" allows tracking errors up to this (rad, or m for a prismatic joint).
    #[arg(
        long = "max-error",
        default_value_t = Thresholds::DEFAULT.max_error,
        value_name = "RAD",
        allow_hyphen_values = true
    )]
    pub max_error: f64,
    /// The verdict "follows" allows a shape's path deviation up to this (mm).
    #[arg(
        long = "max-deviation-mm",
        default_value_t = Thresholds::DEFAULT.max_deviation_mm,
        value_name = "MM",
        allow_hyphen_values = true
    )]
    pub max_deviation_mm: f64,
    /// Exit with status 3 when the verdict is "cannot follow" or "collides" (for CI jobs that guard a motion).
    #[arg(long)]
    pub strict: bool,
    /// Trail CSV (t, x, y, z, q1…); 'none' writes none.
    #[arg(long, default_value = DEFAULT_TRAIL, value_name = "F.csv")]
    pub trail: PathBuf,
    /// Summary JSON (the machine-readable result).
    #[arg(long, value_name = "F.json")]
    pub summary: Option<PathBuf>,
    /// Time between trail rows (s).
    #[arg(
        long = "record-period",
        default_value_t = DEFAULT_RECORD_PERIOD,
        value_name = "S",
        allow_hyphen_values = true
    )]
    pub record_period: f64,
    /// How self-clearance reads a collision mesh: 'mesh', its exact triangles, or 'hull', its
    /// convex hull (as Drake and most simulators do; signed distances).
    #[arg(long = "collision-geometry", default_value = "mesh", value_name = "KIND", value_parser = ["mesh", "hull"])]
    pub collision_geometry: String,
    /// Which pairs of links self-clearance checks: 'all' adds the pairs a joint connects to the
    /// default (Drake's: links on different bodies not connected by a joint).
    #[arg(long = "collision-pairs", value_name = "all", value_parser = ["all"])]
    pub collision_pairs: Option<String>,
    /// How far (mm) the reported self-clearance may be above the true minimum over the
    /// samples: it is the distance of two actual parts, and the true minimum is at most this
    /// much below it. 0 is exact. Intersections are decided exactly whatever it is.
    #[arg(long = "clearance-tolerance", value_name = "MM", default_value_t = DEFAULT_CLEARANCE_TOLERANCE_MM, allow_hyphen_values = true)]
    pub clearance_tolerance: f64,
    /// No self-clearance: the collision geometry is skipped altogether (its meshes not read).
    #[arg(long = "no-collisions", conflicts_with_all = ["collision_geometry", "collision_pairs", "clearance_tolerance"])]
    pub no_collisions: bool,
    /// Contact forces between the checked pairs of the collision geometry, solved inside the
    /// step (Drake's compliant point contact; with --collision-geometry hull the convex hulls
    /// touch, as in Drake; exact meshes that intersect stop the run).
    #[arg(long = "self-collisions", conflicts_with = "no_collisions")]
    pub self_collisions: bool,
    /// Coulomb friction of --self-collisions contacts.
    #[arg(
        long,
        default_value_t = DEFAULT_FRICTION,
        value_name = "MU",
        requires = "self_collisions",
        allow_hyphen_values = true
    )]
    pub friction: f64,
    /// Show the run live in the browser at http://127.0.0.1:PORT, in real time.
    #[arg(long)]
    pub view: bool,
    /// Port of the live view (127.0.0.1 only; 0 picks a free one).
    #[arg(long, default_value_t = DEFAULT_PORT, value_name = "P")]
    pub port: u16,
    /// Keep the live view serving after the run until Ctrl-C (implies --view).
    #[arg(long)]
    pub hold: bool,
    /// One self-contained HTML file that plays the run back offline; 'none' writes none.
    #[arg(long, value_name = "F.html")]
    pub html: Option<PathBuf>,
    /// One figure of joint angles vs command, torques vs limits, tracking error (and path
    /// deviation for shapes), as .svg or .png.
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    /// The motors' sizing plot (with --motors): per joint the operating points (|ω_m|, |τ_m|) over the torque–speed envelope, the continuous torque line and the RMS point, as .svg or .png.
    #[arg(long = "plot-motors", value_name = "F.svg|F.png")]
    pub plot_motors: Option<PathBuf>,
}

/// A comma-separated value per joint; `auto` leaves a joint's value alone
/// ([`crate::config::fields::parse_per_joint`]).
#[derive(Clone, Debug, PartialEq)]
pub struct JointValues(pub Vec<Option<f64>>);

impl FromStr for JointValues {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        crate::config::fields::parse_per_joint(s).map(JointValues)
    }
}

/// `faze4 sweep`.
#[derive(Clone, Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct SweepArgs {
    /// Join the tables of a sweep's parts (--shard K/N).
    #[command(subcommand)]
    pub merge: Option<SweepCommand>,
    /// An option and its values: a range LO:HI:STEP (HI included) or a list v1,v2,… (repeatable:
    /// the runs are the product). NAME is a numeric option of the command (payload-kg, dt,
    /// duration, freq, amp-deg, amp-m, traj-period, message, shape-points, record-period,
    /// supply-voltage, driver-bandwidth, friction, clearance-tolerance, max-error,
    /// max-saturation-pct, max-deviation-mm) or a multiplier of the tuned or given values: kp-scale, kd-scale,
    /// effort-scale, mass-scale, rotor-inertia-scale, efficiency-scale, stall-torque-scale.
    #[arg(long, value_name = "NAME=LO:HI:STEP", allow_hyphen_values = true)]
    pub vary: Vec<String>,
    /// Find the largest value of NAME in [LO, HI] at which the arm still follows (bisection).
    #[arg(long, value_name = "NAME=LO:HI", allow_hyphen_values = true, conflicts_with_all = ["vary", "find_min"])]
    pub find: Option<String>,
    /// Find the smallest value of NAME in [LO, HI] at which the arm follows.
    #[arg(
        long = "find-min",
        value_name = "NAME=LO:HI",
        allow_hyphen_values = true,
        conflicts_with = "vary"
    )]
    pub find_min: Option<String>,
    /// How close --find gets (default: 1 % of the range).
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub resolution: Option<f64>,
    /// Threads (default: one per core; never more than the runs).
    #[arg(long, short, default_value_t = 0, value_name = "N", allow_hyphen_values = true, value_parser = jobs)]
    pub jobs: usize,
    /// The table, one row per run: .csv or .json (default: one line per run on stdout).
    #[arg(long, value_name = "F.csv|F.json")]
    pub out: Option<PathBuf>,
    /// Each figure against the varied option, or heatmaps for two, as .svg or .png.
    #[arg(long, value_name = "F.svg|F.png")]
    pub plot: Option<PathBuf>,
    /// Write each run's trail CSV into this directory (run_0000000.csv, …).
    #[arg(long, value_name = "DIR")]
    pub trails: Option<PathBuf>,
    /// Run only part K of N of the sweep (deterministic; `faze4 sweep merge` joins the tables).
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Each run computes its own self-clearance, as alone. By default, when the varied options
    /// keep the commanded path (payload-kg, supply-voltage, friction, the thresholds, the
    /// multipliers), the path's clearance is computed once and each run's derived from it:
    /// within --clearance-tolerance of its own, with the same intersections (docs/clearance.md,
    /// "Sweeps").
    #[arg(long)]
    pub own_clearance: bool,
    /// No progress bar and no per-run lines.
    #[arg(long, short)]
    pub quiet: bool,
    /// The base command and its options, after `--`: wave|replay|shape ….
    #[arg(last = true, value_name = "COMMAND")]
    pub base: Vec<String>,
}

/// Most threads `--jobs` takes.
pub const MAX_JOBS: usize = 1024;

/// `--jobs N`: a whole number of threads, 0 (one per core) to [`MAX_JOBS`].
fn jobs(text: &str) -> Result<usize, String> {
    let most = MAX_JOBS;
    match text.trim().parse::<usize>() {
        Ok(n) if n <= most => Ok(n),
        Ok(_) => Err(format!("at most {most} threads")),
        Err(_) => Err(format!(
            "a number of threads is a whole number from 0 (one per core) to {most}"
        )),
    }
}

/// `faze4 sweep merge`.
#[derive(Clone, Debug, Subcommand)]
pub enum SweepCommand {
    /// Join the tables of a sweep's parts into one, ordered by run; refuses a set that is not
    /// the whole sweep (a part missing, twice, partial, truncated or of another sweep).
    Merge(MergeArgs),
}

/// `faze4 sweep merge a.csv b.csv … --out all.csv`.
#[derive(Clone, Debug, Args)]
pub struct MergeArgs {
    /// The parts' tables (.csv or .json, each with its .meta beside it).
    #[arg(required = true, value_name = "F.csv|F.json")]
    pub tables: Vec<PathBuf>,
    /// The joined table, .csv or .json.
    #[arg(long, required = true, value_name = "F.csv|F.json")]
    pub out: PathBuf,
    /// Merge the parts there are, even if runs are missing or a part is partial (the output
    /// says which runs are absent).
    #[arg(long = "allow-partial")]
    pub allow_partial: bool,
}
