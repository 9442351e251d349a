//! Fuzz target `parse_step`: its body is `pappus::fuzzing::run`, which the test suite replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pappus::fuzzing::run("parse_step", data));
