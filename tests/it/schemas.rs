//! The JSON Schemas in `schemas/`: current (what `safereach schema` derives from the types
//! today), and every kind of JSON safereach writes validates against its schema —
//! certificates of every shipped problem and fixture (and a planar one), region maps, sweep
//! lines, monitor events and summaries — while edited JSON does not.

use std::collections::BTreeSet;
use std::fs;
use std::path::Path;

use serde_json::Value;

use crate::common::cli::{files, safereach, stdout};
use crate::common::paths::{fixture, root};
use crate::common::tmp;

/// The shipped schema `name` as a validator.
fn validator(name: &str) -> jsonschema::Validator {
    let path = root().join(format!("schemas/{name}.schema.json"));
    let schema: Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    jsonschema::validator_for(&schema).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Asserts `json` validates against schema `name`; `what` names it in the failure.
pub(crate) fn valid(name: &str, json: &Value, what: &str) {
    let errors: Vec<String> = validator(name)
        .iter_errors(json)
        .take(5)
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{what} against {name}: {errors:#?}");
}

/// The schema a certificate is held to, by its format tag.
fn certificate_schema(json: &Value) -> &'static str {
    match json["format"].as_str().unwrap() {
        "safereach-certificate/3" => "certificate",
        "safereach-scene-certificate/5" => "scene-certificate",
        "safereach-scene-search-certificate/4" => "search-certificate",
        "safereach-planar-certificate/1" => "planar-certificate",
        other => panic!("unknown certificate format {other}"),
    }
}

/// Every non-grid problem shipped in `problems/`.
fn shipped_problems() -> Vec<String> {
    let mut names: Vec<String> = files(&root().join("problems"))
        .into_iter()
        .filter(|n| n.ends_with(".toml") && !n.contains("grid"))
        .collect();
    names.sort();
    names
}

#[test]
fn the_shipped_schemas_are_what_the_types_derive() {
    let dir = tmp();
    safereach(dir.path())
        .args(["schema", "--out", "schemas"])
        .assert()
        .code(0);
    let generated = files(&dir.path().join("schemas"));
    let shipped = files(&root().join("schemas"));
    assert_eq!(
        generated, shipped,
        "regenerate: cargo run --release -- schema --out schemas"
    );
    for name in &shipped {
        let now = fs::read_to_string(dir.path().join("schemas").join(name)).unwrap();
        let committed = fs::read_to_string(root().join("schemas").join(name)).unwrap();
        assert!(
            now == committed,
            "schemas/{name} is stale: regenerate with cargo run --release -- schema --out schemas"
        );
    }
}

#[test]
fn every_certificate_validates_and_only_against_its_own_kind() {
    let dir = tmp();
    let kinds = [
        "certificate",
        "scene-certificate",
        "search-certificate",
        "planar-certificate",
    ];
    let mut seen = BTreeSet::new();
    let mut check = |json: Value, what: &str| {
        let own = certificate_schema(&json);
        valid(own, &json, what);
        seen.insert(own);
        for other in kinds.iter().filter(|k| **k != own) {
            assert!(
                !validator(other).is_valid(&json),
                "{what} also fits {other}"
            );
        }
    };
    for name in shipped_problems() {
        let problem = root().join("problems").join(&name);
        for extra in [&[][..], &["--steps"][..]] {
            let out = safereach(dir.path())
                .arg("certify")
                .arg(&problem)
                .arg("--json")
                .args(extra)
                .output()
                .unwrap();
            let json: Value = serde_json::from_slice(&out.stdout)
                .unwrap_or_else(|e| panic!("{name}: certify --json is not JSON: {e}"));
            check(json, &format!("{name} {extra:?}"));
        }
    }
    // Noise, occlusion, weaker brakes and a range of gaps: every optional part written.
    let sets: &[&[&str]] = &[
        &["sensing.gap_noise=0.002", "sensing.speed_noise=0.01"],
        &[
            "sensing.first_detection_gap=1.2",
            "environment.obstacle_speed=0.25",
        ],
        &["robot.braking_min=0.04", "robot.initial_speed=0.1"],
        &["environment.initial_gap=[9.9, 10.1]"],
    ];
    for set in sets {
        let mut cmd = safereach(dir.path());
        cmd.arg("certify")
            .arg(root().join("problems/seed.toml"))
            .arg("--json");
        for s in *set {
            cmd.args(["--set", s]);
        }
        let out = cmd.output().unwrap();
        check(
            serde_json::from_slice(&out.stdout).unwrap(),
            &format!("seed {set:?}"),
        );
    }
    // A planar problem's certificate (the fastest shipped one).
    let out = safereach(dir.path())
        .arg("certify")
        .arg(root().join("problems/planar/crossing-car.toml"))
        .arg("--json")
        .output()
        .unwrap();
    check(
        serde_json::from_slice(&out.stdout).unwrap(),
        "planar crossing-car",
    );
    for name in files(&root().join("tests/fixtures")) {
        if name.ends_with(".cert.json") {
            let json = serde_json::from_str(&fs::read_to_string(fixture(&name)).unwrap()).unwrap();
            check(json, &name);
        }
    }
    assert_eq!(
        seen.len(),
        kinds.len(),
        "every kind of certificate was produced: {seen:?}"
    );
}

/// An edit of a certificate's JSON.
type Edit = fn(&mut Value);

#[test]
fn edited_certificates_do_not_validate() {
    let text = fs::read_to_string(fixture("seed.cert.json")).unwrap();
    let json: Value = serde_json::from_str(&text).unwrap();
    valid("certificate", &json, "seed.cert.json");
    let edits: [(&str, Edit); 5] = [
        ("an unknown field", |j| j["surplus"] = Value::Bool(true)),
        ("no verdict", |j| {
            j.as_object_mut().unwrap().remove("verdict");
        }),
        ("a verdict that is not one", |j| {
            j["verdict"] = "probably".into()
        }),
        ("a text for a number", |j| j["lower_bound"] = "0.33".into()),
        ("another format", |j| {
            j["format"] = "safereach-certificate/2".into()
        }),
    ];
    for (what, edit) in edits {
        let mut edited = json.clone();
        edit(&mut edited);
        assert!(
            !validator("certificate").is_valid(&edited),
            "{what} validates"
        );
    }
}

#[test]
fn region_maps_and_sweep_lines_validate() {
    let dir = tmp();
    safereach(dir.path())
        .arg("region")
        .arg(root().join("problems/seed.toml"))
        .args(["--range", "environment.obstacle_speed=0.10..0.30"])
        .args(["--range", "controller.reaction_radius=1.0..1.6"])
        .args(["--depth", "4", "--out", "map.json"])
        .assert()
        .code(predicates::ord::ne(2));
    let map: Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("map.json")).unwrap()).unwrap();
    valid("region-map", &map, "region --out");
    let mut edited = map.clone();
    edited["leaves"][0]["verdict"] = "maybe".into();
    assert!(
        !validator("region-map").is_valid(&edited),
        "an edited leaf verdict validates"
    );

    // A single-obstacle grid and a two-cell scene grid (its cells carry a worst case).
    fs::write(
        dir.path().join("scene-grid.toml"),
        format!(
            "base = {:?}\n[axes]\n\"obstacle.1.max_speed\" = [0.15, 0.3]\n",
            root()
                .join("problems/scene-oncoming.toml")
                .display()
                .to_string()
        ),
    )
    .unwrap();
    for (grid, name) in [
        (root().join("problems/seed-grid.toml"), "seed-grid"),
        (dir.path().join("scene-grid.toml"), "scene-grid"),
    ] {
        safereach(dir.path())
            .arg("sweep")
            .arg(&grid)
            .args(["--out", "sweep"])
            .assert()
            .code(0);
        let text = fs::read_to_string(dir.path().join(format!("sweep/{name}.jsonl"))).unwrap();
        let lines: Vec<Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert!(lines.len() >= 3, "{name}: provenance and cells");
        for (i, line) in lines.iter().enumerate() {
            valid("sweep-line", line, &format!("{name}.jsonl line {}", i + 1));
        }
        let mut edited = lines[1].clone();
        edited.as_object_mut().unwrap().remove("verdict");
        assert!(
            !validator("sweep-line").is_valid(&edited),
            "a cell without verdict validates"
        );
    }
}

