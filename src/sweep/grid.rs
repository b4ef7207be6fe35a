//! The values a sweep runs: one [`Axis`] per varied option, their Cartesian product
//! ([`Grid`]), and the deterministic parts of it that separate processes run ([`Shard`]).

use std::ops::Range;
use std::str::FromStr;

use crate::error::{Error, Result, shortest};

/// Most values one option takes (80 MB of them); a bigger sweep is a product of options.
pub const MAX_AXIS_VALUES: usize = 10_000_000;

/// The option every axis error names.
const VARY: &str = "`vary`";

/// One varied option and its values, in the order they run.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The option's name as on the command line, without dashes (`payload-kg`).
    pub name: String,
    /// Its values (the option's unit), at least one.
    pub values: Vec<f64>,
}

impl Axis {
    /// Parses `NAME=LO:HI:STEP` (LO, LO+STEP, … up to HI included, within 1e-9 steps) or
    /// `NAME=v1,v2,…`. Range values are rounded to the decimals LO, HI and STEP are written
    /// with, so `0:1:0.1` gives 0.3 and not 0.30000000000000004. The name is not checked here
    /// (the caller knows which options exist); the values must be finite.
    pub fn parse(spec: &str) -> Result<Axis> {
        let (name, values) = spec
            .split_once('=')
            .ok_or_else(|| Error::argument(VARY, format!("'{spec}' is not NAME=LO:HI:STEP or NAME=v1,v2,…")))?;
        let name = name.trim().trim_start_matches("--").to_string();
        if name.is_empty() {
            return Err(Error::argument(VARY, format!("'{spec}' names no option")));
        }
        let values = if values.contains(':') {
            Steps::parse(&name, values)?.values()
        } else {
            list(&name, values)?.collect::<Result<Vec<f64>>>()?
        };
        Ok(Axis { name, values })
    }

    /// How many values `spec` gives, checked as [`Axis::parse`] checks it but without making
    /// the list (so that the size of a product is known before any list is made).
    pub fn count(spec: &str) -> Result<usize> {
        let (name, values) = spec
            .split_once('=')
            .ok_or_else(|| Error::argument(VARY, format!("'{spec}' is not NAME=LO:HI:STEP or NAME=v1,v2,…")))?;
        let name = name.trim().trim_start_matches("--");
        match values.contains(':') {
            true => Ok(Steps::parse(name, values)?.count),
            false => list(name, values)?.try_fold(0, |n, value| value.map(|_| n + 1)),
        }
    }
}

/// `LO:HI:STEP`, checked, before its values are made.
struct Steps {
    lo: f64,
    step: f64,
    count: usize,
    /// The most decimals LO, HI and STEP are written with (`None`: one is in scientific
    /// notation).
    decimals: Option<usize>,
}

impl Steps {
    fn parse(name: &str, text: &str) -> Result<Steps> {
        let parts: Vec<&str> = text.split(':').collect();
        let [lo_text, hi_text, step_text] = parts[..] else {
            return Err(Error::argument(VARY, format!("{name}={text}: a range is LO:HI:STEP")));
        };
        let (lo, hi, step) = (number(name, lo_text)?, number(name, hi_text)?, number(name, step_text)?);
        if step <= 0.0 {
            return Err(Error::argument(
                VARY,
                format!("{name}={text}: the step {} must be > 0", shortest(step)),
            ));
        }
        if hi < lo {
            return Err(Error::argument(
                VARY,
                format!("{name}={text}: empty range ({} < {})", shortest(hi), shortest(lo)),
            ));
        }
        let count = ((hi - lo) / step + 1e-9).floor() + 1.0;
        if count > MAX_AXIS_VALUES as f64 {
            return Err(Error::argument(
                VARY,
                format!("{name}={text}: {count:e} values; one option takes at most {MAX_AXIS_VALUES:e}"),
            ));
        }
        let decimals: Option<Vec<usize>> = [lo_text, hi_text, step_text].iter().map(|t| decimals(t)).collect();
        let decimals = decimals.map(|d| d.into_iter().max().unwrap_or(0));
        Ok(Steps {
            lo,
            step,
            count: count as usize,
            decimals,
        })
    }

