//! Arbitrary bytes as a ROS 1 bag: `faze4::fuzzing::trajectory`.
#![no_main]
use faze4::fuzzing::{TrajectoryFormat::Ros1, trajectory};
libfuzzer_sys::fuzz_target!(|data: &[u8]| drop(trajectory(Ros1, data)));
