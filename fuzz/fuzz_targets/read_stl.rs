//! Fuzz target `read_stl`: its body is `pappus::fuzzing::run`, which the test suite replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pappus::fuzzing::run("read_stl", data));
