//! Real runs for the visual outputs: a scenario built by the library's builder and run by
//! `sim::run`, so the recorders see exactly what the binary gives them. A wave of every joint,
//! or the circle on the board.
#![allow(dead_code)]

use faze4::faze4::{Q_SEED, shape_ik_task};
use faze4::geometry::Robot;
use faze4::ik::solve_path;
use faze4::model::{Model, PackagePaths};
use faze4::sim::{Recorder, Scenario, StopFlag, Summary};
use faze4::spatial::Vec3;
use faze4::traj::shape::Shape;
use faze4::traj::{ShapeRun, Trajectory, Wave};

// `common` is declared by the crate that includes this file (tests/it/main.rs, benches/viz.rs)
pub use crate::common::{repo, shared_description as description};

/// `urdf/faze4_real.urdf` with the official meshes resolved.
pub fn real_model() -> Robot {
    Robot::from_urdf_file(
        &repo().join("urdf/faze4_real.urdf"),
        &PackagePaths::new(vec![description()]),
    )
    .unwrap()
}

/// `urdf/faze4_arm.urdf` (boxes).
pub fn box_model() -> Robot {
    Robot::from_urdf_file(&repo().join("urdf/faze4_arm.urdf"), &PackagePaths::default()).unwrap()
}

/// A closed-loop run, ready to drive recorders.
pub struct SyntheticRun {
    pub scenario: Scenario,
}

impl SyntheticRun {
    /// Every joint follows `amp_deg`·sin(ω t + i·π/3) for `duration` s.
    pub fn wave(Robot { model, geometry, .. }: Robot, duration: f64, amp_deg: f64, omega: f64) -> SyntheticRun {
        let wave = Trajectory::Wave(Wave {
            amplitude: vec![amp_deg.to_radians(); model.dof()],
            omega,
            center: vec![0.0; model.dof()],
        });
        let scenario = Scenario::builder(model, wave)
            .geometry(geometry)
            .collisions(None) // the outputs are tested here: self-clearance has its own tests
            .duration(duration)
            .build()
            .unwrap();
        SyntheticRun { scenario }
    }

    /// The tool draws the circle on the board (240 points, exact IK) for `duration` s.
    pub fn circle(Robot { model, geometry, .. }: Robot, duration: f64) -> SyntheticRun {
        let tool = model.default_tool_frame();
        let (trajectory, shape) = ShapeRun::plan(
            &model,
            tool,
            Shape::Circle,
            240,
            faze4::faze4::BOARD,
            faze4::faze4::SHAPE_PERIOD,
        )
        .unwrap();
        let scenario = Scenario::builder(model, trajectory)
            .geometry(geometry)
            .collisions(None) // the outputs are tested here: self-clearance has its own tests
            .command("shape circle (240 points)")
            .duration(duration)
            .shape(shape)
            .build()
            .unwrap();
        SyntheticRun { scenario }
    }

    /// Runs the closed loop, reporting to `recorders`.
    pub fn drive(&self, recorders: &mut [&mut dyn Recorder]) -> Summary {
        faze4::sim::run(&self.scenario, recorders, &StopFlag::new()).unwrap()
    }
}

/// Joint samples that put the tool on each point of `path` by `faze4::ik` (the shapes' task:
/// J1, J2, J3, J5 free, the first from Q_SEED).
pub fn ik_path(model: &Model, path: &[Vec3]) -> Vec<Vec<f64>> {
    let task = shape_ik_task(model).unwrap();
    solve_path(model, &task, path, &Q_SEED).unwrap().q
}
