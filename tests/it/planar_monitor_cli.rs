//! `safereach monitor` on planar certificates: the witness trace `simulate --replay --trace`
//! writes (CSV and JSON Lines) holds under the certificate it came from; a trace edited out
//! of the model breaks the check that names it, with exit 1; unusable input exits 2 with
//! its reason.

use std::path::{Path, PathBuf};

use crate::common::cli::{safereach, stdout};
use crate::common::tmp;

fn problem(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("problems/planar/{name}.toml"))
}

/// `certify --out` of the seed in the plane (certified), and its witness trace in `ext`.
fn seed_and_trace(dir: &Path, ext: &str) -> (PathBuf, PathBuf) {
    let cert = dir.join("seed.json");
    safereach(dir)
        .arg("certify")
        .arg(problem("seed-in-plane"))
        .arg("--out")
        .arg(&cert)
        .assert()
        .code(0);
    let trace = dir.join(format!("seed.{ext}"));
    safereach(dir)
        .args(["simulate", "--replay"])
        .arg(&cert)
        .arg("--trace")
        .arg(&trace)
        .assert()
        .code(0);
    (cert, trace)
}

/// `monitor --json` of `trace` under `cert`: exit code, events, summary.
fn monitor_json(
    dir: &Path,
    cert: &Path,
    trace: &Path,
) -> (i32, Vec<serde_json::Value>, serde_json::Value) {
    let out = safereach(dir)
        .arg("monitor")
        .arg("--certificate")
        .arg(cert)
        .arg(trace)
        .arg("--json")
        .output()
        .expect("runs");
    let mut lines: Vec<serde_json::Value> = stdout(&out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON lines"))
        .collect();
    let last = lines.pop().expect("a summary");
    crate::schemas::valid("monitor-summary", &last, "planar summary");
    for e in &lines {
        crate::schemas::valid("monitor-event", e, "planar event");
    }
    let summary = last["summary"].clone();
    (out.status.code().unwrap(), lines, summary)
}

#[test]
fn the_certified_witness_trace_holds_in_csv_and_json_lines() {
    let dir = tmp();
    for ext in ["csv", "jsonl"] {
        let (cert, trace) = seed_and_trace(dir.path(), ext);
        let (code, events, summary) = monitor_json(dir.path(), &cert, &trace);
        assert_eq!((code, events.len()), (0, 0), "{ext}: {events:?}");
        assert_eq!(summary["verdict"], "held");
        let plane = &summary["plane"];
        assert_eq!(plane["obstacles"][0]["name"], "oncoming");
        assert_eq!(plane["obstacles"][0]["seen"], true);
        let checks = |list: &serde_json::Value, name: &str| {
            list.as_array()
                .unwrap()
                .iter()
                .find(|c| c["check"] == name || c["premise"] == name)
                .unwrap_or_else(|| panic!("{name} listed"))
                .clone()
        };
        // The brake at the danger is judged, the robot located on its path at every instant.
        let reaction = checks(&summary["behaviour"], "controller_reaction");
        assert_eq!(reaction["status"], "held");
        assert!(reaction["checks"].as_u64().unwrap() >= 1);
        let path = checks(&plane["checks"], "robot_path");
        assert_eq!(path["checks"], summary["instants"]);
        assert_eq!(
            checks(&summary["premises"], "obstacle_speed")["status"],
            "held"
        );
    }
}

#[test]
fn a_faster_obstacle_and_a_robot_that_does_not_brake_are_violations() {
    let dir = tmp();
    let (cert, trace) = seed_and_trace(dir.path(), "csv");
    let text = std::fs::read_to_string(&trace).unwrap();
    let header = text.lines().next().unwrap().to_string();
    let rows: Vec<Vec<String>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let write = |name: &str, rows: &[Vec<String>]| {
        let path = dir.path().join(name);
        let body: Vec<String> = rows.iter().map(|r| r.join(",")).collect();
        std::fs::write(&path, format!("{header}\n{}\n", body.join("\n"))).unwrap();
        path
    };
    // Columns: t, robot_x, robot_y, robot_v, robot_mode, obstacle_id, obstacle_x, ...
    let mut fast = rows.clone();
    for (k, r) in fast.iter_mut().enumerate().skip(100) {
        let x: f64 = r[6].parse().unwrap();
        r[6] = (x - 0.03 * (k - 99) as f64).to_string();
        r[8].clear();
        r[9].clear();
    }
    let (code, events, _) = monitor_json(dir.path(), &cert, &write("fast.csv", &fast));
    assert_eq!(code, 1);
    let first = &events[0];
    assert_eq!(first["premise"], "obstacle_speed");
    assert_eq!(first["obstacle_id"], "oncoming");
    assert!(first["observed"].as_f64().unwrap() > 0.3, "{first}");
    assert_eq!(first["bound"].as_f64().unwrap(), 0.15);
    let brake = rows.iter().position(|r| r[4] == "brake").expect("brakes");
    let mut on = rows.clone();
    on[brake][4] = "drive".into();
    let (code, events, _) = monitor_json(dir.path(), &cert, &write("on.csv", &on));
    assert_eq!(code, 1);
    assert_eq!(events.len(), 1, "{events:?}");
    assert_eq!(events[0]["premise"], "controller_reaction");
    // The text output says the same, one line per sample and a summary.
    let out = safereach(dir.path())
        .arg("monitor")
        .arg("--certificate")
        .arg(&cert)
        .arg(write("on.csv", &on))
        .assert()
        .code(1)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(
        text.contains("VIOLATION controller_reaction obstacle=oncoming"),
        "{text}"
    );
    assert!(
        text.contains("planar checks:") && text.contains("robot_path"),
        "{text}"
    );
}

#[test]
fn unusable_planar_input_exits_2_with_its_reason() {
    let dir = tmp();
    let (cert, trace) = seed_and_trace(dir.path(), "csv");
    // A ROS 2 bag is not read against a planar certificate yet.
    let out = safereach(dir.path())
        .arg("monitor")
        .arg("--certificate")
        .arg(&cert)
        .arg(&trace)
        .args(["--format", "mcap"])
        .assert()
        .code(2)
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("not read against planar certificates"),
        "{err}"
    );
    // A line trace (no robot_y): every sample is malformed, nothing is checked.
    let line = dir.path().join("line.csv");
    std::fs::write(
        &line,
        "t,robot_x,robot_v,obstacle_id,obstacle_x\n0,0,0,oncoming,10\n0.1,0,0,oncoming,10\n",
    )
    .unwrap();
    let out = safereach(dir.path())
        .arg("monitor")
        .arg("--certificate")
        .arg(&cert)
        .arg(&line)
        .assert()
        .code(2)
        .get_output()
        .clone();
    assert!(
        stdout(&out).contains("robot_y is missing"),
        "{}",
        stdout(&out)
    );
    // A refuted planar certificate guarantees nothing to monitor.
    let refuted = dir.path().join("crossing.json");
    safereach(dir.path())
        .arg("certify")
        .arg(problem("crossing-car"))
        .arg("--out")
        .arg(&refuted)
        .assert()
        .code(1);
    let out = safereach(dir.path())
        .arg("monitor")
        .arg("--certificate")
        .arg(&refuted)
        .arg(&trace)
        .assert()
        .code(2)
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not certified"), "{err}");
}
