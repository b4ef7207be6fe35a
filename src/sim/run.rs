//! The closed loop: the discrete step driven by the PD controller (docs/model.md).

use std::time::{Duration, Instant};

use super::{ContactStep, ContactSummary};
use crate::algo::{Data, compute_all_terms, forward_kinematics, frame_position, integrate_discrete};
use crate::error::{Error, Result};
use crate::geometry::{Clearance, CollisionSet};
use crate::model::{FrameId, JointId, JointKind};
use crate::spatial::Pose;
use crate::spatial::Vec3;
use crate::traj::shape::distance_to_closed_path;

use super::{
    Diverged, Intersection, PathDeviation, Recorder, RunInfo, Sample, Scenario, StopFlag, Summary, ToolRange, Verdict,
    steps_per_record,
};

/// Steps between two looks at the stop flag (a fraction of a millisecond of wall time).
const STOP_POLL_STEPS: usize = 1024;

/// A joint moving faster than this (rad/s or m/s) has run away: no arm does, and a discrete
/// loop that has gone unstable passes it within a few steps.
pub const RUNAWAY_SPEED: f64 = 1e3;

/// Runs `scenario` to the end (or until it diverges), reporting to `recorders`.
///
/// Each step k = 0..steps−1, at t_k = k·Δt: g(q_k), C v + g and M(q_k) from one kinematics
/// pass; the command at t_k; the PD torque, held over the step; the discrete step. The summary's
/// tracking error, saturation, speed and time over the speed limit are over those steps; tool
/// range and path deviation over the
/// samples every `record_every` steps and after the last, where the self-clearance of the
/// scenario's collision set is measured too (every frame's pose by forward kinematics, then
/// [`Clearance::add`], completed by [`Clearance::finish`]): the summary's `clearance`, and a verdict that *collides* when
/// any pair intersects at a sample. A diverged run stops at once; its
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
    let mut steps = StepMetrics::new(n);
    let mut samples = SampleMetrics::new();
    let mut clearance = (sc.collision_set.as_deref()).map(|set| ClearanceMetrics::new(set, sc.clearance_tolerance));
    let collision_pairs: Vec<[FrameId; 2]> = (sc.collision_set.iter())
        .flat_map(|set| set.pairs())
        .map(|(a, b)| [sc.geometry.collisions[a].frame, sc.geometry.collisions[b].frame])
        .collect();
    let mut contact =
        (sc.self_contact.zip(sc.collision_set.clone())).map(|(settings, set)| ContactStep::new(model, set, settings));

    let info = RunInfo {
        command: &sc.command,
        model,
        geometry: &sc.geometry,
        tool_frame: sc.tool_frame,
        dt,
        steps: sc.steps,
        gains: &sc.controller.gains,
        feedforward: sc.controller.feedforward,
        start_q: &start_q,
        board: sc.shape.as_ref().map(|s| &s.board),
        reference_path: sc.shape.as_ref().map(|s| s.reference.as_slice()),
        collision_pairs: &collision_pairs,
    };
    for r in recorders.iter_mut() {
        r.begin(&info)?;
    }
    let mut schedule = Schedule::new(recorders, dt, sc.record_every);
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
            sc.controller
                .torque(&q, &v, &q_cmd, &v_cmd, data.g.as_slice(), &mut tau_raw, &mut tau);
        }
        if !last {
            steps.add(sc, &q, &v, &q_cmd, &tau_raw);
        }

        let (record_metrics, recorders_due) = schedule.due(k, last);
        if (record_metrics || recorders_due) && diverged.is_none() {
            let tool = frame_position(model, &q, sc.tool_frame);
            let target = sc.shape.as_ref().map(|s| {
                s.target.eval(t, &mut target, &mut target_rate);
                Vec3::from(target)
            });
            if record_metrics {
                samples.add(&tool, sc.shape.as_ref().map(|s| s.reference.as_slice()));
                if let Some(c) = clearance.as_mut() {
                    forward_kinematics(model, &mut data, &q);
                    c.add(&data.frame_pose, t);
                }
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
                intersecting: clearance.as_ref().map_or(&[], |c| c.clearance.intersecting()),
            };
            schedule.record(recorders, k, last, &sample)?;
        }
        if last {
            break;
        }

        let stepped = match &mut contact {
            Some(contact) => contact.step(model, &mut data, &mut q, &mut v, &tau, dt, t),
            None => integrate_discrete(model, &mut data, &mut q, &mut v, &tau, dt),
        };
        done = k + 1;
        if let Some(joint) = runaway_joint(&q, &v, stepped)? {
            diverged = Some(Diverged {
                t: done as f64 * dt,
                joint,
                stiffness_b: sc.controller.gains.stiffness_b(dt),
            });
        }
    }
    if let Some(c) = clearance.as_mut() {
        c.finish();
    }
    let wall_time_s = wall.elapsed().as_secs_f64();

    let mut summary = Summary {
        dof: n,
        dt,
        steps: done,
        gains: sc.controller.gains.clone(),
        max_tracking_error_rad: steps.max_error,
        saturation_pct: (steps.saturated.iter())
            .map(|&s| 100.0 * s as f64 / done.max(1) as f64)
            .collect(),
        max_speed: steps.max_speed,
        velocity_limit: sc.speed_limit.clone(),
        velocity_limit_pct: (steps.over_speed.iter().zip(&sc.speed_limit))
            .map(|(&s, l)| l.is_finite().then(|| 100.0 * s as f64 / done.max(1) as f64))
            .collect(),
        tool_range_m: samples.range,
        diverged,
        wall_time_s,
        path_deviation_mm: sc.shape.as_ref().map(|_| PathDeviation {
            max: samples.deviation_max * 1e3,
            mean: samples.deviation_sum / samples.samples.max(1) as f64 * 1e3,
        }),
        ik_max_residual_m: sc.shape.as_ref().map(|s| s.ik_max_residual_m),
        interrupted_at_s,
        self_contact: contact
            .as_ref()
            .zip(sc.self_contact)
            .map(|(c, settings)| ContactSummary {
                friction: settings.friction,
                geometry: c.geometry().geometry(),
                steps_in_contact_pct: 100.0 * c.steps_in_contact as f64 / done.max(1) as f64,
                max_depth_m: c.max_depth,
                geometry_queries: c.geometry_queries(),
                newton_iterations_per_step: c.newton_iterations as f64 / c.steps_in_contact.max(1) as f64,
            }),
        ..Summary::default()
    };
    let prismatic: Vec<bool> = (model.joints.iter()).map(|j| j.kind == JointKind::Prismatic).collect();
    let intersections = clearance.as_ref().map_or(Vec::new(), ClearanceMetrics::intersections);
    summary.clearance_wall_time_s = clearance.as_ref().map(|c| c.elapsed.as_secs_f64());
    summary.clearance = clearance.map(|c| c.clearance.into_report());
    summary.verdict = Verdict::judge(&summary, &sc.thresholds, &prismatic).with_intersections(intersections);
    for r in recorders.iter_mut() {
        r.finish(&summary)?;
    }
    Ok(summary)
}

