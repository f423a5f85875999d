//! Planar certificates under `check` (docs/semantics.md §13.5): what `certify --out` writes
//! re-verifies without the solver, and every edit a reader could make to win a verdict —
//! a multiplier, a dropped leaf, a bound, the problem, the witness, the verdict — is named
//! and refused, even with the digest recomputed. `simulate --replay` replays the witness,
//! and its trace agrees with the certificate's bracket. The pursuit witnesses of the
//! overtaking jogger and the hidden pedestrian are held to what they claim to be.

use std::path::{Path, PathBuf};

use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::planar::certificate::PlanarCertificate;
use safereach::proof::verdict::Verdict;

use crate::common::cli::{safereach, stdout};
use crate::common::{rational, tmp};

fn problem(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("problems/planar/{name}.toml"))
}

/// `certify --out` for a shipped planar problem, read back as a planar certificate.
fn certificate(dir: &Path, name: &str, code: i32) -> (PathBuf, PlanarCertificate) {
    let path = dir.join(format!("{name}.json"));
    safereach(dir)
        .arg("certify")
        .arg(problem(name))
        .arg("--out")
        .arg(&path)
        .assert()
        .code(code);
    let text = std::fs::read_to_string(&path).expect("the certificate was written");
    let json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    crate::schemas::valid("planar-certificate", &json, name);
    match CertificateFile::from_json(&text).expect("a certificate") {
        CertificateFile::Planar(c) => (path, *c),
        _ => panic!("not a planar certificate"),
    }
}

/// `check --require verdict` on `path` passes.
fn check_requiring(dir: &Path, path: &Path, verdict: &str) {
    safereach(dir)
        .arg("check")
        .arg(path)
        .args(["--require", verdict])
        .assert()
        .code(0);
}

/// `cert` edited by `edit`, its digest recomputed, must fail `check` saying `why`.
fn refused(cert: &PlanarCertificate, why: &str, edit: impl FnOnce(&mut PlanarCertificate)) {
    let mut c = cert.clone();
    edit(&mut c);
    c.digest = c.compute_digest();
    match CertificateFile::Planar(Box::new(c)).check() {
        Ok(r) => panic!("an edit ({why}) passed check as {:?}", r.verdict),
        Err(e) => assert!(e.0.contains(why), "expected {why:?} in: {}", e.0),
    }
}

