//! `retime`: the fastest timing of a geometric path that the motors can follow
//! (docs/retime.md).
//!
//! The path is a C² spline through the given points ([`PathSpline`]); on a grid in s the
//! limits become rows linear in x = ṡ² and u = s̈ (`grid.rs`, `envelope.rs`, `limits.rs`);
//! TOPP-RA's backward and forward passes give the time-optimal profile under them (`reach.rs`),
//! iterated with lines tangent to the motors' speed-dependent envelopes and each profile
//! checked against them at every grid point (`solve.rs`); that profile is averaged over a
//! window so that s̈ is continuous and 0 at both ends (`smooth.rs`), and the trajectory written
//! is sampled as a controller plays it, TOPP-RA capped where it passes a limit between the
//! points (`played.rs`); the timing is then played in faze4's closed loop, and where it does
//! not follow the segments where it failed are slowed and it is tried again (`check.rs`).
//!
//! ```no_run
//! use faze4::retime::{PathSpline, RetimeOptions, hold, retime};
//! use faze4::sim::Scenario;
//! # fn main() -> faze4::Result<()> {
//! let mut model = faze4::faze4::model();
//! let motors = faze4::config::motors::fit(&mut model, Some(faze4::faze4::motors::faze4(None)), &[], &[])?;
//! let points: Vec<Vec<f64>> = vec![vec![0.0; 6], vec![0.3, 0.4, -0.5, 0.0, 0.2, 0.0], vec![0.6, 0.1, -0.2, 0.0, 0.0, 0.0]];
//! let path = PathSpline::through(&points)?;
//! let base = Scenario::builder(model, hold(&path)).motors(motors.unwrap());
//! let timed = retime(&base, &path, &RetimeOptions::default())?;
//! println!("{:.3} s, {}", timed.profile.duration(), timed.check.as_ref().unwrap().summary.verdict);
//! # Ok(()) }
//! ```

mod check;
mod clearance;
mod ends;
mod envelope;
mod grid;
mod limits;
mod phase;
mod played;
mod reach;
mod smooth;
mod solve;
mod spline;
mod timing;

use std::fmt;

pub use check::command;
pub use clearance::CLEARANCE_STEP;
pub use ends::TANGENT;
pub use limits::SpeedSource;
pub use phase::PhasePlane;
pub use played::{Played, SAMPLES};
pub use solve::{MAX_ITERATIONS, SETTLED};
pub use spline::PathSpline;
pub use timing::timed_trajectory;

use crate::error::{Error, Result, shortest};
use crate::id::JointId;
use crate::input::MAX_RETIME_INTERVALS;
use crate::sim::{ScenarioBuilder, StopFlag, Summary, Tape};
use crate::traj::{Interpolated, TimedTrajectory, Trajectory, Wrap};

/// Default number of grid intervals in s.
pub const DEFAULT_INTERVALS: usize = 200;
/// Default margin: the share of every torque limit (the motor's envelope at each speed, or the
/// constant limit) left for the feedback (docs/retime.md, "The margin").
pub const DEFAULT_MARGIN: f64 = 0.3;
/// Default number of closed-loop checks: the first timing and the slowed ones after it.
pub const DEFAULT_ATTEMPTS: usize = 8;
/// Where a check fails by torque or tracking, x = ṡ² is capped at this share of its value there
/// (ṡ at its square root, about 0.89) and the timing is found again; where a speed passed its
/// limit, at (limit/speed)² of it.
pub const SLOWDOWN: f64 = 0.8;
/// A failure at time t slows every segment the timing spends in [t − LOOKBACK_S, t]: a
/// tracking error builds up over the segments before it shows.
pub const LOOKBACK_S: f64 = 0.05;

