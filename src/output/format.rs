//! Numbers a person can read at a glance.

/// `x` in about `width` characters: fixed-point when its magnitude suits, scientific otherwise.
pub fn number(x: f64, width: usize) -> String {
    let a = x.abs();
    let s = if x == 0.0 {
        "0".to_string()
    } else if !x.is_finite() {
        format!("{x}")
    } else if (1e-2..1e4).contains(&a) {
        let decimals = if a >= 100.0 {
            1
        } else if a >= 10.0 {
            2
        } else if a >= 1.0 {
            3
        } else {
            4
        };
        format!("{x:.decimals$}")
    } else {
        format!("{x:.2e}")
    };
    format!("{s:>width$}")
}

/// Appends `x` exactly: the shortest decimal that reads back to the same `f64` (Ryū), positional
/// from 1e-5 to 1e16 and scientific outside, so that files stay short. The trail calls this for
/// every number of every row; Ryū is several times faster than `{}` formatting.
pub fn push_exact(out: &mut String, x: f64) {
    out.push_str(ryu::Buffer::new().format(x));
}

/// `x` as its shortest decimal that reads back to the same `f64` (see [`push_exact`]).
pub fn exact(x: f64) -> String {
    crate::error::shortest(x)
}

/// A row: a left label, then one right-aligned number per joint.
pub fn row(label: &str, values: impl IntoIterator<Item = f64>) -> String {
    let mut line = format!("{label:<22}");
    for v in values {
        line.push_str(&number(v, 10));
    }
    line
}

/// A row of texts, one right-aligned per joint, as [`row`] aligns numbers.
pub fn text_row(label: &str, values: impl IntoIterator<Item = String>) -> String {
    let mut line = format!("{label:<22}");
    for v in values {
        line.push_str(&format!("{v:>10}"));
    }
    line
}

/// The header row `J1 … Jn` aligned with [`row`].
pub fn joint_header(n: usize) -> String {
    let mut line = format!("{:<22}", "");
    for i in 1..=n {
        line.push_str(&format!("{:>10}", format!("J{i}")));
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readable_numbers() {
        assert_eq!(number(158.0, 0), "158.0");
        assert_eq!(number(0.0412, 0), "0.0412");
        assert_eq!(number(6.452e-6, 0), "6.45e-6");
        assert_eq!(number(0.0, 4), "   0");
        assert_eq!(number(f64::INFINITY, 0), "inf");
        let exact = |x: f64| {
            let mut s = String::new();
            push_exact(&mut s, x);
            s
        };
        for x in [-1.4033517506376317e-16, 0.12000000000000001, 3.0, 1e300, -0.0, 5e-5] {
            assert_eq!(exact(x).parse::<f64>().unwrap().to_bits(), x.to_bits(), "{}", exact(x));
        }
        assert_eq!(exact(-1.4033517506376317e-16), "-1.4033517506376317e-16");
    }
}
