//! The commands on scene files: certify (verdict, worst case by obstacle and lane, exit
//! codes, a certificate that `check` accepts and that names the obstacle), simulate (random
//! runs and the replay of a witness), and bad scene input (exit 2, naming file, key and
//! reason).

use predicates::prelude::*;
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::exact_speed_runs::ExactSpeedSegment;
use safereach::proof::verdict::Verdict;
use safereach::proof::witness_runs::Speeds;

use crate::common::cli::{bad_input_exits_2, safereach, stdout};
use crate::common::paths::problem_file;
use crate::common::tmp;

/// `certify --out` on a shipped scene: the verdict's exit code, the certificate `check`
/// accepts, and its worst case named.
fn certify(name: &str, code: i32, verdict: Verdict, worst: &str) {
    let dir = tmp();
    let cert = dir.path().join("c.json");
    let out = safereach(dir.path())
        .arg("certify")
        .arg(problem_file(name))
        .arg("--out")
        .arg(&cert)
        .assert()
        .code(code)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(
        text.contains(&format!("obstacle \"{worst}\" in lane 0")),
        "{text}"
    );
    let file = CertificateFile::from_json(&std::fs::read_to_string(&cert).unwrap()).unwrap();
    assert!(matches!(file, CertificateFile::Scene(_)));
    assert_eq!(file.check().unwrap().verdict, verdict);
    safereach(dir.path())
        .arg("check")
        .arg(&cert)
        .assert()
        .code(0)
        .stdout(predicate::str::contains(format!(
            "verdict {} re-verified",
            verdict.as_str()
        )));
}

#[test]
fn shipped_scenes_certify_as_documented() {
    certify("scene-oncoming.toml", 0, Verdict::Certified, "second");
    certify("scene-destination.toml", 0, Verdict::Certified, "fast");
    certify("scene-short-sensing.toml", 1, Verdict::Refuted, "oncoming");
}

#[test]
fn a_refuting_witness_replays_to_a_collision() {
    let dir = tmp();
    let cert = dir.path().join("c.json");
    let scene = problem_file("scene-short-sensing.toml");
    safereach(dir.path())
        .args(["certify", scene.to_str().unwrap(), "--out"])
        .arg(&cert)
        .assert()
        .code(1);
    let trace = dir.path().join("t.csv");
    safereach(dir.path())
        .args(["simulate", scene.to_str().unwrap(), "--replay"])
        .arg(&cert)
        .arg("--trace")
        .arg(&trace)
        .assert()
        .code(1)
        .stdout(predicate::str::contains("COLLISION"));
    let text = std::fs::read_to_string(&trace).unwrap();
    assert!(
        text.lines()
            .next()
            .unwrap()
            .ends_with("robot_lane,obstacle_lane,leaving_lane")
    );
}

#[test]
fn random_runs_of_a_certified_scene_never_collide() {
    let dir = tmp();
    safereach(dir.path())
        .args([
            "simulate",
            problem_file("scene-oncoming.toml").to_str().unwrap(),
        ])
        .args(["--runs", "200", "--seed", "5"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("0 collisions"));
}

#[test]
fn an_overridden_obstacle_changes_the_verdict() {
    // "second" at 0.3 m/s > V_a: the wrong-assumption guard brakes, but not in time.
    let dir = tmp();
    safereach(dir.path())
        .args([
            "certify",
            problem_file("scene-oncoming.toml").to_str().unwrap(),
        ])
        .args(["--set", "obstacle.1.max_speed=0.3"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("obstacle \"second\""));
}

#[test]
fn bad_scene_input_exits_2() {
    let dir = tmp();
    bad_input_exits_2(
        dir.path(),
        "certify",
        &problem_file("scene-oncoming.toml"),
        &[
            (
                vec!["--set", "obstacle.3.max_speed=0.1"],
                "a static obstacle must have max_speed = 0",
            ),
            (vec!["--set", "obstacle.9.lane=0"], "obstacle.9"),
            (vec!["--set", "obstacle.0.lane=2"], "lane"),
        ],
    );
}

#[test]
fn a_lane_change_scene_is_certified_by_the_search_and_its_certificate_checks() {
    let dir = tmp();
    let cert = dir.path().join("lanes.json");
    let text = stdout(
        safereach(dir.path())
            .args([
                "certify",
                problem_file("seed-lanes.toml").to_str().unwrap(),
                "--out",
                cert.to_str().unwrap(),
            ])
            .assert()
            .code(0)
            .get_output(),
    );
    assert!(text.contains("seed-lanes: certified"), "{text}");
    assert!(text.contains("changes from lane 0 to lane 1"), "{text}");
    safereach(dir.path())
        .args(["check", cert.to_str().unwrap()])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("by searching its"));
    safereach(dir.path())
        .args([
            "simulate",
            problem_file("seed-lanes.toml").to_str().unwrap(),
            "--replay",
            cert.to_str().unwrap(),
        ])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("no collision"));
    // An edited scene no longer matches its digest.
    let edited = std::fs::read_to_string(&cert)
        .unwrap()
        .replace("\"rear_gap\": 0.5", "\"rear_gap\": 0.25");
    std::fs::write(&cert, edited).unwrap();
    safereach(dir.path())
        .args(["check", cert.to_str().unwrap()])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("INVALID"));
}