/// Runs `monitor --json` and validates each line: events, then the summary.
fn monitor_lines_validate(dir: &Path, certificate: &str, trace: &Path) -> usize {
    let out = safereach(dir)
        .args(["monitor", "--certificate", certificate, "--json"])
        .arg(trace)
        .output()
        .unwrap();
    let text = stdout(&out);
    let lines: Vec<Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let (summary, events) = lines.split_last().expect("a summary line");
    valid("monitor-summary", summary, "the summary");
    assert!(!validator("monitor-event").is_valid(summary));
    for (i, event) in events.iter().enumerate() {
        valid("monitor-event", event, &format!("event {}", i + 1));
    }
    events.len()
}

#[test]
fn monitor_events_and_summaries_validate() {
    let dir = tmp();
    let seed = root().join("problems/seed.toml");
    safereach(dir.path())
        .arg("certify")
        .arg(&seed)
        .args([
            "--set",
            "environment.obstacle_speed=0.2",
            "--out",
            "seed.json",
        ])
        .assert()
        .code(0);
    let mut events = 0;
    for trace in ["crash.csv", "ignores-danger.csv", "noisy.csv"] {
        events += monitor_lines_validate(
            dir.path(),
            "seed.json",
            &root().join("examples/traces").join(trace),
        );
    }
    events += monitor_lines_validate(dir.path(), "seed.json", &fixture("seed-w0.25.run.csv"));
    // Malformed input: fail-safe events with a detail.
    fs::write(
        dir.path().join("bad.csv"),
        "t,robot_x,robot_v,obstacle_x\n0,0,0,10\n0.1,nan,0,9.9\n0.2,0,0\n",
    )
    .unwrap();
    events += monitor_lines_validate(dir.path(), "seed.json", &dir.path().join("bad.csv"));
    assert!(events > 10, "violations were produced: {events}");

    // A scene certificate's summary carries its scene part.
    safereach(dir.path())
        .arg("certify")
        .arg(root().join("problems/scene-oncoming.toml"))
        .args(["--out", "scene.json"])
        .assert()
        .code(0);
    safereach(dir.path())
        .arg("simulate")
        .arg(root().join("problems/scene-oncoming.toml"))
        .args(["--set", "obstacle.1.max_speed=0.25", "--trace", "fast.csv"])
        .assert()
        .code(predicates::ord::ne(2));
    assert!(monitor_lines_validate(dir.path(), "scene.json", &dir.path().join("fast.csv")) > 0);
}
