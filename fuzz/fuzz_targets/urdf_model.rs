//! Arbitrary bytes as a URDF: parse, validate, then run every algorithm on what was accepted.
//! The code is `faze4::fuzzing::urdf_model`, shared with `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::urdf_model(data);
});
