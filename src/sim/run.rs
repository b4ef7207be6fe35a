//! The closed loop: the discrete step driven by the PD controller (docs/model.md).

use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use super::drives::DriveRecord;
use super::step::{self, Step};
use super::{ContactStep, ContactSummary, SelfContact};
use crate::algo::{Data, State, forward_kinematics};
use crate::error::{Error, Result};
use crate::geometry::{Clearance, CollisionSet, PathClearance};
use crate::model::{FrameId, JointId, JointKind, Model};
use crate::spatial::Pose;
use crate::spatial::Vec3;
use crate::traj::Trajectory;
use crate::traj::shape::distance_to_closed_path;

use super::{
    Diverged, Intersection, MotorSummary, PathDeviation, Recorder, RunInfo, Sample, Scenario, Simulated, SizingSums,
    StopFlag, Summary, ToolRange, Verdict, steps_per_record,
};

/// Steps between two looks at the stop flag (a fraction of a millisecond of wall time).
const STOP_POLL_STEPS: usize = 1024;

/// A joint moving faster than this (rad/s or m/s) has run away: no arm does, and a discrete
/// loop that has gone unstable passes it within a few steps.
pub const RUNAWAY_SPEED: f64 = 1e3;

/// Runs `scenario` to the end (or until it diverges), reporting to `recorders`.
///
/// Each step k = 0..steps−1, at t_k = k·Δt, runs the stages of [`mod@super::step`] in the order
/// MuJoCo's `mj_step` does: *dynamics* (g(q_k), C v + g and M(q_k) from one kinematics pass),
/// *command* (q_cmd, v_cmd at t_k; under `--ff full` a_cmd too, and the command's inverse
/// dynamics), *controller* (the PD torque τ_raw), *actuation* (what the
/// actuators give of it, τ, held over the step), *record* (metrics and recorders), *integrate*
/// (the discrete step). The summary's tracking error, saturation, speed and time over the
/// speed limit are over those steps; tool range and path deviation over the samples every
/// `record_every` steps and after the last, where the self-clearance of the scenario's
/// collision set is measured too (every frame's pose by forward kinematics, then
/// [`Clearance::add`], completed by [`Clearance::finish`]): the summary's
/// `clearance`, and a verdict that *collides* when any pair intersects at a sample. A diverged
/// run stops at once; its summary says where (`diverged`), and covers the steps that
/// completed. A raised `stop` flag ends the run at the next poll the same way, as if that step
/// were the last (`interrupted_at_s` in the summary).
pub fn run(sc: &Scenario, recorders: &mut [&mut dyn Recorder], stop: &StopFlag) -> Result<Summary> {
    let mut p = Step::new(sc);
    let start_q = p.state.q.clone();
    let collision_pairs = collision_pairs(sc);
    let info = run_info(sc, &start_q, &collision_pairs);
    // the loop looks at the flag: a signal now stops the run, not the process
    stop.watch();
    for r in recorders.iter_mut() {
        r.begin(&info)?;
    }
    // the clearance's worker thread (when no recorder reads each sample's intersections)
    // borrows the scenario for the run's loop
    std::thread::scope(|scope| run_loop(sc, recorders, stop, &mut p, scope))
}

/// The link frames of each pair whose self-clearance `sc` checks (see [`RunInfo::collision_pairs`]).
pub(super) fn collision_pairs(sc: &Scenario) -> Vec<[FrameId; 2]> {
    (sc.collision_set.iter())
        .flat_map(|set| set.pairs())
        .map(|(a, b)| [sc.geometry.collisions[a].frame, sc.geometry.collisions[b].frame])
        .collect()
}

