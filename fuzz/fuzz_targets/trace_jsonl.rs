//! The JSON Lines trace reader and the monitor behind it, on the seed's certificate: see
//! `safereach_fuzz::trace` for the properties.
#![no_main]

use libfuzzer_sys::fuzz_target;
use safereach::monitor::trace::Format;

fuzz_target!(|data: &[u8]| safereach_fuzz::trace::fuzz_trace(data, Format::Jsonl));
