//! Arbitrary bytes as a Wavefront OBJ mesh: its face references checked, parse, weld, check. The code is
//! `faze4::fuzzing::obj_mesh`, shared with `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::obj_mesh(data);
});
