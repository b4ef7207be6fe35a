//! Running a family of scenarios on every core (rayon), each run a [`Row`] of values.

use std::ops::Range;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::Grid;
use crate::atomic::Outputs;
use crate::control::Stability;
use crate::control::arithmetic_holds;
use crate::error::{Error, Result, shortest};
use crate::output::TrailCsv;
use crate::sim::{self, Recorder, Scenario, StopFlag, Summary};

/// A multiplier of a built scenario: the controller's gains and limits (as tuned, or as
/// given), or the simulated arm's masses. Applied after the build, so the gains stay those tuned
/// for the nominal arm and limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// `kp-scale`: every proportional gain × factor (≥ 0).
    Kp,
    /// `kd-scale`: every derivative gain × factor (≥ 0).
    Kd,
    /// `effort-scale`: every torque limit × factor (> 0; an unlimited joint stays unlimited).
    Effort,
    /// `mass-scale`: every body's mass, first moment and rotational inertia × factor (> 0),
    /// payload included. The gravity feed-forward g(q) is the scaled arm's; the gains are not
    /// retuned, so this is the controller's view of the arm being off by the factor.
    Mass,
    /// `rotor-inertia-scale`: every joint's rotor inertia × factor (> 0), so its reflected
    /// inertia r²·I_rotor too (a joint without a motor has none to scale). Like `mass-scale`,
    /// after tuning: the gains are those of the nominal motors.
    RotorInertia,
    /// `efficiency-scale`: every motor's reducer efficiency η × factor (> 0; `--motors` only),
    /// and with it the constant limit E of each motored joint. After tuning, as `mass-scale`.
    Efficiency,
    /// `stall-torque-scale`: every motor's torques × factor (> 0; `--motors` only): a DC
    /// motor's stall and peak torque, a stepper's whole pull-out curve; and the constant limit
    /// E of each motored joint. After tuning.
    StallTorque,
}

impl Scale {
    /// Every scale, by its option name.
    pub const ALL: [(&'static str, Scale); 7] = [
        ("kp-scale", Scale::Kp),
        ("kd-scale", Scale::Kd),
        ("effort-scale", Scale::Effort),
        ("mass-scale", Scale::Mass),
        ("rotor-inertia-scale", Scale::RotorInertia),
        ("efficiency-scale", Scale::Efficiency),
        ("stall-torque-scale", Scale::StallTorque),
    ];

    /// The option name (`kp-scale`, …).
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, s)| *s == self).map_or("", |(n, _)| n)
    }

    /// Multiplies `scenario`'s gains, limits or masses by `factor`.
    pub fn apply(self, scenario: &mut Scenario, factor: f64) -> Result<()> {
        let zero_allowed = matches!(self, Scale::Kp | Scale::Kd);
        if !factor.is_finite() || factor < 0.0 || (factor == 0.0 && !zero_allowed) {
            let bound = if zero_allowed { "≥ 0" } else { "> 0" };
            return Err(Error::argument(
                self.name(),
                format!("{} must be finite and {bound}", shortest(factor)),
            ));
        }
        let gains = &mut scenario.controller.gains;
        let values = match self {
            Scale::Kp => &mut gains.kp,
            Scale::Kd => &mut gains.kd,
            Scale::Effort => &mut gains.effort,
            Scale::Mass => {
                for inertia in &mut scenario.model.inertia {
                    inertia.mass *= factor;
                    inertia.h *= factor;
                    inertia.rot *= factor;
                }
                return self.holds(scenario, factor);
            }
            Scale::RotorInertia => {
                scenario.model.joints.iter_mut().for_each(|j| j.rotor_inertia *= factor);
                return self.holds(scenario, factor);
            }
            Scale::Efficiency | Scale::StallTorque => {
                let Some(motors) = scenario.motors.as_mut() else {
                    return Err(Error::argument(self.name(), "scales the motors: add `motors`"));
                };
                for (m, e) in motors.iter_mut().zip(gains.effort.iter_mut()) {
                    let Some(m) = m else { continue };
                    *e *= factor;
                    if self == Scale::Efficiency {
                        m.efficiency *= factor;
                        continue;
                    }
                    m.envelope.scale_torque(factor);
                }
                return Ok(());
            }
        };
        values.iter_mut().for_each(|x| *x *= factor);
        match self {
            Scale::Kp | Scale::Kd if values.iter().any(|x| !x.is_finite()) => Err(self.overflows(factor)),
            _ => Ok(()),
        }
    }

    /// Whether the scaled arm's mass matrix at the start pose and the stability figures of the
    /// gains on it are finite (a factor of 1e300 makes them overflow).
    fn holds(self, scenario: &Scenario, factor: f64) -> Result<()> {
        let model = &scenario.model;
        let n = model.dof();
        let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
        scenario.trajectory.start_state(&mut q, &mut v);
        let m = crate::algo::crba(model, &mut crate::algo::Data::new(model), &q).clone();
        let gains = &scenario.controller.gains;
        let damping: Vec<f64> = model.damping().collect();
        let mut scaled = gains.clone();
        scaled.stability = Some(Stability::assess(&m, &damping, &gains.kp, &gains.kd, scenario.dt));
        match arithmetic_holds(&m, &scaled) {
            true => Ok(()),
            false => Err(self.overflows(factor)),
        }
    }

    fn overflows(self, factor: f64) -> Error {
        Error::argument(
            self.name(),
            format!(
                "{}: too large to simulate (the scaled arm's arithmetic overflows)",
                shortest(factor)
            ),
        )
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// It ran (perhaps diverging: see the summary's `diverged` and verdict).
    Ran(Box<Summary>),
    /// It could not be built or run: the reason, one line.
    Failed(String),
}

