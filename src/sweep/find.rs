//! `--find`: the largest (or smallest) value of one option at which the arm still follows.
//!
//! The search assumes one crossing in [lo, hi]: the runs follow on one side of a value and do
//! not on the other. Each round runs `P` points evenly spaced strictly inside the bracket
//! (P = the runner's threads, in parallel) and keeps the part between the last point that
//! follows and the first that does not, counted from the side that follows; the bracket shrinks
//! by a factor P + 1 per round until it is no wider than the resolution. With several crossings
//! it finds one of them.

use super::{Row, Runner};

/// Which end of the following values is sought.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seek {
    /// The largest value that follows (`--find`): low values follow.
    Largest,
    /// The smallest value that follows (`--find-min`): high values follow.
    Smallest,
}

/// The answer of a search.
#[derive(Clone, Debug, PartialEq)]
pub enum Found {
    /// The boundary: `follows` is the run at the sought value, `fails` the next one
    /// (within the resolution), whose reasons say what gives way.
    Boundary {
        /// The last run that follows.
        follows: Row,
        /// The first run beyond it that does not.
        fails: Row,
    },
    /// The end that should follow (lo for [`Seek::Largest`], hi for [`Seek::Smallest`])
    /// already fails: no value in the range follows.
    NoneFollows(Row),
    /// The other end follows too: the whole range follows (as far as its ends say).
    AllFollow(Row),
}

/// Searches [`lo`, `hi`] (lo < hi) to within `resolution` (> 0), each value run as the single
/// varied option of `runner`.
pub fn find(runner: &Runner, lo: f64, hi: f64, resolution: f64, seek: Seek) -> Found {
    let (good_end, bad_end) = match seek {
        Seek::Largest => (lo, hi),
        Seek::Smallest => (hi, lo),
    };
    let mut index = 0;
    let mut next_points = |values: &[f64]| -> Vec<(usize, Vec<f64>)> {
        values
            .iter()
            .map(|&x| {
                index += 1;
                (index - 1, vec![x])
            })
            .collect()
    };
    let mut ends = runner.run_points(next_points(&[good_end, bad_end])).into_iter();
    let (mut good, mut bad) = (ends.next().expect("two runs"), ends.next().expect("two runs"));
    if !good.follows() {
        return Found::NoneFollows(good);
    }
    if bad.follows() {
        return Found::AllFollow(bad);
    }
    let parts = runner.threads().max(1) + 1;
    while (bad.values[0] - good.values[0]).abs() > resolution {
        let (g, b) = (good.values[0], bad.values[0]);
        let inside: Vec<f64> = (1..parts).map(|j| g + (b - g) * j as f64 / parts as f64).collect();
        // the bracket no longer splits in floating point
        if inside.iter().all(|&x| x == g || x == b) {
            break;
        }
        for row in runner.run_points(next_points(&inside)) {
            if row.follows() {
                good = row;
            } else {
                bad = row;
                break;
            }
        }
    }
    Found::Boundary {
        follows: good,
        fails: bad,
    }
}
