//! `retime` as both front ends run it: the path read as `replay` reads its file, the fastest
//! timing the motors follow ([`crate::retime::retime`], its closed-loop check included), the
//! timing written as a time-stamped trajectory file (`out`), the phase plane (`plot`), and the
//! run's other outputs (trail, summary, HTML, the motors' plot, the live view) from the
//! check's last run, taped ([`crate::sim::Tape`]): the run `replay` makes of the file, not
//! played again.

use super::{Finished, OUTPUT_FILES, Prepared, Recorders, write_summary};
use crate::atomic::Outputs;
use crate::config::{Loaded, Motion, Replayed, RunConfig};
use crate::error::{Error, Result};
use crate::retime::{Binding, PathSpline, Retimed, replay_scenario};
use crate::sim::{Recorder, StopFlag, Summary, Warning};
use crate::traj::files;
use crate::viz::PhasePlot;

/// What a retime gives back.
pub struct RetimeFinished {
    /// The timing, its bindings and its check.
    pub retimed: Retimed,
    /// The summary of the checked timing's run (the check's last); `None` under `no_check`.
    pub summary: Option<Summary>,
    /// The input's own timing (s): a time-stamped file's last time, a `.npy`'s `traj_period`.
    pub own_duration: Option<f64>,
    /// The outputs' recorders, handed the check's last run, when any was asked for (trail,
    /// HTML, motors' plot, view).
    pub replayed: Option<Finished>,
    /// Whether the timing was written to `out`: asked for, and the checked timing follows (or
    /// under `no_check`, keeps every limit as played), or `force` writes it anyway.
    pub written: bool,
}

impl RetimeFinished {
    /// Whether the answer is a timing to use: the checked timing follows (a check a stop ended
    /// early has no verdict), or, unchecked (`no_check`), it keeps every limit as a controller
    /// plays it.
    pub fn follows(&self) -> bool {
        match &self.summary {
            Some(summary) => summary.interrupted_at_s.is_none() && summary.verdict.follows,
            None => self.retimed.played.worst <= KEPT,
        }
    }
}

