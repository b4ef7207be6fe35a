//! A joint's torque range as the path speed sets it, and the linear bounds in x = ṡ² that let
//! TOPP-RA use it (docs/retime.md, "Motors that lose torque with speed").
//!
//! At a grid point the joint turns at q̇ = w·y, with w = q'_j(s) and y = ṡ = √x. What the
//! motor may give the motion there is
//!
//! ```text
//!   hi(y) = k·min(E, τ_hi(r·w·y)) − d·w·y        lo(y) = k·max(−E, τ_lo(r·w·y)) − d·w·y
//! ```
//!
//! with k = 1 − margin, E the constant limit, τ_lo/τ_hi the motor's envelope through its
//! reducer ([`Motor::joint_bounds`]), d the joint's viscous damping (the sim's step charges
//! d·q̇ to the motor). Both are continuous and piecewise affine in y between the envelope's
//! kinks and the points where it meets ±E. In x they are not linear, and the torque constraint
//! is not convex (toppra #92); TOPP-RA needs rows linear in (s̈, x). So each side is replaced
//! by a line in x that is a *sound* bound on the whole range the grid point allows,
//! x ∈ [0, x̄]:
//!
//! ```text
//!   h0 + h1·x ≤ hi(√x)   and   l0 + l1·x ≥ lo(√x)    for every x in [0, x̄]
//! ```
//!
//! The slope is the curve's tangent at an operating point x_t (or 0 if that is higher there),
//! and the offset the exact minimum of hi(√x) − h1·x over [0, x̄]: on a piece where hi is
//! A + B·y it is `A + B·y − h1·y²`, a quadratic in y, minimised in closed form. Where the curve
//! is convex in x (a DC motor's falling line, the falling part of a pull-out curve) the tangent
//! is already below it and the bound is exact at x_t; elsewhere it is lowered until it holds.

use crate::control::Motor;

/// Relative round-off within which two slopes of a curve count as equal.
const ROUND_OFF: f64 = 1e-9;

/// The share of a motor's top speed a timing may reach: just below it, where a stepper's
/// curve still gives its last point's torque (past the point it gives none).
pub(crate) const TOP_SPEED_SHARE: f64 = 1.0 - 1e-9;

/// One joint's torque range at a speed (see the module doc), ready to be bounded.
#[derive(Clone, Debug)]
pub(crate) struct JointTorque {
    /// The constant limit E (N·m or N; +∞ for none).
    effort: f64,
    /// The motor and its reducer's ratio r, if the joint has one.
    motor: Option<(Motor, f64)>,
    /// Viscous damping d (N·m·s/rad or N·s/m).
    damping: f64,
    /// k = 1 − margin: the share of the motor's torque the timing may use.
    keep: f64,
    /// The fastest the joint may turn (rad/s or m/s): the motor's top speed over r, times
    /// [`TOP_SPEED_SHARE`]; +∞ without a motor.
    top: f64,
    /// Per side (upper, lower) and direction of motion (q̇ ≥ 0, q̇ < 0): the side's value
    /// against the speed |q̇|.
    curves: [[SpeedCurve; 2]; 2],
}

/// Which side of the torque range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// The upper bound hi: a line below it is wanted.
    Upper,
    /// The lower bound lo: a line above it is wanted (computed as a line below −lo).
    Lower,
}

/// A line `offset + slope·x` in x = ṡ² (N·m or N, and per (unit/s)²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Line {
    /// Its value at x = 0.
    pub offset: f64,
    /// Its slope in x.
    pub slope: f64,
}

impl Line {
    /// The line's value at x.
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        self.offset + self.slope * x
    }
}

/// One side of a joint's range in one direction of motion, against the speed v = |q̇|:
/// continuous, affine between its vertices, and either ending at the last vertex (the motor's
/// top speed) or going on affine with slope `tail`.
#[derive(Clone, Debug, Default)]
struct SpeedCurve {
    /// [v, value], v ascending from 0.
    vertices: Vec<[f64; 2]>,
    /// The slope beyond the last vertex, when the curve goes on (no motor).
    tail: Option<f64>,
    /// Maximal runs of pieces (piece p joins vertices p and p + 1), as ([first, last] pieces,
    /// convex): on a piece the curve is A + B√z in z = v², its derivative B/(2v). A *convex*
    /// run has B ≤ 0 on every piece, not decreasing from one to the next (within
    /// [`ROUND_OFF`] of the largest |B|: a smooth curve's slopes differ by round-off): the
    /// curve is convex in z along it. A *rising* run has B > 0 on every piece.
    runs: Vec<([usize; 2], bool)>,
    /// [`ROUND_OFF`] of the curve's largest |value|: what [`SpeedCurve::lowest`] subtracts so
    /// that the runs' tolerance never makes a bound unsound.
    slack: f64,
}

