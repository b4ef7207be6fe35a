//! Writes the visual outputs of a synthetic run (no simulation: q from a wave or from IK on
//! SPEC's circle, see tests/viz_support) and times them:
//!
//!     cargo run --release --example viz_export -- circle real out.html [plot.svg|plot.png]
//!
//! `circle|wave`, `real|box|bare` (real: urdf/faze4_real.urdf with ../shared/faze4_description; bare: the
//! same without it).

#[path = "../tests/viz_support/mod.rs"]
mod viz_support;

use std::time::Instant;

use faze4::output::Recorder;
use faze4::viz::{HtmlExport, PlotRecorder};
use viz_support::*;

fn main() -> faze4::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_string());
    let model = match arg(1, "real").as_str() {
        "box" => box_model(),
        // the real-look URDF without its meshes: boxes, and one line on stderr
        "bare" => faze4::model::Model::from_urdf_file(
            &repo().join("urdf/faze4_real.urdf"),
            &faze4::model::PackagePaths::default(),
        )?,
        _ => real_model(),
    };
    let run = match arg(0, "circle").as_str() {
        "wave" => SyntheticRun::wave(model, 12.0, 25.0, 0.5),
        _ => SyntheticRun::circle(model, 12.0),
    };
    let html_path = arg(2, "faze4_synthetic.html");
    let started = Instant::now();
    let mut html = HtmlExport::new(&html_path)?;
    let mut recorders: Vec<Box<dyn Recorder>> = vec![];
    if let Some(plot) = args.get(3) {
        recorders.push(Box::new(PlotRecorder::new(plot)?));
    }
    let mut list: Vec<&mut dyn Recorder> = vec![&mut html];
    list.extend(recorders.iter_mut().map(|r| r.as_mut() as &mut dyn Recorder));
    run.drive(&mut list);
    let took = started.elapsed().as_secs_f64();
    let size = std::fs::metadata(&html_path).map(|m| m.len()).unwrap_or(0);
    println!("{html_path}: {size} bytes; all outputs written in {took:.3} s");
    Ok(())
}