/// Retimes the path `config` (a [`Motion::Retime`]) names, or `replayed`, into `files` (the
/// caller commits them): every output path claimed first, `warn` told the warnings, then the
/// timing found and checked (unless `no_check`, which refuses a run's outputs), `out` written
/// when the checked timing follows (unchecked: keeps every limit as played) or `force` asks,
/// `plot` written, and, when the trail, HTML, the
/// motors' plot, the live view or `extra` recorders are asked for, the check's last run handed
/// to them from its tape, as the run of the written file (`replay`'s scenario) would hand it.
pub fn retime(
    config: &RunConfig,
    replayed: Option<Replayed>,
    files: &Outputs,
    extra: &mut [&mut dyn Recorder],
    stop: &StopFlag,
    warn: impl FnOnce(&[Warning]),
) -> Result<RetimeFinished> {
    let Motion::Retime(r) = &config.motion else {
        return Err(Error::argument(
            "retime",
            format!("cannot retime a {}", config.motion.name()),
        ));
    };
    let loaded = Loaded::load(config, replayed)?;
    let base = loaded.builder(config)?;
    // retime has no `duration` (the timing's is found): one second, or one step of a longer `dt`
    let start = base.clone().duration(base.time_step().max(1.0)).build()?;
    let out = &config.outputs;
    // the timing and the figure never replace what was read (the path, the URDF, …)
    files.reading(loaded.inputs().clone())?;
    for (path, field) in [(r.out.as_ref(), "out"), (out.plot.as_ref(), "plot")] {
        if let Some(path) = path {
            files.claim(path, &format!("`{field}`"))?;
        }
    }
    let plot = out.plot.as_ref().map(PhasePlot::new).transpose()?;
    // the run's own outputs, opened by session::run (the figure is the phase plane here)
    let mut played_config = config.clone();
    played_config.outputs.plot = None;
    let records = (OUTPUT_FILES.iter()).any(|output| output.records && (output.path)(&played_config).is_some())
        || out.view
        || out.hold
        || !extra.is_empty();
    let mut warnings = start.warnings.clone();
    warnings.extend(loaded.warnings.iter().cloned());
    let model = &start.model;
    let path = PathSpline::through(&loaded.path_points(model, &r.path.q_traj)?)?;
    if r.no_check && records {
        return Err(Error::option(
            "no_check",
            "plays no run: a run's outputs (summary, trail, HTML, the motors' plot, the view, a returned run) need the check",
        ));
    }
    // the outputs are handed the last check run, taped, rather than a run played again
    let mut options = r.options(stop.clone());
    if records {
        let reads = Recorders::read_intersections(&played_config) || extra.iter().any(|r| r.reads_intersections());
        options.tape = Some(reads);
    }
    let mut retimed = crate::retime::retime(&base, &path, &options)?;
    let summary = retimed.check.as_ref().map(|c| c.summary.clone());
    let tape = retimed.check.as_mut().and_then(|c| c.tape.take());
    // the outputs are written from here on: a signal stops the run, not the process
    stop.watch();
    let interrupted = summary.as_ref().is_some_and(|s| s.interrupted_at_s.is_some());
    // the run `replay` makes of the written file, which the outputs are handed
    let prepared = || -> Result<Prepared> {
        Ok(Prepared {
            config: played_config,
            scenario: replay_scenario(&base, &retimed.trajectory)?,
            warnings: warnings.clone(),
            inputs: loaded.inputs().clone(),
        })
    };
    let replayed = match (records && !interrupted, tape, &summary) {
        (true, Some(tape), Some(summary)) => {
            let finished = super::run_with(&prepared()?, files, extra, stop, warn, |scenario, recorders| {
                tape.play(scenario, recorders, summary)?;
                Ok(summary.clone())
            })?;
            Some(finished)
        }
        // a check run too long to tape (`Tape::fits`): the timing played again, as deterministic
        (true, None, Some(_)) => Some(super::run(&prepared()?, files, extra, stop, warn)?),
        _ => {
            warn(&warnings);
            if let (Some(path), Some(summary)) = (&out.summary, &summary) {
                write_summary(files, path, summary)?;
            }
            None
        }
    };
    let mut finished = RetimeFinished {
        own_duration: loaded.own_duration(r.path.traj_period),
        retimed,
        summary,
        replayed,
        written: false,
    };
    // a timing that does not follow is written only when asked to (`force`); one whose check a
    // stop ended early, never
    finished.written = r.out.is_some() && !interrupted && (finished.follows() || r.force);
    if let (Some(path), true) = (&r.out, finished.written) {
        files::write_within(files, path, &finished.retimed.trajectory)?;
    }
    if let Some(plot) = plot {
        let names: Vec<String> = model.joints.iter().map(|j| j.name.clone()).collect();
        plot.within(files)
            .write(&finished.retimed, &model.name, &names, r.margin)?;
    }
    Ok(finished)
}

/// A share of a limit this close to 1 is the limit itself (round-off of the profile's own
/// bounds).
const KEPT: f64 = 1.0 + 1e-6;

/// What the written trajectory asks of the limits as a controller plays it (a quintic between
/// its points, checked every 1/[`crate::retime::SAMPLES`] of an interval), beyond the grid points where
/// the timing keeps them.
fn played_line(played: &crate::retime::Played) -> String {
    let how = format!(
        "as played (quintic between the written points, checked every 1/{} of an interval)",
        crate::retime::SAMPLES
    );
    if played.worst <= KEPT {
        return format!("{how}: every limit kept, at most {:.3} of one\n", played.worst);
    }
    let share = match played.worst.is_finite() {
        true => format!("up to {:.2}x", played.worst),
        false => String::from("beyond (its motor gives no torque that way at that speed)"),
    };
    format!(
        "{how}: {share} J{}'s {} limit (less the margin) at t = {:.3} s; the timing keeps the limits at its grid points only\n",
        played.joint + 1,
        played.limit,
        played.t
    )
}

