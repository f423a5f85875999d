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