/// How to retime.
#[derive(Clone, Debug)]
pub struct RetimeOptions {
    /// Grid intervals in s (1 to [`MAX_RETIME_INTERVALS`]): the limits are kept at the N + 1
    /// grid points.
    pub intervals: usize,
    /// The share of each torque limit left for the feedback, in [0, 1).
    pub margin: f64,
    /// Whether to play the timing in the closed loop and slow it where it does not follow.
    pub check: bool,
    /// Most checks (≥ 1), the first included.
    pub attempts: usize,
    /// Acceleration limits per joint (rad/s² or m/s²; `None` or an empty list: none), kept
    /// along the played trajectory.
    pub max_acceleration: Vec<Option<f64>>,
    /// Jerk limits per joint (rad/s³ or m/s³; `None` or an empty list: none), kept along the
    /// played trajectory by widening the smoothing window, the joint's acceleration rows
    /// lowered to the jerk times a searched window (docs/retime.md, "Smooth ends and jerk").
    pub max_jerk: Vec<Option<f64>>,
    /// The joint velocity the timing starts at (rad/s or m/s per joint; empty, or `None` for a
    /// joint: 0, so all empty starts at rest): along the path's tangent there, q̇ = q′ ṡ₀ with
    /// ṡ₀ ≥ 0, within [`TANGENT`] of its norm; the check's arm arrives at the path's start
    /// with it (docs/retime.md, "Chaining segments").
    pub start_velocity: Vec<Option<f64>>,
    /// The joint velocity the timing ends at, likewise (empty: at rest).
    pub end_velocity: Vec<Option<f64>>,
    /// Whether the last check run is kept ([`Check::tape`]) to be handed to recorders
    /// afterwards, instead of playing the timing again for them; `Some(reads_intersections)`
    /// (see [`Tape::new`]).
    pub tape: Option<bool>,
    /// Stops a check run early (Ctrl-C); the check then reports what ran.
    pub stop: StopFlag,
}

impl Default for RetimeOptions {
    fn default() -> Self {
        RetimeOptions {
            intervals: DEFAULT_INTERVALS,
            margin: DEFAULT_MARGIN,
            check: true,
            attempts: DEFAULT_ATTEMPTS,
            max_acceleration: Vec::new(),
            max_jerk: Vec::new(),
            start_velocity: Vec::new(),
            end_velocity: Vec::new(),
            tape: None,
            stop: StopFlag::new(),
        }
    }
}

impl RetimeOptions {
    /// Every option within its range, an error naming the field otherwise (`grid`, `margin`,
    /// `attempts`).
    pub fn check(&self) -> Result<()> {
        if self.intervals == 0 {
            return Err(Error::option("grid", "0 intervals: at least 1"));
        }
        if self.intervals > MAX_RETIME_INTERVALS {
            return Err(Error::option(
                "grid",
                format!(
                    "{} intervals: at most {MAX_RETIME_INTERVALS} (each grid point holds about 2 kB; docs/development.md, Caps)",
                    self.intervals
                ),
            ));
        }
        if !(self.margin >= 0.0 && self.margin < 1.0) {
            return Err(Error::option(
                "margin",
                format!("{} is not in [0, 1)", crate::error::shortest(self.margin)),
            ));
        }
        if self.attempts == 0 {
            return Err(Error::option("attempts", "0 checks: at least 1"));
        }
        Ok(())
    }
}

/// A timing on the grid: per grid point s_i the squared path speed x_i = ṡ² and the time
/// t_i; per interval the path acceleration u_i = s̈ (constant on it).
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// s_i (rad or m of path length), N + 1.
    pub s: Vec<f64>,
    /// x_i = ṡ² ((path units/s)²), N + 1; 0 at an end at rest, the given path speed's square
    /// at a moving one.
    pub x: Vec<f64>,
    /// u_i = s̈ on [s_i, s_i+1] (path units/s²), N.
    pub u: Vec<f64>,
    /// t_i (s), N + 1, from 0.
    pub t: Vec<f64>,
    /// s̈ at each grid point (path units/s²), N + 1: the acceleration written there. TOPP-RA's
    /// own profile takes the interval's that starts there (the last point the last
    /// interval's); retime's smooth timing its s̈ at the point, 0 at both ends.
    pub sdd: Vec<f64>,
}

/// The limit that shapes a segment of the timing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// A joint's speed limit.
    Speed(SpeedSource),
    /// A joint's torque at the top of its range.
    TorqueUpper,
    /// A joint's torque at the bottom of its range.
    TorqueLower,
    /// A joint's acceleration limit (`--max-accel`).
    Acceleration,
    /// The cap the closed-loop check set where an earlier timing failed.
    Slowed,
    /// A cap set where the played trajectory (a quintic between the written points) passed a
    /// limit between grid points.
    Played,
    /// Held at the path speed of a given start or end velocity (the first or last ṡ·w/2 of
    /// path: docs/retime.md, "Chaining segments").
    Held,
    /// No constraint of the segment's own (none given).
    None,
}