    /// The values: LO, LO + STEP, … rounded to the decimals they are written with.
    fn values(&self) -> Vec<f64> {
        let (lo, step) = (self.lo, self.step);
        (0..self.count)
            .map(|i| {
                let x = lo + i as f64 * step;
                let rounded = match self.decimals {
                    Some(d) => format!("{x:.d$}"),
                    None => format!("{x:.14e}"),
                };
                rounded.parse().unwrap_or(x)
            })
            .collect()
    }
}

/// Digits after the point of a number written positionally (`0.25` → 2); `None` for
/// scientific notation, whose range values are rounded to 15 significant digits instead.
fn decimals(text: &str) -> Option<usize> {
    let text = text.trim();
    if text.contains(['e', 'E']) {
        return None;
    }
    Some(text.split_once('.').map_or(0, |(_, after)| after.len()))
}

/// `v1,v2,…`: an error if it gives no values, else each value, checked as it is read.
fn list<'t>(name: &'t str, text: &'t str) -> Result<impl Iterator<Item = Result<f64>> + 't> {
    if text.trim().is_empty() {
        return Err(Error::argument(
            VARY,
            format!("{name}: no values: give LO:HI:STEP or v1,v2,…"),
        ));
    }
    Ok(text.split(',').map(move |v| number(name, v)))
}

fn number(name: &str, text: &str) -> Result<f64> {
    if text.trim().is_empty() {
        return Err(Error::argument(
            VARY,
            format!("{name}: an empty value (a comma too many)"),
        ));
    }
    let x: f64 = text
        .trim()
        .parse()
        .map_err(|_| Error::argument(VARY, format!("{name}: '{}' is not a number", text.trim())))?;
    if !x.is_finite() {
        return Err(Error::argument(
            VARY,
            format!("{name}: {} is not a finite number", shortest(x)),
        ));
    }
    Ok(x)
}

/// The Cartesian product of the axes. Run `i` takes, for each axis, the value at the digit of
/// `i` in the mixed radix of the axis lengths, the last axis varying fastest (as nested loops
/// with the first axis outermost).
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// The varied options, outermost first.
    pub axes: Vec<Axis>,
}

impl Grid {
    /// The product of `axes`; an option may be varied once only.
    pub fn new(axes: Vec<Axis>) -> Result<Grid> {
        for (i, a) in axes.iter().enumerate() {
            if axes[..i].iter().any(|b| b.name == a.name) {
                return Err(Error::argument(VARY, format!("'{}' is varied twice", a.name)));
            }
        }
        Ok(Grid { axes })
    }

    /// The grid of `specs` (see [`Axis::parse`]) and the runs of it this process makes (those
    /// of `shard`, or all), refused before any list of values is made when the product has
    /// more than `usize::MAX / 2` runs or the process would make more than `max_runs`.
    pub fn parse(specs: &[String], shard: Option<Shard>, max_runs: usize) -> Result<(Grid, Range<usize>)> {
        let counts = specs.iter().map(|s| Axis::count(s)).collect::<Result<Vec<usize>>>()?;
        let total = (counts.iter())
            .try_fold(1usize, |n, &c| n.checked_mul(c))
            .filter(|&n| n <= usize::MAX / 2)
            .ok_or_else(|| {
                let product: f64 = counts.iter().map(|&c| c as f64).product();
                Error::argument(VARY, format!("{product:e} runs: too many for one sweep"))
            })?;
        let runs = shard.map_or(0..total, |s| s.range(total));
        if runs.len() > max_runs {
            let message = match shard {
                None => format!(
                    "{total} runs: more than {max_runs} in one process; split them with `shard` K/N (see docs/sweep.md)"
                ),
                Some(s) => format!(
                    "part {}/{} has {} of the {total} runs: more than {max_runs} in one process; split them into at least {} parts",
                    s.k,
                    s.n,
                    runs.len(),
                    total.div_ceil(max_runs)
                ),
            };
            let option = if shard.is_some() { "`shard`" } else { VARY };
            return Err(Error::argument(option, message));
        }
        let grid = Grid::new(specs.iter().map(|s| Axis::parse(s)).collect::<Result<_>>()?)?;
        Ok((grid, runs))
    }

    /// Number of runs (the product of the axis lengths; 1 with no axis), or `None` past
    /// `usize`.
    pub fn len(&self) -> Option<usize> {
        self.axes.iter().try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
    }

    /// Whether the grid has no run (never: an axis has at least one value).
    pub fn is_empty(&self) -> bool {
        self.len() == Some(0)
    }

