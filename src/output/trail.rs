//! The trail CSV: `t,x,y,z,q1,…,qN` (tool origin in the world, measured joints), one row per
//! record period, including t = 0 and the last step; `--debug` adds τ, error, v and g columns.

use std::io::Write;
use std::path::Path;

use super::format::push_exact;
use crate::atomic::{AtomicFile, Outputs};
use crate::sim::{Recorder, RunInfo, Sample, Summary};

/// Streams rows into a temporary file and renames it into place at the end, so memory does
/// not grow with the run and a failed run leaves no half file.
pub struct TrailCsv {
    file: Option<AtomicFile>,
    record_period: f64,
    debug: bool,
    rows: usize,
    line: String,
}

impl TrailCsv {
    /// A trail written to `path` on its own, a row every `record_period` seconds.
    pub fn create(path: &Path, record_period: f64, debug: bool) -> crate::Result<Self> {
        Self::within(&Outputs::immediate(), path, record_period, debug)
    }

    /// A trail written to `path` as a file of `outputs` (it appears when they are committed).
    pub fn within(outputs: &Outputs, path: &Path, record_period: f64, debug: bool) -> crate::Result<Self> {
        Ok(Self {
            file: Some(outputs.create(path)?),
            record_period,
            debug,
            rows: 0,
            line: String::new(),
        })
    }

    /// Rows written so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    fn write_line(&mut self) -> crate::Result<()> {
        let file = self.file.as_mut().expect("open until finish");
        self.line.push('\n');
        let result = file.writer().write_all(self.line.as_bytes());
        result.map_err(|e| file.error(e))?;
        self.line.clear();
        Ok(())
    }
}

impl Recorder for TrailCsv {
    fn period(&self) -> f64 {
        self.record_period
    }

    fn begin(&mut self, run: &RunInfo) -> crate::Result<()> {
        let n = run.model.dof();
        let mut columns: Vec<String> = ["t", "x", "y", "z"].iter().map(|s| s.to_string()).collect();
        columns.extend((1..=n).map(|i| format!("q{i}")));
        if self.debug {
            for prefix in ["tau", "err", "v", "g"] {
                columns.extend((1..=n).map(|i| format!("{prefix}{i}")));
            }
        }
        self.line = columns.join(",");
        self.write_line()
    }

    fn record(&mut self, s: &Sample) -> crate::Result<()> {
        // shortest round-trip decimals: the file holds the simulation's exact values
        let mut push = |x: f64| {
            push_exact(&mut self.line, x);
            self.line.push(',');
        };
        push(s.t);
        s.tool.iter().for_each(|&x| push(x));
        s.q.iter().for_each(|&x| push(x));
        if self.debug {
            s.tau.iter().for_each(|&x| push(x));
            s.q_cmd.iter().zip(s.q).for_each(|(c, q)| push(c - q));
            s.v.iter().for_each(|&x| push(x));
            s.g.iter().for_each(|&x| push(x));
        }
        self.line.pop();
        self.rows += 1;
        self.write_line()
    }

    fn finish(&mut self, _summary: &Summary) -> crate::Result<()> {
        self.file.take().expect("finished once").commit()
    }
}
