//! `safereach monitor` on planar certificates: the witness trace `simulate --replay --trace`
//! writes (CSV and JSON Lines) holds under the certificate it came from; a trace edited out
//! of the model breaks the check that names it, with exit 1; unusable input exits 2 with
//! its reason.

use std::path::{Path, PathBuf};

use mcap::Compression;

use crate::bag_writer::{self, Body, odometry, stamp, yaw};
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

/// The trace `csv` (the planar columns) as a ROS 2 bag recorded in an odometry frame in
/// which the problem's frame has origin `origin` and heading `heading`: the robot's
/// odometry on /odom (heading along the seed's path, the problem's x axis), each obstacle's
/// on /obstacles/NAME (child frame NAME), the mode on /mode.
fn planar_bag(csv: &str, path: &Path, origin: [f64; 2], heading: f64) {
    let (c, s) = (heading.cos(), heading.sin());
    let world = |x: f64, y: f64| [origin[0] + c * x - s * y, origin[1] + s * x + c * y];
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let mut bag = bag_writer::Bag::create(path, Some(Compression::Zstd));
    let mut last_t = String::new();
    for (k, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let n = |name: &str| f[col(name)].parse::<f64>().unwrap_or(0.0);
        let t = f[col("t")];
        let st = stamp(t);
        if t != last_t {
            let robot = Body {
                position: world(n("robot_x"), n("robot_y")),
                orientation: yaw(heading),
                velocity: [n("robot_v"), 0.0],
            };
            let k = k as u64;
            bag.write(
                "/odom",
                "nav_msgs/msg/Odometry",
                k,
                &odometry(st, "base_link", &robot),
            );
            let mode = bag_writer::text(f[col("robot_mode")]);
            bag.write("/mode", "std_msgs/msg/String", k, &mode);
            last_t = t.to_string();
        }
        let name = f[col("obstacle_id")];
        // Its velocity in its own frame, which is the problem's turned by `heading`.
        let obstacle = Body {
            position: world(n("obstacle_x"), n("obstacle_y")),
            orientation: yaw(heading),
            velocity: [n("obstacle_vx"), n("obstacle_vy")],
        };
        let topic = format!("/obstacles/{name}");
        bag.write(
            &topic,
            "nav_msgs/msg/Odometry",
            k as u64,
            &odometry(st, name, &obstacle),
        );
    }
    bag.finish();
}

#[test]
fn a_ros_bag_in_a_turned_and_shifted_odometry_frame_reads_as_its_trace() {
    let dir = tmp();
    let d = dir.path();
    let (cert, trace) = seed_and_trace(d, "csv");
    let text = std::fs::read_to_string(&trace).unwrap();
    let run = |bag: &Path, extra: &[&str]| {
        let out = safereach(d)
            .arg("monitor")
            .arg("--certificate")
            .arg(&cert)
            .arg(bag)
            .args([
                "--mode-topic",
                "/mode",
                "--obstacle-topic",
                "/obstacles/*",
                "--json",
            ])
            .args(extra)
            .output()
            .unwrap();
        let lines: Vec<serde_json::Value> = stdout(&out)
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        (out.status.code().unwrap(), lines)
    };
    // The problem's frame 3 m east, 1 m north, turned by 0.5 rad: a robot 1e-14 off its
    // path after the turn there and back is within the tolerance the problem states.
    let tolerant = d.join("tolerant.json");
    safereach(d)
        .arg("certify")
        .arg(problem("seed-in-plane"))
        .args(["--set", "robot.path_tolerance=1e-6", "--out"])
        .arg(&tolerant)
        .assert()
        .code(0);
    let bag = d.join("turned.mcap");
    planar_bag(&text, &bag, [3.0, 1.0], 0.5);
    let out = safereach(d)
        .arg("monitor")
        .arg("--certificate")
        .arg(&tolerant)
        .arg(&bag)
        .args(["--mode-topic", "/mode", "--obstacle-topic", "/obstacles/*"])
        .args(["--lane-axis", "3,1,0.5", "--events-only"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stdout(&out));
    assert!(stdout(&out).contains("summary: held"), "{}", stdout(&out));
    // Unturned, a robot that does not brake is the CSV's violation, at the same instant.
    let brake = text.lines().position(|l| l.contains(",brake,")).unwrap();
    let edited: String = text
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == brake {
                l.replace(",brake,", ",drive,")
            } else {
                l.into()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let flat = d.join("on.mcap");
    planar_bag(&edited, &flat, [0.0, 0.0], 0.0);
    let (code, lines) = run(&flat, &[]);
    assert_eq!(code, 1);
    assert_eq!(lines[0]["premise"], "controller_reaction", "{lines:?}");
    let on_csv = d.join("on.csv");
    std::fs::write(&on_csv, format!("{edited}\n")).unwrap();
    let (_, csv_events, _) = monitor_json(d, &cert, &on_csv);
    assert_eq!(lines[0]["t"], csv_events[0]["t"]);
    assert_eq!(lines[0]["observed"], csv_events[0]["observed"]);
}

/// A planar region map is monitored at its box's weak corner (docs/reductions.md Lemma P7):
/// the seed's witness trace (ρ = 1.4, W = 0.15, inside the box) holds; an obstacle faster
/// than the box's W_hi = 0.2 is flagged against 0.2; `--at` and a ranged V_a are refused.
#[test]
fn a_planar_region_map_is_monitored_at_its_weak_corner() {
    let dir = tmp();
    let (_, trace) = seed_and_trace(dir.path(), "csv");
    let map = |name: &str, extra: &[&str]| {
        let path = dir.path().join(name);
        safereach(dir.path())
            .arg("region")
            .arg(problem("seed-in-plane"))
            .args([
                "--range",
                "controller.reaction_radius=1.3..1.6",
                "--range",
                "obstacle.0.max_speed=0.1..0.2",
                "--depth",
                "0",
                "--out",
            ])
            .arg(&path)
            .args(extra)
            .assert()
            .code(0);
        path
    };
    let whole = map("map.json", &[]);
    let (code, events, summary) = monitor_json(dir.path(), &whole, &trace);
    assert_eq!((code, events.len()), (0, 0), "{events:?}");
    assert_eq!(summary["verdict"], "held");
    let text = std::fs::read_to_string(&trace).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for (k, line) in lines.iter_mut().enumerate().skip(101) {
        let mut r: Vec<String> = line.split(',').map(str::to_string).collect();
        let x: f64 = r[6].parse().unwrap();
        r[6] = (x - 0.03 * (k - 100) as f64).to_string();
        r[8].clear();
        r[9].clear();
        *line = r.join(",");
    }
    let fast = dir.path().join("fast.csv");
    std::fs::write(&fast, lines.join("\n") + "\n").unwrap();
    let (code, events, _) = monitor_json(dir.path(), &whole, &fast);
    assert_eq!(code, 1);
    assert_eq!(events[0]["premise"], "obstacle_speed");
    assert_eq!(events[0]["bound"].as_f64().unwrap(), 0.2);
    let refused = |cert: &std::path::Path, extra: &[&str], needle: &str| {
        let out = safereach(dir.path())
            .arg("monitor")
            .arg("--certificate")
            .arg(cert)
            .arg(&trace)
            .args(extra)
            .assert()
            .code(2)
            .get_output()
            .clone();
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(err.contains(needle), "{err}");
    };
    refused(&whole, &["--at", "controller.reaction_radius=1.4"], "--at");
    let va = map(
        "va.json",
        &["--range", "controller.assumed_obstacle_speed=0.2..0.25"],
    );
    refused(&va, &[], "controller.assumed_obstacle_speed");
}
