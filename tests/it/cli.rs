//! The `safereach` command, run as a user runs it: every call is the real binary in a
//! fresh temporary directory, with the shipped problem files given by absolute path.
//!
//! Exit codes (src/main.rs): `certify` 0 certified, 1 refuted, 3 inconclusive; `check`
//! 0 valid, 1 invalid; `simulate` 0 no collision, 1 a collision; 2 bad input.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use predicates::prelude::*;
use safereach::analysis::Verdict;
use safereach::core::model::Problem;
use safereach::proof::certificate::{Certificate, check};
use serde_json::Value;

use crate::common::cli::{files, safereach, stdout};
use crate::common::paths::{problem_file, seed_file};
use crate::common::tmp;

/// Runs `certify` with `args` and parses its `--json` output; checks the exit code.
fn certify_json(dir: &Path, args: &[&str], code: i32) -> (Certificate, Value) {
    let out = safereach(dir)
        .arg("certify")
        .args(args)
        .arg("--json")
        .assert()
        .code(code)
        .get_output()
        .clone();
    let text = stdout(&out);
    let cert: Certificate = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("--json is not a certificate ({e}):\n{text}"));
    let value: Value = serde_json::from_str(&text).expect("JSON");
    (cert, value)
}

/// Writes the seed's certificate to `dir/cert.json`.
fn write_seed_certificate(dir: &Path) -> PathBuf {
    safereach(dir)
        .args(["certify"])
        .arg(seed_file())
        .args(["--out", "cert.json"])
        .assert()
        .code(0);
    dir.join("cert.json")
}

// ------------------------------------------------------------------------------------------
// certify
// ------------------------------------------------------------------------------------------

#[test]
fn certify_seed_is_certified() {
    let dir = tmp();
    safereach(dir.path())
        .arg("certify")
        .arg(seed_file())
        .assert()
        .code(0)
        .stdout(predicate::str::contains("seed: certified"))
        .stdout(predicate::str::contains("worst-case minimum separation"));
    assert!(
        files(dir.path()).is_empty(),
        "certify without --out writes nothing"
    );
}

#[test]
fn certify_json_is_a_certificate_with_the_documented_fields() {
    let dir = tmp();
    let (cert, value) = certify_json(dir.path(), &[seed_file().to_str().unwrap(), "--steps"], 0);
    assert_eq!(cert.verdict, Verdict::Certified);
    assert_eq!(value["verdict"], "certified");

    // s* and the rigorous bound: the bound is below s* (by at most the replay tolerance)
    // and above the clearance.
    let s = cert.min_separation.expect("min_separation");
    let lb = cert.lower_bound.expect("lower_bound");
    assert!(lb <= s + 1e-6, "lower bound {lb} above s* {s}");
    assert!(lb > cert.clearance, "certified with bound {lb}");
    assert!((s - lb).abs() < 1e-6, "s* {s} vs bound {lb}");
    assert_eq!(value["clearance"], 0.0);

    // The problem it answers is the file's.
    let file = Problem::load(&seed_file()).expect("seed loads");
    assert_eq!(cert.problem, file);

    // premises: [{name, bound, unit}]
    let premises = value["premises"].as_array().expect("premises array");
    assert!(!premises.is_empty());
    for p in premises {
        assert!(p["name"].is_string(), "{p}");
        assert!(p["bound"].is_number(), "{p}");
        assert!(p["unit"].is_string(), "{p}");
    }
    let speed = premises
        .iter()
        .find(|p| p["name"] == "obstacle_speed")
        .expect("an obstacle_speed premise");
    assert_eq!(speed["bound"], 0.15);
    assert_eq!(speed["unit"], "m/s");

    // witness.steps: one row per control-period start, plus the instant of rest.
    let steps = value["witness"]["steps"].as_array().expect("witness.steps");
    assert!(steps.len() > 2);
    let keys: BTreeSet<&str> = [
        "t",
        "robot_position",
        "robot_speed",
        "robot_mode",
        "obstacle_position",
        "obstacle_speed",
        "gap",
    ]
    .into();
    for step in steps {
        let have: BTreeSet<&str> = step
            .as_object()
            .expect("a step is an object")
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(have, keys, "{step}");
        let f = |k: &str| step[k].as_f64().expect("a number");
        assert!(
            (f("obstacle_position") - f("robot_position") - f("gap")).abs() < 1e-9,
            "{step}"
        );
        assert!(
            f("obstacle_speed") >= 0.0 && f("obstacle_speed") <= 0.15,
            "{step}"
        );
    }
    let dt = file.robot.control_period;
    let t = |i: usize| steps[i]["t"].as_f64().unwrap();
    for i in 0..steps.len() - 1 {
        assert!(
            (t(i) - i as f64 * dt).abs() < 1e-9,
            "step {i} at t = {}",
            t(i)
        );
    }
    let last = steps.last().unwrap();
    let n = steps.len() - 1;
    assert!(t(n) > t(n - 1) && t(n) <= t(n - 1) + dt + 1e-12);
    assert_eq!(last["robot_speed"], 0.0);
    assert_eq!(last["robot_mode"], "stop");
    assert!((last["gap"].as_f64().unwrap() - s).abs() <= 1e-6);
    assert_eq!(steps[0]["robot_mode"], "accelerate");
    assert!(
        steps.iter().any(|s| s["robot_mode"] == "brake"),
        "the worst case brakes"
    );
    let w = cert.witness.expect("a witness");
    assert!(!w.collides);
}