impl SpeedCurve {
    /// The curve through `vertices` (at least one), going on with slope `tail` if given.
    fn new(vertices: Vec<[f64; 2]>, tail: Option<f64>) -> Self {
        let slope = |p: usize| {
            let ([v0, h0], [v1, h1]) = (vertices[p], vertices[p + 1]);
            (h1 - h0) / (v1 - v0)
        };
        let pieces = vertices.len().saturating_sub(1);
        let tolerance = ROUND_OFF * (0..pieces).map(|p| slope(p).abs()).fold(0.0, f64::max);
        let mut runs: Vec<([usize; 2], bool)> = Vec::new();
        for p in 0..pieces {
            let (now, convex) = (slope(p), slope(p) <= 0.0);
            let joins = p > 0 && {
                let before = slope(p - 1);
                (before <= 0.0) == convex && (!convex || now >= before - tolerance)
            };
            match (joins, runs.last_mut()) {
                (true, Some(run)) => run.0[1] = p,
                _ => runs.push(([p, p], convex)),
            }
        }
        let slack = ROUND_OFF * vertices.iter().map(|v| v[1].abs()).fold(0.0, f64::max);
        SpeedCurve {
            vertices,
            tail,
            runs,
            slack,
        }
    }

    /// Its value at speed v (within its domain).
    fn value(&self, v: f64) -> f64 {
        let p = self.piece(v);
        let [v0, h0] = self.vertices[p];
        h0 + self.slope(p) * (v - v0)
    }

    /// The piece holding v (the tail's index, `vertices.len() − 1`, past the last vertex).
    fn piece(&self, v: f64) -> usize {
        self.vertices
            .partition_point(|x| x[0] <= v)
            .clamp(1, self.vertices.len())
            - 1
    }

    /// Piece p's slope in v (the tail's past the last vertex; 0 for a curve of one vertex
    /// without a tail).
    fn slope(&self, p: usize) -> f64 {
        match self.vertices.get(p + 1) {
            Some(&[v1, h1]) => (h1 - self.vertices[p][1]) / (v1 - self.vertices[p][0]),
            None => self.tail.unwrap_or(0.0),
        }
    }

    /// The end of its domain (+∞ with a tail).
    fn end(&self) -> f64 {
        match self.tail {
            Some(_) => f64::INFINITY,
            None => self.vertices[self.vertices.len() - 1][0],
        }
    }

    /// A lower bound on value(v) − m·v² over v in [0, v_max], the minimum itself but on a
    /// rising run with m > 0 (−∞ when unbounded below). On a convex run with m ≥ 0, g falls:
    /// its minimum is at the run's end; with m < 0 the derivative in z, B/(2v) − m, does not
    /// decrease, so the minimum is where it turns non-negative (found by bisection over the
    /// run's pieces), at v = B/(2m) inside its piece, or at an end. On a rising run with
    /// m ≤ 0, g rises: its start; with m > 0, value(start) − m·v_end² is below it.
    fn lowest(&self, m: f64, v_max: f64) -> f64 {
        let v_max = v_max.min(self.end());
        // the last piece starting below v_max; at a vertex k, g is its value less m·v_k²
        let cut = self.vertices.partition_point(|x| x[0] < v_max).max(1) - 1;
        let at_vertex = |k: usize| {
            let [v, h] = self.vertices[k];
            h - m * v * v
        };
        let g_max = self.value(v_max) - m * v_max * v_max;
        let g_right = |p: usize| match p < cut {
            true => at_vertex(p + 1),
            false => g_max,
        };
        let right = |p: usize| self.vertices[p + 1][0].min(v_max);
        let mut lowest = at_vertex(0).min(g_max);
        for &([first, last], convex) in &self.runs {
            if first > cut || self.vertices[first][0] >= v_max {
                break;
            }
            let last = last.min(cut);
            if !convex {
                if m > 0.0 {
                    let v_end = right(last);
                    lowest = lowest.min(self.vertices[first][1] - m * v_end * v_end);
                }
                continue; // else its start, the previous run's end (or v = 0)
            }
            lowest = lowest.min(g_right(last));
            if m >= 0.0 {
                continue;
            }
            // the first piece whose derivative at its right end is ≥ 0
            let (mut lo, mut hi) = (first, last + 1);
            while lo < hi {
                let p = (lo + hi) / 2;
                match self.slope(p) / (2.0 * right(p)) - m >= 0.0 {
                    true => hi = p,
                    false => lo = p + 1,
                }
            }
            if lo <= last {
                let [v0, h0] = self.vertices[lo];
                let b = self.slope(lo);
                let v = (b / (2.0 * m)).clamp(v0, right(lo));
                lowest = lowest.min(h0 + b * (v - v0) - m * v * v);
            }
        }
        lowest -= self.slack;
        // the tail, past the last vertex
        if let (Some(b), true) = (self.tail, v_max > self.vertices[self.vertices.len() - 1][0]) {
            let v_end = self.vertices[self.vertices.len() - 1][0];
            let g = |v: f64| self.value(v) - m * v * v;
            if v_max.is_infinite() {
                if m > 0.0 || (m == 0.0 && b < 0.0) {
                    return f64::NEG_INFINITY;
                }
                if m < 0.0 && b < 0.0 {
                    lowest = lowest.min(g((b / (2.0 * m)).max(v_end)));
                }
            } else if m < 0.0 && b < 0.0 {
                lowest = lowest.min(g((b / (2.0 * m)).clamp(v_end, v_max)));
            }
        }
        lowest
    }
}

