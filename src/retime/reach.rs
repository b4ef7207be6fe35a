//! TOPP-RA's two passes on a grid (Pham & Pham 2018, "A New Approach to Time-Optimal Path
//! Parameterization based on Reachability Analysis", IEEE T-RO 34(3); hungpham2511/toppra).
//!
//! The variables are x_i = ṡ² at grid point s_i and u_i = s̈ on [s_i, s_i+1], with
//! x_{i+1} = x_i + 2Δ_i u_i (s̈ constant on each interval). Stage i's constraints are rows
//! linear in (u, x), `α u + β x ≤ γ`, and a cap `0 ≤ x ≤ x̄_i`.
//!
//! * **Backward pass (controllable sets).** K_N = {x_end} (0: rest at the end);
//!   K_i = { x : ∃u, stage i's rows hold and x + 2Δ_i u ∈ K_{i+1} }. Each K_i is an interval,
//!   the projection on x of a polygon in (u, x): its ends are two linear programs in two
//!   variables, solved exactly here by eliminating u (Fourier–Motzkin): every pair of a row
//!   bounding u from below (α < 0) and one from above (α > 0) gives
//!   `(α⁺β⁻ − α⁻β⁺) x ≤ α⁺γ⁻ − α⁻γ⁺`, and rows without u bound x directly.
//! * **Forward pass (greedy).** x_0 = x_start (0: from rest); at each stage the largest u the rows and K_{i+1}
//!   allow at x_i, then x_{i+1} = x_i + 2Δ_i u_i. Pham & Pham prove this profile time-optimal
//!   on the grid (their Theorem 2).
//!
//! A point may also have a floor, x_i ≥ x̲_i: the points where a timing that starts or ends
//! moving holds its boundary speed (docs/retime.md, "Chaining segments").
//!
//! Nothing here allocates.

/// A row `α u + β x ≤ γ` of a stage.
pub(crate) type Row = [f64; 3];

/// The stages' rows (each stage the same number, `per_stage`) and caps, and the grid.
#[derive(Clone, Debug)]
pub(crate) struct Stages {
    /// Rows, stage-major: (N + 1) × `per_stage`.
    pub rows: Vec<Row>,
    /// Rows per stage.
    pub per_stage: usize,
    /// x̄_i: the cap on x at each grid point (may be +∞).
    pub cap: Vec<f64>,
    /// x̲_i: the floor on x at each grid point (0 where none).
    pub floor: Vec<f64>,
    /// x at the first point (0: from rest).
    pub start: f64,
    /// x at the last point (0: to rest).
    pub end: f64,
    /// Δ_i = s_{i+1} − s_i, N entries.
    pub delta: Vec<f64>,
}

/// Why a pass could not go on: the grid point where the set of admissible x is empty.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Stuck(pub usize);

/// Relative slack within which two bounds that cross are taken as equal (round-off).
const ROUND_OFF: f64 = 1e-9;

impl Stages {
    /// Number of grid points N + 1.
    pub fn points(&self) -> usize {
        self.cap.len()
    }

    fn rows(&self, i: usize) -> &[Row] {
        &self.rows[i * self.per_stage..(i + 1) * self.per_stage]
    }

    /// The controllable sets K_i = [lo, hi] into `k` (N + 1 entries), ending at `end`; the
    /// start within K_0. On an error, `k` holds the sets found before it (the start's
    /// included when it is outside K_0).
    pub fn controllable_sets(&self, k: &mut [[f64; 2]]) -> Result<(), Stuck> {
        let n = self.points() - 1;
        k[n] = match x_range(self.rows(n), None, self.floor[n], self.cap[n]) {
            Some(r) if within(self.end, [r.lo, r.hi]) => [self.end, self.end],
            _ => return Err(Stuck(n)),
        };
        for i in (0..n).rev() {
            let reach = (2.0 * self.delta[i], k[i + 1]);
            let r = x_range(self.rows(i), Some(reach), self.floor[i], self.cap[i]).ok_or(Stuck(i))?;
            k[i] = [r.lo, r.hi];
        }
        if !within(self.start, k[0]) {
            return Err(Stuck(0));
        }
        Ok(())
    }

