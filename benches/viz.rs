//! Time to write the HTML export of the 3D view's budget case: a 12 s circle recorded every
//! 0.02 s (601 samples) with the official meshes (reading the STL files included):
//! `cargo bench --bench viz`. Also the plot of the same run, as SVG and PNG.

#[path = "../tests/common/mod.rs"]
mod common;
#[path = "../tests/viz_support/mod.rs"]
mod viz_support;

use criterion::{Criterion, criterion_group, criterion_main};
use faze4::viz::{HtmlExport, PlotRecorder};
use viz_support::*;

fn exports(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("faze4-bench-viz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = SyntheticRun::circle(real_model(), 12.0);
    let mut group = c.benchmark_group("viz");
    group.sample_size(10);
    group.bench_function("html_export_12s_circle_real_meshes", |b| {
        b.iter(|| {
            let mut html = HtmlExport::new(dir.join("circle.html")).unwrap();
            run.drive(&mut [&mut html]);
        })
    });
    for ext in ["svg", "png"] {
        group.bench_function(format!("plot_12s_circle_{ext}"), |b| {
            b.iter(|| {
                let mut plot = PlotRecorder::new(dir.join(format!("circle.{ext}"))).unwrap();
                run.drive(&mut [&mut plot]);
            })
        });
    }
    group.finish();
    if let Ok(m) = std::fs::metadata(dir.join("circle.html")) {
        println!("circle.html: {} bytes", m.len());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

criterion_group!(benches, exports);
criterion_main!(benches);