impl JointTorque {
    /// A joint with the constant limit `effort`, its `motor` through a reducer of ratio
    /// `ratio` (if any), its `damping`, keeping `1 − margin` of the motor's torque.
    pub fn new(effort: f64, motor: Option<(Motor, f64)>, damping: f64, margin: f64) -> Self {
        let top = motor
            .as_ref()
            .map_or(f64::INFINITY, |(m, r)| TOP_SPEED_SHARE * m.envelope.top_speed() / r);
        let kinks: Vec<f64> = motor
            .as_ref()
            .map_or(Vec::new(), |(m, r)| m.envelope.kinks().iter().map(|w| w / r).collect());
        let mut joint = JointTorque {
            effort,
            motor,
            damping,
            keep: 1.0 - margin,
            top,
            curves: Default::default(),
        };
        for side in [Side::Upper, Side::Lower] {
            for direction in [1.0, -1.0] {
                let curve = joint.speed_curve(side, direction, &kinks);
                joint.curves[side as usize][usize::from(direction < 0.0)] = curve;
            }
        }
        joint
    }

    /// The side's curve in one direction of motion: its value at 0, at every kink of the motor
    /// (and every point where it meets ±E) below the top speed, and at the top speed; without
    /// a motor, a line from 0 on.
    fn speed_curve(&self, side: Side, direction: f64, kinks: &[f64]) -> SpeedCurve {
        let value = |v: f64| self.value(side, direction * v);
        if self.motor.is_none() {
            return SpeedCurve::new(vec![[0.0, value(0.0)]], Some(value(1.0) - value(0.0)));
        }
        let mut speeds: Vec<f64> = (kinks.iter())
            .map(|k| k * direction)
            .filter(|&v| v > 0.0 && v < self.top)
            .collect();
        speeds.sort_by(f64::total_cmp);
        let mut vertices = vec![[0.0, value(0.0)]];
        for v in speeds.into_iter().chain([self.top]) {
            // where the motor's own bound crosses E inside the piece, the clip adds a vertex
            let v0 = vertices[vertices.len() - 1][0];
            let (e0, e1) = (
                self.unclipped(side, direction * v0),
                self.unclipped(side, direction * v),
            );
            if self.effort.is_finite() && (e0 - self.effort) * (e1 - self.effort) < 0.0 {
                let cross = v0 + (v - v0) * (self.effort - e0) / (e1 - e0);
                vertices.push([cross, value(cross)]);
            }
            vertices.push([v, value(v)]);
        }
        SpeedCurve::new(vertices, None)
    }

    /// Whether the range depends on speed (a motor, or damping).
    pub fn varies(&self) -> bool {
        self.motor.is_some() || self.damping != 0.0
    }

    /// The fastest the joint may turn, by its motor (rad/s or m/s; +∞ without one): just
    /// below the motor's top speed over its ratio ([`TOP_SPEED_SHARE`]).
    pub fn top_speed(&self) -> f64 {
        self.top
    }

    /// The range [lo, hi] the timing may use at joint speed `qd` (N·m or N).
    #[inline]
    pub fn range(&self, qd: f64) -> (f64, f64) {
        let (lo, hi) = match &self.motor {
            Some((m, r)) => {
                let (lo, hi) = m.joint_bounds(*r, qd);
                (lo.max(-self.effort), hi.min(self.effort))
            }
            None => (-self.effort, self.effort),
        };
        let drag = self.damping * qd;
        (self.keep * lo - drag, self.keep * hi - drag)
    }