    /// Stage `i`'s admissible x under `cap` (its rows, and with `next` (K_{i+1}) reaching it;
    /// no floor) as [bottom, top], and which of the stage's rows set its top (indices into its
    /// rows, none for the cap or the reach alone): the limits that bind there, for a message.
    /// `None` when the stage admits no x at all.
    pub fn top(&self, i: usize, next: Option<[f64; 2]>, cap: f64) -> Option<([f64; 2], Vec<usize>)> {
        let reach = next.map(|k| (2.0 * self.delta[i], k));
        x_range(self.rows(i), reach, 0.0, cap).map(|r| {
            let per = self.per_stage;
            (
                [r.lo, r.hi],
                r.hi_by.into_iter().flatten().filter(|&p| p < per).collect(),
            )
        })
    }

    /// The top of the set of x reachable at point `at` from the start, without the floors
    /// (Pham & Pham's reachable sets): R_0 = {x_start}, R_{i+1} = {x + 2Δ_i u : stage i's rows
    /// hold at (u, x), x ∈ R_i} within stage i + 1's own range. With y = x + 2Δu, a row
    /// `α u + β x ≤ γ` reads `(β − α/2Δ) x + (α/2Δ) y ≤ γ`, and y's range is found as stage
    /// ranges are, eliminating x. Without the floors the sets only grow, so no speed above the
    /// top is reachable with them. `None` when a set is empty on the way. For messages only
    /// (it allocates one stage's rows).
    pub fn reachable_top(&self, at: usize) -> Option<f64> {
        let mut reached = [self.start, self.start];
        let mut shifted: Vec<Row> = Vec::with_capacity(self.per_stage + 2);
        for i in 0..at {
            let two_delta = 2.0 * self.delta[i];
            shifted.clear();
            shifted.extend(
                self.rows(i)
                    .iter()
                    .map(|&[alpha, beta, gamma]| [beta - alpha / two_delta, alpha / two_delta, gamma]),
            );
            // x ∈ R_i
            shifted.extend([[1.0, 0.0, reached[1]], [-1.0, 0.0, -reached[0]]]);
            let next = x_range(&shifted, None, 0.0, f64::INFINITY)?;
            let own = x_range(self.rows(i + 1), None, 0.0, self.cap[i + 1])?;
            let (lo, hi) = (next.lo.max(own.lo), next.hi.min(own.hi));
            if lo > hi + ROUND_OFF * hi.abs().max(1.0) {
                return None;
            }
            reached = [lo.min(hi), hi];
        }
        Some(reached[1])
    }

    /// The greedy forward pass from the start through the controllable sets `k`: x (N + 1) and
    /// u (N).
    pub fn forward(&self, k: &[[f64; 2]], x: &mut [f64], u: &mut [f64]) {
        let n = self.points() - 1;
        x[0] = self.start;
        for i in 0..n {
            let two_delta = 2.0 * self.delta[i];
            let [lo_next, hi_next] = k[i + 1];
            // u's range at x_i: every row, and x_i + 2Δu within K_{i+1}
            let mut u_max = (hi_next - x[i]) / two_delta;
            let mut u_min = (lo_next - x[i]) / two_delta;
            for &[alpha, beta, gamma] in self.rows(i) {
                if alpha > 0.0 {
                    u_max = u_max.min((gamma - beta * x[i]) / alpha);
                } else if alpha < 0.0 {
                    u_min = u_min.max((gamma - beta * x[i]) / alpha);
                }
            }
            // x_i is controllable, so u_min ≤ u_max up to round-off: keep x_{i+1} in K_{i+1}
            let next = (x[i] + two_delta * u_max.max(u_min)).clamp(lo_next, hi_next);
            x[i + 1] = next;
            u[i] = (next - x[i]) / two_delta;
        }
    }
}

/// `x` within `range` up to round-off.
fn within(x: f64, [lo, hi]: [f64; 2]) -> bool {
    let round_off = ROUND_OFF * x.abs().max(1.0);
    x >= lo - round_off && x <= hi + round_off
}

/// A stage's admissible x, and the rows (indices, the reach's after the stage's) that set its
/// top.
struct Range {
    lo: f64,
    hi: f64,
    hi_by: [Option<usize>; 2],
}