/// What a run of `sc` tells its recorders before the first sample, from its start state q
/// and its checked pairs ([`collision_pairs`]).
pub(super) fn run_info<'a>(sc: &'a Scenario, start_q: &'a [f64], collision_pairs: &'a [[FrameId; 2]]) -> RunInfo<'a> {
    RunInfo {
        command: &sc.command,
        model: &sc.model,
        geometry: &sc.geometry,
        tool_frame: sc.tool_frame,
        dt: sc.dt,
        steps: sc.steps,
        gains: &sc.controller.gains,
        feedforward: sc.controller.feedforward,
        start_q,
        board: sc.shape.as_ref().map(|s| &s.board),
        reference_path: sc.shape.as_ref().map(|s| s.reference.as_slice()),
        collision_pairs,
        motors: sc.motors.as_deref(),
        playback: match &sc.trajectory {
            Trajectory::Spline(s) => s.playback(),
            _ => None,
        },
        drives: &sc.drives,
    }
}

/// [`run`]'s loop and summary, the self-clearance's worker thread (if any) spawned in `scope`.
fn run_loop<'a, 's>(
    sc: &'a Scenario,
    recorders: &mut [&mut dyn Recorder],
    stop: &StopFlag,
    p: &mut Step,
    scope: &'s std::thread::Scope<'s, 'a>,
) -> Result<Summary> {
    let dt = sc.dt;
    let mut rec = Records::new(sc, recorders, scope);

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
            step::dynamics(sc, p);
            step::command(sc, p, t);
            step::controller(sc, p);
            step::actuation(sc, p, t);
        }
        if !last {
            rec.steps.add(sc, &p.state, &p.q_cmd, &p.tau_raw);
            if let Some(m) = rec.motors.as_mut() {
                m.add(sc, p, t);
            }
        }
        if diverged.is_none() {
            rec.record(sc, recorders, p, k, t, last)?;
        }
        if last {
            break;
        }
        let stepped = step::integrate(sc, p, t);
        done = k + 1;
        if let Some(joint) = runaway_joint(&p.state.q, &p.state.v, stepped)? {
            diverged = Some(Diverged {
                t: done as f64 * dt,
                joint,
                stiffness_b: sc.controller.gains.stiffness_b(dt),
            });
        }
    }
    let ended = Ended {
        records: rec,
        steps: done,
        diverged,
        interrupted_at_s,
        wall,
        contact: p.contact.as_ref(),
    };
    let summary = Summary::of_run(sc, ended);
    for r in recorders.iter_mut() {
        r.finish(&summary)?;
    }
    Ok(summary)
}

/// How a run's loop ended: its metrics, the steps it completed, and why it stopped.
struct Ended<'a, 's, 'r> {
    records: Records<'a, 's>,
    /// Steps completed.
    steps: usize,
    diverged: Option<Diverged>,
    interrupted_at_s: Option<f64>,
    /// When the loop started.
    wall: Instant,
    contact: Option<&'r ContactStep>,
}

impl Summary {
    /// The summary of `sc`'s run that `ended` so: the metrics over its steps and samples, the
    /// self-clearance once its last samples are folded in, the verdict.
    fn of_run(sc: &Scenario, ended: Ended) -> Summary {
        let Ended {
            records,
            steps: done,
            diverged,
            interrupted_at_s,
            wall,
            contact,
        } = ended;
        let dynamics_wall_time_s = (wall.elapsed().saturating_sub(records.clearance_held)).as_secs_f64();
        let Records {
            steps,
            samples,
            clearance,
            motors,
            ..
        } = records;
        let clearance = clearance.map(ClearanceStage::finish);
        let wall_time_s = wall.elapsed().as_secs_f64();
        let (model, n, dt) = (&sc.model, sc.model.dof(), sc.dt);
        let mut summary = Summary {
            simulated: Simulated::of(sc),
            dof: n,
            dt,
            steps: done,
            gains: sc.controller.gains.clone(),
            feed_forward: sc.controller.feedforward,
            interpolation: match &sc.trajectory {
                Trajectory::Spline(s) => Some(s.interpolation()),
                _ => None,
            },
            playback: match &sc.trajectory {
                Trajectory::Spline(s) => s.playback().cloned(),
                _ => None,
            },
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
            dynamics_wall_time_s,
            path_deviation_mm: sc.shape.as_ref().map(|_| PathDeviation {
                max: samples.deviation_max * 1e3,
                mean: samples.deviation_sum / samples.samples.max(1) as f64 * 1e3,
            }),
            ik_max_residual_m: sc.shape.as_ref().map(|s| s.ik_max_residual_m),
            interrupted_at_s,
            self_contact: contact
                .zip(sc.self_contact)
                .map(|(c, settings)| contact_summary(c, settings, done)),
            motors: motors.map(|m| m.summary(sc, done)),
            ..Summary::default()
        };
        if sc.slip_margins {
            summary.add_slip_margins(sc);
        }
        let prismatic: Vec<bool> = (model.joints.iter()).map(|j| j.kind == JointKind::Prismatic).collect();
        let intersections = clearance.as_ref().map_or(Vec::new(), ClearanceMetrics::intersections);
        summary.clearance_wall_time_s = clearance.as_ref().map(|c| c.elapsed.as_secs_f64());
        summary.clearance = clearance.map(|c| c.clearance.into_report());
        summary.verdict = Verdict::judge(&summary, &sc.thresholds, &prismatic).with_intersections(intersections);
        summary
    }
}

