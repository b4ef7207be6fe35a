//! Converts a time-stamped trajectory between the formats faze4 reads (docs/trajectories.md):
//! `.yaml` (as `ros2 topic echo` prints it), `.json`, `.mcap` (rosbag2) and `.csv`. The oracle
//! (`tools/oracle/trajectory_fixtures.py`) reads what it writes with PyYAML and the `mcap` /
//! `mcap-ros2-support` readers.
//!
//!     cargo run --example convert_trajectory -- IN OUT [--message K] [--topic NAME]

use std::path::PathBuf;

use faze4::traj::files::{self, Selection};

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut paths, mut selection) = (Vec::new(), Selection::default());
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--message" => selection.message = args.next().and_then(|k| k.parse().ok()),
            "--topic" => selection.topic = args.next(),
            _ => paths.push(PathBuf::from(arg)),
        }
    }
    let [input, output] = paths.as_slice() else {
        eprintln!("usage: convert_trajectory IN OUT [--message K] [--topic NAME]");
        std::process::exit(2);
    };
    let converted = files::read(input, &selection).and_then(|t| files::write(output, &t));
    if let Err(e) = converted {
        eprintln!("convert_trajectory: {e}");
        std::process::exit(2);
    }
}