/// The range of x over the polygon of `rows`, `floor` ≤ x ≤ `cap`, and (with `reach` = (2Δ, K))
/// x + 2Δu ∈ K: eliminate u pairwise (see the module doc). `None` when empty beyond round-off.
fn x_range(rows: &[Row], reach: Option<(f64, [f64; 2])>, floor: f64, cap: f64) -> Option<Range> {
    let mut lo = floor;
    let mut hi = cap;
    let mut hi_by = [None; 2];
    // the reach rows: 2Δ u + x ≤ K_hi and −2Δ u − x ≤ −K_lo
    let extra: [Row; 2] = match reach {
        Some((two_delta, [k_lo, k_hi])) => [[two_delta, 1.0, k_hi], [-two_delta, -1.0, -k_lo]],
        None => [[0.0, 0.0, 0.0]; 2],
    };
    let all = || rows.iter().chain(&extra).enumerate();
    for (p, &[alpha, beta, gamma]) in all() {
        if alpha == 0.0 && bound(beta, gamma, &mut lo, &mut hi)? {
            hi_by = [Some(p), None];
        }
    }
    for (p, &[a_up, b_up, g_up]) in all().filter(|(_, r)| r[0] > 0.0) {
        for (q, &[a_dn, b_dn, g_dn]) in all().filter(|(_, r)| r[0] < 0.0) {
            if bound(a_up * b_dn - a_dn * b_up, a_up * g_dn - a_dn * g_up, &mut lo, &mut hi)? {
                hi_by = [Some(p), Some(q)];
            }
        }
    }
    if lo > hi {
        if lo - hi > ROUND_OFF * hi.abs().max(1.0) {
            return None;
        }
        lo = hi;
    }
    Some(Range { lo, hi, hi_by })
}

