//! Synthetic runs for the visual outputs: the recorder calls a simulation makes (`begin`,
//! `record` at each recorder's period, `finish`), for a moving Faze4, without the simulation
//! loop. A wave (q = a sine per joint) or a circle on the board (q from `faze4::ik`, the
//! "measured" q lagging the command by 10 ms).
#![allow(dead_code)]

use faze4::algo::{Data, forward_kinematics, gravity};
use faze4::control::{FAZE4_EFFORT, Gains, auto_tune};
use faze4::geometry::GeometryModel;
use faze4::ik::{IkTask, solve_path};
use faze4::model::{Model, PackagePaths, Robot, urdf};
use faze4::output::{Recorder, RunInfo, Sample};
use faze4::sim::{PathDeviation, Summary};
use faze4::spatial::Vec3;
use faze4::traj::shape::{BOARD, Q_SEED, SHAPE_PERIOD, Shape, distance_to_closed_path};
use faze4::traj::{Interpolated, Wrap};

#[path = "../common/mod.rs"]
mod common;
pub use common::{repo, shared_description as description};

/// `urdf/faze4_real.urdf` with the official meshes resolved.
pub fn real_model() -> Robot {
    urdf::read_file(
        &repo().join("urdf/faze4_real.urdf"),
        &PackagePaths::new(vec![description()]),
    )
    .unwrap()
}

/// `urdf/faze4_arm.urdf` (boxes).
pub fn box_model() -> Robot {
    urdf::read_file(&repo().join("urdf/faze4_arm.urdf"), &PackagePaths::default()).unwrap()
}

pub enum Motion {
    /// q_i(t) = amp·sin(ω t + i·π/3).
    Wave { amp: f64, omega: f64 },
    /// The tool draws SPEC's circle (5 s per loop); joint samples by IK.
    Circle { samples: Interpolated },
}

pub struct SyntheticRun {
    pub model: Model,
    pub geometry: GeometryModel,
    pub motion: Motion,
    pub dt: f64,
    pub duration: f64,
    gains: Gains,
    reference: Option<Vec<Vec3>>,
    tool: usize,
}

impl SyntheticRun {
    pub fn wave(robot: Robot, duration: f64, amp_deg: f64, omega: f64) -> SyntheticRun {
        Self::new(
            robot,
            Motion::Wave {
                amp: amp_deg.to_radians(),
                omega,
            },
            duration,
            None,
        )
    }

    pub fn circle(robot: Robot, duration: f64) -> SyntheticRun {
        let reference = Shape::Circle.targets(240, &BOARD);
        let samples = Interpolated::new(&ik_path(&robot.model, &reference), SHAPE_PERIOD, Wrap::Closed);
        Self::new(robot, Motion::Circle { samples }, duration, Some(reference))
    }

    fn new(robot: Robot, motion: Motion, duration: f64, reference: Option<Vec<Vec3>>) -> SyntheticRun {
        let Robot { model, geometry } = robot;
        let dt = 2e-4;
        let mut data = Data::new(&model);
        let m = faze4::algo::crba(&model, &mut data, &[0.0; 6]).clone();
        let inertia: Vec<f64> = (0..6).map(|i| m[(i, i)]).collect();
        let gains = auto_tune(&inertia, &FAZE4_EFFORT, dt);
        let tool = model.default_tool_frame();
        SyntheticRun {
            model,
            geometry,
            motion,
            dt,
            duration,
            gains,
            reference,
            tool,
        }
    }

    /// The commanded q at t.
    pub fn q_cmd(&self, t: f64) -> Vec<f64> {
        match &self.motion {
            Motion::Wave { amp, omega } => (0..6)
                .map(|i| amp * (omega * t + i as f64 * std::f64::consts::PI / 3.0).sin())
                .collect(),
            Motion::Circle { samples } => {
                let (mut q, mut v) = (vec![0.0; 6], vec![0.0; 6]);
                samples.eval(t, &mut q, &mut v);
                q
            }
        }
    }

