//! A sweep's family of runs: a base configuration, what it reads once ([`Loaded`]: the arm, a
//! replay's frames, a shape's plan, the collision meshes), and the options its points vary,
//! each a field of the configuration or a multiplier of the built scenario ([`Knob`]).

use std::ops::Range;

use super::{Found, Grid, Outcome, Row, Runner, Scale, Seek, find};
use crate::config::fields::{Field, field};
use crate::config::{Loaded, Motion, Replayed, RunConfig};
use crate::error::{Error, Result, one_line};
use crate::output::format::exact;
use crate::sim::{Scenario, StopFlag, Warning};

/// What a sweep NAME changes.
#[derive(Clone, Copy, Debug)]
pub enum Knob {
    /// A numeric field of the configuration (`payload_kg`, `dt`, `shape_points`, …).
    Field(&'static Field),
    /// A multiplier of the built scenario (`kp_scale`, …).
    Scale(Scale),
}

/// Numeric fields that say how a run is shown, not what it does: not varied.
const NOT_VARIED: [&str; 2] = ["port", "print_period"];

/// Whether a sweep varies field `f`.
fn varies(f: &Field) -> bool {
    f.is_numeric() && !NOT_VARIED.contains(&f.name)
}

impl Knob {
    /// The knob a sweep NAME names, written with dashes (the command line's `payload-kg`) or
    /// underscores (the field's `payload_kg`).
    pub fn named(name: &str) -> Option<Knob> {
        let snake = name.trim().trim_start_matches("--").replace('-', "_");
        match field(&snake) {
            Some(f) if varies(f) => Some(Knob::Field(f)),
            Some(_) => None,
            None => (Scale::ALL.iter())
                .find(|(n, _)| n.replace('-', "_") == snake)
                .map(|(_, s)| Knob::Scale(*s)),
        }
    }
}

/// The names a sweep can vary, for messages: the numeric fields, then the multipliers.
pub fn known_names() -> String {
    let fields = (crate::config::fields::FIELDS.iter())
        .filter(|f| varies(f))
        .map(|f| f.name.replace('_', "-"));
    let scales = Scale::ALL.iter().map(|(n, _)| n.to_string());
    fields.chain(scales).collect::<Vec<_>>().join(", ")
}

/// A base configuration, what it read once, and the knobs of a sweep over it.
pub struct Family {
    base: RunConfig,
    loaded: Loaded,
    knobs: Vec<Knob>,
}

impl Family {
    /// Loads `base` (a replay's `frames` given, or read from its `q_traj`) for a sweep varying
    /// `names` (each checked against the base command, with its `values` where given). The
    /// base's single-run outputs (summary, html, plot, live view, joint samples) are refused:
    /// a sweep writes its own.
    pub fn load(base: RunConfig, replayed: Option<Replayed>, names: &[(&str, &[f64])]) -> Result<Family> {
        let out = &base.outputs;
        if let Some(path) = &out.summary {
            return Err(Error::option(
                "summary",
                format!(
                    "{}: a sweep writes its table with `out`, not a summary per run",
                    path.display()
                ),
            ));
        }
        let save_q = matches!(&base.motion, Motion::Shape(s) if s.save_q.is_some());
        for (given, name) in [
            (out.html.is_some(), "html"),
            (out.plot.is_some(), "plot"),
            (out.plot_motors.is_some(), "plot_motors"),
            (out.view || out.hold, "view"),
            (save_q, "save_q"),
        ] {
            if given {
                return Err(Error::option(
                    name,
                    "is for single runs: a sweep's outputs are `out`, `plot` and `trails` before the `--`",
                ));
            }
        }
        let knobs = (names.iter())
            .map(|(name, values)| knob(&base, name, values))
            .collect::<Result<Vec<_>>>()?;
        let loaded = Loaded::load(&base, replayed)?;
        Ok(Family { base, loaded, knobs })
    }

    /// What loading found that changes every run (meshes not found), said once.
    pub fn warnings(&self) -> &[Warning] {
        &self.loaded.warnings
    }

    /// The knobs, one per varied name.
    pub fn knobs(&self) -> &[Knob] {
        &self.knobs
    }

    /// The scenario of one point: knob i set to `values[i]`.
    pub fn build(&self, values: &[f64]) -> Result<Scenario> {
        let mut config = self.base.clone();
        let mut scales = Vec::new();
        for (knob, &x) in self.knobs.iter().zip(values) {
            match knob {
                Knob::Field(f) => f.set_number(&mut config, x)?,
                Knob::Scale(scale) => scales.push((*scale, x)),
            }
        }
        let mut scenario = self.loaded.scenario(&config)?;
        for (scale, x) in scales {
            scale.apply(&mut scenario, x)?;
        }
        Ok(scenario)
    }

    /// The runs `indices` of `grid` on `jobs` threads (0: one per core), in index order, each
    /// stopping at `stop`; a raised `stop` ends the sweep early (fewer rows than runs).
    pub fn rows(&self, grid: &Grid, indices: Range<usize>, jobs: usize, stop: &StopFlag) -> Result<Vec<Row>> {
        let build = |values: &[f64]| self.build(values);
        let runner = Runner::new(&build, threads(jobs, indices.len()))?.with_stop(stop);
        let mut rows = Vec::with_capacity(indices.len());
        runner.sweep(grid, indices, stop, |row| {
            rows.push(row);
            Ok(())
        })?;
        Ok(rows)
    }

