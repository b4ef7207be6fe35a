//! Sweeps: many runs of one experiment with some options varied over a grid, run on every
//! core, each run a row of a table; the search for the largest (or smallest) value of an option
//! at which the arm still follows; and the deterministic parts (shards) a sweep splits into
//! for a cluster's job array. No command line here: the binary's `cli` and the Python binding map
//! their arguments onto this.

mod base;
mod family;
mod find;
mod grid;
mod merge;
mod part;
mod table;

pub use base::{Family, Knob, Searched, Sharing, known_names, refuse_given_and_varied, search, threads, varied_fields};
pub use family::{Build, Outcome, Row, Runner, Scale};
pub use find::{Found, Seek, find};
pub use grid::{Axis, Grid, MAX_AXIS_VALUES, Shard};
pub use merge::{Merged, merge};
pub use part::{PartMeta, fingerprint, meta_path};
pub use table::{Cell, Cells, Format, TableWriter, cells};

/// Most runs one process takes without `--shard`.
pub const MAX_RUNS: usize = 1_000_000;