/// One run of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The run's index in the whole sweep (0-based).
    pub index: usize,
    /// Its values, one per varied option.
    pub values: Vec<f64>,
    /// What it did.
    pub outcome: Outcome,
}

impl Row {
    /// Whether the run's verdict is "follows" (a failed run does not follow).
    pub fn follows(&self) -> bool {
        matches!(&self.outcome, Outcome::Ran(s) if s.verdict.follows)
    }

    /// Why it does not follow, one line: the verdict's reasons or the failure; empty when it
    /// follows.
    pub fn reasons(&self) -> String {
        match &self.outcome {
            Outcome::Ran(s) => s
                .verdict
                .reasons
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join("; "),
            Outcome::Failed(reason) => format!("failed: {reason}"),
        }
    }
}

/// Builds the scenario of a point (one value per varied option). Called from many threads.
pub type Build<'a> = dyn Fn(&[f64]) -> Result<Scenario> + Sync + 'a;

/// Runs points of a family in parallel.
pub struct Runner<'a> {
    pool: rayon::ThreadPool,
    build: &'a Build<'a>,
    /// `--trails`: the directory, and the set its files are written in.
    trails: Option<(PathBuf, Outputs)>,
    on_done: Option<&'a (dyn Fn() + Sync)>,
    /// Each run's stop flag (none: runs go to their end).
    stop: StopFlag,
}

/// Runs handed to the pool at once by [`Runner::sweep`], per thread: enough to keep every core
/// busy, few enough that memory does not grow with the sweep.
const CHUNK_PER_THREAD: usize = 32;

impl<'a> Runner<'a> {
    /// A runner on `jobs` threads (0: one per core) building each run with `build`.
    pub fn new(build: &'a Build<'a>, jobs: usize) -> Result<Runner<'a>> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(jobs)
            .build()
            .map_err(|e| Error::option("jobs", e.to_string()))?;
        Ok(Runner {
            pool,
            build,
            trails: None,
            on_done: None,
            stop: StopFlag::new(),
        })
    }

    /// Also write each run's trail CSV as `dir/run_INDEX.csv` (INDEX zero-padded to 7 digits),
    /// a file of `outputs` (they appear when the set is committed).
    pub fn with_trails(mut self, dir: &Path, outputs: &Outputs) -> Self {
        self.trails = Some((dir.to_path_buf(), outputs.clone()));
        self
    }

    /// Call `on_done` after every run, from the thread that ran it (a progress bar).
    pub fn with_progress(mut self, on_done: &'a (dyn Fn() + Sync)) -> Self {
        self.on_done = Some(on_done);
        self
    }

    /// Each run polls `stop` as a single run does (and ends there, `interrupted_at_s` in its
    /// summary); runs not yet started when it is raised fail as interrupted.
    pub fn with_stop(mut self, stop: &StopFlag) -> Self {
        self.stop = stop.clone();
        self
    }

    /// Threads the runner uses.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// Runs `points` (index, values) in parallel; the rows in the same order. A run the stop
    /// flag kept from starting fails as interrupted.
    pub fn run_points(&self, points: Vec<(usize, Vec<f64>)>) -> Vec<Row> {
        (self.run_each(points).into_iter())
            .map(|(index, values, outcome)| Row {
                index,
                values,
                outcome: outcome.unwrap_or_else(|| Outcome::Failed("interrupted before this run started".into())),
            })
            .collect()
    }

    /// Runs the points `indices` of `grid` and hands the rows to `on_row` in index order, a
    /// chunk at a time, so that memory stays flat in the number of runs. A raised `stop` ends
    /// the runs in flight where they are (when the runner polls it: [`Runner::with_stop`]) and
    /// the sweep there: only whole runs are handed over, those before the first that it ended
    /// early or kept from starting. Returns the number of rows handed over.
    pub fn sweep(
        &self,
        grid: &Grid,
        indices: Range<usize>,
        stop: &StopFlag,
        mut on_row: impl FnMut(Row) -> Result<()>,
    ) -> Result<usize> {
        let chunk = CHUNK_PER_THREAD * self.threads();
        let mut handed = 0;
        let mut start = indices.start;
        while start < indices.end && !stop.is_raised() {
            let end = (start + chunk).min(indices.end);
            let points = (start..end).map(|i| (i, grid.point(i))).collect();
            let mut whole = true;
            for (index, values, outcome) in self.run_each(points) {
                match outcome {
                    Some(Outcome::Ran(summary)) if summary.interrupted_at_s.is_some() => whole = false,
                    Some(outcome) if whole => {
                        on_row(Row { index, values, outcome })?;
                        handed += 1;
                        continue;
                    }
                    _ => whole = false,
                }
                // the stop ended this run early or kept it from starting: neither it nor a run
                // after it is a row of the sweep, nor its trail a file of it
                if let Some((dir, outputs)) = &self.trails {
                    outputs.withdraw(&trail_path(dir, index));
                }
            }
            if !whole {
                break;
            }
            start = end;
        }
        Ok(handed)
    }

    /// Runs `points` in parallel: each with what it did, in the same order; `None` for a run
    /// the stop flag kept from starting.
    fn run_each(&self, points: Vec<(usize, Vec<f64>)>) -> Vec<(usize, Vec<f64>, Option<Outcome>)> {
        self.pool.install(|| {
            points
                .into_par_iter()
                .map(|(index, values)| {
                    let outcome = (!self.stop.is_raised()).then(|| match self.build_and_run(index, &values) {
                        Ok(summary) => Outcome::Ran(Box::new(summary)),
                        Err(e) => Outcome::Failed(crate::error::one_line(&e.to_string())),
                    });
                    if let Some(done) = self.on_done {
                        done();
                    }
                    (index, values, outcome)
                })
                .collect()
        })
    }

    fn build_and_run(&self, index: usize, values: &[f64]) -> Result<Summary> {
        let scenario = (self.build)(values)?;
        let stop = &self.stop;
        match &self.trails {
            None => sim::run(&scenario, &mut [], stop),
            Some((dir, outputs)) => {
                let period = scenario.record_every as f64 * scenario.dt;
                let path = trail_path(dir, index);
                let mut trail = TrailCsv::within(outputs, &path, period, false)?;
                let mut recorders: [&mut dyn Recorder; 1] = [&mut trail];
                sim::run(&scenario, &mut recorders, stop)
            }
        }
    }
}