/// What shapes one segment: the constraint with the least slack at the segment's start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Binding {
    /// The joint (none for a slowdown).
    pub joint: Option<JointId>,
    /// Which of its limits.
    pub limit: Limit,
    /// Its slack, relative (to the torque range's width, or to the cap): 0 where it binds;
    /// a segment whose least slack is above 0 follows a limit further on (it brakes or
    /// accelerates towards it).
    pub slack: f64,
}

/// A relative slack at or below which a [`Binding`] binds (round-off of the passes).
pub const BINDS: f64 = 1e-6;

impl Binding {
    /// Whether the limit binds on the segment (its slack at most [`BINDS`]).
    pub fn binds(&self) -> bool {
        self.slack <= BINDS
    }
}

impl fmt::Display for Binding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let joint = self.joint.map_or(String::new(), |j| format!("{j} "));
        let limit = match self.limit {
            Limit::Speed(SpeedSource::Given) => "speed limit",
            Limit::Speed(SpeedSource::Motor) => "motor top speed",
            Limit::TorqueUpper => "torque (upper)",
            Limit::TorqueLower => "torque (lower)",
            Limit::Acceleration => "acceleration limit",
            Limit::Slowed => "slowed by the check",
            Limit::Played => "slowed to keep the limits between the points",
            Limit::Held => "held at the given start or end velocity (half the smoothing window)",
            Limit::None => "none",
        };
        write!(f, "{joint}{limit}")
    }
}

/// The closed-loop check of the timing.
#[derive(Clone, Debug)]
pub struct Check {
    /// The summary of the last check run (its verdict says whether the timing follows).
    pub summary: Summary,
    /// Check runs made (the first timing's included).
    pub attempts: usize,
    /// Grid points whose speed the checks capped.
    pub slowed_points: usize,
    /// The last check run's samples, with [`RetimeOptions::tape`]: [`Tape::play`] hands them to
    /// recorders as a run of [`replay_scenario`] would (the same run: the summary is
    /// [`Check::summary`]).
    pub tape: Option<Tape>,
}

/// What retime found.
#[derive(Clone, Debug)]
pub struct Retimed {
    /// The timing on the grid: TOPP-RA's averaged over [`Retimed::window`], s̈ continuous,
    /// starting and ending at rest (or at the given velocities) with s̈ = 0.
    pub profile: Profile,
    /// TOPP-RA's time-optimal profile on the grid under the limits (s̈ bang-bang, the limits
    /// kept at the grid points only), before any cap or averaging: what toppra gives.
    pub toppra: Profile,
    /// The averaging window (s): the timing is this much longer than TOPP-RA's (half of it
    /// with one end moving, as long with both).
    pub window: f64,
    /// The timing at the grid points as a joint trajectory (positions, velocities,
    /// accelerations, times to the nanosecond; [`timed_trajectory`]): what the check played
    /// and the file writers write.
    pub trajectory: TimedTrajectory,
    /// Per segment, what shapes it.
    pub bindings: Vec<Binding>,
    /// The duration with each torque limit at its standstill value (a motor's holding torque),
    /// constant, and no cap from the check (s): no timing that keeps the envelopes is faster.
    pub relaxed_duration: f64,
    /// Rounds of the envelopes' bounds (0 when no limit depends on speed).
    pub iterations: usize,
    /// The trajectory as a controller plays it (a quintic between its points), sampled
    /// [`SAMPLES`] times per interval: the most it asks of a speed or torque limit (less the
    /// margin), ≤ 1 where every limit is kept between the grid points too.
    pub played: Played,
    /// The closed-loop check, when asked for.
    pub check: Option<Check>,
    /// The grid, the limits and the last pass's controllable sets, for [`Retimed::phase_plane`].
    grid: grid::PathGrid,
    limits: limits::Limits,
    controllable: Vec<[f64; 2]>,
}

impl Retimed {
    /// The phase plane's curves, for the figure (each joint's torque-limit curve is found by
    /// bisection at every grid point: about a millisecond per joint).
    pub fn phase_plane(&self) -> PhasePlane {
        phase::phase_plane(&self.grid, &self.limits, &self.profile, &self.controllable)
    }
}

/// A command holding the path's first point: the trajectory to give
/// [`crate::sim::Scenario::builder`] for the `base` of [`retime`] (retime replaces it).
pub fn hold(path: &PathSpline) -> Trajectory {
    let mut start = vec![0.0; path.dof()];
    path.position(0.0, &mut start);
    Trajectory::Interpolated(Interpolated::new(&[start.clone(), start], 1.0, Wrap::Repeat))
}

