//! The `safereach` binary, run as a user runs it (through `assert_cmd`), and what the tests
//! read back from a run.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Output;

use assert_cmd::Command;

/// The binary, run in `dir`.
pub fn safereach(dir: &Path) -> Command {
    let mut cmd = Command::cargo_bin("safereach").expect("the safereach binary is built");
    cmd.current_dir(dir);
    cmd
}

/// `safereach region` on the seed over the box of issue 11's first example, W ∈ [0.10, 0.20]
/// × ρ ∈ [1.3, 1.6] (certified whole), with `args` added; exit 0 asserted.
pub fn seed_box_region(dir: &Path, args: &[&str]) -> Output {
    safereach(dir)
        .arg("region")
        .arg(super::paths::seed_file())
        .args([
            "--range",
            "environment.obstacle_speed=0.10..0.20",
            "--range",
            "controller.reaction_radius=1.3..1.6",
        ])
        .args(args)
        .assert()
        .code(0)
        .get_output()
        .clone()
}

/// The names of the files in `dir`.
pub fn files(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("readable")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

/// A run's standard output as text.
pub fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("UTF-8 output")
}

/// Runs `safereach <command> <problem> <args>` in `dir` for each `(args, needle)` of `cases`:
/// each run must exit 2 (bad input) and name `needle` on standard error.
pub fn bad_input_exits_2(dir: &Path, command: &str, problem: &Path, cases: &[(Vec<&str>, &str)]) {
    for (args, needle) in cases {
        let out = safereach(dir)
            .arg(command)
            .arg(problem)
            .args(args)
            .assert()
            .code(2)
            .get_output()
            .clone();
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}
