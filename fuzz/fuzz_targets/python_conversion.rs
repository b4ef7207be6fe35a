//! Arbitrary bytes as the Python binding's inputs without Python: keyword values as trees of
//! Python values (a motors dict, per-joint lists, numpy arrays, paths, …) into a run's
//! configuration, or a replay's arrays. The code is `faze4::fuzzing::python_conversion`, shared
//! with `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::python_conversion(data);
});
