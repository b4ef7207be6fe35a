//! Arbitrary bytes as a `--motors FILE.toml`: parse and check against the bundled Faze4. The code is
//! `faze4::fuzzing::motors_file`, shared with `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::motors_file(data);
});
