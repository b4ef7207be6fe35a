//! The closed loop: SPEC §2's step driven by SPEC §3's controller.

use std::time::Instant;

use crate::algo::{Data, compute_all_terms, frame_position, integrate_discrete};
use crate::error::Result;
use crate::output::{Recorder, RunInfo, Sample};
use crate::spatial::Vec3;
use crate::traj::shape::distance_to_closed_path;

use super::{Diverged, PathDeviation, Scenario, StopFlag, Summary, ToolRange};

/// Steps between two looks at the stop flag (a fraction of a millisecond of wall time).
const STOP_POLL_STEPS: usize = 1024;

/// A joint moving faster than this (rad/s or m/s) has run away: no arm does, and a discrete
/// loop that has gone unstable passes it within a few steps.
pub const RUNAWAY_SPEED: f64 = 1e3;

/// Runs `scenario` to the end (or until it diverges), reporting to `recorders`.
///
/// Each step k = 0..steps−1, at t_k = k·Δt: g(q_k), C v + g and M(q_k) from one kinematics
/// pass; the command at t_k; the PD torque, held over the step; the discrete step. The summary's
/// tracking error and saturation are over those steps; tool range and path deviation over the
/// samples every `record_every` steps and after the last. A diverged run stops at once; its
/// summary says where (`diverged`), and covers the steps that completed. A raised `stop` flag
/// ends the run at the next poll the same way, as if that step were the last
/// (`interrupted_at_s` in the summary).
pub fn run(sc: &Scenario, recorders: &mut [&mut dyn Recorder], stop: &StopFlag) -> Result<Summary> {
    let model = &sc.model;
    let n = model.dof();
    let dt = sc.dt;
    let mut data = Data::new(model);
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    sc.trajectory.eval(0.0, &mut q, &mut v);
    let start_q = q.clone();
    let (mut q_cmd, mut v_cmd) = (vec![0.0; n], vec![0.0; n]);
    let (mut tau_raw, mut tau) = (vec![0.0; n], vec![0.0; n]);
    let mut saturated = vec![0u64; n];
    let mut max_error = vec![0.0f64; n];
    let mut metrics = SampleMetrics::new();

    let info = RunInfo {
        command: &sc.command,
        model,
        geometry: &sc.geometry,
        tool_frame: sc.tool_frame,
        dt,
        steps: sc.steps,
        gains: &sc.gains,
        feedforward: sc.pd.feedforward,
        start_q: &start_q,
        board: sc.shape.as_ref().map(|s| &s.board),
        reference_path: sc.shape.as_ref().map(|s| s.reference.as_slice()),
    };
    for r in recorders.iter_mut() {
        r.begin(&info)?;
    }
    // each recorder's period in steps, and the next step it is due (counters, not k % every:
    // an integer division per recorder per step is a measurable share of a 1 µs step)
    let every: Vec<usize> = recorders.iter().map(|r| r.every(dt).max(1)).collect();
    let mut due: Vec<usize> = vec![0; recorders.len()];
    let mut metrics_due = 0;
    let mut target = [0.0; 3];
    let mut target_rate = [0.0; 3];

    let wall = Instant::now();
    let mut done = 0;
    let mut diverged = None;
    let mut interrupted_at_s = None;
    for k in 0..=sc.steps {
        let t = k as f64 * dt;
        if k % STOP_POLL_STEPS == 0 && k > 0 && k < sc.steps && stop.is_raised() {
            interrupted_at_s = Some(t);
        }
        let last = k == sc.steps || diverged.is_some() || interrupted_at_s.is_some();
        if diverged.is_none() {
            // g, bias and M at (q_k, v_k); the command at t_k; the held torque
            compute_all_terms(model, &mut data, &q, &v);
            sc.trajectory.eval(t, &mut q_cmd, &mut v_cmd);
            sc.pd
                .torque(&q, &v, &q_cmd, &v_cmd, data.g.as_slice(), &mut tau_raw, &mut tau);
        }
        if !last {
            for i in 0..n {
                max_error[i] = max_error[i].max((q_cmd[i] - q[i]).abs());
                saturated[i] += u64::from(sc.pd.saturated(i, tau_raw[i]));
            }
        }

        let record_metrics = k == metrics_due || last;
        let recorders_due = due.contains(&k) || last;
        if k == metrics_due {
            metrics_due += sc.record_every;
        }
        if (record_metrics || recorders_due) && diverged.is_none() {
            let tool = frame_position(model, &q, sc.tool_frame);
            let target = sc.shape.as_ref().map(|s| {
                s.target.eval(t, &mut target, &mut target_rate);
                Vec3::from(target)
            });
            if record_metrics {
                metrics.add(&tool, sc.shape.as_ref().map(|s| s.reference.as_slice()));
            }
            let sample = Sample {
                step: k,
                t,
                q: &q,
                v: &v,
                q_cmd: &q_cmd,
                v_cmd: &v_cmd,
                tau: &tau,
                g: data.g.as_slice(),
                tool,
                target,
            };
            for ((r, next), &e) in recorders.iter_mut().zip(due.iter_mut()).zip(&every) {
                if k == *next || last {
                    r.record(&sample)?;
                }
                if k == *next {
                    *next += e;
                }
            }
        }
        if last {
            break;
        }

        // the step; then: still finite, still sane?
        let stepped = integrate_discrete(model, &mut data, &mut q, &mut v, &tau, dt);
        done = k + 1;
        let bad_joint = (0..n).find(|&i| !q[i].is_finite() || !v[i].is_finite()).or_else(|| {
            (0..n)
                .filter(|&i| v[i].abs() > RUNAWAY_SPEED)
                .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
        });
        if let Some(joint) = bad_joint.or(stepped.is_err().then_some(0)) {
            diverged = Some(Diverged {
                t: done as f64 * dt,
                joint: joint + 1,
                stiffness_b: sc.gains.stiffness_b(dt),
            });
        }
    }
    let wall_time_s = wall.elapsed().as_secs_f64();

    let steps_done = done.max(1) as f64;
    let summary = Summary {
        dof: n,
        dt,
        steps: sc.steps,
        effective_inertia: sc.gains.effective_inertia.clone(),
        kp: sc.gains.kp.clone(),
        kd: sc.gains.kd.clone(),
        effort: sc.gains.effort.clone(),
        max_tracking_error_rad: max_error,
        saturation_pct: saturated.iter().map(|&s| 100.0 * s as f64 / steps_done).collect(),
        tool_range_m: metrics.range,
        diverged,
        wall_time_s,
        path_deviation_mm: sc.shape.as_ref().map(|_| PathDeviation {
            max: metrics.deviation_max * 1e3,
            mean: metrics.deviation_sum / metrics.samples.max(1) as f64 * 1e3,
        }),
        ik_max_residual_m: sc.shape.as_ref().map(|s| s.ik_max_residual_m),
        interrupted_at_s,
    };
    for r in recorders.iter_mut() {
        r.finish(&summary)?;
    }
    Ok(summary)
}

/// Tool range and path deviation over the metric samples.
struct SampleMetrics {
    range: ToolRange,
    deviation_max: f64,
    deviation_sum: f64,
    samples: usize,
}

impl SampleMetrics {
    fn new() -> Self {
        let empty = [f64::INFINITY, f64::NEG_INFINITY];
        Self {
            range: ToolRange {
                x: empty,
                y: empty,
                z: empty,
            },
            deviation_max: 0.0,
            deviation_sum: 0.0,
            samples: 0,
        }
    }

    fn add(&mut self, tool: &Vec3, reference: Option<&[Vec3]>) {
        for (range, x) in [&mut self.range.x, &mut self.range.y, &mut self.range.z]
            .into_iter()
            .zip(tool.iter())
        {
            range[0] = range[0].min(*x);
            range[1] = range[1].max(*x);
        }
        if let Some(path) = reference {
            let d = distance_to_closed_path(tool, path);
            self.deviation_max = self.deviation_max.max(d);
            self.deviation_sum += d;
        }
        self.samples += 1;
    }
}
