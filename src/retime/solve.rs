//! The time-optimal profile under the limits: TOPP-RA on rows rebuilt around the profile until
//! it settles (docs/retime.md, "The algorithm").
//!
//! 1. **Relaxed.** Each joint's range at standstill, constant in x (for a stepper its holding
//!    torque): TOPP-RA gives a profile at least as fast as any that keeps the true envelope (a
//!    lower bound on the optimal duration), but not one the motors can give.
//! 2. **Sound.** Each side of each range replaced by a line in x that bounds it over the whole
//!    admissible x of its grid point ([`JointTorque::line_below`]), as tight as it can be at
//!    the relaxed profile; TOPP-RA again. This profile keeps the true envelope at every grid
//!    point, and is the answer if step 3 finds none faster.
//! 3. **Tangent, verified.** A line below the value over the whole admissible x gives up
//!    torque where the curve bends down (a pull-out curve past its knee: the tangent there
//!    passes above the flat part at low speed, so the sound line is lowered to stay below it).
//!    Each side is replaced by its tangent at the previous profile
//!    ([`JointTorque::line_tangent`]), which holds only near it; TOPP-RA again, and every grid
//!    point of the new profile is checked against the true range ([`JointTorque::range`] at the
//!    point's own speed). A point and joint found outside it takes the sound line from then on.
//!    Repeat until a profile keeps every range and its duration changes by less than
//!    [`SETTLED`] (or [`MAX_ITERATIONS`] rounds in all); the fastest profile that keeps every
//!    range is kept, so the result keeps the true envelope at every grid point as step 2's
//!    does (the circle: 0.8163 s sound, 0.7920 s after 5 tangent rounds).

use super::ends::Ends;
use super::envelope::{Line, Side};
use super::grid::PathGrid;
use super::limits::Limits;
use super::reach::{Row, Stages, Stuck};
use super::{Binding, Limit, Profile};
use crate::error::{Error, Result, six_digits};
use crate::id::JointId;

/// Relative change of duration below which the iteration has settled (0.01 %).
pub const SETTLED: f64 = 1e-4;
/// Most rounds of lines in all (the sound one and the tangent ones).
pub const MAX_ITERATIONS: usize = 30;
/// The share step 2's operating points are lowered by when nothing follows under its lines.
const LOWER: f64 = 0.25;
/// Most lowerings of step 2's operating points (0.25⁴⁰ ≈ 10⁻²⁴ of the relaxed x).
const LOWERINGS: usize = 40;
/// A torque beyond its range by at most this share of the range's larger end is round-off of
/// the passes, not outside it.
const OUTSIDE: f64 = 1e-9;

/// The grid, the limits and the workspaces of the passes.
pub(crate) struct Solver<'a> {
    grid: &'a PathGrid,
    limits: &'a Limits,
    stages: Stages,
    /// Per point and joint: the line below hi and the line below −lo (see [`Side`]).
    lines: Vec<[Line; 2]>,
    /// Per point: the cap on x from the speed limits, and the joint that sets it.
    speed_cap: Vec<(f64, Option<usize>)>,
    k: Vec<[f64; 2]>,
    /// Per point: the largest x any timing under the limits can have there (the relaxed
    /// controllable set's top, within the cap), over which a sound line holds.
    reach: Vec<f64>,
    /// The path speeds at the ends.
    ends: Ends,
    /// The last point held at the start's speed and the first held at the end's (0 and N when
    /// neither end moves): see [`Solver::hold`].
    held: [usize; 2],
}

/// A profile and how it was found.
pub(crate) struct Solved {
    /// The fastest sound profile.
    pub profile: Profile,
    /// The relaxed profile's duration (s): a lower bound on any timing's under these limits.
    pub relaxed_duration: f64,
    /// Rounds of lines run (the sound one and the tangent ones).
    pub iterations: usize,
}

