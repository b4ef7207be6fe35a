//! Arbitrary bytes as a CSV trajectory file: `faze4::fuzzing::trajectory`.
#![no_main]
use faze4::fuzzing::{TrajectoryFormat::Csv, trajectory};
libfuzzer_sys::fuzz_target!(|data: &[u8]| drop(trajectory(Csv, data)));
