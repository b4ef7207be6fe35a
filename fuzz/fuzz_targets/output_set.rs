//! Arbitrary bytes as a script of outputs written through one `Outputs` set (the command line's
//! output layer). The code is `faze4::fuzzing::output_set`, shared with
//! `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::output_set(data);
});
