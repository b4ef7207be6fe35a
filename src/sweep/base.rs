//! A sweep's family of runs: a base configuration, what it reads once ([`Loaded`]: the arm, a
//! replay's frames, a shape's plan, the collision meshes), and the options its points vary,
//! each a field of the configuration or a multiplier of the built scenario ([`Knob`]). When
//! the options varied leave the commanded path as it is ([`Swept::KeepsPath`]), the runs share its
//! clearance, computed once ([`PathClearance`]).

use std::ops::Range;
use std::sync::Arc;

use super::{Found, Grid, Outcome, Row, Runner, Scale, Seek, find};
use crate::config::fields::{self, Field, Swept, any_field, field};
use crate::config::{Command, Loaded, Motion, Replayed, RunConfig};
use crate::error::{Error, Result, one_line};
use crate::geometry::PathClearance;
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

/// Whether a sweep varies field `f`.
fn varies(f: &Field) -> bool {
    matches!(f.swept, Some(Swept::KeepsPath | Swept::MovesPath))
}

impl Knob {
    /// The knob a sweep NAME names for `command`, written with dashes (the command line's
    /// `payload-kg`) or underscores (the field's `payload_kg`). A field of another command is
    /// its knob too, which [`Field::set_number`] then refuses naming the command.
    pub fn named(name: &str, command: Command) -> Option<Knob> {
        let snake = name.trim().trim_start_matches("--").replace('-', "_");
        match field(&snake, command).or_else(|| any_field(&snake)) {
            Some(f) if varies(f) => Some(Knob::Field(f)),
            Some(_) => None,
            None => (Scale::ALL.iter())
                .find(|(n, _)| n.replace('-', "_") == snake)
                .map(|(_, s)| Knob::Scale(*s)),
        }
    }

    /// Whether it leaves the commanded path and the clearance's samples as they are (a field
    /// declared [`Swept::KeepsPath`], and every multiplier).
    pub fn keeps_path(&self) -> bool {
        match self {
            Knob::Field(f) => f.swept == Some(Swept::KeepsPath),
            Knob::Scale(_) => true,
        }
    }
}

/// Whether the runs of a family share their commanded path's clearance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sharing {
    /// Computed once and shared when the options varied keep the path ([`Knob::keeps_path`]):
    /// each run's clearance is then within the tolerance of its own, with its exact
    /// intersections (docs/clearance.md "Sweeps").
    Shared,
    /// Each run computes its own, as a single run does.
    Own,
}

/// The fields a sweep can vary (`payload_kg`, …), each once, in the order of
/// [`fields::FIELDS`]; the multipliers are [`Scale::ALL`].
pub fn varied_fields() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for f in fields::FIELDS.iter().filter(|f| varies(f)) {
        if !names.contains(&f.name) {
            names.push(f.name);
        }
    }
    names
}

/// The names a sweep can vary, for messages: the fields, then the multipliers, written with
/// dashes as a sweep's NAME may be.
pub fn known_names() -> String {
    let fields = varied_fields().into_iter().map(|n| n.replace('_', "-"));
    let scales = Scale::ALL.iter().map(|(n, _)| n.to_string());
    fields.chain(scales).collect::<Vec<_>>().join(", ")
}

/// A base configuration, what it read once, and the knobs of a sweep over it.
pub struct Family {
    base: RunConfig,
    loaded: Loaded,
    knobs: Vec<Knob>,
    /// The commanded path's clearance, computed once for every run to follow
    /// ([`Sharing::Shared`]).
    path: Option<Arc<PathClearance>>,
}

