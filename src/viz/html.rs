//! `--html F`: one self-contained HTML file with the scene, the motion and the player.

use std::path::{Path, PathBuf};

use serde_json::json;

use super::scene::{SampleEncoder, Scene};
use super::util::{base64, f32_bytes};
use super::{DEFAULT_PERIOD, page};
use crate::atomic::{Outputs, check_output_path};
use crate::error::{Result, escape_controls};
use crate::sim::Summary;
use crate::sim::{Recorder, RunInfo, Sample, steps_per_record};

/// Records a run and writes it, on [`Recorder::finish`], as one HTML file that plays it back
/// offline (WebGL2; geometry, motion and player inside, no network).
#[derive(Debug)]
pub struct HtmlExport {
    path: PathBuf,
    outputs: Outputs,
    period: f64,
    scene: Option<Scene>,
    encoder: Option<SampleEncoder>,
    records: Vec<f32>,
}

impl HtmlExport {
    /// An export to `path`, recording every [`DEFAULT_PERIOD`] s. Fails at once (before the
    /// run) when the file's directory does not exist.
    pub fn new(path: impl Into<PathBuf>) -> Result<HtmlExport> {
        let path = path.into();
        check_output_path(&path, "`html`")?;
        Ok(HtmlExport {
            path,
            outputs: Outputs::immediate(),
            period: DEFAULT_PERIOD,
            scene: None,
            encoder: None,
            records: Vec::new(),
        })
    }

    /// Records every `period` seconds of simulated time instead.
    pub fn with_period(mut self, period: f64) -> HtmlExport {
        self.period = period;
        self
    }

    /// Writes the page as a file of `outputs` (it appears when they are committed) instead of
    /// on its own.
    pub fn within(mut self, outputs: &Outputs) -> HtmlExport {
        self.outputs = outputs.clone();
        self
    }

    /// The file this export writes.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Recorder for HtmlExport {
    fn period(&self) -> f64 {
        self.period
    }

    fn begin(&mut self, run: &RunInfo) -> Result<()> {
        let scene = Scene::for_run(run, self.period);
        scene.warn_fallbacks();
        self.encoder = Some(SampleEncoder::new(run.model, &scene.slots).collision_pairs(run.collision_pairs));
        self.records = Vec::with_capacity(
            (run.steps / steps_per_record(self.period, run.dt) + 2) * self.encoder.as_ref().unwrap().stride(),
        );
        self.scene = Some(scene);
        Ok(())
    }

    fn reads_intersections(&self) -> bool {
        true
    }

    fn record(&mut self, sample: &Sample) -> Result<()> {
        if let Some(enc) = &mut self.encoder {
            enc.push(sample, &mut self.records);
        }
        Ok(())
    }

    fn finish(&mut self, summary: &Summary) -> Result<()> {
        let Some(scene) = &self.scene else {
            return Ok(());
        };
        let config = json!({ "mode": "export", "summary": summary });
        let title = format!(
            "faze4 · {} · {}",
            scene.name,
            scene.run["command"].as_str().unwrap_or("run")
        );
        let title = escape_controls(&title);
        let scene_b64 = base64(&scene.encode());
        let samples_b64 = base64(&f32_bytes(&self.records));
        let mut file = self.outputs.create(&self.path)?;
        page::write(file.writer(), &title, &config, &scene_b64, &samples_b64).map_err(|e| file.error(e))?;
        file.commit()
    }
}
