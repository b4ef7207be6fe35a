//! A sequence of targets, each solved from the previous solution.

use super::position::{check_inputs, check_target, solve};
use super::{IkTask, IkWorkspace};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::spatial::Vec3;

/// The joint path that follows a sequence of targets.
#[derive(Clone, Debug, PartialEq)]
pub struct PathSolution {
    /// One row per target (N rows of n joint positions, rad or m); held joints equal the seed's.
    pub q: Vec<Vec<f64>>,
    /// Largest position residual over the rows (m).
    pub max_residual_m: f64,
    /// Iterations summed over the rows.
    pub iterations: usize,
}

/// Solves every target of `targets` (world, m) in order with [`solve_position`]: sample 0 from
/// `seed` (n joint positions), sample k from the solution of sample k − 1, so each row is the
/// smallest weighted change from the row before it. A closed path is not closed in joint space
/// by construction: the last row is wherever the sweep ends.
///
/// Errors: as [`solve_position`]; an unreachable sample stops the sweep with
/// [`Error::Unreachable`] naming the sample index, its target and the closest distance reached.
///
/// [`solve_position`]: super::solve_position
pub fn solve_path(model: &Model, task: &IkTask, targets: &[Vec3], seed: &[f64]) -> Result<PathSolution> {
    check_inputs(model, task, seed)?;
    let mut ws = IkWorkspace::new(model);
    let mut rows: Vec<Vec<f64>> = Vec::with_capacity(targets.len());
    let (mut max_residual_m, mut iterations) = (0.0_f64, 0);
    for (k, target) in targets.iter().enumerate() {
        check_target(target)?;
        let q_prev = rows.last().map_or(seed, Vec::as_slice);
        let sol = solve(model, &mut ws, task, target, q_prev).map_err(|closest_m| Error::Unreachable {
            sample: Some((k, targets.len())),
            target: (*target).into(),
            frame: model.frame(task.frame).name.clone(),
            closest_m,
        })?;
        max_residual_m = max_residual_m.max(sol.residual_m);
        iterations += sol.iterations;
        rows.push(sol.q);
    }
    Ok(PathSolution {
        q: rows,
        max_residual_m,
        iterations,
    })
}