#[test]
fn radius_refuses_lane_changes_and_says_why() {
    let dir = tmp();
    safereach(dir.path())
        .args(["radius", problem_file("seed-lanes.toml").to_str().unwrap()])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("need not form an interval"));
}

#[test]
fn scene_radius_matches_the_single_obstacle_radius_and_respects_the_sensing_range() {
    let dir = tmp();
    let scene = problem_file("scene-short-sensing.toml");
    // The sensors cap ρ at 1.0 m; the robot needs 1.07 m (as seed.toml's radius says).
    safereach(dir.path())
        .args(["radius", scene.to_str().unwrap()])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("no safe radius up to 1.000000 m"));
    let single = stdout(
        &safereach(dir.path())
            .args([
                "radius",
                crate::common::paths::seed_file().to_str().unwrap(),
                "--json",
            ])
            .assert()
            .code(0)
            .get_output()
            .clone(),
    );
    let single: serde_json::Value = serde_json::from_str(&single).unwrap();
    let text = stdout(
        &safereach(dir.path())
            .args(["radius", scene.to_str().unwrap(), "--json"])
            .args(["--set", "robot.sensing_range=2"])
            .assert()
            .code(0)
            .get_output()
            .clone(),
    );
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    let scene_radius = value[0]["radius"].as_f64().unwrap();
    let single_radius = single["safe_radius"].as_f64().unwrap();
    // Both searches close their brackets to 1e-10 and report the certified end on that
    // grid: the scene's answer is the single obstacle's to within that grid.
    assert!(
        (scene_radius - single_radius).abs() <= 5e-10,
        "{scene_radius} vs {single_radius}"
    );
}

#[test]
fn scene_max_speed_matches_the_single_obstacle_max_speed() {
    let dir = tmp();
    let json = |args: &[&str], code: i32| -> serde_json::Value {
        let out = safereach(dir.path())
            .args(args)
            .arg("--json")
            .assert()
            .code(code)
            .get_output()
            .clone();
        serde_json::from_str(&stdout(&out)).unwrap()
    };
    let seed = crate::common::paths::seed_file();
    let single = json(&["max-speed", seed.to_str().unwrap()], 0);
    let single = single["max_obstacle_speed"].as_f64().unwrap();
    // The short-sensing scene with the seed's radius is the seed problem as a scene.
    let scene = problem_file("scene-short-sensing.toml");
    let value = json(
        &[
            "max-speed",
            scene.to_str().unwrap(),
            "--set",
            "robot.sensing_range=2",
            "--set",
            "controller.reaction_radius=1.4",
        ],
        0,
    );
    let found = value["max_speed"].as_f64().unwrap();
    assert!(
        found <= single + 1e-9 && single - found <= 2e-6,
        "{found} vs {single}"
    );
}

/// A scene's certificate keeps the witness's rows per period only with `--steps`, for both
/// engines (the schedule analyser and the run search): without them the file is smaller and
/// `check` replays the speeds all the same; with them every row is compared with the
/// replay, so an edited row is rejected even under a fresh digest.
#[test]
fn scene_witness_rows_only_with_steps() {
    let dir = tmp();
    for (name, obstacles) in [("scene-oncoming.toml", 4), ("seed-lanes.toml", 3)] {
        let certify = |steps: bool| {
            let mut cmd = safereach(dir.path());
            cmd.arg("certify").arg(problem_file(name)).arg("--json");
            if steps {
                cmd.arg("--steps");
            }
            let text = stdout(&cmd.assert().code(0).get_output().clone());
            let value: serde_json::Value = serde_json::from_str(&text).unwrap();
            (text, value)
        };
        let (lean_text, lean) = certify(false);
        let (full_text, full) = certify(true);
        assert!(lean["witness"].get("steps").is_none(), "{name}");
        let rows = full["witness"]["steps"]
            .as_array()
            .expect("rows with --steps");
        // One row per obstacle per instant, past the brake.
        assert_eq!(rows.len() % obstacles, 0, "{name}");
        assert!(rows.len() / obstacles > 100, "{name}: {} rows", rows.len());
        assert!(lean_text.len() * 3 < full_text.len(), "{name}");
        // The same answer and witness otherwise.
        let strip = |v: &serde_json::Value| {
            let mut v = v.clone();
            v["witness"].as_object_mut().unwrap().remove("steps");
            v.as_object_mut().unwrap().remove("digest");
            v
        };
        assert_eq!(strip(&lean), strip(&full), "{name}");
        for text in [&lean_text, &full_text] {
            let file = CertificateFile::from_json(text).unwrap();
            assert_eq!(file.check().unwrap().verdict, Verdict::Certified, "{name}");
        }
        // An edited row, digest recomputed: rejected by the replay.
        let mut forged = CertificateFile::from_json(&full_text).unwrap();
        match &mut forged {
            CertificateFile::Scene(c) => {
                let w = c.witness.as_mut().unwrap();
                let k = w.steps.len() / 2;
                w.steps[k].row.robot_position += 1e-3;
                c.digest = c.compute_digest();
            }
            CertificateFile::Search(c) => {
                let w = c.witness.as_mut().unwrap();
                let k = w.steps.len() / 2;
                w.steps[k].row.robot_position += 1e-3;
                c.digest = c.compute_digest();
            }
            CertificateFile::Single(_) | CertificateFile::Planar(_) => unreachable!("a scene"),
        }
        let e = forged.check().expect_err("an edited row");
        assert!(e.0.contains("trace differs"), "{name}: {e}");
    }
}