#[test]
fn a_refuted_planar_certificate_checks_and_every_edit_is_named() {
    let dir = tmp();
    let (path, cert) = certificate(dir.path(), "crossing-car", 1);
    assert_eq!(cert.verdict, Verdict::Refuted);
    let out = safereach(dir.path())
        .arg("check")
        .arg(&path)
        .args(["--require", "refuted"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    assert!(
        stdout(&out).contains("valid; verdict refuted"),
        "{}",
        stdout(&out)
    );
    // The verdict rests on the witness's exact replay: a certified claim is refused.
    refused(&cert, "give refuted", |c| {
        c.verdict = Verdict::Certified;
    });
    refused(&cert, "give refuted", |c| c.verdict = Verdict::Inconclusive);
    // A leaf's multipliers (the highest bound's, far above the floor): the bound they
    // prove changes, or they prove none.
    let (leaf_at, _) = cert.runs[0].obstacles[0]
        .leaves
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.empty && !l.multipliers.is_empty())
        .max_by(|a, b| a.1.bound.partial_cmp(&b.1.bound).unwrap())
        .expect("a bounded leaf");
    refused(&cert, &format!("leaf {leaf_at} "), |c| {
        let l = &mut c.runs[0].obstacles[0].leaves[leaf_at];
        for z in &mut l.multipliers {
            *z *= 0.9;
        }
    });
    // A leaf dropped: the piece is no longer tiled.
    refused(&cert, "has no leaf", |c| {
        c.runs[0].obstacles[0].leaves.remove(leaf_at);
    });
    // A leaf declared empty without a proof.
    refused(&cert, "emptiness does not hold", |c| {
        let l = &mut c.runs[0].obstacles[0].leaves[leaf_at];
        l.empty = true;
        l.bound = None;
    });
    // The claimed bound raised.
    refused(&cert, "its runs prove", |c| {
        c.lower_bound_exact = "1/2".into();
        c.lower_bound = 0.5;
    });
    // The witness's velocity changed: its replay no longer is what it states.
    refused(&cert, "the witness", |c| {
        let w = c.witness.as_mut().expect("a witness");
        w.obstacles[0].velocities[0] = ["0".into(), "1".into()];
    });
    // A slower car in the stored problem: the pieces and bounds are not this problem's.
    refused(&cert, "run 0", |c| {
        c.problem_toml = c
            .problem_toml
            .replace("max_speed = 10.0", "max_speed = 5.0");
        assert!(
            c.problem_toml.contains("max_speed = 5.0"),
            "the edit applies"
        );
    });
    // An edit without the digest recomputed is named as such.
    let mut edited = cert.clone();
    edited.clearance = 0.5;
    let e = CertificateFile::Planar(Box::new(edited))
        .check()
        .unwrap_err();
    assert!(e.0.contains("digest mismatch"), "{}", e.0);
}

#[test]
fn a_certified_planar_certificate_checks_and_its_goal_cannot_be_raised() {
    let dir = tmp();
    let (path, cert) = certificate(dir.path(), "seed-in-plane", 0);
    assert_eq!(cert.verdict, Verdict::Certified);
    check_requiring(dir.path(), &path, "certified");
    // The line's s* (0.33 m) is inside the checked bracket, stated to 1e-6.
    let s = cert.min_separation.expect("a bracket within tolerance");
    assert!(cert.lower_bound <= 0.33 + 1e-12 && 0.33 <= cert.upper_bound.unwrap() + 1e-12);
    assert!((s - 0.33).abs() <= 1e-6, "{s}");
    // A goal moves the horizon: past it nothing is proved above the new goal.
    refused(&cert, "run 0", |c| {
        c.runs[0].goal = "1000".into();
    });
    refused(&cert, "it claims", |c| c.runs[0].claim = 0.5);
}

#[test]
fn simulate_replays_a_planar_certificate_and_its_trace_shows_the_collision() {
    let dir = tmp();
    let (path, cert) = certificate(dir.path(), "crossing-car", 1);
    let trace = dir.path().join("trace.csv");
    let out = safereach(dir.path())
        .arg("simulate")
        .arg("--replay")
        .arg(&path)
        .arg("--trace")
        .arg(&trace)
        .assert()
        .code(1)
        .get_output()
        .clone();
    assert!(
        stdout(&out).contains("reaches the clearance"),
        "{}",
        stdout(&out)
    );
    // Independently of the replay's separations: the distance between the centres at each
    // step start, less the radii (0.3 m robot, 1 m car), is never below the proved bound.
    let text = std::fs::read_to_string(&trace).expect("a trace");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "t,robot_x,robot_y,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_y,obstacle_vx,\
             obstacle_vy,step"
        )
    );
    let mut least = f64::INFINITY;
    let mut rows = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let n = |i: usize| f[i].parse::<f64>().unwrap();
        let d = (n(1) - n(6)).hypot(n(2) - n(7)) - 1.3;
        if f[4] != "stop" {
            least = least.min(d);
        }
        rows += 1;
    }
    assert!(rows > 10, "{rows} rows");
    assert!(
        least >= cert.lower_bound - 1e-9,
        "{least} < {}",
        cert.lower_bound
    );
    // The step starts sample the motion: they come no closer than the closest instant.
    let upper = cert.upper_bound.unwrap();
    assert!(least >= upper - 1e-9 && least <= 0.5, "{least} vs {upper}");
    // The problem given with --replay must be the certificate's.
    safereach(dir.path())
        .arg("simulate")
        .arg(problem("seed-in-plane"))
        .arg("--replay")
        .arg(&path)
        .assert()
        .code(2);
}

