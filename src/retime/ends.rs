//! The path speeds a timing starts and ends at (docs/retime.md, "Chaining segments"): from
//! rest (0), or from the joint velocity `start_velocity` / `end_velocity` gives, which must lie
//! along the path's tangent there, q̇ = q′(s) ṡ with ṡ ≥ 0.

use super::RetimeOptions;
use super::spline::PathSpline;
use crate::error::{Error, Result, shortest, six_digits};
use crate::model::Model;
use crate::sim::check::override_per_joint;

/// A given velocity's part off the path's tangent may be at most this share of its norm
/// (per joint): the written velocity is the part along it, so a junction of two chained
/// timings is continuous to this share.
pub const TANGENT: f64 = 1e-6;

/// The path speeds ṡ at the two ends (path units/s, ≥ 0; 0: at rest).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Ends {
    pub start: f64,
    pub end: f64,
}

impl Ends {
    /// The path speeds `options` give at `path`'s ends on `model` (0 where none is given): an
    /// error naming the option and the joint where a velocity is not along the tangent within
    /// [`TANGENT`] of its norm, or points back along the path.
    pub fn of(model: &Model, path: &PathSpline, options: &RetimeOptions) -> Result<Ends> {
        let length = path.length();
        Ok(Ends {
            start: path_speed(model, path, 0.0, "start_velocity", &options.start_velocity)?,
            end: path_speed(model, path, length, "end_velocity", &options.end_velocity)?,
        })
    }
}

/// ṡ of the joint velocity `given` (one per joint; empty or `None`: 0) at `s`: the least-squares
/// ṡ = q′·q̇ / q′·q′ of q̇ = q′ ṡ.
fn path_speed(model: &Model, path: &PathSpline, s: f64, field: &str, given: &[Option<f64>]) -> Result<f64> {
    let dof = model.dof();
    let mut velocity = vec![0.0; dof];
    override_per_joint(field, &mut velocity, given, f64::is_finite, "a finite number")?;
    // the norm and ṡ of the velocity scaled by its largest entry, so that neither overflows
    // (a velocity of 1e200 rad/s would otherwise have an infinite norm and pass any share of it)
    let largest = velocity.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if largest == 0.0 {
        return Ok(0.0);
    }
    let scaled: Vec<f64> = velocity.iter().map(|v| v / largest).collect();
    let norm = largest * scaled.iter().map(|v| v * v).sum::<f64>().sqrt();
    let (mut q, mut dq, mut ddq) = (vec![0.0; dof], vec![0.0; dof], vec![0.0; dof]);
    path.eval(s, &mut q, &mut dq, &mut ddq);
    let along =
        largest * (dq.iter().zip(&scaled).map(|(d, v)| d * v).sum::<f64>() / dq.iter().map(|d| d * d).sum::<f64>());
    let end = match s == 0.0 {
        true => "start",
        false => "end",
    };
    let unit = |j: usize| model.joints[j].kind.unit();
    for j in 0..dof {
        let residual = velocity[j] - dq[j] * along;
        if residual.abs() > TANGENT * norm {
            return Err(Error::option(
                field,
                format!(
                    "J{} {} {}/s is not along the path's tangent at its {end}: the nearest velocity along it (q′ ṡ, ṡ = {}) gives J{} {} {}/s, {:.3e} off, more than {TANGENT:e} of the velocity's norm {}; the path's tangent there is ({})",
                    j + 1,
                    shortest(velocity[j]),
                    unit(j),
                    six_digits(along),
                    j + 1,
                    six_digits(dq[j] * along),
                    unit(j),
                    residual,
                    six_digits(norm),
                    dq.iter().map(|d| format!("{d:.6}")).collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    }
    if along < 0.0 {
        return Err(Error::option(
            field,
            format!(
                "points back along the path at its {end} (ṡ = {} < 0): a timing moves forwards along the path; reverse the velocity or the path",
                six_digits(along)
            ),
        ));
    }
    // TOPP-RA works in x = ṡ²
    if !(along * along).is_finite() {
        return Err(Error::option(
            field,
            format!(
                "its path speed at the path's {end}, ṡ = {}, is beyond any limit (ṡ² is not a finite number)",
                six_digits(along)
            ),
        ));
    }
    Ok(along)
}