    /// A row with the sweep's columns, for a part none of whose runs ran: the first of the
    /// sweep's first [`PROBES`] runs that builds, run for one step (the columns depend on the
    /// model and the base command, not on the values). `None` when none builds.
    pub fn probe(&self, grid: &Grid, total: usize) -> Option<Row> {
        (0..total.min(PROBES)).find_map(|index| {
            let values = grid.point(index);
            let mut scenario = self.build(&values).ok()?;
            scenario.steps = scenario.steps.min(1);
            let summary = crate::sim::run(&scenario, &mut [], &StopFlag::new()).ok()?;
            Some(Row {
                index,
                values,
                outcome: Outcome::Ran(Box::new(summary)),
            })
        })
    }
}

/// Most runs [`Family::probe`] tries to build.
const PROBES: usize = 100;

/// The knob `name`, checked against `base`'s command with `values` (the first must be
/// settable, every one a value of the field's kind).
fn knob(base: &RunConfig, name: &str, values: &[f64]) -> Result<Knob> {
    let knob = Knob::named(name).ok_or_else(|| {
        Error::option(
            "vary",
            format!("'{name}' is not a numeric option a sweep can vary ({})", known_names()),
        )
    })?;
    if let Knob::Field(f) = knob {
        let bad = |e: Error| {
            let reason = match &e {
                Error::InvalidArgument { message, .. } => message.clone(),
                other => other.to_string(),
            };
            Error::option("vary", format!("{name} {reason} (faze4 {})", base.motion.name()))
        };
        for &x in values {
            f.set_number(&mut base.clone(), x).map_err(bad)?;
        }
    }
    Ok(knob)
}

/// The threads of a sweep of `runs` runs: `jobs` (0: one per core), never more than the runs.
pub fn threads(jobs: usize, runs: usize) -> usize {
    let jobs = match jobs {
        0 => std::thread::available_parallelism().map_or(1, usize::from),
        n => n,
    };
    jobs.min(runs).max(1)
}

/// What a search found, with the line that says it.
pub struct Searched {
    /// The runs at the boundary (or the end that decides).
    pub found: Found,
    /// The answer for people, one line.
    pub line: String,
}

/// The largest (or smallest, `seek`) value of `name` in [`lo`, `hi`] at which the arm follows,
/// to within `resolution` (default 1 % of the range), by parallel bisection over `family`'s
/// base on `jobs` threads. `option` names the search for messages (`find`, `find_min`).
#[allow(clippy::too_many_arguments)]
pub fn search(
    base: RunConfig,
    replayed: Option<Replayed>,
    name: &str,
    lo: f64,
    hi: f64,
    resolution: Option<f64>,
    seek: Seek,
    jobs: usize,
    stop: &StopFlag,
    warn: impl Fn(&[Warning]),
) -> Result<Searched> {
    let option = match seek {
        Seek::Largest => "find",
        Seek::Smallest => "find_min",
    };
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::option(
            option,
            format!("{name}={}:{}: the ends must be finite numbers", exact(lo), exact(hi)),
        ));
    }
    if hi <= lo {
        return Err(Error::option(
            option,
            format!(
                "{name}={}:{}: empty range (the upper end {} is not above the lower {})",
                exact(lo),
                exact(hi),
                exact(hi),
                exact(lo)
            ),
        ));
    }
    let resolution = resolution.unwrap_or((hi - lo) / 100.0);
    if !resolution.is_finite() || resolution <= 0.0 {
        return Err(Error::option(
            "resolution",
            format!(
                "{}: give a finite width > 0 (default: 1 % of the range)",
                exact(resolution)
            ),
        ));
    }
    let family = Family::load(base, replayed, &[(name, &[lo, hi])]).map_err(|e| match e {
        Error::InvalidArgument { option: o, message } if o == "`vary`" => Error::option(option, message),
        other => other,
    })?;
    warn(family.warnings());
    if let [Knob::Field(f)] = family.knobs()
        && f.kind == crate::config::Kind::Count
    {
        return Err(Error::option(
            option,
            format!("{name} takes whole numbers: list them with `vary` {name}=v1,v2,…"),
        ));
    }
    // each end is a value the option takes, as the command would check it
    for x in [lo, hi] {
        family.build(&[x]).map_err(|e| {
            let e = one_line(&e.to_string());
            Error::option(option, format!("{name}={}: {e}", exact(x)))
        })?;
    }
    let build = |values: &[f64]| family.build(values);
    let runner = Runner::new(&build, jobs)?.with_stop(stop);
    let (lo_text, hi_text) = (exact(lo), exact(hi));
    let found = find(&runner, lo, hi, resolution, seek);
    let line = match &found {
        Found::Boundary { follows, fails } => {
            let which = match seek {
                Seek::Largest => "largest",
                Seek::Smallest => "smallest",
            };
            // the values run, each as its shortest round-trip decimal: rerunning either with
            // the option gives the same row
            let (follows_at, fails_at) = (exact(follows.values[0]), exact(fails.values[0]));
            format!(
                "{which} {name} that follows: {follows_at} (at {fails_at}: {})",
                fails.reasons()
            )
        }
        Found::NoneFollows(row) => {
            if let Outcome::Failed(reason) = &row.outcome {
                return Err(Error::option(
                    option,
                    format!("the run at {name}={} could not run: {reason}", exact(row.values[0])),
                ));
            }
            format!(
                "no {name} in [{lo_text}, {hi_text}] follows: already at {}: {}",
                exact(row.values[0]),
                row.reasons()
            )
        }
        Found::AllFollow(row) => {
            let (end, widen) = match seek {
                Seek::Largest => ("largest", "raise HI"),
                Seek::Smallest => ("smallest", "lower LO"),
            };
            format!(
                "every {name} in [{lo_text}, {hi_text}] follows, {} too: the {end} that follows is beyond the range ({widen})",
                exact(row.values[0])
            )
        }
    };
    Ok(Searched { found, line })
}
