//! The sweep grid loader: see `safereach_fuzz::grid` for the input and the properties.
#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;

/// The repository's `problems/`, where the fuzzed grid is read as if it were.
fn problems() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../problems"))
            .canonicalize()
            .expect("the problems directory exists")
    })
}

fuzz_target!(|data: &[u8]| safereach_fuzz::grid::fuzz_grid(data, problems()));
