//! The certificate reader and `check`, and the region map checker: see
//! `safereach_fuzz::certificate` for the input and the properties.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| safereach_fuzz::certificate::fuzz_certificate(data));
