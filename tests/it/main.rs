//! The integration tests, one module a file, in one test binary: the library is linked once for
//! all of them instead of once for each (issue 47). Three tests keep a binary of their own:
//! `tests/browser.rs` and `tests/slurm.rs` have their own `main` (`harness = false`: a missing
//! Chromium or Slurm is one visible line), and `tests/panic_hook.rs` replaces the process's panic
//! hook. Run one file's tests with `cargo test --test it NAME::` (e.g. `cargo test --test it
//! docs::`). The modules share one process: each writes under a directory of its own
//! (`common::temp_dir` names it after the module).

#[path = "../common/mod.rs"]
mod common;
// also used by benches/viz.rs
#[path = "../viz_support/mod.rs"]
mod viz_support;

mod all_or_nothing;
mod any_arm;
mod arm_facts;
mod bags;
mod clearance;
mod clearance_run_oracle;
mod cli;
mod closed_loop_vs_drake;
mod contact;
mod contact_solver;
mod core_vs_drake;
mod coupled_stability;
mod docs;
mod fuzz_regressions;
mod hostile;
mod ik_shapes;
mod kubernetes;
mod mimic;
mod mjcf;
mod model_errors;
mod motors;
mod motors_drive;
mod motors_pairing;
mod properties;
mod real_model;
mod retime;
mod retime_chain;
mod retime_drive;
mod retime_played;
mod retime_vs_ruckig;
mod retime_vs_toppra;
mod rotor_inertia;
mod self_clearance;
mod servo;
mod spec_faze4;
mod speed;
mod step_api;
mod stepper_oracle;
mod sweep;
mod sweep_clearance;
mod trajectories;
mod verdict;
mod viz;
mod wave_center;
mod xacro;
