//! Linear interpolation of joint (or point) samples over a repeating period.

/// How the last sample connects to the first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// `replay`: N frames span [0, T] (frame N−1 at T, N−1 segments); past T the motion
    /// starts over at frame 0.
    Repeat,
    /// `shape`: N samples, sample k at k·T/N, and a last segment from sample N−1 back to
    /// sample 0 (a closed loop).
    Closed,
}

/// Samples played at a fixed period with linear interpolation; the velocity is the slope of
/// the current segment. With h the sample spacing, `tm = t mod T`, `s = tm/h`,
/// `j = min(⌊s⌋, last segment)`, `a = s − j`:  `q = Q_j + a (Q_{j+1} − Q_j)`, `v = (Q_{j+1} − Q_j)/h`.
#[derive(Clone, Debug, PartialEq)]
pub struct Interpolated {
    /// Samples, row-major: `rows × columns` values.
    samples: Vec<f64>,
    rows: usize,
    columns: usize,
    period: f64,
    wrap: Wrap,
}

impl Interpolated {
    /// Samples given as rows of equal length; at least 2 rows and 1 column, period > 0
    /// (the caller validates and reports; this panics on violations).
    pub fn new(rows: &[Vec<f64>], period: f64, wrap: Wrap) -> Self {
        assert!(rows.len() >= 2 && !rows[0].is_empty() && period > 0.0);
        let columns = rows[0].len();
        assert!(rows.iter().all(|r| r.len() == columns));
        Self {
            samples: rows.concat(),
            rows: rows.len(),
            columns,
            period,
            wrap,
        }
    }

    /// Values per sample.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// Number of samples.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Sample `k`.
    pub fn row(&self, k: usize) -> &[f64] {
        &self.samples[k * self.columns..(k + 1) * self.columns]
    }

    /// The last sample at or before time `t` (s), counted on over the periods, and its time:
    /// sample k at k·h, h the period over the segments (within 10⁻⁹ of a sample, at it).
    pub fn frame(&self, t: f64) -> (u64, f64) {
        let segments = match self.wrap {
            Wrap::Repeat => self.rows - 1,
            Wrap::Closed => self.rows,
        };
        let h = self.period / segments as f64;
        let k = (t / h + 1e-9).floor().max(0.0);
        (k as u64, k * h)
    }

    /// The interpolated value at t into `q` and the segment slope into `v`.
    #[inline]
    pub fn eval(&self, t: f64, q: &mut [f64], v: &mut [f64]) {
        let (segments, last) = match self.wrap {
            Wrap::Repeat => (self.rows - 1, self.rows - 2),
            Wrap::Closed => (self.rows, self.rows - 1),
        };
        let h = self.period / segments as f64;
        let s = (t % self.period) / h;
        let j = (s.floor() as usize).min(last);
        let a = s - j as f64;
        let next = (j + 1) % self.rows;
        let (qj, qn) = (self.row(j), self.row(next));
        for i in 0..self.columns {
            let dq = qn[i] - qj[i];
            q[i] = qj[i] + a * dq;
            v[i] = dq / h;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeat_spans_the_period_and_starts_over() {
        let p = Interpolated::new(&[vec![0.0], vec![1.0], vec![3.0]], 2.0, Wrap::Repeat);
        let (mut q, mut v) = ([0.0], [0.0]);
        p.eval(0.5, &mut q, &mut v);
        assert_eq!((q[0], v[0]), (0.5, 1.0));
        p.eval(1.5, &mut q, &mut v);
        assert_eq!((q[0], v[0]), (2.0, 2.0));
        p.eval(2.5, &mut q, &mut v); // past T: frame 0 again
        assert_eq!((q[0], v[0]), (0.5, 1.0));
    }

    #[test]
    fn closed_loops_back_to_the_first_sample() {
        let p = Interpolated::new(&[vec![0.0], vec![1.0], vec![3.0]], 3.0, Wrap::Closed);
        let (mut q, mut v) = ([0.0], [0.0]);
        p.eval(2.5, &mut q, &mut v); // between sample 2 (3.0) and sample 0 (0.0)
        assert_eq!((q[0], v[0]), (1.5, -3.0));
        p.eval(3.0, &mut q, &mut v);
        assert_eq!((q[0], v[0]), (0.0, 1.0));
    }
}