    /// The side's value at joint speed `qd`: hi, or −lo.
    #[inline]
    fn value(&self, side: Side, qd: f64) -> f64 {
        let (lo, hi) = self.range(qd);
        match side {
            Side::Upper => hi,
            Side::Lower => -lo,
        }
    }

    /// The motor's own bound on the side at `qd` (hi, or −lo), before ±E and the margin.
    fn unclipped(&self, side: Side, qd: f64) -> f64 {
        let Some((m, r)) = &self.motor else {
            return f64::INFINITY;
        };
        let (lo, hi) = m.joint_bounds(*r, qd);
        match side {
            Side::Upper => hi,
            Side::Lower => -lo,
        }
    }

    /// The tangent of the side's value at `x_at` (a line in x that may pass above the value
    /// elsewhere: the caller checks the profile it gives against [`JointTorque::range`]).
    pub fn line_tangent(&self, side: Side, w: f64, x_at: f64) -> Line {
        if !self.varies() || w == 0.0 || x_at <= 0.0 {
            return Line {
                offset: self.value(side, 0.0),
                slope: 0.0,
            };
        }
        let c = w.abs();
        let curve = &self.curves[side as usize][usize::from(w < 0.0)];
        let v_at = (c * x_at.sqrt()).min(curve.end());
        let m = curve.slope(curve.piece(v_at)) / (2.0 * v_at);
        Line {
            offset: curve.value(v_at) - curve.slack - m * v_at * v_at,
            slope: m * c * c,
        }
    }