/// Plays `profile` along `path` in the closed loop of the scenario `base` builds, as
/// [`retime`]'s check does (the timing at its grid points, [`timed_trajectory`], played as
/// `faze4 replay` plays a file, [`command`]), and returns the run's summary: how a timing
/// found elsewhere (another retimer) fares in faze4's loop.
pub fn play(base: &ScenarioBuilder, path: &PathSpline, profile: &Profile, stop: &StopFlag) -> Result<Summary> {
    let start = at_start(base, path)?;
    let trajectory = timed_trajectory(profile, path, joint_names(&start.model));
    let (command, duration) = command(&start.model, &trajectory)?;
    let scenario = check::scenario(base, command, duration, start.collision_set.clone())?;
    Ok(check::run_check(&scenario, None, stop)?.0)
}

/// The scenario that plays `trajectory` (a timing of [`retime`]) on `base` as `faze4 replay`
/// plays its file: the check's, for a front end that records the run.
pub fn replay_scenario(base: &ScenarioBuilder, trajectory: &TimedTrajectory) -> Result<crate::sim::Scenario> {
    let (command, duration) = command(base.model(), trajectory)?;
    base.clone()
        .trajectory(command)
        .duration(duration)
        .command("replay (retimed)")
        .build()
}

/// The scenario `base` builds holding the path's first point: its model, limits and
/// collision set (never run; its duration 1 s, or one step of a longer `dt`, which the check
/// refuses naming `dt` if the timing is shorter).
fn at_start(base: &ScenarioBuilder, path: &PathSpline) -> Result<crate::sim::Scenario> {
    check::scenario(base, hold(path), base.time_step().max(1.0), None)
}

/// The model's joint names, in its order (the trajectory's columns).
fn joint_names(model: &crate::model::Model) -> Vec<String> {
    model.joints.iter().map(|j| j.name.clone()).collect()
}

/// The fastest timing of `path` that keeps the limits of the scenario `base` builds (its
/// model with payload and motors, torque and speed limits), less `options.margin`, on a grid of
/// `options.intervals`; then, with `options.check`, played in `base`'s closed loop and slowed
/// where it fails, up to `options.attempts` runs. The check's scenario is `base` with the
/// timing's command ([`command`]).
///
/// Errors: bad options; a path whose points do not fit the model or leave its joint limits
/// ([`Error::BadPath`]); limits that no timing keeps, however slow
/// ([`Error::NothingFollows`]); a path whose collision geometry intersects itself
/// ([`Error::PathCollides`], checked before any timing, at every grid point and between them, each joint moving at
/// most [`CLEARANCE_STEP`] from one sample to the next); and whatever building the scenario reports. A timing that the
/// checks never see follow is returned, its check's verdict saying why.
pub fn retime(base: &ScenarioBuilder, path: &PathSpline, options: &RetimeOptions) -> Result<Retimed> {
    options.check()?;
    check_points(base.model(), path)?;
    let start = at_start(base, path)?;
    let model = &start.model;
    let grid = grid::PathGrid::new(model, path, options.intervals);
    check_between(model, path, &grid)?;
    if let Some(set) = &start.collision_set {
        clearance::check_path(model, set, start.clearance_tolerance, path, &grid, &options.stop)?;
    }
    let limits = limits::Limits::of(&start, options)?;
    let ends = ends::Ends::of(model, path, options)?;
    let names = joint_names(model);
    let given = AsPlayed {
        model,
        path,
        limits: &limits,
        names: &names,
        longest: longest(start.dt, options.check),
        options,
    };
    let limits = jerk_bound(given, &grid, ends)?;
    let mut solver = solve::Solver::new(&grid, &limits, ends);
    let n = grid.points();
    let mut cap = vec![f64::INFINITY; n];
    let mut slowed = vec![false; n];
    let located = |e: Error| match e {
        Error::NothingFollows {
            s,
            length,
            joint,
            message,
            ..
        } => Error::NothingFollows {
            s,
            length,
            point: path.nearest_point(s),
            joint,
            message,
        },
        e => e,
    };
    limits::held_at_ends(&start, &grid, ends).map_err(located)?;
    let as_played = AsPlayed {
        limits: &limits,
        ..given
    };
    let mut window = 0.0;
    let mut timed = as_played.solve(&mut solver, &mut cap, &mut window).map_err(located)?;
    // the bound without the check's caps (a capped solve's relaxed profile is capped too)
    let relaxed_duration = timed.solved.relaxed_duration;
    let toppra = timed.uncapped.clone();
    let mut check = None;
    let mut tape = options.tape.map(Tape::new);
    let mut taped = false;
    if options.check {
        for attempt in 1..=options.attempts {
            let (command, duration) = command(model, &timed.trajectory)?;
            let scenario = check::scenario(base, command, duration, start.collision_set.clone())?;
            // taped only when it fits the budget: else the outputs play the timing again
            taped = Tape::fits(&scenario, duration);
            let recording = tape.as_mut().filter(|_| taped);
            let (summary, failed_at) = check::run_check(&scenario, recording, &options.stop)?;
            let done = summary.verdict.follows || attempt == options.attempts || summary.interrupted_at_s.is_some();
            let slowed_now = match done {
                true => 0,
                false => {
                    let at = Slowing {
                        raw: &timed.solved.profile,
                        smooth: &timed.profile,
                        window,
                        offset: timed.offset,
                    };
                    slow_down(&at, &grid, &limits, &failed_at, &mut cap, &mut slowed)
                }
            };
            check = Some(Check {
                summary,
                attempts: attempt,
                slowed_points: slowed.iter().filter(|&&s| s).count(),
                tape: None,
            });
            if done || slowed_now == 0 {
                break;
            }
            timed = as_played.solve(&mut solver, &mut cap, &mut window).map_err(located)?;
        }
    }
    if let Some(check) = check.as_mut() {
        check.tape = tape.filter(|_| taped);
    }
    let bindings = solver.bindings(&timed.solved.profile, &slowed);
    let controllable = solver.controllable().to_vec();
    Ok(Retimed {
        trajectory: timed.trajectory,
        profile: timed.profile,
        toppra,
        window,
        bindings,
        relaxed_duration,
        iterations: timed.solved.iterations,
        played: timed.played,
        check,
        controllable,
        limits,
        grid,
    })
}