    /// The values of run `index` (< [`Grid::len`]), one per axis.
    pub fn point(&self, index: usize) -> Vec<f64> {
        let mut rest = index;
        let mut point = vec![0.0; self.axes.len()];
        for (slot, axis) in point.iter_mut().zip(&self.axes).rev() {
            *slot = axis.values[rest % axis.values.len()];
            rest /= axis.values.len();
        }
        point
    }
}

/// Part `k` (1-based) of `n` of a sweep: the `k`-th of `n` contiguous blocks of run indices,
/// sizes differing by at most one. The parts of a sweep are disjoint and together are all of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which part, 1 ≤ k ≤ n.
    pub k: usize,
    /// How many parts, ≥ 1.
    pub n: usize,
}

impl Shard {
    /// The run indices of this part of a sweep of `total` runs: `⌊total·(k−1)/n⌋ ..
    /// ⌊total·k/n⌋`.
    pub fn range(&self, total: usize) -> Range<usize> {
        let at = |k: usize| (total as u128 * k as u128 / self.n as u128) as usize;
        at(self.k - 1)..at(self.k)
    }
}

impl FromStr for Shard {
    type Err = Error;

    /// `K/N` with 1 ≤ K ≤ N.
    fn from_str(text: &str) -> Result<Shard> {
        let bad = || Error::option("shard", format!("'{text}' is not K/N with 1 ≤ K ≤ N (e.g. 3/8)"));
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let (k, n): (usize, usize) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_include_their_end_and_keep_the_written_decimals() {
        let a = Axis::parse("payload-kg=0:1:0.1").unwrap();
        assert_eq!(a.name, "payload-kg");
        assert_eq!(a.values.len(), 11);
        assert_eq!(a.values[3], 0.3);
        assert_eq!(a.values[10], 1.0);
        assert_eq!(Axis::parse("dt=1e-4:3e-4:1e-4").unwrap().values, vec![1e-4, 2e-4, 3e-4]);
        assert_eq!(Axis::parse("freq=0.5,1,2").unwrap().values, vec![0.5, 1.0, 2.0]);
        assert_eq!(Axis::parse("freq=2:2:1").unwrap().values, vec![2.0]);
    }

    #[test]
    fn bad_axes_are_refused() {
        for spec in [
            "freq",
            "=1,2",
            "freq=1:0:0.1",
            "freq=0:1:0",
            "freq=0:1:-1",
            "freq=a,b",
            "freq=0:1",
            "freq=nan",
        ] {
            assert!(Axis::parse(spec).is_err(), "{spec}");
        }
        // an empty list, and an empty value in one, say so (they said "'' is not a number")
        let message = |spec: &str| Axis::parse(spec).unwrap_err().to_string();
        assert_eq!(message("freq="), "`vary`: freq: no values: give LO:HI:STEP or v1,v2,…");
        assert_eq!(message("freq=1,"), "`vary`: freq: an empty value (a comma too many)");
        assert_eq!(Axis::count("freq= ").unwrap_err().to_string(), message("freq="));
    }

    #[test]
    fn the_product_runs_the_last_axis_fastest() {
        let grid = Grid::new(vec![Axis::parse("a=1,2").unwrap(), Axis::parse("b=10,20,30").unwrap()]).unwrap();
        assert_eq!(grid.len(), Some(6));
        let points: Vec<Vec<f64>> = (0..6).map(|i| grid.point(i)).collect();
        assert_eq!(points[0], vec![1.0, 10.0]);
        assert_eq!(points[2], vec![1.0, 30.0]);
        assert_eq!(points[3], vec![2.0, 10.0]);
        assert!(Grid::new(vec![Axis::parse("a=1").unwrap(), Axis::parse("a=2").unwrap()]).is_err());
    }

    #[test]
    fn shards_cover_the_sweep_once() {
        for total in [0, 1, 7, 200, 1001] {
            for n in 1..=9 {
                let mut next = 0;
                for k in 1..=n {
                    let r = Shard { k, n }.range(total);
                    assert_eq!(r.start, next);
                    assert!(r.len() <= total / n + 1);
                    next = r.end;
                }
                assert_eq!(next, total);
            }
        }
        assert_eq!("3/8".parse::<Shard>().unwrap(), Shard { k: 3, n: 8 });
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", "-1/2"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
