//! Arbitrary bytes as a JSON trajectory file: `faze4::fuzzing::trajectory`.
#![no_main]
use faze4::fuzzing::{TrajectoryFormat::Json, trajectory};
libfuzzer_sys::fuzz_target!(|data: &[u8]| drop(trajectory(Json, data)));
