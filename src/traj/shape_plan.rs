//! A shape's plan: the board targets along a shape, their exact IK, and the joint samples as a
//! closed loop (docs/model.md, the shapes).

use super::shape::{Board, Shape};
use super::{Interpolated, Trajectory, Wrap};
use crate::error::{Error, Result};
use crate::ik::{IkTask, solve_path};
use crate::input::MAX_SHAPE_POINTS;
use crate::model::{FrameId, JointId, Model};
use crate::spatial::Vec3;

/// The drawing part of a `shape` run.
#[derive(Clone, Debug)]
pub struct ShapeRun {
    /// The board drawn on.
    pub board: Board,
    /// The closed reference path (the IK targets, world, m).
    pub reference: Vec<Vec3>,
    /// The target point over time: the reference samples played like the joint samples.
    pub target: Interpolated,
    /// Largest IK position residual over the samples (m).
    pub ik_max_residual_m: f64,
}

impl ShapeRun {
    /// Plans `shape` on `board`: `points` targets along it, their exact IK for the origin of
    /// frame `tool`, and the joint samples as a closed loop every `period` (s). The IK moves
    /// the joints and starts from the pose of the model's [`crate::model::ShapeIk`] where it
    /// has one (the Faze4: J1, J2, J3 and J5 from the original's seed); on any other arm every
    /// joint is free, from the zero pose clamped into the limits. Returns the joint command
    /// and the drawing part of the run.
    pub fn plan(
        model: &Model,
        tool: FrameId,
        shape: Shape,
        points: usize,
        board: Board,
        period: f64,
    ) -> Result<(Trajectory, ShapeRun)> {
        if points < 3 {
            return Err(Error::option(
                "shape_points",
                format!("{points} samples cannot make a closed path: at least 3"),
            ));
        }
        if points > MAX_SHAPE_POINTS {
            return Err(Error::option(
                "shape_points",
                format!(
                    "{points} samples: at most {MAX_SHAPE_POINTS} (each is an IK solve and about 200 bytes; docs/development.md, Caps)"
                ),
            ));
        }
        let (free, seed): (Vec<JointId>, Vec<f64>) = match &model.defaults.shape_ik {
            Some(ik) => (ik.free_joints.clone(), ik.seed.clone()),
            None => {
                let seed = model.joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)).collect();
                (JointId::all(model.dof()).collect(), seed)
            }
        };
        let task = IkTask::new(model, tool, &free)?;
        let targets = shape.targets(points, &board);
        let ik = solve_path(model, &task, &targets, &seed)?;
        let rows: Vec<Vec<f64>> = targets.iter().map(|p| vec![p.x, p.y, p.z]).collect();
        let run = ShapeRun {
            board,
            target: Interpolated::new(&rows, period, Wrap::Closed),
            reference: targets,
            ik_max_residual_m: ik.max_residual_m,
        };
        let trajectory = Trajectory::Interpolated(Interpolated::new(&ik.q, period, Wrap::Closed));
        Ok((trajectory, run))
    }
}
