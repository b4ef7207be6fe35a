//! The geometric path retime times: a C² cubic spline through the input points, one per joint,
//! over their cumulative chord length (docs/retime.md, "The path").
//!
//! With the points q_0 … q_N (N + 1 of them) the knots are
//!
//! ```text
//!   s_0 = 0,   s_k = s_{k−1} + ‖q_k − q_{k−1}‖₂        (joint space, rad or m)
//! ```
//!
//! so s is a length along the path in joint space and ṡ reads as the joints' combined speed.
//! Each joint is the *not-a-knot* cubic spline through (s_k, q_k,j): C² everywhere, and C³ at
//! s_1 and s_{N−1} (the end conditions of SciPy's `CubicSpline` and toppra's
//! `SplineInterpolator`, so both sides time the same curve). Two points give the straight line,
//! three the parabola through them, as SciPy does.

use crate::error::{Error, Result};

/// Consecutive points closer than this (rad or m, joint-space distance) are one point: a pause
/// has no length to time, and a step of 1e-300 rad none a spline can divide by (it overflowed).
pub const SAME_POINT: f64 = 1e-9;

/// A cubic spline through joint-space points, parameterised by cumulative chord length:
/// q(s), q'(s), q''(s) for s in [0, [`PathSpline::length`]].
#[derive(Clone, Debug, PartialEq)]
pub struct PathSpline {
    /// Knots s_k (rad or m, the points' chord lengths summed), N + 1 of them, increasing.
    knots: Vec<f64>,
    /// The input index of the point at each knot (repeated points are one knot).
    indices: Vec<usize>,
    /// The distinct points, knot-major (N + 1 rows of `dof`).
    points: Vec<f64>,
    /// Per interval k and joint j, the cubic's coefficients `[y, b, c, d]` in
    /// `q_j = y + b t + c t² + d t³`, t = s − s_k: N × dof entries, interval-major.
    coefficients: Vec<[f64; 4]>,
    dof: usize,
}

impl PathSpline {
    /// The spline through `points` (rows of one value per joint). A point within `SAME_POINT`
    /// (1e-9) of the point kept before it is one point with it (a pause in a recorded motion
    /// has no length to time). Errors:
    /// fewer than two distinct points, rows of different lengths or none, a value that is not
    /// finite.
    pub fn through(points: &[Vec<f64>]) -> Result<PathSpline> {
        let dof = points.first().map_or(0, Vec::len);
        if dof == 0 {
            return Err(Error::BadPath {
                point: None,
                message: "no points (a path needs at least two)".into(),
            });
        }
        let mut kept: Vec<&[f64]> = Vec::with_capacity(points.len());
        let mut indices = Vec::with_capacity(points.len());
        for (k, p) in points.iter().enumerate() {
            if p.len() != dof {
                return Err(Error::BadPath {
                    point: Some(k),
                    message: format!("has {} values; the first point has {dof}", p.len()),
                });
            }
            if let Some(j) = p.iter().position(|x| !x.is_finite()) {
                return Err(Error::BadPath {
                    point: Some(k),
                    message: format!("J{} is {}, not a finite number", j + 1, p[j]),
                });
            }
            if kept.last().is_none_or(|last| distance(last, p) >= SAME_POINT) {
                kept.push(p);
                indices.push(k);
            }
        }
        if kept.len() < 2 {
            return Err(Error::BadPath {
                point: None,
                message: format!(
                    "{} point{} ({} distinct, points within {SAME_POINT:e} of the one before being one): a path needs at least two distinct points",
                    points.len(),
                    if points.len() == 1 { "" } else { "s" },
                    kept.len()
                ),
            });
        }
        let mut knots = Vec::with_capacity(kept.len());
        knots.push(0.0);
        for (k, w) in kept.windows(2).enumerate() {
            let s = knots.last().copied().unwrap_or(0.0) + distance(w[0], w[1]);
            if !s.is_finite() {
                return Err(Error::BadPath {
                    point: Some(indices[k + 1]),
                    message: "the path's length up to here overflows floating-point numbers (a step of 1e200 rad or m is no path an arm follows)".into(),
                });
            }
            knots.push(s);
        }
        let intervals = kept.len() - 1;
        let mut coefficients = vec![[0.0; 4]; intervals * dof];
        let mut y = vec![0.0; kept.len()];
        let mut moments = vec![0.0; kept.len()];
        for j in 0..dof {
            for (yk, p) in y.iter_mut().zip(&kept) {
                *yk = p[j];
            }
            not_a_knot_moments(&knots, &y, &mut moments);
            for k in 0..intervals {
                let h = knots[k + 1] - knots[k];
                let (m0, m1) = (moments[k], moments[k + 1]);
                let slope = (y[k + 1] - y[k]) / h;
                coefficients[k * dof + j] = [y[k], slope - h * (2.0 * m0 + m1) / 6.0, 0.5 * m0, (m1 - m0) / (6.0 * h)];
            }
        }
        Ok(PathSpline {
            points: kept.concat(),
            knots,
            indices,
            coefficients,
            dof,
        })
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The path's length L (rad or m): s runs over [0, L].
    pub fn length(&self) -> f64 {
        self.knots.last().copied().unwrap_or(0.0)
    }

    /// The knots s_k: where the (distinct) input points are on the path.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The distinct points the spline passes through, with each one's index among the points
    /// given.
    pub fn points(&self) -> impl Iterator<Item = (usize, &[f64])> {
        self.indices.iter().copied().zip(self.points.chunks(self.dof))
    }

    /// The input point (its index among the points given) nearest to path position `s`.
    pub fn nearest_point(&self, s: f64) -> usize {
        let k = self.knots.partition_point(|&x| x < s).min(self.knots.len() - 1);
        let k = match k > 0 && s - self.knots[k - 1] < self.knots[k] - s {
            true => k - 1,
            false => k,
        };
        self.indices[k]
    }

    /// q(s), q'(s) = dq/ds and q''(s) = d²q/ds² into the three slices (one entry per joint);
    /// s is clamped into [0, L].
    #[inline]
    pub fn eval(&self, s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]) {
        let s = s.clamp(0.0, self.length());
        // the interval [s_k, s_k+1] holding s: the last knot at or before s, the last interval
        // for s = L
        let k = (self.knots.partition_point(|&x| x <= s).max(1) - 1).min(self.knots.len() - 2);
        let t = s - self.knots[k];
        let row = &self.coefficients[k * self.dof..(k + 1) * self.dof];
        for (j, &[y, b, c, d]) in row.iter().enumerate() {
            q[j] = y + t * (b + t * (c + t * d));
            dq[j] = b + t * (2.0 * c + 3.0 * t * d);
            ddq[j] = 2.0 * c + 6.0 * t * d;
        }
    }