    /// A line below the side's value (hi, or −lo) as a function of x over [0, `x_max`], for
    /// the joint moving at q'_j = `w` per unit ṡ, as tight as it can be at `x_at` (see the
    /// module doc). Without a motor or damping, or with w = 0: the constant value (which may
    /// be +∞: no bound).
    pub fn line_below(&self, side: Side, w: f64, x_max: f64, x_at: f64) -> Line {
        if !self.varies() || w == 0.0 {
            return Line {
                offset: self.value(side, 0.0),
                slope: 0.0,
            };
        }
        // in the speed v = |w|·√x the curve is fixed; a line h0 + m·v² is h0 + m·w²·x
        let c = w.abs();
        let curve = &self.curves[side as usize][usize::from(w < 0.0)];
        let v_max = c * x_max.max(0.0).sqrt();
        let v_at = match x_at > 0.0 {
            true => c * x_at.min(x_max).sqrt(),
            false if v_max.is_finite() => 1e-3 * v_max,
            false => 1e-3 * c,
        }
        .min(curve.end());
        let tangent = curve.slope(curve.piece(v_at)) / (2.0 * v_at);
        let mut best: Option<(f64, f64)> = None; // (offset, m) in v
        for m in [0.0, tangent] {
            let offset = curve.lowest(m, v_max);
            let at = offset + m * v_at * v_at;
            // equal at v_at (v_at at the reach's end), the higher at rest
            if offset.is_finite()
                && best.is_none_or(|(o, bm)| at > o + bm * v_at * v_at || (at == o + bm * v_at * v_at && offset > o))
            {
                best = Some((offset, m));
            }
        }
        // a curve that ends (a motor's) has both; one that goes on falls with damping (its
        // tangent is below it) or rises (the constant is)
        let (offset, m) = best.expect("a finite line below");
        Line {
            offset,
            slope: m * c * c,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::Envelope;

    fn stepper() -> Motor {
        Motor {
            label: String::new(),
            envelope: Envelope::Stepper {
                curve: vec![[0.0, 0.32], [60.0, 0.31], [120.0, 0.2], [200.0, 0.08]],
            },
            efficiency: 0.9,
            continuous_torque: None,
            stepping: None,
            electrics: None,
            servo: None,
        }
    }

    fn dc() -> Motor {
        Motor {
            label: String::new(),
            envelope: Envelope::Dc {
                stall_torque: 0.5,
                no_load_speed: 300.0,
                peak_torque: 0.4,
            },
            efficiency: 1.0,
            continuous_torque: None,
            stepping: None,
            electrics: None,
            servo: None,
        }
    }

    /// The line is below the true range at every x of the interval (dense check), for both
    /// sides, both directions of motion, with damping and a constant limit that cuts the
    /// envelope, at operating points across the range; and it touches the curve at the
    /// operating point where the curve is convex there.
    #[test]
    fn the_line_is_a_sound_bound_over_the_whole_interval() {
        for (motor, effort) in [(stepper(), 5.0), (stepper(), 3.0), (dc(), 10.0), (dc(), 3.5)] {
            let joint = JointTorque::new(effort, Some((motor, 12.0)), 0.1, 0.2);
            for w in [0.7, -1.3] {
                let x_max = (joint.top_speed() / w).powi(2) * 0.999;
                for frac in [0.0, 0.05, 0.3, 0.6, 0.95, 1.0] {
                    for side in [Side::Upper, Side::Lower] {
                        let line = joint.line_below(side, w, x_max, frac * x_max);
                        for k in 0..=2000 {
                            let x = x_max * k as f64 / 2000.0;
                            let f = joint.value(side, w * x.sqrt());
                            assert!(line.at(x) <= f + 1e-12, "{side:?} w {w} at {x}: {} > {f}", line.at(x));
                        }
                    }
                }
            }
        }
    }

    /// A DC motor's falling line (its peak at its stall torque, no flat part) is convex in x:
    /// the tangent is tight where it is taken.
    #[test]
    fn the_line_touches_a_convex_curve_at_the_operating_point() {
        let mut motor = dc();
        motor.envelope = Envelope::Dc {
            stall_torque: 0.5,
            no_load_speed: 300.0,
            peak_torque: 0.5,
        };
        let joint = JointTorque::new(f64::INFINITY, Some((motor, 10.0)), 0.0, 0.0);
        let w = 1.0;
        let x_max = 900.0; // q̇ up to 30 rad/s: ω_m up to 300, the no-load speed
        for x_at in [100.0, 400.0, 800.0] {
            let line = joint.line_below(Side::Upper, w, x_max, x_at);
            let f = joint.value(Side::Upper, w * f64::sqrt(x_at));
            assert!((line.at(x_at) - f).abs() < 1e-8, "at {x_at}: {} vs {f}", line.at(x_at));
        }
    }

    /// Without a motor or damping the range is the constant k·E.
    #[test]
    fn a_constant_limit_is_its_own_line() {
        let joint = JointTorque::new(8.0, None, 0.0, 0.25);
        let line = joint.line_below(Side::Lower, 2.0, 10.0, 3.0);
        assert_eq!(
            line,
            Line {
                offset: 6.0,
                slope: 0.0
            }
        );
    }

    /// Damping alone, no speed limit (x up to +∞): the side that falls with speed gets its
    /// tangent (below the whole curve, touching at the operating point), the side that rises
    /// its constant.
    #[test]
    fn damping_alone_without_a_speed_limit_is_bounded_soundly() {
        let joint = JointTorque::new(8.0, None, 0.5, 0.0);
        let (w, x_at) = (2.0, 4.0);
        let falling = joint.line_below(Side::Upper, w, f64::INFINITY, x_at);
        let rising = joint.line_below(Side::Lower, w, f64::INFINITY, x_at);
        for x in (0..4000).map(|k| k as f64 * 0.05) {
            assert!(
                falling.at(x) <= joint.value(Side::Upper, w * x.sqrt()) + 1e-12,
                "upper at {x}"
            );
            assert!(
                rising.at(x) <= joint.value(Side::Lower, w * x.sqrt()) + 1e-12,
                "lower at {x}"
            );
        }
        assert!((falling.at(x_at) - joint.value(Side::Upper, w * x_at.sqrt())).abs() < 1e-8);
        assert!((rising.offset - 8.0).abs() < 1e-8 && rising.slope == 0.0, "{rising:?}");
    }

    /// The run-wise minimum is never above the minimum over a dense scan of the curve (and the
    /// vertices), and equals it for m ≤ 0, on a curve with a knee, a rising piece and convex
    /// runs.
    #[test]
    fn the_lowest_offset_is_the_minimum_over_the_curve() {
        let vertices = vec![
            [0.0, 5.0],
            [1.0, 5.0],
            [2.0, 3.0],
            [3.0, 2.2],
            [4.0, 2.5],
            [5.0, 1.0],
            [6.0, 0.6],
        ];
        let curve = SpeedCurve::new(vertices, None);
        for m in [-3.0, -0.4, -0.05, 0.0, 0.1, 1.0] {
            for v_max in [0.5, 2.5, 4.2, 6.0] {
                let vertices = curve.vertices.iter().map(|v| v[0]).filter(|&v| v <= v_max);
                let scan = ((0..=60000).map(|k| v_max * k as f64 / 60000.0))
                    .chain(vertices)
                    .map(|v| curve.value(v) - m * v * v)
                    .fold(f64::INFINITY, f64::min);
                let got = curve.lowest(m, v_max);
                assert!(got <= scan + 1e-12, "m {m} v_max {v_max}: {got} above {scan}");
                if m <= 0.0 {
                    assert!(got >= scan - 1e-6, "m {m} v_max {v_max}: {got} vs {scan}");
                }
            }
        }
    }
}