impl<'a> Solver<'a> {
    /// The solver of `grid` under `limits`, starting and ending at the path speeds `ends`.
    pub fn new(grid: &'a PathGrid, limits: &'a Limits, ends: Ends) -> Self {
        let (n, dof) = (grid.points(), grid.dof);
        let speed_cap = (0..n)
            .map(|i| {
                let mut cap = (f64::INFINITY, None);
                for j in 0..dof {
                    let w = grid.dq[i * dof + j].abs();
                    let x = (limits.speed[j] / w).powi(2);
                    if x < cap.0 {
                        cap = (x, Some(j));
                    }
                }
                cap
            })
            .collect();
        Solver {
            grid,
            limits,
            stages: Stages {
                // per joint: the torque under its upper line, over its lower line, and the
                // acceleration within ± its limit
                rows: vec![[0.0; 3]; n * 4 * dof],
                per_stage: 4 * dof,
                cap: vec![0.0; n],
                floor: vec![0.0; n],
                start: ends.start * ends.start,
                end: ends.end * ends.end,
                delta: grid.s.windows(2).map(|w| w[1] - w[0]).collect(),
            },
            lines: vec![
                [Line {
                    offset: 0.0,
                    slope: 0.0
                }; 2];
                n * dof
            ],
            speed_cap,
            k: vec![[0.0; 2]; n],
            reach: vec![f64::INFINITY; n],
            ends,
            held: [0, n - 1],
        }
    }

    /// Holds the start's path speed over its first ṡ₀·w/2 of path and the end's over its last
    /// ṡ_N·w/2 (each rounded out to a grid point), for a window of `w` seconds: the average over
    /// the window then starts and ends at exactly those speeds with s̈ = 0 (docs/retime.md,
    /// "Chaining segments"). The held stretches only grow. Returns whether they grew; an error
    /// naming the option when the two would overlap.
    pub fn hold(&mut self, w: f64) -> Result<bool> {
        let s = &self.grid.s;
        let (n, length) = (s.len(), s[s.len() - 1]);
        let mut held = self.held;
        if self.ends.start > 0.0 {
            let reach = self.ends.start * w / 2.0;
            held[0] = held[0].max(s.partition_point(|&si| si < reach).min(n - 1));
        }
        if self.ends.end > 0.0 {
            let reach = length - self.ends.end * w / 2.0;
            held[1] = held[1].min(s.partition_point(|&si| si <= reach).saturating_sub(1));
        }
        if held[0] >= held[1] {
            return Err(Error::option(
                self.moving_end(),
                format!(
                    "the path ({length:.4} long) is too short to hold the start's path speed {:.4} and the end's {:.4} over half the {w:.4} s smoothing window each (ṡ·w/2 of path at each end: docs/retime.md, \"Chaining segments\")",
                    self.ends.start, self.ends.end
                ),
            ));
        }
        let grew = held != self.held;
        self.held = held;
        Ok(grew)
    }