/// A scene witness's speeds are segments per obstacle: the certificate of a scene stepped at
/// 1 kHz is about as small as at 10 Hz (it was 3.3 MB with a speed per obstacle per
/// period), still checks, and a segment's speed past its obstacle's bound is rejected by the
/// period it starts at, under a fresh digest.
#[test]
fn a_scene_witness_is_segments_whatever_the_control_period() {
    let dir = tmp();
    let certify = |dt: &str| {
        let text = stdout(
            &safereach(dir.path())
                .arg("certify")
                .arg(problem_file("scene-oncoming.toml"))
                .args(["--set", &format!("robot.control_period={dt}"), "--json"])
                .assert()
                .code(0)
                .get_output()
                .clone(),
        );
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        (text, value)
    };
    let (slow_text, _) = certify("0.1");
    let (fast_text, fast) = certify("0.001");
    assert!(
        fast_text.len() < 2 * slow_text.len() && fast_text.len() < 20_000,
        "{} bytes at 1 kHz, {} at 10 Hz",
        fast_text.len(),
        slow_text.len()
    );
    let lists = fast["witness"]["obstacle_speeds"].as_array().unwrap();
    assert_eq!(lists.len(), 4);
    for list in lists {
        let segments = list.as_array().unwrap();
        let periods: u64 = segments.iter().map(|s| s["length"].as_u64().unwrap()).sum();
        assert!(segments.len() <= 4 && periods > 40_000, "{list}");
    }
    let file = CertificateFile::from_json(&fast_text).unwrap();
    assert_eq!(file.check().unwrap().verdict, Verdict::Certified);

    let CertificateFile::Scene(mut forged) = file else {
        panic!("a scene certificate");
    };
    let w = forged.witness.as_mut().unwrap();
    let mut segments = w.obstacle_speeds[1].segments().to_vec();
    let last = segments.last_mut().unwrap();
    last.speed = 0.5;
    let start = last.start;
    w.obstacle_speeds[1] = Speeds::from_segments(&segments).unwrap();
    forged.digest = forged.compute_digest();
    let e = CertificateFile::Scene(forged)
        .check()
        .expect_err("a speed past W");
    assert!(
        e.0.contains(&format!("in period {start} is outside [0, W]")),
        "{e}"
    );
}

/// The run search's witness (lane changes) keeps its exact speeds as segments too: at
/// 100 Hz its certificate is about as small as at 10 Hz (it listed a "p/q" per obstacle
/// per period, 194 KB), it checks, and under a fresh digest a gap between segments or a
/// segment's speed past W is rejected, naming the obstacle.
#[test]
fn a_run_search_witness_is_exact_segments() {
    let dir = tmp();
    let certify = |dt: &str| {
        stdout(
            &safereach(dir.path())
                .arg("certify")
                .arg(problem_file("seed-lanes.toml"))
                .args(["--set", &format!("robot.control_period={dt}"), "--json"])
                .assert()
                .code(0)
                .get_output()
                .clone(),
        )
    };
    let slow = certify("0.1");
    let fast = certify("0.01");
    assert!(
        fast.len() < 2 * slow.len() && fast.len() < 20_000,
        "{} bytes at 100 Hz, {} at 10 Hz",
        fast.len(),
        slow.len()
    );
    let CertificateFile::Search(cert) = CertificateFile::from_json(&fast).unwrap() else {
        panic!("a run-search certificate");
    };
    let periods: Vec<usize> = cert.witness.as_ref().unwrap().obstacle_speeds[0]
        .iter()
        .map(|s| s.length)
        .collect();
    assert!(
        periods.iter().sum::<usize>() > 1_000 && periods.len() <= 8,
        "{periods:?}"
    );
    let report = CertificateFile::Search(cert.clone()).check().unwrap();
    assert_eq!(report.verdict, Verdict::Certified);

    let forge = |edit: &dyn Fn(&mut Vec<ExactSpeedSegment>)| {
        let mut forged = cert.clone();
        edit(&mut forged.witness.as_mut().unwrap().obstacle_speeds[0]);
        forged.digest = forged.compute_digest();
        CertificateFile::Search(forged)
            .check()
            .expect_err("a forged witness")
            .0
    };
    let gap = forge(&|s| s[1].start += 1);
    assert!(
        gap.contains("witness speeds of obstacle") && gap.contains("follow each other"),
        "{gap}"
    );
    let fast_speed = forge(&|s| s[0].speed = "7/10".into());
    assert!(
        fast_speed.contains("is not an exact speed in [0, W]"),
        "{fast_speed}"
    );
}