/// The lines a retime prints before its verdict: the duration and the speed-up over the
/// input's own timing, what binds along the path (consecutive segments with the same limit
/// as one range of s and t), and the check (and whether `out` was written; options named as
/// `field`, for each front end to show in its own words).
pub fn retime_lines(finished: &RetimeFinished, out: Option<&std::path::Path>) -> String {
    let retimed = &finished.retimed;
    let p = &retimed.profile;
    let duration = p.duration();
    let mut text = format!(
        "retime: {duration:.4} s over {} grid intervals of s in [0, {:.4}]",
        p.u.len(),
        p.s.last().copied().unwrap_or(0.0)
    );
    if let Some(own) = finished.own_duration {
        text.push_str(&format!("; the input's own timing {own:.4} s ({:.2}x)", own / duration));
    }
    text.push_str(&format!(
        "; none is faster than {:.4} s (the relaxed bound: every torque limit at its standstill value)\n",
        retimed.relaxed_duration
    ));
    let (start, end) = (p.x[0].sqrt(), p.x[p.x.len() - 1].sqrt());
    if start > 0.0 {
        text.push_str(&format!(
            "starts moving at ṡ = {start:.4} (`start_velocity`): the check's arm arrives at the path's start at that velocity, on the path, without tracking error\n"
        ));
    }
    if end > 0.0 {
        text.push_str(&format!(
            "ends moving at ṡ = {end:.4} (`end_velocity`): the check stops at the last point; what follows it (the next segment) is not checked here\n"
        ));
    }
    for (first, last, binding) in ranges(&retimed.bindings) {
        let what = match binding.binds() {
            true => binding.to_string(),
            false => format!("towards a limit further on ({binding} nearest)"),
        };
        text.push_str(&format!(
            "  s {:>8.4} to {:>8.4}   t {:>7.4} to {:>7.4} s   {what}\n",
            p.s[first],
            p.s[last + 1],
            p.t[first],
            p.t[last + 1]
        ));
    }
    text.push_str(&played_line(&retimed.played));
    if let Some(c) = &retimed.check {
        text.push_str(&format!(
            "checked in the closed loop: {} run{}, {} grid point{} slowed{}\n",
            c.attempts,
            if c.attempts == 1 { "" } else { "s" },
            c.slowed_points,
            if c.slowed_points == 1 { "" } else { "s" },
            match c.summary.interrupted_at_s {
                Some(_) => written(out, false, "the check was stopped", ""),
                None => written(out, finished.written, "it does not follow", " (`force` writes it)"),
            }
        ));
    } else {
        text.push_str(&format!(
            "not checked in the closed loop (`no_check`): whether the loop follows it is not known (replay it to know){}\n",
            written(out, finished.written, "it passes a limit as played", " (`force` writes it)")
        ));
    }
    text
}

/// What the check's line says of `out`: written, or not, `why`, and what would write it.
fn written(out: Option<&std::path::Path>, written: bool, why: &str, hint: &str) -> String {
    match (out, written) {
        (None, _) => String::new(),
        (Some(p), true) => format!("; wrote {}", crate::error::shown_path(p)),
        (Some(p), false) => format!("; {why}: nothing is written to {}{hint}", crate::error::shown_path(p)),
    }
}

/// Consecutive segments that the same limit shapes, as (first, last, binding).
fn ranges(bindings: &[Binding]) -> Vec<(usize, usize, Binding)> {
    let mut ranges: Vec<(usize, usize, Binding)> = Vec::new();
    for (i, b) in bindings.iter().enumerate() {
        match ranges.last_mut() {
            Some((_, last, r)) if r.joint == b.joint && r.limit == b.limit && r.binds() == b.binds() => *last = i,
            _ => ranges.push((i, i, *b)),
        }
    }
    ranges
}