/// Narrows [lo, hi] by `coefficient · x ≤ rhs`; `None` when a row without x fails, else
/// whether it lowered `hi`.
#[inline]
fn bound(coefficient: f64, rhs: f64, lo: &mut f64, hi: &mut f64) -> Option<bool> {
    if coefficient > 0.0 {
        if rhs / coefficient < *hi {
            *hi = rhs / coefficient;
            return Some(true);
        }
    } else if coefficient < 0.0 {
        *lo = lo.max(rhs / coefficient);
    } else if rhs < -ROUND_OFF * rhs.abs().max(1.0) {
        return None;
    }
    Some(false)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The double integrator's length L, acceleration limit A, speed limit V and intervals N.
    const DOUBLE_INTEGRATOR: (f64, f64, f64, usize) = (2.0, 3.0, 1.5, 400);

    /// The double integrator's stages from x = `start` to x = `end`: u ≤ A, −u ≤ A, x ≤ V².
    fn double_integrator(start: f64, end: f64) -> Stages {
        let (length, accel, speed, n) = DOUBLE_INTEGRATOR;
        Stages {
            rows: (0..=n).flat_map(|_| [[1.0, 0.0, accel], [-1.0, 0.0, accel]]).collect(),
            per_stage: 2,
            cap: vec![speed * speed; n + 1],
            floor: vec![0.0; n + 1],
            start,
            end,
            delta: vec![length / n as f64; n],
        }
    }

    /// A point mass on a line of length L with |s̈| ≤ A and ṡ ≤ V: the time-optimal profile is
    /// bang-coast-bang, x = min(2As, V², 2A(L − s)), and TOPP-RA's grid profile equals it at
    /// the grid points (s̈ is constant on each interval, so the collocation is exact).
    #[test]
    fn a_double_integrator_gets_bang_coast_bang() {
        let (length, accel, speed, n) = DOUBLE_INTEGRATOR;
        let stages = double_integrator(0.0, 0.0);
        let mut k = vec![[0.0; 2]; n + 1];
        stages.controllable_sets(&mut k).unwrap();
        let (mut x, mut u) = (vec![0.0; n + 1], vec![0.0; n]);
        stages.forward(&k, &mut x, &mut u);
        for (i, &xi) in x.iter().enumerate() {
            let s = length * i as f64 / n as f64;
            let want = (2.0 * accel * s).min(speed * speed).min(2.0 * accel * (length - s));
            assert!((xi - want).abs() < 1e-12, "x at s = {s}: {xi} vs {want}");
        }
        assert!(u.iter().all(|&u| u.abs() <= accel + 1e-12));
    }

    /// The double integrator from a moving start to a moving end: x = min(x₀ + 2As, V²,
    /// x_N + 2A(L − s)); a start beyond what braking to x_N allows is outside K_0, and the
    /// top of stage 0 names the deceleration row that sets it.
    #[test]
    fn a_double_integrator_from_and_to_a_speed() {
        let (length, accel, speed, n) = DOUBLE_INTEGRATOR;
        let mut stages = double_integrator(0.5, 1.0);
        let mut k = vec![[0.0; 2]; n + 1];
        stages.controllable_sets(&mut k).unwrap();
        let (mut x, mut u) = (vec![0.0; n + 1], vec![0.0; n]);
        stages.forward(&k, &mut x, &mut u);
        for (i, &xi) in x.iter().enumerate() {
            let s = length * i as f64 / n as f64;
            let want = (0.5 + 2.0 * accel * s)
                .min(speed * speed)
                .min(1.0 + 2.0 * accel * (length - s));
            assert!((xi - want).abs() < 1e-12, "x at s = {s}: {xi} vs {want}");
        }
        // a short path: from x = 2 the most braking reaches 2 − 2·3·0.1 = 1.4 > 1 at the end
        let short = Stages {
            cap: vec![4.0; 11],
            start: 2.0,
            floor: vec![0.0; 11],
            rows: stages.rows[..22].to_vec(),
            delta: vec![0.01; 10],
            ..stages.clone()
        };
        stages = short;
        let mut k = vec![[0.0; 2]; 11];
        assert_eq!(stages.controllable_sets(&mut k), Err(Stuck(0)));
        let ([_, top], rows) = stages.top(0, Some(k[1]), 4.0).unwrap();
        assert!((top - (1.0 + 2.0 * 3.0 * 0.1)).abs() < 1e-12, "{top}");
        assert_eq!(rows, vec![1]);
    }

    /// The reachable sets' top of the double integrator from x₀: min(x₀ + 2As, V²) at every
    /// point, whatever the end (the sets look forward only); a cap below what a stage's rows
    /// need empties them.
    #[test]
    fn a_double_integrator_reaches_at_most_its_acceleration_allows() {
        let (length, accel, speed, n) = DOUBLE_INTEGRATOR;
        let mut stages = double_integrator(0.5, 2.0);
        for i in [0, 1, 10, 57, 200, 400] {
            let s = length * i as f64 / n as f64;
            let want = (0.5 + 2.0 * accel * s).min(speed * speed);
            let top = stages.reachable_top(i).unwrap();
            assert!((top - want).abs() < 1e-12, "top at s = {s}: {top} vs {want}");
        }
        // x ≥ 1 at point 3 (a row without u), which a cap of 0.9 before it cannot reach
        stages.rows[3 * 2] = [0.0, -1.0, -1.0];
        stages.cap[2] = 0.9;
        stages.cap[3] = 0.9;
        assert_eq!(stages.reachable_top(3), None);
        assert!(stages.reachable_top(2).is_some());
    }

    /// A constraint coupling u and x (the torque rows' shape): |u + x| ≤ 1 on a short path.
    /// Every step of the profile keeps the rows and the sets; the sets hold every x the
    /// profile visits.
    #[test]
    fn the_profile_keeps_every_row_and_stays_in_the_sets() {
        let n = 50;
        let stages = Stages {
            rows: (0..=n)
                .flat_map(|i| {
                    let b = 1.0 + 0.5 * (i as f64 * 0.3).sin();
                    [[1.0, b, 1.0], [-1.0, -b, 1.0]]
                })
                .collect(),
            per_stage: 2,
            cap: vec![f64::INFINITY; n + 1],
            floor: vec![0.0; n + 1],
            start: 0.0,
            end: 0.0,
            delta: vec![0.01; n],
        };
        let mut k = vec![[0.0; 2]; n + 1];
        stages.controllable_sets(&mut k).unwrap();
        let (mut x, mut u) = (vec![0.0; n + 1], vec![0.0; n]);
        stages.forward(&k, &mut x, &mut u);
        for i in 0..n {
            for &[a, b, g] in stages.rows(i) {
                assert!(a * u[i] + b * x[i] <= g + 1e-12, "row at {i}");
            }
            assert!(x[i] >= k[i][0] - 1e-12 && x[i] <= k[i][1] + 1e-12);
            assert!((x[i + 1] - x[i] - 2.0 * 0.01 * u[i]).abs() < 1e-15);
        }
        assert_eq!(x[n], 0.0);
        assert!(x[n / 2] > 0.1);
    }

    /// A stage that holds no x (a row 0·u + 0·x ≤ −1) stops the backward pass there.
    #[test]
    fn an_empty_stage_is_reported() {
        let n = 10;
        let mut rows: Vec<Row> = (0..=n).flat_map(|_| [[1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]]).collect();
        rows[2 * 4] = [0.0, 0.0, -1.0];
        let stages = Stages {
            rows,
            per_stage: 2,
            cap: vec![1.0; n + 1],
            floor: vec![0.0; n + 1],
            start: 0.0,
            end: 0.0,
            delta: vec![0.1; n],
        };
        let mut k = vec![[0.0; 2]; n + 1];
        assert_eq!(stages.controllable_sets(&mut k), Err(Stuck(4)));
    }
}
