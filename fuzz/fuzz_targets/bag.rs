//! The ROS 2 bag reader and the monitor behind it, on the seed's certificate: see
//! `safereach_fuzz::bag` for the properties.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| safereach_fuzz::bag::fuzz_bag(data));