/// `limits` with each jerk-limited joint's acceleration lowered to J̄·w, w searched (a log
/// grid, then golden sections) for the shortest played timing that keeps every limit; `limits`
/// unchanged without a jerk limit or where none is shorter (docs/retime.md, "Smooth ends and
/// jerk").
fn jerk_bound(as_played: AsPlayed, grid: &grid::PathGrid, ends: ends::Ends) -> Result<limits::Limits> {
    let limits = as_played.limits;
    if limits.jerk.iter().all(|j| j.is_infinite()) {
        return Ok(limits.clone());
    }
    let timed = |limits: &limits::Limits, ends: ends::Ends| -> Result<(f64, f64)> {
        let mut solver = solve::Solver::new(grid, limits, ends);
        let mut cap = vec![f64::INFINITY; grid.points()];
        let mut window = 0.0;
        let as_played = AsPlayed { limits, ..as_played };
        let timed = as_played.solve(&mut solver, &mut cap, &mut window)?;
        let duration = match timed.played.worst <= 1.0 {
            true => timed.profile.duration(),
            false => f64::INFINITY,
        };
        Ok((duration, window))
    };
    let lowered = |w: f64| {
        let mut l = limits.clone();
        for (a, j) in l.acceleration.iter_mut().zip(&limits.jerk) {
            *a = a.min(j * w);
        }
        l
    };
    let (full, widest) = match timed(limits, ends) {
        Ok(timed) => timed,
        // a moving end's held stretch may not fit the window the full acceleration needs
        // (the jerk over it): searched on the scale of that window with the ends at rest
        Err(e) if ends != ends::Ends::default() => {
            (f64::INFINITY, timed(limits, ends::Ends::default()).map_err(|_| e)?.1)
        }
        Err(e) => return Err(e),
    };
    let duration = |w: f64| timed(&lowered(w), ends).map_or(f64::INFINITY, |(d, _)| d);
    // a log grid over [widest/50, widest], then golden sections around its best
    let at = |k: usize| widest * 50f64.powf(k as f64 / 15.0 - 1.0);
    let tried: Vec<(f64, f64)> = (0..=15).map(|k| (at(k), duration(at(k)))).collect();
    let best = (0..tried.len())
        .min_by(|&a, &b| tried[a].1.total_cmp(&tried[b].1))
        .unwrap_or(0);
    let (mut lo, mut hi) = (at(best.saturating_sub(1)), at((best + 1).min(15)));
    let (mut best_w, mut best_d) = tried[best];
    // each section keeps one of its two inner points as an inner point of the next (φ² = 1 − φ),
    // so each of the 10 sections times one new window
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let mut timed_and_kept = |w: f64| {
        let d = duration(w);
        if d < best_d {
            (best_w, best_d) = (w, d);
        }
        d
    };
    let (mut a, mut b) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
    let (mut da, mut db) = (timed_and_kept(a), timed_and_kept(b));
    for _ in 0..10 {
        match da < db {
            true => {
                (hi, b, db) = (b, a, da);
                a = hi - phi * (hi - lo);
                da = timed_and_kept(a);
            }
            false => {
                (lo, a, da) = (a, b, db);
                b = lo + phi * (hi - lo);
                db = timed_and_kept(b);
            }
        }
    }
    match best_d < full {
        true => Ok(lowered(best_w)),
        false => Ok(limits.clone()),
    }
}