    pub fn steps(&self) -> usize {
        (self.duration / self.dt).round() as usize
    }

    /// Drives `recorders` through the run as the simulation would.
    pub fn drive(&self, recorders: &mut [&mut dyn Recorder]) {
        let steps = self.steps();
        let start = self.q_cmd(0.0);
        let info = RunInfo {
            command: if self.reference.is_some() { "shape" } else { "wave" },
            model: &self.model,
            geometry: &self.geometry,
            tool_frame: self.tool,
            dt: self.dt,
            steps,
            gains: &self.gains,
            feedforward: true,
            start_q: &start,
            board: self.reference.as_ref().map(|_| &BOARD),
            reference_path: self.reference.as_deref(),
        };
        for r in recorders.iter_mut() {
            r.begin(&info).unwrap();
        }
        let every: Vec<usize> = recorders.iter().map(|r| r.every(self.dt)).collect();
        let mut data = Data::new(&self.model);
        let mut summary = Summary {
            dof: 6,
            dt: self.dt,
            steps,
            max_tracking_error_rad: vec![0.0; 6],
            saturation_pct: vec![0.0; 6],
            effort: self.gains.effort.clone(),
            kp: self.gains.kp.clone(),
            kd: self.gains.kd.clone(),
            effective_inertia: self.gains.effective_inertia.clone(),
            ..Summary::default()
        };
        let mut deviation: Vec<f64> = Vec::new();
        for step in 0..=steps {
            let wanted: Vec<bool> = every.iter().map(|&e| step % e == 0 || step == steps).collect();
            if !wanted.iter().any(|&w| w) {
                continue;
            }
            let t = step as f64 * self.dt;
            let q_cmd = self.q_cmd(t);
            let q = self.q_cmd(t - 0.01);
            let v_cmd: Vec<f64> = self
                .q_cmd(t + 1e-4)
                .iter()
                .zip(self.q_cmd(t - 1e-4))
                .map(|(a, b)| (a - b) / 2e-4)
                .collect();
            let g = gravity(&self.model, &mut data, &q).as_slice().to_vec();
            let tau: Vec<f64> = (0..6)
                .map(|i| {
                    (self.gains.kp[i] * (q_cmd[i] - q[i]) + g[i]).clamp(-self.gains.effort[i], self.gains.effort[i])
                })
                .collect();
            forward_kinematics(&self.model, &mut data, &q);
            let tool = data.frame_pose[self.tool].pos;
            let target = self
                .reference
                .as_ref()
                .map(|_| Shape::Circle.point((t / SHAPE_PERIOD).rem_euclid(1.0), &BOARD));
            for i in 0..6 {
                let e = (q_cmd[i] - q[i]).abs();
                summary.max_tracking_error_rad[i] = summary.max_tracking_error_rad[i].max(e);
            }
            if let Some(path) = &self.reference {
                deviation.push(distance_to_closed_path(&tool, path) * 1e3);
            }
            let sample = Sample {
                step,
                t,
                q: &q,
                v: &v_cmd,
                q_cmd: &q_cmd,
                v_cmd: &v_cmd,
                tau: &tau,
                g: &g,
                tool,
                target,
            };
            for (r, w) in recorders.iter_mut().zip(&wanted) {
                if *w {
                    r.record(&sample).unwrap();
                }
            }
        }
        if !deviation.is_empty() {
            summary.path_deviation_mm = Some(PathDeviation {
                max: deviation.iter().copied().fold(0.0, f64::max),
                mean: deviation.iter().sum::<f64>() / deviation.len() as f64,
            });
        }
        for r in recorders.iter_mut() {
            r.finish(&summary).unwrap();
        }
    }
}

/// Joint samples that put the tool on each point of `path` by `faze4::ik` (SPEC §4's task:
/// J1, J2, J3, J5 free, the first from Q_SEED).
pub fn ik_path(model: &Model, path: &[Vec3]) -> Vec<Vec<f64>> {
    let task = IkTask::shapes(model).unwrap();
    solve_path(model, &task, path, &Q_SEED).unwrap().q
}
