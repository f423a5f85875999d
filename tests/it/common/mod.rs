//! The scaffolding the integration tests share, written once: the problem builder and the
//! random problems ([`spec`]), where files are ([`paths`]), the committed fixtures
//! ([`fixtures`]), the command runner ([`cli`]), certificate forgeries ([`forgery`]),
//! points of region maps ([`map_points`]), feeding trace text to the monitor
//! ([`monitoring`]), a deterministic generator ([`split_mix`]) and its exact rational draws
//! ([`rational_draws`]).
//!
//! Nothing here needs the solver or the binary at compile time, so `tests/lean` (built
//! without default features) and `tests/brute_force.rs` include this module too, by path.

pub mod cli;
pub mod fixtures;
pub mod forgery;
pub mod line_in_plane;
pub mod map_points;
pub mod monitoring;
pub mod paths;
pub mod planar_oracle;
pub mod rational_draws;
pub mod spec;
pub mod split_mix;

use tempfile::TempDir;

/// `text` with each `(from, to)` applied once; every `from` must occur.
pub fn edit(text: &str, edits: &[(&str, &str)]) -> String {
    let mut text = text.to_string();
    for (from, to) in edits {
        assert!(text.contains(from), "`{from}` is not in the text");
        text = text.replacen(from, to, 1);
    }
    text
}

/// A fresh temporary directory, removed when dropped.
pub fn tmp() -> TempDir {
    tempfile::tempdir().expect("a temporary directory")
}

/// An exact rational's text (`"n"` or `"n/d"`, as certificates write them) as a float.
pub fn rational(text: &str) -> f64 {
    match text.split_once('/') {
        Some((n, d)) => n.parse::<f64>().unwrap() / d.parse::<f64>().unwrap(),
        None => text.parse().unwrap(),
    }
}
