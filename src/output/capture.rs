//! The trail kept in memory: the rows of the trail CSV (t, tool origin, q) and the command
//! q_cmd, as flat arrays (the Python binding's `Run.t`, `Run.q`, `Run.q_cmd`, `Run.tool_xyz`).

use crate::sim::{Recorder, RunInfo, Sample};

/// Records at the trail's samples, one row per record period (t = 0 and the last step
/// included), row-major.
#[derive(Clone, Debug, Default)]
pub struct Capture {
    record_period: f64,
    /// Joints per row of `q` and `q_cmd`.
    pub dof: usize,
    /// Simulated time of each row (s).
    pub t: Vec<f64>,
    /// Measured joint positions, `dof` per row.
    pub q: Vec<f64>,
    /// Commanded joint positions, `dof` per row.
    pub q_cmd: Vec<f64>,
    /// Tool frame origin in the world, 3 per row (m).
    pub tool_xyz: Vec<f64>,
}

impl Capture {
    /// A capture with a row every `record_period` seconds (the trail's `--record-period`).
    pub fn new(record_period: f64) -> Self {
        Capture {
            record_period,
            ..Capture::default()
        }
    }

    /// Rows recorded.
    pub fn rows(&self) -> usize {
        self.t.len()
    }
}

impl Recorder for Capture {
    fn period(&self) -> f64 {
        self.record_period
    }

    fn begin(&mut self, run: &RunInfo) -> crate::Result<()> {
        self.dof = run.model.dof();
        Ok(())
    }

    fn record(&mut self, sample: &Sample) -> crate::Result<()> {
        self.t.push(sample.t);
        self.q.extend_from_slice(sample.q);
        self.q_cmd.extend_from_slice(sample.q_cmd);
        self.tool_xyz
            .extend_from_slice(&[sample.tool[0], sample.tool[1], sample.tool[2]]);
        Ok(())
    }
}
