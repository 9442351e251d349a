//! Fuzz target `read_glb`: its body is `pappus::fuzzing::run`, which the test suite replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pappus::fuzzing::run("read_glb", data));
