//! Arbitrary bytes as a YAML trajectory file: `faze4::fuzzing::trajectory`.
#![no_main]
use faze4::fuzzing::{TrajectoryFormat::Yaml, trajectory};
libfuzzer_sys::fuzz_target!(|data: &[u8]| drop(trajectory(Yaml, data)));
