//! Arbitrary bytes as a COLLADA (.dae) mesh: its claims checked, parse, weld, check. The code is
//! `faze4::fuzzing::dae_mesh`, shared with `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::dae_mesh(data);
});
