//! `simulate` against `certify` on every shipped problem: random behaviours are behaviours
//! of the model, so where the analyser certifies, no run may come closer than the certified
//! lower bound on s*. Floats used to break this: a position on a danger threshold rounded
//! past it, the guard fired a period late and seed-lanes showed 0.46 m below s* = 0.48 m.

use serde_json::Value;

use crate::common::cli::{safereach, stdout};
use crate::common::paths::root;
use crate::common::tmp;

/// The JSON `safereach <args> --json` prints, with its exit code.
fn json(dir: &std::path::Path, args: &[&str]) -> (Value, i32) {
    let out = safereach(dir)
        .args(args)
        .arg("--json")
        .output()
        .expect("runs");
    let code = out.status.code().expect("exited");
    let value = serde_json::from_str(&stdout(&out)).unwrap_or(Value::Null);
    (value, code)
}

#[test]
fn no_random_run_comes_closer_than_a_certified_bound() {
    let dir = tmp();
    let mut problems: Vec<_> = std::fs::read_dir(root().join("problems"))
        .expect("problems/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    problems.sort();
    let mut certified = 0;
    for problem in &problems {
        let file = problem.to_str().expect("utf-8 path");
        let (cert, code) = json(dir.path(), &["certify", file]);
        // Grids (exit 2: not one problem) and refuted problems bound nothing.
        if code != 0 {
            continue;
        }
        certified += 1;
        let bound = cert["lower_bound"]
            .as_f64()
            .expect("a certified lower bound");
        let star = cert["min_separation"].as_f64().expect("s*");
        for seed in ["0", "3"] {
            let (mc, code) = json(
                dir.path(),
                &["simulate", file, "--runs", "200", "--seed", seed],
            );
            assert_eq!(code, 0, "{file} seed {seed}: a run collided");
            let seen = mc["min_separation"]
                .as_f64()
                .expect("a separation was seen");
            assert!(
                seen >= bound,
                "{file} seed {seed}: Monte Carlo saw {seen} m, below the certified {bound} m"
            );
            // A static obstacle has one behaviour: every run is the worst case.
            if file.ends_with("static-obstacle.toml") {
                assert_eq!(seen, star, "{file}: the one behaviour is the worst case");
            }
        }
    }
    assert!(
        certified >= 8,
        "only {certified} shipped problems certified"
    );
}
