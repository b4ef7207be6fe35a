//! Arbitrary bytes as a rosbag2 SQLite database (`.db3`): `faze4::fuzzing::trajectory`.
#![no_main]
use faze4::fuzzing::{TrajectoryFormat::Db3, trajectory};
libfuzzer_sys::fuzz_target!(|data: &[u8]| drop(trajectory(Db3, data)));