impl Family {
    /// Loads `base` (a replay's `frames` given, or read from its `q_traj`) for a sweep varying
    /// `names` (each checked against the base command, with its `values` where given). The
    /// base's single-run outputs (summary, html, plot, live view, joint samples) are refused:
    /// a sweep writes its own. With [`Sharing::Shared`], when every knob keeps the path, the
    /// path's clearance is computed (on threads of its own) at the point of each name's first
    /// value, and every run follows it.
    pub fn load(
        base: RunConfig,
        replayed: Option<Replayed>,
        names: &[(&str, &[f64])],
        sharing: Sharing,
    ) -> Result<Family> {
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
        // a sweep writes none of it: its runs' trails are `trails DIR`, before the `--`
        if let Some(path) = &out.trail {
            return Err(Error::option(
                "trail",
                format!(
                    "{}: a sweep writes one trail per run with `trails` DIR before the `--`, not one file",
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
        let mut family = Family {
            base,
            loaded,
            knobs,
            path: None,
        };
        if sharing == Sharing::Shared && family.knobs.iter().all(Knob::keeps_path) {
            let first: Option<Vec<f64>> = names.iter().map(|(_, values)| values.first().copied()).collect();
            if let Some(Ok(scenario)) = first.map(|values| family.build(&values)) {
                family.path = crate::sim::commanded_path(&scenario);
            }
        }
        Ok(family)
    }

    /// The commanded path's clearance its runs share, if they do.
    pub fn path(&self) -> Option<&Arc<PathClearance>> {
        self.path.as_ref()
    }

    /// What loading found that changes every run (meshes not found), said once.
    pub fn warnings(&self) -> &[Warning] {
        &self.loaded.warnings
    }

    /// The files the base loaded, which no output of the sweep may replace.
    pub fn inputs(&self) -> &crate::atomic::Inputs {
        self.loaded.inputs()
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
        scenario.path_clearance = self.path.clone();
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
    /// sweep's first `PROBES` runs that builds, run for one step (the columns depend on the
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

/// Refuses a sweep NAME (`names`, as the user wrote them, for `command`) that the base command
/// is also given (`given`: the fields the user set there, by name): the sweep sets it at each
/// run, so the given value would be dropped unsaid. `option` is the sweep's (`vary`, `find`).
pub fn refuse_given_and_varied(names: &[&str], command: Command, given: &[&str], option: &str) -> Result<()> {
    for name in names {
        if let Some(Knob::Field(f)) = Knob::named(name, command)
            && given.iter().any(|g| f.is_called(g))
        {
            return Err(Error::option(
                option,
                format!(
                    "'{}' is varied and also given to the command (`{}`): the sweep sets it at each run, so that value would be dropped; give it in one place",
                    name.trim(),
                    f.name
                ),
            ));
        }
    }
    Ok(())
}

/// The knob `name`, checked against `base`'s command with `values` (the first must be
/// settable, every one a value of the field's kind).
fn knob(base: &RunConfig, name: &str, values: &[f64]) -> Result<Knob> {
    let knob = Knob::named(name, base.motion.command()).ok_or_else(|| {
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
/// base on `jobs` threads, its steps sharing the path's clearance as `sharing` says.
#[allow(clippy::too_many_arguments)]
pub fn search(
    base: RunConfig,
    replayed: Option<Replayed>,
    sharing: Sharing,
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
    let family = Family::load(base, replayed, &[(name, &[lo, hi])], sharing).map_err(|e| match e {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::fields::FIELDS;
    use crate::config::{Motion, WaveConfig};

    /// Every numeric field says what a sweep does with it (a new one must be decided), and
    /// no other field does.
    #[test]
    fn every_numeric_field_says_what_a_sweep_does_with_it() {
        for f in FIELDS {
            assert_eq!(f.swept.is_some(), f.is_numeric(), "{}", f.name);
        }
    }

    /// A family shares one path when every varied name keeps it (and `Sharing::Shared`), and
    /// every run it builds follows that path; otherwise each run has its own.
    #[test]
    fn a_family_shares_its_path_only_when_every_varied_option_keeps_it() {
        let mut base = RunConfig::new(Motion::Wave(WaveConfig::default()));
        base.duration = Some(0.05);
        let values: &[f64] = &[0.0, 0.5];
        let scales: &[f64] = &[1.0, 2.0];
        let load = |names: &[(&str, &[f64])], sharing| Family::load(base.clone(), None, names, sharing).unwrap();
        let shared = load(&[("payload-kg", values), ("kp-scale", scales)], Sharing::Shared);
        let path = shared.path().expect("payload and a scale keep the path").clone();
        assert_eq!(path.len(), 4, "the samples at 0, 0.02, 0.04 and the last step, 0.05 s");
        let run = shared.build(&[0.5, 2.0]).unwrap();
        assert!(run.path_clearance.as_ref().is_some_and(|p| Arc::ptr_eq(p, &path)));
        for (names, sharing) in [
            (&[("payload-kg", values)][..], Sharing::Own),
            (
                &[("payload-kg", values), ("dt", &[2e-4, 1e-4][..])][..],
                Sharing::Shared,
            ),
            (&[("amp-deg", values)][..], Sharing::Shared),
        ] {
            let family = load(names, sharing);
            assert!(family.path().is_none(), "{names:?} {sharing:?}");
            assert!(
                family
                    .build(&vec![0.0002; names.len()])
                    .unwrap()
                    .path_clearance
                    .is_none()
            );
        }
    }
}
