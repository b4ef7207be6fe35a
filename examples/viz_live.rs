//! The live view of a synthetic run (no simulation: q from a wave or from IK on SPEC's circle,
//! see tests/viz_support), paced to the wall clock; `hold` keeps serving until Ctrl-C:
//!
//!     cargo run --release --example viz_live -- circle real 7000 hold
//!
//! `circle|wave`, `real|box|bare` (real: urdf/faze4_real.urdf with ../shared/faze4_description; bare: the
//! same without it).

#[path = "../tests/viz_support/mod.rs"]
mod viz_support;

use faze4::viz::{DEFAULT_PORT, LiveView};
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
    let port = arg(2, &DEFAULT_PORT.to_string())
        .parse()
        .map_err(|_| faze4::Error::argument("port", "not a port number"))?;
    let mut live = LiveView::start(port)?;
    run.drive(&mut [&mut live]);
    if arg(3, "") == "hold" {
        live.hold();
    }
    Ok(())
}
