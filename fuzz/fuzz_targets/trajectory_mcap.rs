//! Arbitrary bytes as an MCAP file (or any bag its bytes say): `faze4::fuzzing::trajectory`.
#![no_main]
use faze4::fuzzing::{TrajectoryFormat::Mcap, trajectory};
libfuzzer_sys::fuzz_target!(|data: &[u8]| drop(trajectory(Mcap, data)));