/// What [`retime`] needs to time the path as a controller plays it.
#[derive(Clone, Copy)]
struct AsPlayed<'a> {
    model: &'a crate::model::Model,
    path: &'a PathSpline,
    limits: &'a limits::Limits,
    names: &'a [String],
    /// The longest timing that can be written and checked (s, [`longest`]).
    longest: f64,
    /// The options, to name the limit a timing too long comes from.
    options: &'a RetimeOptions,
}

/// [`Error::Stopped`] once a stop is asked for ([`StopFlag::asked`]): timing a path has nothing
/// to finish (on the command line a signal ends the process at once instead).
pub(super) fn not_stopped(stop: &StopFlag) -> Result<()> {
    match stop.asked() {
        true => Err(Error::Stopped {
            what: "retime timed the path",
        }),
        false => Ok(()),
    }
}

/// The longest timing (s) retime writes: its times are whole nanoseconds in an `i64` (about
/// 292 years), and with the check, at most the 10^12 steps of `dt` a run may take.
fn longest(dt: f64, check: bool) -> f64 {
    let nanoseconds = crate::traj::timed::seconds_from_nanoseconds(i64::MAX);
    match check {
        true => nanoseconds.min(crate::sim::MAX_STEPS * dt),
        false => nanoseconds,
    }
}

/// A timing as [`AsPlayed::solve`] finds it.
struct Timed {
    /// TOPP-RA's profile (s̈ constant on each interval) and how it was found.
    solved: solve::Solved,
    /// It averaged over the window: the timing written.
    profile: Profile,
    /// Where the written timing starts on the raw profile's clock (s): 0 from rest.
    offset: f64,
    /// The written trajectory.
    trajectory: TimedTrajectory,
    /// The most it asks of a limit as played.
    played: Played,
    /// The first TOPP-RA profile, before the caps of this call.
    uncapped: Profile,
}

/// The smoothing window as a share of TOPP-RA's duration, where no jerk limit asks for a
/// wider one (docs/retime.md, "Smooth ends and jerk").
pub const WINDOW: f64 = 0.05;
/// Most widenings of the window for a jerk limit in one round.
const WIDENINGS: usize = 12;
/// Most rounds of holding a moving end's speed over half the window, which lengthens the
/// timing and so the window (a fixed point; docs/retime.md, "Chaining segments").
pub const HOLD_ROUNDS: usize = 30;