#[test]
fn out_writes_a_file_that_check_accepts_and_leaves_no_temporary_files() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("certify")
        .arg(seed_file())
        .args(["--json", "--out", "cert.json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    assert_eq!(files(dir.path()), BTreeSet::from(["cert.json".to_string()]));
    let written = std::fs::read_to_string(dir.path().join("cert.json")).expect("written");
    assert_eq!(
        written,
        stdout(&out),
        "--out and --json write the same certificate"
    );
    let _: Certificate = serde_json::from_str(&written).expect("a certificate");

    safereach(dir.path())
        .args(["check", "cert.json"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("valid"))
        .stdout(predicate::str::contains("certified"));

    // Overwriting an existing file is atomic too.
    safereach(dir.path())
        .arg("certify")
        .arg(problem_file("fast-obstacle.toml"))
        .args(["--out", "cert.json"])
        .assert()
        .code(1);
    assert_eq!(files(dir.path()), BTreeSet::from(["cert.json".to_string()]));
    safereach(dir.path())
        .args(["check", "cert.json"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("refuted"));
}

#[test]
fn out_into_a_missing_directory_is_an_error_naming_the_path() {
    let dir = tmp();
    safereach(dir.path())
        .arg("certify")
        .arg(seed_file())
        .args(["--out", "no/such/dir/cert.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("no/such/dir/cert.json"));
    assert!(files(dir.path()).is_empty());
}

#[test]
fn refuted_problem_exits_1_and_its_witness_collides() {
    let dir = tmp();
    let fast = problem_file("fast-obstacle.toml");
    safereach(dir.path())
        .arg("certify")
        .arg(&fast)
        .assert()
        .code(1)
        .stdout(predicate::str::contains("refuted"))
        .stdout(predicate::str::contains("collides"));
    let (cert, value) = certify_json(dir.path(), &[fast.to_str().unwrap(), "--steps"], 1);
    assert_eq!(cert.verdict, Verdict::Refuted);
    assert_eq!(value["verdict"], "refuted");
    let w = cert.witness.as_ref().expect("a witness");
    assert!(w.collides, "the refuting witness collides");
    let clearance = cert.clearance;
    // A collision: an instant with the robot moving and gap ≤ clearance. The gap never
    // grows, so the robot's last moving row before the end has gap > the final gap, and the
    // final gap is ≤ clearance.
    let last = w.steps.last().expect("steps");
    if cert.never_stops {
        assert!(last.robot_speed > 0.0 && last.gap <= clearance);
    } else {
        let s = cert.min_separation.expect("s*");
        assert!(s <= clearance, "refuted with s* {s}");
        assert_eq!(last.robot_speed, 0.0);
        assert!((last.gap - s).abs() <= 1e-6);
        assert!(w.steps[w.steps.len() - 2].robot_speed > 0.0);
    }

    // The certificate of a refutation is valid, and its witness replays to a collision.
    std::fs::write(dir.path().join("refuted.json"), value.to_string()).unwrap();
    safereach(dir.path())
        .args(["check", "refuted.json"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("refuted"));
    safereach(dir.path())
        .arg("simulate")
        .arg(&fast)
        .args(["--replay", "refuted.json"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("COLLISION"));
}

/// A problem whose worst case sits exactly on the clearance: brake on entry, no latency,
/// ρ = v²/(2b) + W·v/b + (v+W)·dt = 0.4 + 0.6 + 0.035 = 1.035 m, so s* = 0 = clearance.
/// The robot never collides (a collision needs gap < clearance at rest), but no bound can
/// exceed the clearance either: neither certified nor refuted.
///
/// (Regression: a still obstacle reached exactly at gap ρ used to be inconclusive because
/// the piece "brake one step later" holds only on that boundary; such pieces are now
/// proved empty — see `strict_boundary_piece_is_proved_empty`.)
#[test]
fn boundary_problem_is_inconclusive() {
    let dir = tmp();
    let sets = [
        "controller.danger_rule=area",
        "robot.latency=0",
        "controller.reaction_radius=1.035",
    ];
    let mut args = vec![seed_file().to_str().unwrap().to_string()];
    for s in sets {
        args.push("--set".into());
        args.push(s.into());
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    safereach(dir.path())
        .arg("certify")
        .args(&args)
        .assert()
        .code(3)
        .stdout(predicate::str::contains("inconclusive"));
    let (cert, value) = certify_json(dir.path(), &args, 3);
    assert_eq!(cert.verdict, Verdict::Inconclusive);
    let lb = cert.lower_bound.expect("a finite bound");
    assert!(lb <= cert.clearance, "bound {lb}");
    let w = cert.witness.as_ref().expect("a closest approach");
    assert!(!w.collides);
    std::fs::write(dir.path().join("inconclusive.json"), value.to_string()).unwrap();
    safereach(dir.path())
        .args(["check", "inconclusive.json"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("inconclusive"));
}

/// The robot reaches gap ρ exactly after four steps of a still obstacle
/// (g0 − P_4 = 1.82 − 0.32 = 1.5 = ρ), so the closed program of "brake at step 5" (which
/// needs the observed gap *above* ρ at step 4) is attained only on that boundary, with a
/// negative bound, while every real behaviour rests at 0.26 m. The strict piece is empty and
/// the certificate proves it: certified, and `check` accepts the proof.
#[test]
fn strict_boundary_piece_is_proved_empty() {
    let dir = tmp();
    let sets = [
        "robot.max_speed=1.0",
        "robot.acceleration=1.0",
        "robot.braking=0.3",
        "robot.control_period=0.2",
        "robot.latency=0",
        "controller.assumed_obstacle_speed=0.1",
        "controller.reaction_radius=1.5",
        "controller.danger_rule=area",
        "controller.buffer=0",
        "controller.wrong_assumption_brake=false",
        "environment.obstacle_speed=0.05",
        "environment.initial_gap=1.82",
    ];
    let mut args = vec![seed_file().to_str().unwrap().to_string()];
    for s in sets {
        args.push("--set".into());
        args.push(s.into());
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (cert, value) = certify_json(dir.path(), &args, 0);
    assert_eq!(cert.verdict, Verdict::Certified);
    let lb = cert.lower_bound.expect("a finite bound");
    assert!((lb - 0.26).abs() < 1e-9, "bound {lb}");
    std::fs::write(dir.path().join("boundary.json"), value.to_string()).unwrap();
    safereach(dir.path())
        .args(["check", "boundary.json"])
        .assert()
        .code(0);
}

#[test]
fn set_changes_the_problem_answered() {
    let dir = tmp();
    let seed_path = seed_file();
    let seed_arg = seed_path.to_str().unwrap();
    let (base, _) = certify_json(dir.path(), &[seed_arg], 0);
    let out = safereach(dir.path())
        .arg("certify")
        .arg(&seed_path)
        .args(["--set", "environment.obstacle_speed=0.25", "--json"])
        .output()
        .expect("runs");
    let code = out.status.code().expect("exit code");
    assert!([0, 1, 3].contains(&code), "exit {code}");
    let cert: Certificate = serde_json::from_str(&stdout(&out)).expect("a certificate");
    assert_eq!(cert.problem.environment.obstacle_speed, 0.25);
    let mut expected = base.problem.clone();
    expected.environment.obstacle_speed = 0.25;
    assert_eq!(cert.problem, expected, "only the overridden key changes");
    let premise = cert
        .premises
        .iter()
        .find(|p| p.name == "obstacle_speed")
        .expect("premise");
    assert_eq!(premise.bound, 0.25);
    // A faster obstacle: a different answer, strictly closer (or the robot may never stop).
    let base_s = base.min_separation.expect("the seed's s*");
    assert!(
        cert.never_stops || cert.min_separation.is_some_and(|s| s < base_s),
        "s* {:?} with W = 0.25 vs {base_s} with W = 0.15",
        cert.min_separation
    );
    let expected_code = match cert.verdict {
        Verdict::Certified => 0,
        Verdict::Refuted => 1,
        Verdict::Inconclusive => 3,
    };
    assert_eq!(code, expected_code);
}

#[test]
fn bad_set_exits_2_naming_the_key() {
    let dir = tmp();
    let cases: &[(&str, &[&str])] = &[
        (
            "environment.obstacle_speed=-1",
            &["environment.obstacle_speed", "must be >= 0"],
        ),
        (
            "environment.obstacle_speed=abc",
            &["environment.obstacle_speed", "abc"],
        ),
        ("robot.wheels=3", &["robot.wheels", "unknown key"]),
        ("robot.latency=0.5", &["robot.latency"]),
        ("controller.danger_rule=fast", &["controller.danger_rule"]),
        ("robot.braking=0", &["robot.braking", "must be > 0"]),
        ("robot", &["--set robot", "key=value"]),
        ("robot=1", &["robot", "table"]),
    ];
    for (set, expect) in cases {
        for cmd in ["certify", "simulate"] {
            let assert = safereach(dir.path())
                .arg(cmd)
                .arg(seed_file())
                .args(["--set", set])
                .assert()
                .code(2)
                .stdout(predicate::str::is_empty());
            let err = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
            for e in *expect {
                assert!(err.contains(e), "{cmd} --set {set}: {err:?} lacks {e:?}");
            }
        }
    }
    assert!(files(dir.path()).is_empty());
}

#[test]
fn bad_problem_file_exits_2_naming_the_file_and_key() {
    let dir = tmp();
    let text = std::fs::read_to_string(seed_file()).expect("seed");
    let cases: &[(&str, String, &[&str])] = &[
        (
            "negative.toml",
            text.replace("braking = 0.05", "braking = -0.5"),
            &["negative.toml", "robot.braking", "must be > 0"],
        ),
        (
            "unknown.toml",
            text.replace("[robot]\n", "[robot]\nwheels = 3\n"),
            &["unknown.toml", "wheels"],
        ),
        (
            "missing.toml",
            text.replace("initial_gap = 10.0", ""),
            &["missing.toml", "initial_gap"],
        ),
        (
            "syntax.toml",
            text.replace("latency = 1", "latency = = 1"),
            &["syntax.toml", "latency"],
        ),
        ("empty.toml", String::new(), &["empty.toml", "name"]),
    ];
    for (name, content, expect) in cases {
        assert_ne!(content, &text, "{name}: the edit applies");
        std::fs::write(dir.path().join(name), content).unwrap();
        let assert = safereach(dir.path())
            .args(["certify", name])
            .assert()
            .code(2)
            .stdout(predicate::str::is_empty());
        let err = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
        for e in *expect {
            assert!(err.contains(e), "{name}: {err:?} lacks {e:?}");
        }
    }
    safereach(dir.path())
        .args(["certify", "does-not-exist.toml"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("does-not-exist.toml"));
}

// ------------------------------------------------------------------------------------------
// check
// ------------------------------------------------------------------------------------------

#[test]
fn check_rejects_an_edited_certificate() {
    let dir = tmp();
    let path = write_seed_certificate(dir.path());
    let text = std::fs::read_to_string(&path).unwrap();
    let value: Value = serde_json::from_str(&text).unwrap();
    let s = value["min_separation"].as_f64().unwrap();

    // A number edited by hand (old digest kept).
    let mut edited = value.clone();
    edited["min_separation"] = (s + 0.5).into();
    std::fs::write(dir.path().join("edited.json"), edited.to_string()).unwrap();
    safereach(dir.path())
        .args(["check", "edited.json"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("INVALID"));

    // Forgeries that recompute the digest are caught by the exact re-verification.
    let forge = |name: &str, edit: &dyn Fn(&mut Certificate)| {
        let mut cert: Certificate = serde_json::from_str(&text).unwrap();
        edit(&mut cert);
        cert.digest = cert.compute_digest();
        std::fs::write(dir.path().join(name), serde_json::to_string(&cert).unwrap()).unwrap();
        safereach(dir.path())
            .args(["check", name])
            .assert()
            .code(1)
            .stdout(predicate::str::contains("INVALID"));
    };
    forge("faster.json", &|c| {
        c.problem.environment.obstacle_speed = 0.25
    });
    forge("bound.json", &|c| {
        c.lower_bound = c.lower_bound.map(|b| b + 0.01);
    });
    forge("dropped.json", &|c| {
        c.proofs.pop();
        c.pieces -= 1;
    });
    forge("verdict.json", &|c| c.verdict = Verdict::Refuted);
    forge("multiplier.json", &|c| {
        let z = c
            .proofs
            .iter_mut()
            .find_map(|p| p.multipliers.iter_mut().find(|z| **z > 0.0))
            .expect("a positive multiplier");
        *z *= 1.5;
    });

    // Re-serialised unchanged, it stays valid (the edits above were the cause).
    std::fs::write(dir.path().join("same.json"), value.to_string()).unwrap();
    safereach(dir.path())
        .args(["check", "same.json"])
        .assert()
        .code(0);
}

#[test]
fn check_on_unreadable_input_exits_2() {
    let dir = tmp();
    std::fs::write(dir.path().join("notes.txt"), "not JSON at all\n").unwrap();
    safereach(dir.path())
        .args(["check", "notes.txt"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("notes.txt"));
    std::fs::write(dir.path().join("other.json"), r#"{"verdict": "certified"}"#).unwrap();
    safereach(dir.path())
        .args(["check", "other.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("other.json"));
    safereach(dir.path())
        .args(["check", "missing.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("missing.json"));
}

// ------------------------------------------------------------------------------------------
// simulate
// ------------------------------------------------------------------------------------------

#[test]
fn simulate_seed_never_collides_and_is_reproducible() {
    let dir = tmp();
    let run = || {
        let out = safereach(dir.path())
            .arg("simulate")
            .arg(seed_file())
            .args(["--runs", "1000", "--seed", "7"])
            .assert()
            .code(0)
            .stdout(predicate::str::contains("1000 runs"))
            .stdout(predicate::str::contains(" 0 collisions"))
            .get_output()
            .clone();
        stdout(&out)
    };
    let first = run();
    assert_eq!(first, run(), "same seed, same output");

    let out = safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--runs", "1000", "--seed", "7", "--json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let v: Value = serde_json::from_str(&stdout(&out)).expect("--json parses");
    assert_eq!(v["runs"], 1000);
    assert_eq!(v["collisions"], 0);
    assert_eq!(v["seed"], 7);
    // Random behaviours never come closer than the certified worst case.
    let seen = v["min_separation"].as_f64().expect("min_separation");
    let (cert, _) = certify_json(dir.path(), &[seed_file().to_str().unwrap()], 0);
    assert!(seen >= cert.lower_bound.unwrap(), "{seen}");

    // Another seed gives other runs.
    let other = safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--runs", "1000", "--seed", "8"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    assert_ne!(stdout(&other), first);
    assert!(files(dir.path()).is_empty());
}

#[test]
fn simulate_replay_writes_the_worst_case_trace() {
    let dir = tmp();
    write_seed_certificate(dir.path());
    let cert: Certificate =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cert.json")).unwrap())
            .unwrap();
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--replay", "cert.json", "--trace", "worst.csv"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("no collision"));
    assert_eq!(
        files(dir.path()),
        BTreeSet::from(["cert.json".to_string(), "worst.csv".to_string()]),
        "no temporary files left"
    );
    let csv = std::fs::read_to_string(dir.path().join("worst.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().all(|r| r.len() == 7), "7 columns");
    let witness = cert.witness.as_ref().unwrap();
    let periods: usize = witness.robot_modes.iter().map(|m| m.length).sum();
    assert_eq!(periods, witness.obstacle_speeds.len());
    assert_eq!(
        rows.len(),
        periods + 1,
        "one row per period of the witness, and its instant of rest"
    );
    let num = |r: &[&str], i: usize| r[i].parse::<f64>().expect("a number");
    let last = rows.last().unwrap();
    assert_eq!(num(last, 2), 0.0, "the robot rests at the end: {last:?}");
    assert_eq!(last[3], "stop");
    let gap = num(last, 5) - num(last, 1);
    let s = cert.min_separation.unwrap();
    assert!((gap - s).abs() <= 1e-6, "final gap {gap} vs s* {s}");
    let mut t = -1.0;
    for r in &rows {
        assert!(num(r, 0) > t, "time increases");
        t = num(r, 0);
    }

    // The JSON form of a replay parses too.
    let out = safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--replay", "cert.json", "--json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let v: Value = serde_json::from_str(&stdout(&out)).expect("--json parses");
    assert_eq!(v["collided"], false);
    assert!((v["separation"].as_f64().unwrap() - s).abs() <= 1e-6);
}

#[test]
fn simulate_trace_of_random_runs_has_the_monitor_header() {
    let dir = tmp();
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--runs", "50", "--seed", "3", "--trace", "closest.csv"])
        .assert()
        .code(0);
    let csv = std::fs::read_to_string(dir.path().join("closest.csv")).unwrap();
    assert!(csv.starts_with("t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v\n"));
    assert!(csv.lines().count() > 2);
    assert_eq!(
        files(dir.path()),
        BTreeSet::from(["closest.csv".to_string()])
    );
}

#[test]
fn simulate_rejects_zero_runs_and_bad_input() {
    let dir = tmp();
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--runs", "0"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--runs"));
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--replay", "missing.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("missing.json"));
}

/// `simulate --replay` replays a checked certificate on its own problem: the problem argument
/// may be left out, must be the certificate's when given, `--set` is refused, and a
/// certificate that fails `check` is refused with the reason (issue 15: it used to replay the
/// problem file given, with `--set` applied, and certificates that failed `check`).
#[test]
fn simulate_replay_checks_the_certificate_and_replays_its_own_problem() {
    let dir = tmp();
    let cert_path = write_seed_certificate(dir.path());
    let cert: Certificate =
        serde_json::from_str(&std::fs::read_to_string(&cert_path).unwrap()).unwrap();
    let witness_sep = cert.witness.as_ref().unwrap().separation.unwrap();
    // Without the problem: the certificate's own, replayed to its witness's separation.
    let out = safereach(dir.path())
        .args(["simulate", "--replay", "cert.json", "--json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let sep = v["separation"].as_f64().unwrap();
    assert!((sep - witness_sep).abs() <= 1e-12, "{sep} vs {witness_sep}");
    // With its own problem file: the same.
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--replay", "cert.json"])
        .assert()
        .code(0);
    // Another problem file is refused, naming the key that differs.
    safereach(dir.path())
        .arg("simulate")
        .arg(problem_file("fast-obstacle.toml"))
        .args(["--replay", "cert.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("environment.obstacle_speed"));
    // --set changes the problem: refused (it used to replay a robot braking at 0.01 m/s² to
    // "no collision").
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--replay", "cert.json", "--set", "robot.braking=0.01"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--set"));
    // A certificate that fails check: its s* moved out of its bracket and re-signed.
    let mut forged = cert.clone();
    forged.min_separation = Some(witness_sep + 0.5);
    forged.digest = forged.compute_digest();
    std::fs::write(
        dir.path().join("forged.json"),
        serde_json::to_string(&forged).unwrap(),
    )
    .unwrap();
    safereach(dir.path())
        .args(["simulate", "--replay", "forged.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("fails check").and(predicate::str::contains("bracket")));
    // Neither a problem nor --replay: clap's usage error.
    safereach(dir.path()).arg("simulate").assert().code(2);
}

/// The numbers in the words of `text` that follow `marker` (e.g. every `t = X`).
fn numbers_after<'a>(text: &'a str, marker: &str) -> Vec<&'a str> {
    text.match_indices(marker)
        .map(|(i, _)| {
            let rest = &text[i + marker.len()..];
            let end = rest
                .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
                .unwrap_or(rest.len());
            &rest[..end]
        })
        .collect()
}

/// A shown decimal, read exactly.
fn exact_shown(text: &str) -> safereach::core::num::Exact {
    safereach::core::num::exact_decimal(text.parse().expect("a number"))
}

/// Issue 15: a lower bound is shown rounded down (0.3299999999993427 as 0.329999999, not
/// 0.330000000), the witness's separation — an upper bound on s* — rounded up, and times
/// without float noise (t = 44.1, never 44.10000000000001). Held against the certificate's
/// own numbers, exactly.
#[test]
fn certify_shows_bounds_rounded_their_own_way_and_times_without_noise() {
    use safereach::core::num::exact_float;
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("certify")
        .arg(seed_file())
        .args(["--out", "cert.json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let text = stdout(&out);
    let cert: Certificate =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cert.json")).unwrap())
            .unwrap();
    let nano = exact_shown("1e-9");
    let lb = exact_float(cert.lower_bound.unwrap());
    let shown_lb = numbers_after(&text, "rigorous lower bound ");
    assert_eq!(shown_lb.len(), 1, "{text}");
    let shown = exact_shown(shown_lb[0]);
    assert!(shown <= lb && lb < shown + nano.clone(), "{text}");
    // The s* bracket: the bound below, rounded down; the witness above, rounded up.
    let r = exact_float(cert.witness.as_ref().unwrap().separation.unwrap());
    let below = exact_shown(numbers_after(&text, "(between ")[0]);
    let above = exact_shown(numbers_after(&text, " and ")[0]);
    assert!(below <= lb && r <= above && above < r + nano, "{text}");
    // Times are whole periods or the rest instant, shown as short decimals.
    let dt = exact_shown("0.1");
    for t in numbers_after(&text, "t = ") {
        let digits = t.chars().filter(char::is_ascii_digit).count();
        assert!(digits <= 15, "{t} in {text}");
        let periods = exact_shown(t) / dt.clone();
        assert_eq!(periods.clone().floor(), periods.ceil(), "{t} is k·dt");
    }
    assert!(
        !text.contains("0000000000") && !text.contains("9999999999"),
        "{text}"
    );
}

/// Traces written by `simulate` carry times without float noise (each k·dt as its short
/// decimal), so the monitor's `t=` lines have none either.
#[test]
fn simulated_traces_and_monitor_lines_have_times_without_noise() {
    let dir = tmp();
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--runs", "20", "--trace", "run.csv"])
        .assert()
        .code(0);
    let csv = std::fs::read_to_string(dir.path().join("run.csv")).unwrap();
    let times: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert!(times.len() > 100);
    let dt = exact_shown("0.1");
    for (k, t) in times.iter().enumerate().take(times.len() - 1) {
        // Every row but the rest instant is a period start: exactly k·dt, shown shortest.
        assert_eq!(
            exact_shown(t),
            dt.clone() * safereach::core::num::Exact::from(k),
            "{t}"
        );
    }
    write_seed_certificate(dir.path());
    let out = safereach(dir.path())
        .args(["monitor", "--certificate", "cert.json", "run.csv"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let text = stdout(&out);
    for t in numbers_after(&text, "t=") {
        assert!(
            !t.contains("0000000000") && !t.contains("9999999999"),
            "{t}"
        );
    }
}

/// A witness is stored as runs: at 100 Hz over 50,000 periods the seed's worst case is a few
/// speed and mode segments, the certificate a few KB and `check` accepts it; `--steps` adds
/// the per-period rows (one per period), which `check` then compares as well.
#[test]
fn a_long_horizon_keeps_the_certificate_small_unless_steps_are_asked_for() {
    let dir = tmp();
    let sets = [
        "--set",
        "environment.initial_gap=100",
        "--set",
        "robot.control_period=0.01",
    ];
    let mut args = vec![seed_file().to_str().unwrap().to_string()];
    args.extend(sets.iter().map(|s| s.to_string()));
    let as_str: Vec<&str> = args.iter().map(String::as_str).collect();
    let (cert, value) = certify_json(dir.path(), &as_str, 0);
    let text = value.to_string();
    assert!(text.len() < 50_000, "{} bytes", text.len());
    let w = cert.witness.as_ref().expect("a witness");
    assert!(
        w.obstacle_speeds.len() > 40_000,
        "{}",
        w.obstacle_speeds.len()
    );
    let segments = value["witness"]["obstacle_speeds"].as_array().unwrap();
    assert!(segments.len() <= 5, "{segments:?}");
    assert!(w.steps.is_empty() && value["witness"].get("steps").is_none());
    assert_eq!(check(&cert).expect("checks").verdict, Verdict::Certified);
    let mut with = as_str.clone();
    with.push("--steps");
    let (full, _) = certify_json(dir.path(), &with, 0);
    let fw = full.witness.as_ref().unwrap();
    assert_eq!(fw.steps.len(), fw.obstacle_speeds.len() + 1);
    assert_eq!(fw.obstacle_speeds, w.obstacle_speeds);
    assert_eq!(fw.robot_modes, w.robot_modes);
    assert_eq!(check(&full).expect("checks").verdict, Verdict::Certified);
}
