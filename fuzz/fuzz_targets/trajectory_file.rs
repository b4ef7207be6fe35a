//! Arbitrary bytes as a time-stamped trajectory file (`replay --q-traj F.yaml|json|mcap|csv`):
//! the first byte picks the format. The code is `faze4::fuzzing::trajectory_file`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::trajectory_file(data);
});