/// After a step: the joint that has gone bad, if any — a non-finite state, the fastest joint
/// beyond [`RUNAWAY_SPEED`], the joint whose pivot failed when the step could not be solved, or
/// the fastest joint when the step's contact problem did not converge.
fn runaway_joint(q: &[f64], v: &[f64], stepped: Result<()>) -> Result<Option<JointId>> {
    let n = q.len();
    let bad = (0..n)
        .find(|&i| !q[i].is_finite() || !v[i].is_finite())
        .or_else(|| {
            (0..n)
                .filter(|&i| v[i].abs() > RUNAWAY_SPEED)
                .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
        })
        .map(JointId);
    match stepped {
        Ok(()) => Ok(bad),
        Err(Error::Diverged { joint, .. }) => Ok(bad.or(Some(joint))),
        // no joint is to blame for a contact solve that does not converge: the fastest is named
        Err(Error::ContactNotConverged { .. }) => {
            Ok(bad.or_else(|| (0..n).max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs())).map(JointId)))
        }
        Err(e) => Err(e),
    }
}

/// When each recorder and the metric samples are due. Each recorder's period in steps, and the
/// next step it is due: counters, not `k % every` (an integer division per recorder per step is
/// a measurable share of a 1 µs step).
struct Schedule {
    every: Vec<usize>,
    due: Vec<usize>,
    metrics_every: usize,
    metrics_due: usize,
}

impl Schedule {
    fn new(recorders: &[&mut dyn Recorder], dt: f64, metrics_every: usize) -> Self {
        Schedule {
            every: recorders.iter().map(|r| steps_per_record(r.period(), dt)).collect(),
            due: vec![0; recorders.len()],
            metrics_every,
            metrics_due: 0,
        }
    }