impl AsPlayed<'_> {
    /// An error when the timing (`duration` s, of which TOPP-RA's `raw`) is longer than
    /// [`longest`], naming the limit it comes from: the jerk's where the window made it so,
    /// else the acceleration's if one is given, else the speeds' if one is given, else the
    /// torques'.
    fn within_longest(&self, raw: f64, duration: f64) -> Result<()> {
        if duration <= self.longest {
            return Ok(());
        }
        let speed_given = (self.limits.speed.iter().zip(&self.limits.speed_source))
            .any(|(v, source)| v.is_finite() && *source == limits::SpeedSource::Given);
        let field = match raw <= self.longest {
            true => "max_jerk",
            false if self.options.max_acceleration.iter().any(Option::is_some) => "max_accel",
            false if speed_given => "max_speed",
            false => "effort",
        };
        Err(Error::option(
            field,
            format!(
                "the timing would take {} s, more than the {} s retime writes{}: is a limit given in the wrong unit?",
                shortest(duration),
                shortest(self.longest),
                match self.options.check {
                    true => " and checks (10^12 steps of `dt`, or times in whole nanoseconds)",
                    false => " (times in whole nanoseconds)",
                }
            ),
        ))
    }

    /// TOPP-RA's profile under `cap`, averaged over the window (`window`, s; at least
    /// [`WINDOW`] of the profile's duration, widened until the played jerk keeps its limits),
    /// then, while its trajectory played (a quintic between points) passes a limit, `cap`
    /// lowered where the raw profile fed the failing interval and all found again (at most
    /// [`played::ROUNDS`] rounds).
    /// With a moving end, its speed is held over the path's first (last) ṡ·w/2 and all found
    /// again while the window outgrows what is held (at most [`HOLD_ROUNDS`] rounds).
    fn solve(&self, solver: &mut solve::Solver, cap: &mut [f64], window: &mut f64) -> Result<Timed> {
        let mut keep = vec![1.0; cap.len().saturating_sub(1)];
        let mut uncapped = None;
        let (mut round, mut holds) = (0, 0);
        loop {
            not_stopped(&self.options.stop)?;
            let solved = solver.solve(cap)?;
            if uncapped.is_none() {
                uncapped = Some(solved.profile.clone());
            }
            let raw = &solved.profile;
            *window = window.max(WINDOW * raw.duration()).max(self.limits.window);
            let mut widened = 0;
            let (profile, offset, trajectory, played) = loop {
                not_stopped(&self.options.stop)?;
                let averaged = smooth::Averaged::new(raw, *window);
                let (profile, offset) = (averaged.profile(), averaged.offset());
                self.within_longest(raw.duration(), profile.duration())?;
                let trajectory = timed_trajectory(&profile, self.path, self.names.to_vec());
                let (command, _) = command(self.model, &trajectory)?;
                let times: Vec<f64> = trajectory.points.iter().map(|p| p.time_from_start).collect();
                let (played, jerk) = played::sample(self.model, self.limits, &command, &times, &mut keep);
                if jerk <= 1.0 || widened == WIDENINGS {
                    break (profile, offset, trajectory, played);
                }
                // the path's jerk falls about as 1/w
                *window *= jerk * 1.02;
                widened += 1;
            };
            if solver.hold(*window)? {
                holds += 1;
                if holds > HOLD_ROUNDS {
                    return Err(Error::option(
                        solver.moving_end(),
                        format!(
                            "the smoothing window ({:.4} s) and the stretch of path held at the given speed (half a window) did not settle in {HOLD_ROUNDS} rounds",
                            *window
                        ),
                    ));
                }
                // TOPP-RA's own profile is the one under the held stretches
                uncapped = None;
                continue;
            }
            let capped = match round < played::ROUNDS {
                true => cap_raw(raw, &profile, *window, offset, &keep, cap),
                false => 0,
            };
            round += 1;
            if capped == 0 {
                let uncapped = uncapped.take().unwrap_or_else(|| solved.profile.clone());
                return Ok(Timed {
                    solved,
                    profile,
                    offset,
                    trajectory,
                    played,
                    uncapped,
                });
            }
        }
    }
}

/// Caps x at each raw grid point that fed an interval of the smooth profile whose played
/// samples passed a limit (the raw timing over [t_i − w, t_{i+1}], the smooth one's
/// interval and its window before it, its times `offset` later on the raw clock), at that
/// interval's `keep` share of the raw x. Returns how many points it capped lower.
fn cap_raw(raw: &Profile, smooth: &Profile, window: f64, offset: f64, keep: &[f64], cap: &mut [f64]) -> usize {
    let mut capped = 0;
    for (i, &k) in keep.iter().enumerate().filter(|&(_, &k)| k < 1.0) {
        let first = raw.interval_at(smooth.t[i] + offset - window);
        let last = raw.interval_at(smooth.t[i + 1] + offset);
        for p in first..=last + 1 {
            let limit = k * raw.x[p];
            if limit < cap[p] && raw.x[p] > 0.0 {
                cap[p] = limit;
                capped += 1;
            }
        }
    }
    capped
}

