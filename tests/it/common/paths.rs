//! Where the tests find the crate's own files: the manifest directory, the shipped problem
//! files and the committed fixtures, by absolute path (tests run in temporary directories).

use std::path::PathBuf;

use safereach::core::model::Problem;

/// The crate's root (the manifest directory).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `problems/<name>`.
pub fn problem_file(name: &str) -> PathBuf {
    root().join("problems").join(name)
}

/// `problems/seed.toml`.
pub fn seed_file() -> PathBuf {
    problem_file("seed.toml")
}

/// `problems/<name>` loaded with `sets` applied (each `dotted.key=value`, as `--set`).
pub fn load_problem(name: &str, sets: &[&str]) -> Problem {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Problem::load_with_overrides(&problem_file(name), &sets).expect("problem loads")
}

/// `tests/fixtures/<name>`.
pub fn fixture(name: &str) -> PathBuf {
    root().join("tests").join("fixtures").join(name)
}