    /// The option of a moving end, for a message: `start_velocity` when the start moves.
    pub fn moving_end(&self) -> &'static str {
        match self.ends.start > 0.0 {
            true => "start_velocity",
            false => "end_velocity",
        }
    }

    /// The points held at a boundary speed, `Some(x)` with its x = ṡ², at `i`.
    fn held_at(&self, i: usize) -> Option<f64> {
        let (start, end) = (self.stages.start, self.stages.end);
        match i {
            _ if start > 0.0 && i <= self.held[0] => Some(start),
            _ if end > 0.0 && i >= self.held[1] => Some(end),
            _ => None,
        }
    }

    /// The caps of every point (the speeds' and `extra_cap`, a held point's at its x, which
    /// no slowdown lowers) and the floors (a held point's x).
    fn set_caps(&mut self, extra_cap: &[f64]) {
        for i in 0..self.grid.points() {
            let floor = self.held_at(i).unwrap_or(0.0);
            let cap = self.speed_cap[i].0.min(extra_cap[i].max(floor));
            self.stages.floor[i] = floor;
            self.stages.cap[i] = match self.held_at(i) {
                Some(x) => cap.min(x),
                None => cap,
            };
        }
    }

    /// The fastest profile found under the limits and `extra_cap` (a cap on x per point, +∞
    /// where none: the closed-loop check's slowdowns).
    pub fn solve(&mut self, extra_cap: &[f64]) -> Result<Solved> {
        let n = self.grid.points();
        self.set_caps(extra_cap);
        // 1. relaxed: every range at standstill
        for i in 0..n {
            for j in 0..self.grid.dof {
                let torque = &self.limits.torque[j];
                let (lo, hi) = torque.range(0.0);
                self.lines[i * self.grid.dof + j] = [
                    Line { offset: hi, slope: 0.0 },
                    Line {
                        offset: -lo,
                        slope: 0.0,
                    },
                ];
            }
        }
        // the bound holds no stretch at a moving end's speed (only its first or last point):
        // a timing need not hold it, the average over the window does
        let unheld = match self.held != [0, n - 1] {
            true => {
                let held = std::mem::replace(&mut self.held, [0, n - 1]);
                self.set_caps(extra_cap);
                let unheld = self.pass().map(|p| p.duration());
                self.held = held;
                self.set_caps(extra_cap);
                unheld.ok()
            }
            false => None,
        };
        let relaxed = self.pass()?;
        let relaxed_duration = unheld.unwrap_or(relaxed.duration());
        if self.limits.torque.iter().all(|t| !t.varies()) {
            return Ok(Solved {
                profile: relaxed,
                relaxed_duration,
                iterations: 0,
            });
        }
        // 2. sound lines tangent at the relaxed profile: a profile inside every range. Each
        // line need hold only over the x a timing can have at its point: at most the relaxed
        // controllable set's top (the relaxed ranges hold every true one), which near the ends
        // is far below the speed cap (a line below a pull-out curve out to the motor's top
        // speed starts below the holding torque, and refused every move against gravity)
        // The profiles are kept within it, so the lines hold wherever they go (damping that
        // helps a joint brake widens its true range beyond the relaxed one, which could
        // otherwise take a profile past the reach)
        self.reach = self
            .k
            .iter()
            .zip(&self.stages.cap)
            .map(|(k, &cap)| k[1].min(cap))
            .collect();
        self.stages.cap.copy_from_slice(&self.reach);
        let mut at = relaxed.x.clone();
        let mut sound = vec![true; self.lines.len()];
        let sound_profile = self.sound_pass(&mut at, &sound)?;
        at.copy_from_slice(&sound_profile.x);
        let mut best: Fastest = (sound_profile, self.lines.clone(), self.k.clone());
        let mut iterations = 1;
        // 3. tangent lines around the previous profile, each point checked against the true
        // ranges; a point and joint found outside them keeps the sound line from then on; the
        // fastest profile inside every range is kept with the lines and sets it was found under
        sound.fill(false);
        let mut previous = f64::INFINITY;
        while iterations < MAX_ITERATIONS {
            iterations += 1;
            self.lines_at(&at, &sound);
            let Ok(profile) = self.pass() else { break };
            let outside = self.mark_outside(&profile, &mut sound);
            let duration = profile.duration();
            at.copy_from_slice(&profile.x);
            let settled = (previous - duration).abs() <= SETTLED * duration;
            previous = duration;
            if outside == 0 {
                if duration < best.0.duration() {
                    best = (profile, self.lines.clone(), self.k.clone());
                }
                if settled {
                    break;
                }
            }
        }
        let (profile, lines, k) = best;
        self.lines = lines;
        self.k = k;
        self.fill_rows();
        // the caps the bindings name: the speeds' and the check's, not the reach
        self.set_caps(extra_cap);
        Ok(Solved {
            profile,
            relaxed_duration,
            iterations,
        })
    }

    /// Step 2's pass on sound lines taken at `at`, and where nothing follows under them, at
    /// `at` lowered by [`LOWER`] each time, up to [`LOWERINGS`] times. A sound line is below
    /// its range over the whole reach, but the higher it is at `at` the lower it may start at
    /// x = 0: a joint whose range falls fast with speed (a light wrist's damping, a pull-out
    /// curve) and whose relaxed profile is fast gets a line below its holding torque there,
    /// and a move that must start and stop at rest is refused. Lines taken at a lower speed
    /// keep more at rest (every one of them is sound, so any profile found keeps the ranges).
    /// The first error if none passes.
    fn sound_pass(&mut self, at: &mut [f64], sound: &[bool]) -> Result<Profile> {
        let mut first = None;
        for _ in 0..=LOWERINGS {
            self.lines_at(at, sound);
            match self.pass() {
                Ok(profile) => return Ok(profile),
                Err(e) => first = first.or(Some(e)),
            }
            at.iter_mut().for_each(|x| *x *= LOWER);
        }
        Err(first.expect("one pass at least"))
    }

    /// The lines of every joint at every point around `at` (x per point): per point and joint
    /// the sound line below ([`JointTorque::line_below`], as tight as it can be at `at`) where
    /// `sound` says, the tangent at `at` ([`JointTorque::line_tangent`]) elsewhere.
    fn lines_at(&mut self, at: &[f64], sound: &[bool]) {
        let dof = self.grid.dof;
        for i in 0..self.grid.points() {
            for j in 0..dof {
                let p = i * dof + j;
                let torque = &self.limits.torque[j];
                let w = self.grid.dq[p];
                let cap = self.reach[i];
                self.lines[p] = [Side::Upper, Side::Lower].map(|side| match sound[p] {
                    true => torque.line_below(side, w, cap, at[i]),
                    false => torque.line_tangent(side, w, at[i]),
                });
            }
        }
    }

    /// Marks in `sound` every point and joint where `profile`'s torque (at the point's x and
    /// the acceleration u of the interval starting there) leaves the joint's true range at the
    /// point's speed, beyond round-off; returns how many there are.
    fn mark_outside(&self, profile: &Profile, sound: &mut [bool]) -> usize {
        let dof = self.grid.dof;
        let mut outside = 0;
        for (i, (&x, &u)) in profile.x.iter().zip(&profile.u).enumerate() {
            for j in 0..dof {
                let p = i * dof + j;
                let tau = self.grid.a[p] * u + self.grid.b[p] * x + self.grid.c[p];
                let (lo, hi) = self.limits.torque[j].range(self.grid.dq[p] * x.sqrt());
                let round_off = OUTSIDE * hi.abs().max(lo.abs());
                if tau > hi + round_off || tau < lo - round_off {
                    sound[p] = true;
                    outside += 1;
                }
            }
        }
        outside
    }

    /// The rows from the current lines, both passes, and the profile with its times.
    fn pass(&mut self) -> Result<Profile> {
        self.fill_rows();
        let n = self.grid.points();
        if let Err(Stuck(i)) = self.stages.controllable_sets(&mut self.k) {
            return Err(self.stuck(i));
        }
        let (mut x, mut u) = (vec![0.0; n], vec![0.0; n - 1]);
        self.stages.forward(&self.k, &mut x, &mut u);
        // rest at two neighbouring points: the limits allow no motion between them
        if let Some(i) = (0..n - 1).find(|&i| x[i] == 0.0 && x[i + 1] == 0.0) {
            return Err(self.nothing_follows(i.max(1).min(n - 2)));
        }
        let mut profile = Profile::from_x(self.grid.s.clone(), x);
        profile.sdd = (0..n).map(|i| u[i.min(n - 2)]).collect();
        profile.u = u;
        Ok(profile)
    }

    /// Stage rows `α u + β x ≤ γ` from the lines: per joint
    /// `a u + (b − h1) x ≤ h0 − c` (τ below the line under hi),
    /// `−a u − (b + l1) x ≤ l0 + c` (τ above the line over lo), and the acceleration
    /// q̈ = q′ u + q″ x within ± its limit Ā: `q′ u + q″ x ≤ Ā`, `−q′ u − q″ x ≤ Ā`.
    fn fill_rows(&mut self) {
        let dof = self.grid.dof;
        for i in 0..self.grid.points() {
            for j in 0..dof {
                let p = i * dof + j;
                let (a, b, c) = (self.grid.a[p], self.grid.b[p], self.grid.c[p]);
                let [hi, lo] = self.lines[p];
                let (d1, d2, limit) = (self.grid.dq[p], self.grid.ddq[p], self.limits.acceleration[j]);
                let rows = &mut self.stages.rows[4 * p..4 * p + 4];
                rows[0] = row([a, b - hi.slope, hi.offset - c]);
                rows[1] = row([-a, -b - lo.slope, lo.offset + c]);
                rows[2] = row([d1, d2, limit]);
                rows[3] = row([-d1, -d2, limit]);
            }
        }
    }

    /// What limits each segment of `profile` (see [`Binding`]): the stage constraint with the
    /// least slack at (u_i, x_i), the torque rows' slack relative to the range's width there,
    /// the cap's relative to the cap. `slowed` says which points' caps the check set.
    pub fn bindings(&mut self, profile: &Profile, slowed: &[bool]) -> Vec<Binding> {
        let dof = self.grid.dof;
        (0..profile.u.len())
            .map(|i| {
                let (x, u) = (profile.x[i], profile.u[i]);
                let cap = self.stages.cap[i];
                let mut best = Binding {
                    joint: None,
                    limit: Limit::None,
                    slack: f64::INFINITY,
                };
                if self.held_at(i).is_some() && self.held_at(i + 1).is_some() {
                    return Binding {
                        joint: None,
                        limit: Limit::Held,
                        slack: 0.0,
                    };
                }
                if cap.is_finite() && cap > 0.0 {
                    let slack = (cap - x) / cap;
                    best = match (slowed[i], self.speed_cap[i]) {
                        (false, (c, Some(j))) if c <= cap => Binding {
                            joint: Some(JointId(j)),
                            limit: Limit::Speed(self.limits.speed_source[j]),
                            slack,
                        },
                        (true, _) => Binding {
                            joint: None,
                            limit: Limit::Slowed,
                            slack,
                        },
                        _ => Binding {
                            joint: None,
                            limit: Limit::Played,
                            slack,
                        },
                    };
                }
                for j in 0..dof {
                    let p = i * dof + j;
                    let limit = self.limits.acceleration[j];
                    let acceleration = self.grid.dq[p] * u + self.grid.ddq[p] * x;
                    let slack = (limit - acceleration.abs()) / limit;
                    if slack < best.slack {
                        best = Binding {
                            joint: Some(JointId(j)),
                            limit: Limit::Acceleration,
                            slack,
                        };
                    }
                    let tau = self.grid.a[p] * u + self.grid.b[p] * x + self.grid.c[p];
                    let [hi, lo] = self.lines[p];
                    let width = hi.at(x) + lo.at(x);
                    if !(width.is_finite() && width > 0.0) {
                        continue;
                    }
                    for (slack, limit) in [
                        ((hi.at(x) - tau) / width, Limit::TorqueUpper),
                        ((tau + lo.at(x)) / width, Limit::TorqueLower),
                    ] {
                        if slack < best.slack {
                            best = Binding {
                                joint: Some(JointId(j)),
                                limit,
                                slack,
                            };
                        }
                    }
                }
                best
            })
            .collect()
    }

    /// The controllable sets of the last pass, [lo, hi] of x per point.
    pub fn controllable(&self) -> &[[f64; 2]] {
        &self.k
    }

    /// The error for stage `i`, where no x is admissible: at a point held at a boundary speed,
    /// or the start outside K_0, or the end outside the last stage's range, an error naming the
    /// option and the limits that bind there (or the range a held speed is below); elsewhere a
    /// moving end no timing reaches ([`Solver::end_unreachable`]); else
    /// [`Solver::nothing_follows`].
    fn stuck(&self, i: usize) -> Error {
        let n = self.grid.points();
        let (start, end) = (self.stages.start, self.stages.end);
        // the option of the end held at i, and that end's x
        let (field, x) = match i {
            0 if start > 0.0 => ("start_velocity", start),
            _ if i == n - 1 && end > 0.0 => ("end_velocity", end),
            _ if self.held_at(i).is_some() => match start > 0.0 && i <= self.held[0] {
                true => ("start_velocity", start),
                false => ("end_velocity", end),
            },
            _ => return self.end_unreachable().unwrap_or_else(|| self.nothing_follows(i)),
        };
        let next = (i + 1 < n).then(|| self.k[i + 1]);
        let Some(([bottom, top], rows)) = self.stages.top(i, next, self.speed_cap[i].0) else {
            return self.nothing_follows(i);
        };
        let held = match i == 0 || i == n - 1 {
            true => "",
            false => " (held there: the path's first or last ṡ·w/2, half the smoothing window, keeps the given speed)",
        };
        let way = match (i, next) {
            (0, Some(_)) => " with the rest of the path timed within them",
            _ => "",
        };
        // within the top, the speed is below the stage's range: a slower speed there cannot
        // go on to the next point's (held at a steady speed, a joint's torque leaves its range)
        let (verdict, allowed) = match x <= top * (1.0 + 1e-9) {
            true => (
                "outside",
                format!("ṡ from {:.6} to {:.6}", bottom.max(0.0).sqrt(), top.max(0.0).sqrt()),
            ),
            false => (
                "beyond",
                format!(
                    "at most ṡ = {:.6}, where {} binds",
                    top.max(0.0).sqrt(),
                    self.binding(i, top, &rows)
                ),
            ),
        };
        Error::option(
            field,
            format!(
                "its path speed ṡ = {} at s = {:.4}{held} is {verdict} what the limits (less the margin) allow there{way}: {allowed}",
                six_digits(x.sqrt()),
                self.grid.s[i],
            ),
        )
    }

    /// The limits that set stage `i`'s `top`: its `rows` (each a joint's torque side or
    /// acceleration limit), or where none does, the speed cap's joint or the cap itself.
    fn binding(&self, i: usize, top: f64, rows: &[usize]) -> String {
        let mut binds: Vec<String> = rows
            .iter()
            .map(|&r| {
                let what = [
                    "torque (upper)",
                    "torque (lower)",
                    "acceleration limit",
                    "acceleration limit",
                ][r % 4];
                format!("J{}'s {what}", r / 4 + 1)
            })
            .collect();
        binds.dedup();
        if binds.is_empty() {
            binds.push(match self.speed_cap[i] {
                (cap, Some(j)) if cap <= top * (1.0 + 1e-9) => format!(
                    "J{}'s {}",
                    j + 1,
                    match self.limits.speed_source[j] {
                        super::SpeedSource::Given => "speed limit",
                        super::SpeedSource::Motor => "motor top speed",
                    }
                ),
                _ => "a cap that keeps the limits as played or the check's slowdown".to_string(),
            });
        }
        binds.join(" and ")
    }

    /// The error for a moving end that no timing from the start reaches (the backward pass
    /// stuck before the end's held stretch, though each stage alone admits some x): the
    /// largest speed reachable where the stretch begins. `None` when the end is at rest or
    /// reachable, or when the path cannot be timed at all.
    fn end_unreachable(&self) -> Option<Error> {
        let end = self.stages.end;
        if end == 0.0 {
            return None;
        }
        let h = self.held[1];
        let top = self.stages.reachable_top(h)?;
        if top >= end * (1.0 - 1e-9) {
            return None;
        }
        let at = match h == self.grid.points() - 1 {
            true => "at the end".to_string(),
            false => format!(
                "by s = {:.4}, where the end's speed is held (the path's last ṡ·w/2, half the smoothing window)",
                self.grid.s[h]
            ),
        };
        Some(Error::option(
            "end_velocity",
            format!(
                "its path speed ṡ = {} cannot be reached from the {} within the limits (less the margin): at most ṡ = {:.6} {at}",
                six_digits(end.sqrt()),
                match self.stages.start > 0.0 {
                    true => "start's speed",
                    false => "start at rest",
                },
                top.max(0.0).sqrt(),
            ),
        ))
    }

    /// The error for a stage where no x is admissible: the joint whose standstill torque
    /// (gravity) is furthest beyond its range there, if any is; else why no speed is left
    /// there ([`Solver::no_speed_here`]).
    fn nothing_follows(&self, i: usize) -> Error {
        let dof = self.grid.dof;
        let length = *self.grid.s.last().unwrap_or(&0.0);
        let mut worst: Option<(usize, f64)> = None;
        for j in 0..dof {
            let c = self.grid.c[i * dof + j];
            let (lo, hi) = self.limits.torque[j].range(0.0);
            let excess = (c - hi).max(lo - c);
            if excess > 0.0 && worst.is_none_or(|(_, e)| excess > e) {
                worst = Some((j, excess));
            }
        }
        let (joint, message) = match worst {
            Some((j, _)) => {
                let c = self.grid.c[i * dof + j];
                let (lo, hi) = self.limits.torque[j].range(0.0);
                (
                    Some(JointId(j)),
                    format!(
                        "J{} needs {c:.4} {unit} to hold the arm still there; the timing may use [{lo:.4}, {hi:.4}] (its limit less the margin)",
                        j + 1,
                        unit = self.limits.torque_unit[j]
                    ),
                )
            }
            None => (None, self.no_speed_here(i)),
        };
        Error::NothingFollows {
            s: self.grid.s[i],
            length,
            point: 0,
            joint,
            message,
        }
    }

    /// Why stage `i` admits no x though no joint's standstill torque is beyond its range:
    /// its rows alone admit none (at any path speed), or the speeds they admit (under the caps
    /// that keep the limits as played) cannot reach the next point's controllable set.
    fn no_speed_here(&self, i: usize) -> String {
        let n = self.grid.points();
        let Some(([lo, hi], _)) = self.stages.top(i, None, f64::INFINITY) else {
            return "the joints' torque ranges (less the margin) leave no path acceleration that all of them allow, at any path speed".to_string();
        };
        let cap = self.stages.cap[i];
        let capped = match cap < hi {
            true => format!(
                ", at most {:.6} under the caps that keep the limits as played between the grid's points",
                cap.max(0.0).sqrt()
            ),
            false => String::new(),
        };
        let speeds = |[lo, hi]: [f64; 2]| format!("ṡ from {:.6} to {:.6}", lo.max(0.0).sqrt(), hi.max(0.0).sqrt());
        match i + 1 < n {
            true => format!(
                "the path speeds the limits (less the margin) allow here ({}{capped}) cannot reach those the next grid point at s = {:.4} allows on to the end ({}): a finer `grid` may time it",
                speeds([lo, hi]),
                self.grid.s[i + 1],
                speeds(self.k[i + 1]),
            ),
            false => format!(
                "the path speeds the limits (less the margin) allow here ({}{capped}) leave none to end at",
                speeds([lo, hi])
            ),
        }
    }
}

/// The fastest profile of the iteration, with the lines and controllable sets it was found under.
type Fastest = (Profile, Vec<[Line; 2]>, Vec<[f64; 2]>);

/// A row with an infinite bound (a joint without a limit) as one that never binds.
#[inline]
fn row(r: Row) -> Row {
    match r[2].is_finite() {
        true => r,
        false => [0.0, 0.0, f64::INFINITY],
    }
}
