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

use super::envelope::{Line, Side};
use super::grid::PathGrid;
use super::limits::Limits;
use super::reach::{Row, Stages, Stuck};
use super::{Binding, Limit, Profile};
use crate::error::{Error, Result};
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
    /// The solver of `grid` under `limits`.
    pub fn new(grid: &'a PathGrid, limits: &'a Limits) -> Self {
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
        }
    }

    /// The fastest profile found under the limits and `extra_cap` (a cap on x per point, +∞
    /// where none: the closed-loop check's slowdowns).
    pub fn solve(&mut self, extra_cap: &[f64]) -> Result<Solved> {
        let n = self.grid.points();
        for i in 0..n {
            self.stages.cap[i] = self.speed_cap[i].0.min(extra_cap[i]);
        }
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
        let relaxed = self.pass()?;
        let relaxed_duration = relaxed.duration();
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
        for i in 0..n {
            self.stages.cap[i] = self.speed_cap[i].0.min(extra_cap[i]);
        }
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
            return Err(self.nothing_follows(i));
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

    /// The error for a stage where no x is admissible: the joint whose standstill torque
    /// (gravity) is furthest beyond its range there, if any is; else the ranges together.
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
            None => (
                None,
                "the joints' torque ranges (less the margin) leave no path acceleration that all of them allow, at any path speed".to_string(),
            ),
        };
        Error::NothingFollows {
            s: self.grid.s[i],
            length,
            point: 0,
            joint,
            message,
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