    /// Whether step k takes a metric sample, and whether any recorder records it (the last step
    /// always does both).
    #[inline]
    fn due(&mut self, k: usize, last: bool) -> (bool, bool) {
        let metrics = k == self.metrics_due || last;
        if k == self.metrics_due {
            self.metrics_due += self.metrics_every;
        }
        (metrics, last || self.due.contains(&k))
    }

    /// Hands step k's sample to the recorders that are due, and moves their next due step on.
    fn record(&mut self, recorders: &mut [&mut dyn Recorder], k: usize, last: bool, sample: &Sample) -> Result<()> {
        for ((r, next), &e) in recorders.iter_mut().zip(self.due.iter_mut()).zip(&self.every) {
            if k == *next || last {
                r.record(sample)?;
            }
            if k == *next {
                *next += e;
            }
        }
        Ok(())
    }
}

/// Tracking error, saturation and speed over the steps.
struct StepMetrics {
    /// max over steps of |q_cmd − q| per joint (rad or m).
    max_error: Vec<f64>,
    /// Steps with |τ_raw| ≥ E per joint.
    saturated: Vec<u64>,
    /// max over steps of |v| per joint (rad/s or m/s).
    max_speed: Vec<f64>,
    /// Steps with |v| above the joint's speed limit.
    over_speed: Vec<u64>,
}

impl StepMetrics {
    fn new(n: usize) -> Self {
        StepMetrics {
            max_error: vec![0.0; n],
            saturated: vec![0; n],
            max_speed: vec![0.0; n],
            over_speed: vec![0; n],
        }
    }

    #[inline]
    fn add(&mut self, sc: &Scenario, q: &[f64], v: &[f64], q_cmd: &[f64], tau_raw: &[f64]) {
        for i in 0..q.len() {
            self.max_error[i] = self.max_error[i].max((q_cmd[i] - q[i]).abs());
            self.saturated[i] += u64::from(sc.controller.saturated(i, tau_raw[i]));
            self.max_speed[i] = self.max_speed[i].max(v[i].abs());
            self.over_speed[i] += u64::from(v[i].abs() > sc.speed_limit[i]);
        }
    }
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

/// Self-clearance over the trail samples: the report, and when each pair first intersected.
struct ClearanceMetrics<'a> {
    clearance: Clearance<'a>,
    /// Per checked pair, the time of the first sample at which it intersects (s).
    first_intersection: Vec<Option<f64>>,
    /// Wall-clock time spent in [`ClearanceMetrics::add`] and [`ClearanceMetrics::finish`].
    elapsed: Duration,
}

impl<'a> ClearanceMetrics<'a> {
    fn new(set: &'a CollisionSet, tolerance: f64) -> Self {
        let clearance = Clearance::with_tolerance(set, tolerance);
        let first_intersection = vec![None; clearance.intersecting().len()];
        ClearanceMetrics {
            clearance,
            first_intersection,
            elapsed: Duration::ZERO,
        }
    }

    /// Folds the sample at time `t` (s), whose frames are at `frame_pose`, in.
    fn add(&mut self, frame_pose: &[Pose], t: f64) {
        let started = Instant::now();
        self.clearance.add(frame_pose, t);
        for (first, &now) in self.first_intersection.iter_mut().zip(self.clearance.intersecting()) {
            if now && first.is_none() {
                *first = Some(t);
            }
        }
        self.elapsed += started.elapsed();
    }

    /// Completes the report after the last sample ([`Clearance::finish`]).
    fn finish(&mut self) {
        let started = Instant::now();
        self.clearance.finish();
        self.elapsed += started.elapsed();
    }

    /// The pairs of links that intersected, each once (a link may carry several shapes), in
    /// the order they first did (pair order among equals).
    fn intersections(&self) -> Vec<Intersection> {
        let mut pairs: Vec<Intersection> = (self.clearance.report().pairs.iter().zip(&self.first_intersection))
            .filter_map(|(p, first)| {
                first.map(|from_t| Intersection {
                    links: p.links.clone(),
                    from_t,
                })
            })
            .collect();
        pairs.sort_by(|a, b| a.from_t.total_cmp(&b.from_t));
        let mut seen: Vec<[String; 2]> = Vec::new();
        pairs.retain(|p| {
            let new = !seen.contains(&p.links);
            if new {
                seen.push(p.links.clone());
            }
            new
        });
        pairs
    }
}
