//! A run kept to be handed to recorders afterwards: a [`Tape`] records every step's sample of a
//! run, and [`Tape::play`] gives each recorder what the run would have given it (`begin`, its
//! samples at its own period, `finish`), without running it again. `retime` tapes its check
//! runs and plays the last one into the outputs (docs/retime.md, "The closed-loop check").

use super::run::{collision_pairs, run_info};
use super::step::Step;
use super::{Recorder, RunInfo, Sample, Scenario, Summary, steps_per_record};
use crate::error::Result;
use crate::spatial::Vec3;

/// Every sample of one run, owned: per step the seven joint vectors of [`Sample`] and the
/// rest. About 60 f64 a step for six joints (30,000 steps of a 6 s run at 5 kHz: about 15 MB),
/// kept in flat buffers that a new run reuses (`begin` empties them).
#[derive(Clone, Debug, Default)]
pub struct Tape {
    /// Whether the run measures its self-clearance at each sample (see
    /// [`Recorder::reads_intersections`]): needed when one of the recorders it is played to
    /// reads [`Sample::intersecting`].
    reads_intersections: bool,
    /// Joints, and the flags in each sample's [`Sample::intersecting`] (0 where the run
    /// measures no clearance inline).
    dof: usize,
    pairs: usize,
    /// Per sample: its step and time (s).
    step: Vec<usize>,
    t: Vec<f64>,
    /// Per sample, 7·dof values: q, v, q_cmd, v_cmd, τ, τ_raw, g.
    values: Vec<f64>,
    /// Per sample: the tool's position and the shape's target.
    tool: Vec<Vec3>,
    target: Vec<Option<Vec3>>,
    /// Per sample, `pairs` flags.
    intersecting: Vec<bool>,
}

/// The joint vectors of a sample, in the order of [`Tape::values`].
const VECTORS: usize = 7;

/// The most a tape may hold (bytes): 64 MiB, about 27 s of a six-joint run at 5 kHz. A longer
/// run is not taped ([`Tape::fits`]), and its outputs come from the run played again, so that
/// memory does not grow with the motion's length.
pub const TAPE_BUDGET: usize = 64 << 20;

impl Tape {
    /// An empty tape; `reads_intersections` when a recorder it will be played to reads
    /// [`Sample::intersecting`] (the run then measures its clearance inline).
    pub fn new(reads_intersections: bool) -> Tape {
        Tape {
            reads_intersections,
            ..Tape::default()
        }
    }

    /// Whether a run of `sc` lasting `duration` seconds fits in [`TAPE_BUDGET`] (every step's
    /// sample, with a flag per checked pair).
    pub fn fits(sc: &Scenario, duration: f64) -> bool {
        let pairs = sc.collision_set.as_ref().map_or(0, |set| set.pairs().count());
        let per_step = size_of::<usize>()
            + size_of::<f64>() * (1 + VECTORS * sc.model.dof())
            + size_of::<Vec3>()
            + size_of::<Option<Vec3>>()
            + pairs;
        let steps = (duration / sc.dt).ceil() + 2.0;
        steps * per_step as f64 <= TAPE_BUDGET as f64
    }

    /// Samples recorded (the run's steps, and its last).
    pub fn len(&self) -> usize {
        self.step.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.step.is_empty()
    }

    /// Sample `i`.
    fn sample(&self, i: usize) -> Sample<'_> {
        let n = self.dof;
        let v = &self.values[i * VECTORS * n..(i + 1) * VECTORS * n];
        Sample {
            step: self.step[i],
            t: self.t[i],
            q: &v[..n],
            v: &v[n..2 * n],
            q_cmd: &v[2 * n..3 * n],
            v_cmd: &v[3 * n..4 * n],
            tau: &v[4 * n..5 * n],
            tau_raw: &v[5 * n..6 * n],
            g: &v[6 * n..],
            tool: self.tool[i],
            target: self.target[i],
            intersecting: &self.intersecting[i * self.pairs..(i + 1) * self.pairs],
        }
    }

    /// Hands the taped run of `sc` to `recorders` as [`super::run`] would have: `begin` with
    /// `sc`'s [`RunInfo`], to each recorder the samples at its own period (step 0, every
    /// [`steps_per_record`] steps, and the run's last), `finish` with `summary` (the taped
    /// run's). A run that diverged handed no sample as its last; one that was interrupted, or
    /// ended, did.
    pub fn play(&self, sc: &Scenario, recorders: &mut [&mut dyn Recorder], summary: &Summary) -> Result<()> {
        let start_q = Step::new(sc).state.q.clone();
        let pairs = collision_pairs(sc);
        let info: RunInfo = run_info(sc, &start_q, &pairs);
        for r in recorders.iter_mut() {
            r.begin(&info)?;
        }
        let every: Vec<usize> = recorders.iter().map(|r| steps_per_record(r.period(), sc.dt)).collect();
        let mut due = vec![0; recorders.len()];
        let ends = summary.diverged.is_none();
        for i in 0..self.len() {
            let sample = self.sample(i);
            let last = ends && i + 1 == self.len();
            for ((r, next), &e) in recorders.iter_mut().zip(due.iter_mut()).zip(&every) {
                if sample.step == *next || last {
                    r.record(&sample)?;
                }
                if sample.step == *next {
                    *next += e;
                }
            }
        }
        for r in recorders.iter_mut() {
            r.finish(summary)?;
        }
        Ok(())
    }
}

impl Recorder for Tape {
    /// Every step.
    fn period(&self) -> f64 {
        0.0
    }

    fn reads_intersections(&self) -> bool {
        self.reads_intersections
    }

    fn begin(&mut self, run: &RunInfo) -> Result<()> {
        self.dof = run.model.dof();
        self.pairs = 0;
        self.step.clear();
        self.t.clear();
        self.values.clear();
        self.tool.clear();
        self.target.clear();
        self.intersecting.clear();
        Ok(())
    }

    fn record(&mut self, s: &Sample) -> Result<()> {
        self.step.push(s.step);
        self.t.push(s.t);
        for v in [s.q, s.v, s.q_cmd, s.v_cmd, s.tau, s.tau_raw, s.g] {
            self.values.extend_from_slice(v);
        }
        self.tool.push(s.tool);
        self.target.push(s.target);
        // as many as the run hands (none when it measures no clearance inline)
        if self.step.len() == 1 {
            self.pairs = s.intersecting.len();
        }
        self.intersecting.extend_from_slice(s.intersecting);
        Ok(())
    }
}