    /// q(s) alone into `q`.
    #[inline]
    pub fn position(&self, s: f64, q: &mut [f64]) {
        let s = s.clamp(0.0, self.length());
        let k = (self.knots.partition_point(|&x| x <= s).max(1) - 1).min(self.knots.len() - 2);
        let t = s - self.knots[k];
        let row = &self.coefficients[k * self.dof..(k + 1) * self.dof];
        for (qj, &[y, b, c, d]) in q.iter_mut().zip(row) {
            *qj = y + t * (b + t * (c + t * d));
        }
    }
}

/// ‖b − a‖₂, the joint-space distance of two points (rad or m).
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| (b - a) * (b - a)).sum::<f64>().sqrt()
}

/// The second derivatives M_k of the not-a-knot cubic spline through (x_k, y_k) into
/// `moments`. With h_k = x_{k+1} − x_k and δ_k = (y_{k+1} − y_k)/h_k, the interior knots satisfy
///
/// ```text
///   h_{k−1} M_{k−1} + 2(h_{k−1} + h_k) M_k + h_k M_{k+1} = 6(δ_k − δ_{k−1}),   k = 1 … N−1
/// ```
///
/// and not-a-knot asks the third derivative to be continuous at x_1 and x_{N−1}:
/// `h_1 (M_1 − M_0) = h_0 (M_2 − M_1)`, likewise at the end. Eliminating M_0 and M_N leaves a
/// diagonally dominant tridiagonal system in M_1 … M_{N−1}, solved by the Thomas algorithm.
/// Two points: M = 0 (the line); three: the parabola, M constant.
fn not_a_knot_moments(x: &[f64], y: &[f64], moments: &mut [f64]) {
    let n = x.len();
    let h = |k: usize| x[k + 1] - x[k];
    let delta = |k: usize| (y[k + 1] - y[k]) / h(k);
    match n {
        2 => return moments.fill(0.0),
        3 => return moments.fill(2.0 * (delta(1) - delta(0)) / (x[2] - x[0])),
        _ => {}
    }
    // unknowns M_1 … M_{N−1}: m = n − 2 of them, row r for knot r + 1
    let m = n - 2;
    let (h0, h1) = (h(0), h(1));
    let (hl, hp) = (h(n - 2), h(n - 3)); // the last interval and the one before it
    let mut lower = vec![0.0; m];
    let mut diag = vec![0.0; m];
    let mut upper = vec![0.0; m];
    let mut rhs = vec![0.0; m];
    for r in 0..m {
        let k = r + 1;
        lower[r] = h(k - 1);
        diag[r] = 2.0 * (h(k - 1) + h(k));
        upper[r] = h(k);
        rhs[r] = 6.0 * (delta(k) - delta(k - 1));
    }
    // M_0 = ((h0 + h1) M_1 − h0 M_2)/h1 into row 0, M_N = ((hl + hp) M_{N−1} − hl M_{N−2})/hp
    // into row m − 1 (m ≥ 2 here)
    let (a0, cl) = (lower[0], upper[m - 1]);
    lower[0] = 0.0;
    upper[m - 1] = 0.0;
    diag[0] += a0 * (h0 + h1) / h1;
    diag[m - 1] += cl * (hl + hp) / hp;
    upper[0] -= a0 * h0 / h1;
    lower[m - 1] -= cl * hl / hp;
    // Thomas: eliminate the sub-diagonal, then substitute back
    for r in 1..m {
        let w = lower[r] / diag[r - 1];
        diag[r] -= w * upper[r - 1];
        rhs[r] -= w * rhs[r - 1];
    }
    moments[m] = rhs[m - 1] / diag[m - 1];
    for r in (0..m - 1).rev() {
        moments[r + 1] = (rhs[r] - upper[r] * moments[r + 2]) / diag[r];
    }
    moments[0] = ((h0 + h1) * moments[1] - h0 * moments[2]) / h1;
    moments[n - 1] = ((hl + hp) * moments[n - 2] - hl * moments[n - 3]) / hp;
}