#[test]
fn the_hidden_pedestrian_walks_into_the_robots_blind_side_while_it_drives() {
    let dir = tmp();
    let (path, cert) = certificate(dir.path(), "pedestrian-crossing", 1);
    assert_eq!(cert.verdict, Verdict::Refuted);
    // Full overlap is the floor -(0.3 + 0.3): the bracket pins s* there.
    assert!(cert.lower_bound >= -0.6 - 1e-8, "{}", cert.lower_bound);
    assert!(cert.upper_bound.unwrap() <= -0.6 + 1e-8);
    check_requiring(dir.path(), &path, "refuted");
    // From the trace alone: at some step start the robot drives (speed > 0) with the
    // pedestrian's centre within 0.6 m of its own, inside the crossing.
    let trace = dir.path().join("trace.jsonl");
    safereach(dir.path())
        .arg("simulate")
        .arg("--replay")
        .arg(&path)
        .arg("--trace")
        .arg(&trace)
        .assert()
        .code(1);
    let hit = std::fs::read_to_string(&trace)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .find(|r| {
            let f = |k: &str| r[k].as_f64().unwrap();
            f("robot_v") > 0.0
                && (f("robot_x") - f("obstacle_x")).hypot(f("robot_y") - f("obstacle_y")) <= 0.6
                && (5.0..=7.0).contains(&f("obstacle_x"))
        });
    assert!(hit.is_some(), "no step start shows the collision");
}

#[test]
fn the_overtaking_jogger_stalks_below_the_assumed_speed_then_sprints() {
    let dir = tmp();
    let (_, cert) = certificate(dir.path(), "overtaking", 1);
    assert_eq!(cert.verdict, Verdict::Refuted);
    let w = cert.witness.as_ref().expect("a witness");
    assert!(w.collides);
    let speeds: Vec<f64> = w.obstacles[0]
        .velocities
        .iter()
        .map(|[x, y]| rational(x).hypot(rational(y)))
        .collect();
    // Within W = 2.5 m/s throughout; the wrong-assumption guard (V_a = 1.4 m/s) never
    // fires, since the robot brakes for danger.
    assert!(speeds.iter().all(|s| *s <= 2.5 + 1e-12), "{speeds:?}");
    assert!(
        w.guard.as_deref() == Some("danger (jogger)"),
        "{:?}",
        w.guard
    );
    let sprint = speeds
        .iter()
        .position(|s| *s > 1.4 + 1e-9)
        .expect("a sprint");
    assert!(sprint > 0 && speeds[..sprint].iter().all(|s| *s <= 1.4));
}

#[test]
fn the_worst_case_is_drawn_from_above_with_its_legend_and_scale() {
    let dir = tmp();
    let svg = dir.path().join("worst.svg");
    safereach(dir.path())
        .arg("certify")
        .arg(problem("crossing-car"))
        .arg("--plot")
        .arg(&svg)
        .assert()
        .code(1);
    let text = std::fs::read_to_string(&svg).expect("the figure was written");
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let texts: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text().map(str::to_string))
        .collect();
    for needed in [
        "path",
        "car",
        "x (m)",
        "y (m)",
        "closest approach (filled discs)",
    ] {
        assert!(
            texts.iter().any(|t| t == needed),
            "no {needed:?} in {texts:?}"
        );
    }
    assert!(
        texts
            .iter()
            .any(|t| t.ends_with(" m") && t.parse::<f64>().is_err())
    );
    assert!(
        texts
            .iter()
            .any(|t| t.starts_with("closest: separation -1.2084")),
        "{texts:?}"
    );
    // A line problem has no top view: named, exit 2.
    let seed = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("problems/seed.toml");
    safereach(dir.path())
        .arg("certify")
        .arg(seed)
        .arg("--plot")
        .arg(&svg)
        .assert()
        .code(2);
}
