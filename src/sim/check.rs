//! The checks of a run's input values, each error naming the option it checks as a field
//! (`` `dt` ``; [`Error::option`]), which each front end shows in its own words.

use crate::error::{Error, Result, shortest};

/// `x` is a finite number, else an error for `field`.
pub fn finite(field: &str, x: f64) -> Result<()> {
    if !x.is_finite() {
        return Err(Error::option(field, format!("{} is not a finite number", shortest(x))));
    }
    Ok(())
}

/// `x` is finite and > 0, else an error for `field`.
pub fn positive(field: &str, x: f64) -> Result<()> {
    finite(field, x)?;
    if x <= 0.0 {
        return Err(Error::option(field, format!("{} must be > 0", shortest(x))));
    }
    Ok(())
}

/// `x` is finite and ≥ 0, else an error for `field`.
pub fn non_negative(field: &str, x: f64) -> Result<()> {
    finite(field, x)?;
    if x < 0.0 {
        return Err(Error::option(field, format!("{} must be ≥ 0", shortest(x))));
    }
    Ok(())
}

/// `given` values for a model of `n` joints, else an error for `field`.
pub fn count(field: &str, given: usize, n: usize) -> Result<()> {
    if given != n {
        return Err(Error::option(
            field,
            format!("{given} values given; the model has {n} joints"),
        ));
    }
    Ok(())
}

/// Each joint's value that `values` gives replaces its entry of `target` (`None` keeps it; an
/// empty `values` keeps them all), if `valid`; otherwise an error for `field` saying the value
/// must be `rule`. `values` must have one entry per entry of `target`.
pub fn override_per_joint(
    field: &str,
    target: &mut [f64],
    values: &[Option<f64>],
    valid: impl Fn(f64) -> bool,
    rule: &str,
) -> Result<()> {
    if values.is_empty() {
        return Ok(());
    }
    count(field, values.len(), target.len())?;
    for (i, v) in values.iter().enumerate() {
        if let Some(v) = *v {
            if !valid(v) {
                return Err(Error::option(
                    field,
                    format!("J{} value {} must be {rule}", i + 1, shortest(v)),
                ));
            }
            target[i] = v;
        }
    }
    Ok(())
}
