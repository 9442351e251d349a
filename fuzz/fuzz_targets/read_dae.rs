//! Fuzz target `read_dae`: its body is `pappus::fuzzing::run`, which the test suite replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pappus::fuzzing::run("read_dae", data));