/// The trail of run `index` of a sweep, in `--trails` folder `dir` (`run_INDEX.csv`, INDEX
/// zero-padded to 7 digits).
fn trail_path(dir: &Path, index: usize) -> PathBuf {
    dir.join(format!("run_{index:07}.csv"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::{Trajectory, Wave};

    fn scenario() -> Scenario {
        let model = crate::faze4::model();
        let wave = Trajectory::Wave(Wave {
            amplitude: vec![0.1; model.dof()],
            omega: 0.5,
            center: vec![0.0; model.dof()],
        });
        Scenario::builder(model, wave).duration(0.01).build().unwrap()
    }

    #[test]
    fn scales_multiply_the_built_scenario_and_refuse_bad_factors() {
        let base = scenario();
        let mut s = base.clone();
        Scale::Kp.apply(&mut s, 0.5).unwrap();
        Scale::Effort.apply(&mut s, 2.0).unwrap();
        Scale::Mass.apply(&mut s, 1.2).unwrap();
        for i in 0..base.model.dof() {
            assert_eq!(s.controller.gains.kp[i], base.controller.gains.kp[i] * 0.5);
            assert_eq!(s.controller.gains.kd[i], base.controller.gains.kd[i]);
            assert_eq!(s.controller.gains.effort[i], base.controller.gains.effort[i] * 2.0);
            assert_eq!(s.model.inertia[i].mass, base.model.inertia[i].mass * 1.2);
            assert_eq!(s.model.inertia[i].rot, base.model.inertia[i].rot * 1.2);
        }
        assert!(Scale::Kd.apply(&mut s, 0.0).is_ok());
        for (scale, bad) in [(Scale::Mass, 0.0), (Scale::Effort, -1.0), (Scale::Kp, f64::NAN)] {
            let e = scale.apply(&mut s, bad).unwrap_err().to_string();
            assert!(e.starts_with(scale.name()), "{e}");
        }
    }

    #[test]
    fn a_family_runs_in_order_and_a_failed_build_is_a_row() {
        let build = |values: &[f64]| -> Result<Scenario> {
            if values[0] < 0.0 {
                return Err(Error::option("payload_kg", "negative"));
            }
            let mut s = scenario();
            Scale::Kp.apply(&mut s, values[0])?;
            Ok(s)
        };
        let grid = Grid::new(vec![super::super::Axis::parse("kp-scale=-1,0.5,1,2").unwrap()]).unwrap();
        let runner = Runner::new(&build, 2).unwrap();
        let mut rows = Vec::new();
        let ran = runner
            .sweep(&grid, 0..4, &StopFlag::new(), |row| {
                rows.push(row);
                Ok(())
            })
            .unwrap();
        assert_eq!(ran, 4);
        assert_eq!(rows.iter().map(|r| r.index).collect::<Vec<_>>(), [0, 1, 2, 3]);
        assert_eq!(rows[0].outcome, Outcome::Failed("`payload_kg`: negative".into()));
        assert!(!rows[0].follows());
        for (row, factor) in rows[1..].iter().zip([0.5, 1.0, 2.0]) {
            let Outcome::Ran(s) = &row.outcome else {
                panic!("{row:?}")
            };
            assert_eq!(s.gains.kp[0], scenario().controller.gains.kp[0] * factor);
        }
    }
}
