//! Arbitrary bytes as a `.npy` trajectory. The code is `faze4::fuzzing::npy_samples`, shared
//! with `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::npy_samples(data);
});