impl Summary {
    /// Each open-loop stepper's slip margin (its `ringing.slips_below`): where its slip begins
    /// as its damping goes down, found by running `sc` again ([`super::margin::margins`]).
    fn add_slip_margins(&mut self, sc: &Scenario) {
        let margins = super::margin::margins(sc, self, |probe| run(probe, &mut [], &StopFlag::new()).ok());
        for (m, margin) in self.motors.iter_mut().flatten().zip(margins) {
            if let Some(ringing) = m.as_mut().and_then(|m| m.ringing.as_mut()) {
                ringing.slips_below = margin;
            }
        }
    }
}

/// The summary's `self_contact` of a run of `done` steps with `settings`, from its contact
/// step `c`.
fn contact_summary(c: &ContactStep, settings: SelfContact, done: usize) -> ContactSummary {
    ContactSummary {
        friction: settings.friction,
        geometry: c.geometry().geometry(),
        steps_in_contact_pct: 100.0 * c.steps_in_contact as f64 / done.max(1) as f64,
        max_depth_m: c.max_depth,
        geometry_queries: c.geometry_queries(),
        newton_iterations_per_step: c.newton_iterations as f64 / c.steps_in_contact.max(1) as f64,
    }
}

/// The record stage: the metrics over the steps and the samples, and when the recorders are
/// due.
struct Records<'a, 's> {
    steps: StepMetrics,
    /// `--motors`: the motors' figures over the steps.
    motors: Option<MotorMetrics>,
    samples: SampleMetrics,
    clearance: Option<ClearanceStage<'a, 's>>,
    /// Wall-clock time the run's thread spent on the self-clearance: measuring it inline, or
    /// waiting to hand a sample to its worker (timed at metric samples only, not every step).
    clearance_held: Duration,
    schedule: Schedule,
}

impl<'a, 's> Records<'a, 's> {
    fn new(sc: &'a Scenario, recorders: &[&mut dyn Recorder], scope: &'s std::thread::Scope<'s, 'a>) -> Self {
        let inline = recorders.iter().any(|r| r.reads_intersections());
        Records {
            steps: StepMetrics::new(sc.model.dof()),
            motors: sc.motors.as_ref().map(|_| MotorMetrics::new(sc)),
            samples: SampleMetrics::new(),
            clearance: (sc.collision_set.as_deref()).map(|set| {
                let metrics = ClearanceMetrics::new(set, sc.clearance_tolerance, sc.path_clearance.as_deref());
                match inline {
                    true => ClearanceStage::Inline(Box::new(metrics)),
                    false => ClearanceStage::worker(&sc.model, metrics, scope),
                }
            }),
            clearance_held: Duration::ZERO,
            schedule: Schedule::new(recorders, sc.dt, sc.record_every),
        }
    }

