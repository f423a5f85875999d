//! The problem and scene readers, with and without a `--set` override: see
//! `safereach_fuzz::problem` for the input and the properties.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| safereach_fuzz::problem::fuzz_problem(data));
