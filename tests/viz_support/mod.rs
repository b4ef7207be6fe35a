//! Synthetic runs for the visual outputs: the recorder calls a simulation makes (`begin`,
//! `record` at each recorder's period, `finish`), for a moving Faze4, without the simulation
//! loop. A wave (q = a sine per joint) or a circle on the board (q from a small IK, the
//! "measured" q lagging the command by 10 ms).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use faze4::algo::{Data, forward_kinematics, frame_jacobian, gravity};
use faze4::control::{FAZE4_EFFORT, Gains, auto_tune};
use faze4::model::{Model, PackagePaths};
use faze4::output::{Recorder, RunInfo, Sample};
use faze4::sim::{PathDeviation, Summary};
use faze4::spatial::Vec3;
use faze4::traj::shape::{BOARD, Q_SEED, SHAPE_PERIOD, Shape, distance_to_closed_path};

pub fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The official Faze4 description (meshes), never copied into the repository:
/// `$FAZE4_DESCRIPTION`, else `shared/faze4_description` beside the repository or above it.
pub fn description() -> PathBuf {
    if let Some(dir) = std::env::var_os("FAZE4_DESCRIPTION") {
        return PathBuf::from(dir);
    }
    repo()
        .ancestors()
        .map(|a| a.join("shared/faze4_description"))
        .find(|p| p.join("meshes").is_dir())
        .unwrap_or_else(|| {
            panic!(
                "test data missing: no shared/faze4_description above {}; set FAZE4_DESCRIPTION",
                repo().display()
            )
        })
}

/// `urdf/faze4_real.urdf` with the official meshes resolved.
pub fn real_model() -> Model {
    Model::from_urdf_file(
        &repo().join("urdf/faze4_real.urdf"),
        &PackagePaths::new(vec![description()]),
    )
    .unwrap()
}

/// `urdf/faze4_arm.urdf` (boxes).
pub fn box_model() -> Model {
    Model::from_urdf_file(&repo().join("urdf/faze4_arm.urdf"), &PackagePaths::default()).unwrap()
}

pub enum Motion {
    /// q_i(t) = amp·sin(ω t + i·π/3).
    Wave { amp: f64, omega: f64 },
    /// The tool draws SPEC's circle (5 s per loop); joint samples by IK.
    Circle { samples: Vec<Vec<f64>> },
}

pub struct SyntheticRun {
    pub model: Model,
    pub motion: Motion,
    pub dt: f64,
    pub duration: f64,
    gains: Gains,
    reference: Option<Vec<Vec3>>,
    tool: usize,
}

impl SyntheticRun {
    pub fn wave(model: Model, duration: f64, amp_deg: f64, omega: f64) -> SyntheticRun {
        Self::new(
            model,
            Motion::Wave {
                amp: amp_deg.to_radians(),
                omega,
            },
            duration,
            None,
        )
    }

    pub fn circle(model: Model, duration: f64) -> SyntheticRun {
        let reference = Shape::Circle.targets(240, &BOARD);
        let samples = ik_path(&model, &reference);
        Self::new(model, Motion::Circle { samples }, duration, Some(reference))
    }

    fn new(model: Model, motion: Motion, duration: f64, reference: Option<Vec<Vec3>>) -> SyntheticRun {
        let dt = 2e-4;
        let mut data = Data::new(&model);
        let m = faze4::algo::crba(&model, &mut data, &[0.0; 6]).clone();
        let inertia: Vec<f64> = (0..6).map(|i| m[(i, i)]).collect();
        let gains = auto_tune(&inertia, &FAZE4_EFFORT, dt);
        let tool = model.default_tool_frame();
        SyntheticRun {
            model,
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
                let n = samples.len();
                let x = (t / SHAPE_PERIOD).rem_euclid(1.0) * n as f64;
                let k = (x.floor() as usize).min(n - 1);
                let f = x - k as f64;
                let (a, b) = (&samples[k], &samples[(k + 1) % n]);
                a.iter().zip(b).map(|(a, b)| a + f * (b - a)).collect()
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

/// Joint samples that put the tool on each point of `path` (J1, J2, J3, J5; J4 = J6 = 0),
/// each solved from the previous one, the first from Q_SEED (damped least squares).
pub fn ik_path(model: &Model, path: &[Vec3]) -> Vec<Vec<f64>> {
    let tool = model.default_tool_frame();
    let mut data = Data::new(model);
    let mut q = Q_SEED.to_vec();
    let free = [0usize, 1, 2, 4];
    path.iter()
        .map(|target| {
            for _ in 0..100 {
                forward_kinematics(model, &mut data, &q);
                let e = target - data.frame_pose[tool].pos;
                if e.norm() < 1e-9 {
                    break;
                }
                let jac = frame_jacobian(model, &mut data, tool);
                let j = nalgebra::Matrix3x4::from_fn(|r, c| jac[(r + 3, free[c])]);
                let jjt = j * j.transpose() + nalgebra::Matrix3::identity() * 1e-8;
                let dq = j.transpose() * jjt.try_inverse().unwrap() * e;
                for (c, &i) in free.iter().enumerate() {
                    q[i] += dq[c];
                }
            }
            forward_kinematics(model, &mut data, &q);
            let residual = (target - data.frame_pose[tool].pos).norm();
            assert!(residual < 1e-6, "IK residual {residual} at {target:?}");
            q.clone()
        })
        .collect()
}