/// The raw and smooth profiles of a checked timing, to map a failure's time to the raw grid
/// points that fed it.
struct Slowing<'a> {
    raw: &'a Profile,
    smooth: &'a Profile,
    window: f64,
    /// Where the smooth timing starts on the raw profile's clock (s).
    offset: f64,
}

/// Caps x at the failure's share of the profile's at the ends of every segment the timing
/// spends within [`LOOKBACK_S`] before a failure (a failure after the end: the last segments);
/// and where a joint passed its speed limit, at every point where the profile rides that
/// joint's limit ([`RIDING`]), at the lowest share its failures found: the loop overshoots
/// each stretch at the limit alike, and one run then slows them all. Returns how many points
/// it capped lower.
fn slow_down(
    at: &Slowing,
    grid: &grid::PathGrid,
    limits: &limits::Limits,
    failures: &[check::Failure],
    cap: &mut [f64],
    slowed: &mut [bool],
) -> usize {
    let profile = at.raw;
    let mut capped = 0;
    let mut lower = |i: usize, keep: f64| {
        let limit = keep * profile.x[i];
        if limit < cap[i] && profile.x[i] > 0.0 {
            cap[i] = limit;
            slowed[i] = true;
            capped += 1;
        }
    };
    for f in failures {
        // the raw timing's [t − w, t] fed the smooth one's state at t (on the raw clock)
        let last = profile.interval_at(f.t.min(at.smooth.duration()) + at.offset);
        let first = profile.interval_at(f.t + at.offset - LOOKBACK_S - at.window);
        for i in first..=last + 1 {
            lower(i, f.keep);
        }
    }
    let mut too_fast = vec![false; grid.dof];
    for j in failures.iter().filter_map(|f| f.too_fast) {
        too_fast[j] = true;
    }
    for j in (0..grid.dof).filter(|&j| too_fast[j]) {
        for (i, &x) in profile.x.iter().enumerate() {
            // x at joint j's limit: (v̄_j / |q′_j|)²
            let at_limit = (limits.speed[j] / grid.dq[i * grid.dof + j].abs()).powi(2);
            if x >= RIDING * at_limit {
                lower(i, check::SPEED_HEADROOM);
            }
        }
    }
    capped
}

/// A profile rides a joint's speed limit where its x is at least this share of the limit's.
const RIDING: f64 = 0.99;

/// Every point of the path within the model's joints and their limits.
fn check_points(model: &crate::model::Model, path: &PathSpline) -> Result<()> {
    if path.dof() != model.dof() {
        return Err(Error::BadPath {
            point: None,
            message: format!(
                "points have {} values; the model has {} joints",
                path.dof(),
                model.dof()
            ),
        });
    }
    for (k, q) in path.points() {
        for (j, (joint, &qj)) in model.joints.iter().zip(q).enumerate() {
            if !joint.within_limits(qj) {
                return Err(Error::BadPath {
                    point: Some(k),
                    message: format!(
                        "{} is beyond its limits [{}, {}]",
                        at_value(j, joint, qj),
                        joint.lower,
                        joint.upper
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The spline within the joint limits at every grid point (a cubic can overshoot between its
/// points).
fn check_between(model: &crate::model::Model, path: &PathSpline, grid: &grid::PathGrid) -> Result<()> {
    let dof = grid.dof;
    for i in 0..grid.points() {
        for (j, joint) in model.joints.iter().enumerate() {
            let qj = grid.q[i * dof + j];
            if !joint.within_limits(qj) {
                let s = grid.s[i];
                let k = path
                    .knots()
                    .partition_point(|&x| x <= s)
                    .clamp(1, path.knots().len() - 1);
                let (a, b) = (
                    path.nearest_point(path.knots()[k - 1]),
                    path.nearest_point(path.knots()[k]),
                );
                return Err(Error::BadPath {
                    point: None,
                    message: format!(
                        "the spline between points {a} and {b} reaches {}, beyond its limits [{}, {}]: add a point there or move them inside",
                        at_value(j, joint, qj),
                        joint.lower,
                        joint.upper
                    ),
                });
            }
        }
    }
    Ok(())
}

/// Joint j at `value`, for a message: `J2 ('nadlaktica') = 1.9 rad`.
fn at_value(j: usize, joint: &crate::model::Joint, value: f64) -> String {
    format!(
        "J{} ({}) = {value} {}",
        j + 1,
        crate::error::quoted(&joint.name),
        joint.kind.unit()
    )
}
