//! Arbitrary bytes as a mesh file: the first byte picks STL, COLLADA or OBJ, the rest is the
//! file; parse (mesh-loader), weld, check. The code is `faze4::fuzzing::mesh_file`, shared with
//! `tests/it/fuzz_regressions.rs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = faze4::fuzzing::mesh_file(data);
});
