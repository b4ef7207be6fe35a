//! Arbitrary bytes as an STL mesh (binary or ASCII): parse, weld, check. The code is
//! `faze4::fuzzing::stl_mesh`, shared with `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::stl_mesh(data);
});