    /// Step k's sample at time `t` (s), when the metrics or a recorder are due (the last step
    /// always is): tool position, shape target, path deviation, self-clearance.
    fn record(
        &mut self,
        sc: &Scenario,
        recorders: &mut [&mut dyn Recorder],
        p: &mut Step,
        k: usize,
        t: f64,
        last: bool,
    ) -> Result<()> {
        let (record_metrics, recorders_due) = self.schedule.due(k, last);
        if !(record_metrics || recorders_due) {
            return Ok(());
        }
        if let (true, Some(clearance)) = (record_metrics, self.clearance.as_mut()) {
            let started = Instant::now();
            match clearance {
                ClearanceStage::Inline(c) => {
                    forward_kinematics(&sc.model, &mut p.data, &p.state.q);
                    c.add(&p.data.frame_pose, t);
                }
                ClearanceStage::Worker(feed) => feed.send(t, &p.state.q),
            }
            self.clearance_held += started.elapsed();
        }
        let intersecting = match &self.clearance {
            Some(ClearanceStage::Inline(c)) => c.clearance.intersecting(),
            _ => &[],
        };
        let sample = step::sample(sc, p, k, t, intersecting);
        if record_metrics {
            (self.samples).add(&sample.tool, sc.shape.as_ref().map(|s| s.reference.as_slice()));
        }
        self.schedule.record(recorders, k, last, &sample)
    }
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

/// The clearance of `sc`'s commanded path at the run's metric samples (the trail's: step 0,
/// every `record_every` steps and the last; the command q_cmd(t) there, placed by forward
/// kinematics), computed once for the runs of the same command to follow
/// ([`crate::geometry::PathClearance`], [`super::ScenarioBuilder::path_clearance`]): a sweep
/// whose rows differ by payload, gains or limits shares one. `None` without a collision set.
/// Returns once the poses are placed; the bounds are computed on threads of their own
/// ([`crate::geometry::PathBuilder::build`]).
pub fn commanded_path(sc: &Scenario) -> Option<Arc<PathClearance>> {
    let set = sc.collision_set.clone()?;
    let model = &sc.model;
    let mut data = Data::new(model);
    let (mut q, mut v) = (vec![0.0; model.dof()], vec![0.0; model.dof()]);
    let mut path = PathClearance::builder(set, sc.clearance_tolerance);
    for k in Schedule::metric_steps(sc.steps, sc.record_every) {
        let t = k as f64 * sc.dt;
        sc.trajectory.eval(t, &mut q, &mut v);
        forward_kinematics(model, &mut data, &q);
        if !path.add(&data.frame_pose, t) {
            break;
        }
    }
    Some(path.build())
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

    /// The steps of a run of `steps` steps that take a metric sample when every
    /// `metrics_every`-th does (as [`Schedule::due`] finds them): 0, `metrics_every`, … and
    /// the last.
    fn metric_steps(steps: usize, metrics_every: usize) -> impl Iterator<Item = usize> {
        let every = metrics_every.max(1);
        (0..=steps)
            .step_by(every)
            .chain((!steps.is_multiple_of(every)).then_some(steps))
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
    fn add(&mut self, sc: &Scenario, state: &State, q_cmd: &[f64], tau_raw: &[f64]) {
        let State { q, v, .. } = state;
        for i in 0..q.len() {
            self.max_error[i] = self.max_error[i].max((q_cmd[i] - q[i]).abs());
            // an open-loop drive's torque is its own (a stepper's, its curve's): no limit acts on it
            let open_loop = sc.drives[i].open_loop();
            self.saturated[i] += u64::from(!open_loop && sc.controller.saturated(i, tau_raw[i]));
            self.max_speed[i] = self.max_speed[i].max(v[i].abs());
            self.over_speed[i] += u64::from(v[i].abs() > sc.speed_limit[i]);
        }
    }
}

/// The motors' figures over the steps (`--motors`).
struct MotorMetrics {
    /// max |ω_m| (rad/s).
    max_speed: Vec<f64>,
    /// Σ τ_m² over the steps (N²·m²).
    sum_sq: Vec<f64>,
    /// What each joint's drive records (the PD's steps beyond the envelope and a stepper's
    /// step loss, an open-loop stepper's slips).
    drives: Vec<DriveRecord>,
    /// The sizing report's sums.
    sizing: Vec<SizingSums>,
}

impl MotorMetrics {
    fn new(sc: &Scenario) -> Self {
        let n = sc.model.dof();
        MotorMetrics {
            max_speed: vec![0.0; n],
            sum_sq: vec![0.0; n],
            drives: sc.drives.iter().map(|d| d.record()).collect(),
            sizing: vec![SizingSums::default(); n],
        }
    }

    /// Step `p`'s actuation at time `t` (s).
    #[inline]
    fn add(&mut self, sc: &Scenario, p: &Step, t: f64) {
        let Some(motors) = &sc.motors else { return };
        for (i, m) in motors.iter().enumerate() {
            let Some(m) = m else { continue };
            let ratio = sc.model.joints[i].gear_ratio;
            let k = ratio * m.efficiency;
            let omega = ratio * p.state.v[i];
            let speed = omega.abs();
            self.max_speed[i] = self.max_speed[i].max(speed);
            // an open-loop drive's own torque: its joint's τ_raw (τ adds the drive's friction)
            let tau_m = match sc.drives[i].open_loop() {
                true => p.tau_raw[i] / k,
                false => p.state.tau[i] / k,
            };
            self.sum_sq[i] += tau_m * tau_m;
            let inertia = p.data.m[(i, i)] / (ratio * ratio);
            self.sizing[i].add(m, tau_m, omega, inertia, sc.dt);
            self.drives[i].add(&sc.drives[i], m, sc, p, i, t);
        }
    }

    /// The summary's `motors` over `done` steps.
    fn summary(self, sc: &Scenario, done: usize) -> Vec<Option<MotorSummary>> {
        let steps = done.max(1) as f64;
        (sc.motors.iter().flatten().enumerate())
            .map(|(i, m)| {
                m.as_ref().map(|m| {
                    let joint = &sc.model.joints[i];
                    let mut summary = MotorSummary {
                        label: m.label.clone(),
                        kind: m.envelope.kind(),
                        max_motor_speed: self.max_speed[i],
                        rms_torque: (self.sum_sq[i] / steps).sqrt(),
                        continuous_torque: m.continuous_torque,
                        sizing: self.sizing[i].sizing(m, joint.rotor_inertia, done as f64 * sc.dt),
                        ..MotorSummary::default()
                    };
                    self.drives[i].summarize(&sc.drives[i], m, joint, steps, &mut summary);
                    summary
                })
            })
            .collect()
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

/// Where the self-clearance of the trail samples is measured.
enum ClearanceStage<'a, 's> {
    /// On the run's thread, at each sample: the recorders see each sample's intersecting pairs.
    Inline(Box<ClearanceMetrics<'a>>),
    /// On a worker thread, fed each sample's q: the dynamics need none of the meshes, so they
    /// run while the meshes' BVHs are built ([`CollisionSet::new`] leaves them to loader
    /// threads) and while the samples are folded in; samples that queue up while the worker
    /// is busy are folded in with the pairs in parallel ([`Clearance::fold_queued`]).
    Worker(Feed<'a, 's>),
}

/// The run's end of a [`ClearanceStage::Worker`]: each sample's time and q go over `samples`,
/// their buffers come back over `spare` (nothing is allocated per sample once the worker keeps
/// up). `samples` holds at most [`MAX_SENT`] of them: when the worker falls that far behind, the
/// dynamics wait for it, so a run's memory does not grow with its length (an hour's wave sent
/// 180,000 samples the worker had not reached, 9 MB more at its peak than a 6-minute one).
struct Feed<'a, 's> {
    samples: mpsc::SyncSender<(f64, Vec<f64>)>,
    spare: mpsc::Receiver<Vec<f64>>,
    worker: std::thread::ScopedJoinHandle<'s, ClearanceMetrics<'a>>,
}

/// Most samples the worker queues before folding them in (their objects' poses: about 0.4 kB a
/// sample on the Faze4).
const MAX_QUEUED: usize = 1024;

/// Most samples sent to the worker and not yet taken by it (a sample's time and q: about 0.1 kB
/// on the Faze4).
const MAX_SENT: usize = 2 * MAX_QUEUED;

impl<'a, 's> ClearanceStage<'a, 's> {
    /// `metrics` measured on a worker thread spawned in `scope`, with its own forward
    /// kinematics of `model`.
    fn worker(model: &'a Model, mut metrics: ClearanceMetrics<'a>, scope: &'s std::thread::Scope<'s, 'a>) -> Self {
        let (samples, queue) = mpsc::sync_channel::<(f64, Vec<f64>)>(MAX_SENT);
        let (give_back, spare) = mpsc::channel();
        let worker = scope.spawn(move || {
            let mut data = Data::new(model);
            while let Ok(first) = queue.recv() {
                let started = Instant::now();
                let mut next = Some(first);
                while let Some((t, q)) = next {
                    forward_kinematics(model, &mut data, &q);
                    metrics.clearance.queue(&data.frame_pose, t);
                    let _ = give_back.send(q);
                    next = (metrics.clearance.queued() < MAX_QUEUED)
                        .then(|| queue.try_recv().ok())
                        .flatten();
                }
                metrics.clearance.fold_queued();
                metrics.elapsed += started.elapsed();
            }
            metrics.finish();
            metrics
        });
        ClearanceStage::Worker(Feed { samples, spare, worker })
    }

    /// The measured clearance, complete: [`ClearanceMetrics::finish`]ed, or the worker's once
    /// it has folded in every sample sent and finished.
    fn finish(self) -> ClearanceMetrics<'a> {
        match self {
            ClearanceStage::Inline(mut metrics) => {
                metrics.finish();
                *metrics
            }
            ClearanceStage::Worker(Feed { samples, worker, .. }) => {
                drop(samples);
                worker.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            }
        }
    }
}

impl Feed<'_, '_> {
    /// Sends the sample at time `t` (s), at joint positions `q`, to the worker.
    fn send(&mut self, t: f64, q: &[f64]) {
        let mut buffer = self.spare.try_recv().unwrap_or_default();
        buffer.clear();
        buffer.extend_from_slice(q);
        // the worker lives until the sender is dropped: a failed send is its panic, raised at
        // the join
        let _ = self.samples.send((t, buffer));
    }
}

/// Self-clearance over the trail samples: the report, and when each pair first intersected.
struct ClearanceMetrics<'a> {
    clearance: Clearance<'a>,
    /// Wall-clock time spent folding the samples in and in [`ClearanceMetrics::finish`].
    elapsed: Duration,
}

impl<'a> ClearanceMetrics<'a> {
    /// Measured with `set` to within `tolerance` (m), following `path` if given.
    fn new(set: &'a CollisionSet, tolerance: f64, path: Option<&'a PathClearance>) -> Self {
        let clearance = Clearance::with_tolerance(set, tolerance);
        ClearanceMetrics {
            clearance: match path {
                Some(path) => clearance.following(path),
                None => clearance,
            },
            elapsed: Duration::ZERO,
        }
    }

    /// Folds the sample at time `t` (s), whose frames are at `frame_pose`, in.
    fn add(&mut self, frame_pose: &[Pose], t: f64) {
        let started = Instant::now();
        self.clearance.add(frame_pose, t);
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
        let mut pairs: Vec<Intersection> = (self.clearance.report().pairs.iter())
            .zip(self.clearance.first_intersections())
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
