//! `safereach monitor` on ROS 2 bags (MCAP) that the tests write themselves
//! ([`crate::bag_writer`]): the seed's 0.2 / 0.25 example as a bag gives the verdicts and the
//! first violation of its CSV, through every layout a recorder may choose (compression,
//! message order, tracked objects or odometry, a rotated lane, a mode topic or inferred
//! modes), and every unreadable part of a bag is a fail-safe event, never a crash.

use std::fs;
use std::path::Path;

use mcap::Compression;
use serde_json::Value;

use crate::bag_writer::{self, Body, Layout, odometry, rows, seed_bag, stamp, yaw};
use crate::common::cli::safereach;
use crate::common::paths::{fixture, problem_file, root, seed_file};
use crate::common::tmp;
use crate::schemas::valid;

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

/// `safereach monitor ARGS`, with the topics the test bags use when the trace is a bag.
fn monitor(dir: &Path, args: &[&str]) -> Run {
    let mut cmd = safereach(dir);
    cmd.arg("monitor").args(args);
    if args.iter().any(|a| a.ends_with(".mcap")) && !args.contains(&"--obstacle-topic") {
        cmd.args([
            "--obstacle-topic",
            "/obstacles/*",
            "--obstacle-topic",
            "/perception/*",
        ]);
    }
    if args.iter().any(|a| a.ends_with(".mcap"))
        && !args.contains(&"--infer-mode")
        && !args.contains(&"--mode-topic")
    {
        cmd.args(["--mode-topic", "/mode"]);
    }
    let out = cmd.output().unwrap();
    Run {
        code: out.status.code().unwrap(),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

/// The seed certified for W = 0.2, as the README's worked example.
fn seed_certificate(dir: &Path) {
    safereach(dir)
        .arg("certify")
        .arg(seed_file())
        .args([
            "--set",
            "environment.obstacle_speed=0.2",
            "--out",
            "cert.json",
        ])
        .assert()
        .code(0);
}

/// `monitor --json` lines: the events and the summary, each validated against its shipped
/// schema.
fn json(run: &Run) -> (Vec<Value>, Value) {
    let mut lines: Vec<Value> = run
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let last = lines.pop().unwrap();
    valid("monitor-summary", &last, "a bag's summary");
    for (i, e) in lines.iter().enumerate().take(20) {
        valid("monitor-event", e, &format!("a bag's event {}", i + 1));
    }
    (lines, last["summary"].clone())
}

/// An event without its place in the input (a CSV line, a bag message) and, when the names
/// differ by design, without its obstacle.
fn event(e: &Value, keep_obstacle: bool) -> Value {
    let mut e = e.clone();
    e.as_object_mut().unwrap().remove("line");
    if !keep_obstacle {
        e.as_object_mut().unwrap().remove("obstacle_id");
    }
    e
}

/// The premises' summaries, without `latency`: a bag's observations carry their stamps, so
/// latency is monitored there and not in a CSV without `obstacle_t`.
fn premises(summary: &Value) -> Vec<Value> {
    summary["premises"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["premise"] != "latency")
        .cloned()
        .collect()
}

/// What a bag's monitoring must share with the CSV's, exactly.
fn same_as_csv(csv: &Run, bag: &Run, keep_obstacle: bool, what: &str) {
    assert_eq!(
        bag.code, csv.code,
        "{what}: exit code; stderr {}",
        bag.stderr
    );
    let (csv_events, csv_summary) = json(csv);
    let (bag_events, bag_summary) = json(bag);
    let strip = |v: &[Value]| {
        v.iter()
            .map(|e| event(e, keep_obstacle))
            .collect::<Vec<_>>()
    };
    assert_eq!(strip(&bag_events), strip(&csv_events), "{what}: events");
    for key in [
        "verdict",
        "samples",
        "instants",
        "obstacles",
        "violations",
        "behaviour",
    ] {
        assert_eq!(bag_summary[key], csv_summary[key], "{what}: summary {key}");
    }
    assert_eq!(
        premises(&bag_summary),
        premises(&csv_summary),
        "{what}: premises"
    );
    assert_eq!(
        event(&bag_summary["first_violation"], keep_obstacle),
        event(&csv_summary["first_violation"], keep_obstacle),
        "{what}: first violation"
    );
}

#[test]
fn the_seed_example_as_a_bag_gives_the_verdicts_and_first_violation_of_its_csv() {
    let dir = tmp();
    seed_certificate(dir.path());
    let csv_path = fixture("seed-w0.25.run.csv");
    let trace = rows(&fs::read_to_string(&csv_path).unwrap());
    let csv_path = csv_path.to_str().unwrap();
    let csv = monitor(
        dir.path(),
        &["--certificate", "cert.json", "--json", csv_path],
    );
    assert_eq!(csv.code, 1, "the CSV violates obstacle_speed");
    let (_, csv_summary) = json(&csv);
    assert_eq!(csv_summary["first_violation"]["premise"], "obstacle_speed");

    let layouts = [
        (
            "zstd, odometry per obstacle, mode topic",
            Layout::default(),
            true,
        ),
        (
            "lz4",
            Layout {
                compression: Some(Compression::Lz4),
                ..Layout::default()
            },
            true,
        ),
        (
            "uncompressed, obstacle written before the robot",
            Layout {
                compression: None,
                obstacle_first: true,
                ..Layout::default()
            },
            true,
        ),
        (
            "tracked objects",
            Layout {
                tracked: true,
                ..Layout::default()
            },
            false,
        ),
    ];
    for (what, layout, same_names) in layouts {
        seed_bag(&trace, &dir.path().join("run.mcap"), layout);
        // The simulator's trace holds true positions: as ground truth, the bag is the CSV.
        let bag = monitor(
            dir.path(),
            &[
                "--certificate",
                "cert.json",
                "--json",
                "--ground-truth",
                "run.mcap",
            ],
        );
        same_as_csv(&csv, &bag, same_names, what);
        let (_, summary) = json(&bag);
        assert_eq!(
            summary["premises"], csv_summary["premises"],
            "{what}: premises, latency too"
        );
        let name = if same_names {
            "0".to_string()
        } else {
            bag_writer::uuid_name("0")
        };
        assert_eq!(
            summary["first_violation"]["obstacle_id"],
            name.as_str(),
            "{what}"
        );

        // Read as observations (the default), each stamp is when the controller had it: the
        // first violation is the same, latency is monitored, and a reaction the simulated
        // controller made one period late (it had each position L = 1 period later) is now
        // flagged on top.
        let observed = monitor(
            dir.path(),
            &["--certificate", "cert.json", "--json", "run.mcap"],
        );
        assert_eq!(observed.code, 1);
        let (events, summary) = json(&observed);
        assert_eq!(
            event(&summary["first_violation"], same_names),
            event(&csv_summary["first_violation"], same_names),
            "{what}"
        );
        let latency = &summary["premises"].as_array().unwrap()[3];
        assert_eq!(latency["premise"], "latency");
        assert_eq!(latency["status"], "held", "{what}: stamps carry latency");
        let (csv_events, _) = json(&csv);
        let extra: Vec<&Value> = events
            .iter()
            .filter(|e| {
                !csv_events
                    .iter()
                    .any(|c| event(c, false) == event(e, false))
            })
            .collect();
        assert!(
            extra.iter().all(|e| e["premise"] == "controller_reaction"),
            "{what}: {extra:?}"
        );
    }

    // The text output names the same first violation, at the bag message it came from.
    seed_bag(&trace, &dir.path().join("run.mcap"), Layout::default());
    let text = monitor(
        dir.path(),
        &["--certificate", "cert.json", "--ground-truth", "run.mcap"],
    );
    let csv_text = monitor(dir.path(), &["--certificate", "cert.json", csv_path]);
    let first = |s: &str| {
        let line = s
            .lines()
            .find(|l| l.starts_with("first violation:"))
            .unwrap()
            .to_string();
        line.split(" (").next().unwrap().to_string()
    };
    assert_eq!(first(&text.stdout), first(&csv_text.stdout));
    // CSV line L (after the header) is row L - 2, written as three messages: robot, mode,
    // obstacle — the obstacle's is message 3 (L - 1).
    let line = csv_summary["first_violation"]["line"].as_u64().unwrap();
    let place = format!("(message {})", 3 * (line - 1));
    assert!(text.stdout.contains(&place), "{place}: {}", text.stdout);
    let n = trace.len();
    let counts = format!(
        "{} messages: {n} robot instants, {n} obstacle observations, {n} modes, 0 skipped",
        3 * n
    );
    assert!(text.stderr.contains(&counts), "{counts}: {}", text.stderr);
}

/// The README's example as a test case: the certificate for W = 0.2, the W = 0.25 run as a
/// bag laid out as `layout` (`run.mcap`), and `monitor --json` on its CSV.
fn seed_case(layout: Layout) -> (tempfile::TempDir, Run) {
    let dir = tmp();
    seed_certificate(dir.path());
    let csv_path = fixture("seed-w0.25.run.csv");
    let trace = rows(&fs::read_to_string(&csv_path).unwrap());
    seed_bag(&trace, &dir.path().join("run.mcap"), layout);
    let csv_path = csv_path.to_str().unwrap();
    let csv = monitor(
        dir.path(),
        &["--certificate", "cert.json", "--json", csv_path],
    );
    (dir, csv)
}

#[test]
fn modes_inferred_from_speeds_give_the_same_verdict_and_first_violation() {
    let (dir, csv) = seed_case(Layout {
        mode_topic: false,
        ..Layout::default()
    });
    let inferred = monitor(
        dir.path(),
        &[
            "--certificate",
            "cert.json",
            "--json",
            "--ground-truth",
            "--infer-mode",
            "run.mcap",
        ],
    );
    let (_, c) = json(&csv);
    let (_, b) = json(&inferred);
    assert_eq!(inferred.code, csv.code);
    assert_eq!(
        event(&b["first_violation"], true),
        event(&c["first_violation"], true)
    );
    let braking = |s: &Value| s["premises"][1].clone();
    assert_eq!(braking(&b)["status"], "held");
    assert!(
        braking(&b)["checks"].as_u64().unwrap() > 0,
        "braking is recognised"
    );
    // Without modes, braking cannot be recognised, and says so.
    let none = monitor(
        dir.path(),
        &[
            "--certificate",
            "cert.json",
            "--json",
            "--ground-truth",
            "run.mcap",
            "--mode-topic",
            "/none",
        ],
    );
    assert_eq!(json(&none).1["premises"][1]["status"], "not_monitored");
}

#[test]
fn a_rotated_and_shifted_lane_reads_as_the_same_run() {
    let heading = 35f64.to_radians();
    let (dir, csv) = seed_case(Layout {
        heading,
        origin: [120.5, -40.25],
        ..Layout::default()
    });
    let (_, c) = json(&csv);
    // The lane from the robot's first pose, and the same lane given by hand.
    let axis = format!("120.5,-40.25,{heading}");
    for extra in [vec![], vec!["--lane-axis", axis.as_str()]] {
        let mut args = vec![
            "--certificate",
            "cert.json",
            "--json",
            "--ground-truth",
            "run.mcap",
        ];
        args.extend(extra);
        let bag = monitor(dir.path(), &args);
        let (_, b) = json(&bag);
        assert_eq!(bag.code, csv.code, "{}", bag.stderr);
        let first = |s: &Value| {
            (
                s["first_violation"]["t"].clone(),
                s["first_violation"]["premise"].clone(),
            )
        };
        assert_eq!(first(&b), first(&c));
        assert_eq!(b["violations"], c["violations"]);
        let gap = |s: &Value| {
            s["behaviour"]
                .as_array()
                .unwrap()
                .iter()
                .find(|x| x["check"] == "collision")
                .unwrap()["margin"]["slack"]
                .as_f64()
                .unwrap()
        };
        assert!(
            (gap(&b) - gap(&c)).abs() < 1e-9,
            "the smallest gap is the CSV's up to rounding"
        );
    }
}

#[test]
fn a_held_run_holds_from_a_bag_too() {
    // The seed's own W = 0.15 run under the seed certificate: every premise holds.
    let dir = tmp();
    safereach(dir.path())
        .arg("simulate")
        .arg(seed_file())
        .args(["--runs", "20", "--trace", "run.csv"])
        .assert()
        .code(0);
    let trace = rows(&fs::read_to_string(dir.path().join("run.csv")).unwrap());
    seed_bag(&trace, &dir.path().join("run.mcap"), Layout::default());
    let cert = fixture("seed.cert.json");
    let cert = cert.to_str().unwrap();
    let csv = monitor(dir.path(), &["--certificate", cert, "run.csv"]);
    let bag = monitor(
        dir.path(),
        &["--certificate", cert, "--ground-truth", "run.mcap"],
    );
    assert_eq!(csv.code, 0, "{}", csv.stdout);
    assert_eq!(bag.code, 0, "{}\n{}", bag.stdout, bag.stderr);
    assert!(bag.stdout.contains("summary: held"));
}

/// A short valid bag: `n` instants of the robot at rest and one obstacle far away.
fn quiet_bag(bag: &mut bag_writer::Bag, n: usize) {
    for k in 0..n {
        let t = format!("{}.{}", k / 10, k % 10);
        let robot = Body {
            position: [0.0, 0.0],
            orientation: yaw(0.0),
            velocity: [0.0, 0.0],
        };
        let obstacle = Body {
            position: [10.0, 0.0],
            orientation: yaw(std::f64::consts::PI),
            velocity: [0.0, 0.0],
        };
        let log = k as u64 * 100_000_000;
        bag.write(
            "/odom",
            "nav_msgs/msg/Odometry",
            log,
            &odometry(stamp(&t), "base_link", &robot),
        );
        bag.write(
            "/obstacles/0/odom",
            "nav_msgs/msg/Odometry",
            log,
            &odometry(stamp(&t), "0", &obstacle),
        );
    }
}

#[test]
fn unreadable_messages_and_damaged_bags_are_fail_safe_events() {
    let dir = tmp();
    let cert = fixture("seed.cert.json");
    let cert = cert.to_str().unwrap();
    let d = dir.path();

    // A clean quiet bag holds.
    let mut bag = bag_writer::Bag::create(&d.join("quiet.mcap"), Some(Compression::Zstd));
    quiet_bag(&mut bag, 20);
    bag.finish();
    let clean = monitor(
        d,
        &[
            "--certificate",
            cert,
            "quiet.mcap",
            "--obstacle-topic",
            "/obstacles/*",
        ],
    );
    assert_eq!(clean.code, 0, "{}{}", clean.stdout, clean.stderr);

    // A truncated robot message, an obstacle topic of another type, a mode that is none.
    let mut bag = bag_writer::Bag::create(&d.join("bad.mcap"), Some(Compression::Lz4));
    quiet_bag(&mut bag, 5);
    let full = odometry(
        stamp("0.5"),
        "base_link",
        &Body {
            position: [0.0, 0.0],
            orientation: yaw(0.0),
            velocity: [0.0, 0.0],
        },
    );
    bag.write("/odom", "nav_msgs/msg/Odometry", 600_000_000, &full[..100]);
    bag.write(
        "/obstacles/imu",
        "sensor_msgs/msg/Imu",
        600_000_000,
        &[0, 1, 0, 0, 1, 2, 3],
    );
    bag.write_encoded(
        "/obstacles/json",
        "nav_msgs/msg/Odometry",
        "json",
        600_000_000,
        b"{}",
    );
    bag.write(
        "/mode",
        "std_msgs/msg/String",
        600_000_000,
        &bag_writer::text("hover"),
    );
    bag.write("/odom", "nav_msgs/msg/Odometry", 700_000_000, &[9, 9, 9]);
    bag.finish();
    let bad = monitor(
        d,
        &[
            "--certificate",
            cert,
            "--json",
            "bad.mcap",
            "--obstacle-topic",
            "/obstacles/*",
            "--mode-topic",
            "/mode",
        ],
    );
    assert_eq!(bad.code, 1, "{}{}", bad.stdout, bad.stderr);
    let (events, summary) = json(&bad);
    let details: Vec<&str> = events
        .iter()
        .map(|e| e["detail"].as_str().unwrap())
        .collect();
    assert!(
        events
            .iter()
            .all(|e| e["premise"] == "malformed_sample" && e["action"] == "brake"),
        "{events:?}"
    );
    let expected = [
        "ends before its last field",
        "message type is not one the monitor reads",
        "message type is not one the monitor reads",
        "robot_mode is not one of",
        "not CDR",
    ];
    assert_eq!(details.len(), expected.len(), "{details:?}");
    for (detail, part) in details.iter().zip(expected) {
        assert!(detail.contains(part), "{part:?} in {details:?}");
    }
    assert_eq!(summary["fail_safe"]["malformed_sample"], 5);

    // A bag cut off mid-chunk: what came before is checked, then the damage is an event.
    let mut bag = bag_writer::Bag::create(&d.join("long.mcap"), None);
    quiet_bag(&mut bag, 200);
    bag.finish();
    let bytes = fs::read(d.join("long.mcap")).unwrap();
    fs::write(d.join("cut.mcap"), &bytes[..bytes.len() / 2]).unwrap();
    let cut = monitor(
        d,
        &[
            "--certificate",
            cert,
            "--json",
            "cut.mcap",
            "--obstacle-topic",
            "/obstacles/*",
        ],
    );
    assert_eq!(cut.code, 1, "{}", cut.stderr);
    let (events, summary) = json(&cut);
    assert_eq!(events.len(), 1);
    assert!(
        events[0]["detail"].as_str().unwrap().contains("truncated"),
        "{events:?}"
    );
    assert!(
        summary["instants"].as_u64().unwrap() > 50,
        "the first half was checked"
    );

    // A flipped byte inside the first compressed chunk: its CRC fails before any of its
    // messages is used.
    let mut bag = bag_writer::Bag::create(&d.join("z.mcap"), Some(Compression::Zstd));
    quiet_bag(&mut bag, 200);
    bag.finish();
    let mut bytes = fs::read(d.join("z.mcap")).unwrap();
    let chunk = bytes.iter().position(|&b| b == 0x06).unwrap(); // the chunk opcode
    bytes[chunk + 200] ^= 0x5a;
    fs::write(d.join("flipped.mcap"), &bytes).unwrap();
    let flipped = monitor(
        d,
        &[
            "--certificate",
            cert,
            "--json",
            "flipped.mcap",
            "--obstacle-topic",
            "/obstacles/*",
        ],
    );
    assert_eq!(
        flipped.code, 2,
        "nothing trustworthy was read: {}",
        flipped.stderr
    );
    let (events, summary) = json(&flipped);
    assert_eq!(summary["verdict"], "nothing_checked");
    assert!(
        events[0]["detail"].as_str().unwrap().contains("CRC"),
        "{events:?}"
    );

    // Not a bag at all: nothing checked, exit 2.
    fs::write(d.join("text.mcap"), "t,robot_x\n0,0\n").unwrap();
    let text = monitor(d, &["--certificate", cert, "text.mcap"]);
    assert_eq!(text.code, 2);
    assert!(text.stdout.contains("not an MCAP file"), "{}", text.stdout);
}

#[test]
fn a_misnamed_robot_topic_lists_the_bags_topics() {
    let dir = tmp();
    let d = dir.path();
    let mut bag = bag_writer::Bag::create(&d.join("q.mcap"), None);
    quiet_bag(&mut bag, 3);
    bag.finish();
    let cert = fixture("seed.cert.json");
    let run = monitor(
        d,
        &[
            "--certificate",
            cert.to_str().unwrap(),
            "q.mcap",
            "--robot-topic",
            "/robot/odom",
        ],
    );
    assert_eq!(run.code, 2);
    assert!(
        run.stderr
            .contains("no robot odometry on /robot/odom (--robot-topic)"),
        "{}",
        run.stderr
    );
    assert!(
        run.stderr.contains("/odom (nav_msgs/msg/Odometry)"),
        "{}",
        run.stderr
    );
}

#[test]
fn bad_bag_flags_name_the_flag_and_exit_2() {
    let dir = tmp();
    let d = dir.path();
    let mut bag = bag_writer::Bag::create(&d.join("q.mcap"), None);
    quiet_bag(&mut bag, 3);
    bag.finish();
    let cert = fixture("seed.cert.json");
    let cert = cert.to_str().unwrap();
    let csv = fixture("seed-w0.25.run.csv");
    let cases: [(Vec<&str>, &str); 5] = [
        (
            vec!["q.mcap", "--lane-axis", "1,2"],
            "--lane-axis \"1,2\": expected three numbers",
        ),
        (
            vec!["q.mcap", "--lane-axis", "1,x,0"],
            "--lane-axis \"1,x,0\": expected three finite numbers",
        ),
        (
            vec!["q.mcap", "--obstacle-topic", "/a/[b"],
            "--obstacle-topic: obstacle topic pattern \"/a/[b\" is not a glob",
        ),
        (
            vec![csv.to_str().unwrap(), "--robot-topic", "/x"],
            "--robot-topic applies to ROS 2 bags (MCAP)",
        ),
        (
            vec!["q.mcap", "--columns", "t,robot_x"],
            "--columns names CSV columns",
        ),
    ];
    for (args, message) in cases {
        let mut all = vec!["--certificate", cert];
        all.extend(args.iter().copied());
        let run = monitor(d, &all);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(message), "{args:?}: {}", run.stderr);
    }
    let run = monitor(
        d,
        &[
            "--certificate",
            cert,
            "q.mcap",
            "--infer-mode",
            "--mode-topic",
            "/m",
        ],
    );
    assert_eq!(run.code, 2, "clap refuses two mode sources");
}

#[test]
fn scene_obstacles_on_their_own_topics_are_matched_by_name() {
    // The scene with several oncoming obstacles, simulated with one of them too fast; each
    // obstacle published on its own odometry topic named by its scene name.
    let dir = tmp();
    let d = dir.path();
    let scene = problem_file("scene-oncoming.toml");
    safereach(d)
        .arg("certify")
        .arg(&scene)
        .args(["--out", "scene.json"])
        .assert()
        .code(0);
    safereach(d)
        .arg("simulate")
        .arg(&scene)
        .args(["--set", "obstacle.1.max_speed=0.25", "--trace", "fast.csv"])
        .output()
        .unwrap();
    let text = fs::read_to_string(d.join("fast.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let mut bag = bag_writer::Bag::create(&d.join("fast.mcap"), Some(Compression::Zstd));
    let mut last_t = String::new();
    let mut k = 0u64;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let t = f[col("t")];
        let st = stamp(t);
        if t != last_t {
            let robot = Body {
                position: [f[col("robot_x")].parse().unwrap(), 0.0],
                orientation: yaw(0.0),
                velocity: [f[col("robot_v")].parse().unwrap(), 0.0],
            };
            bag.write(
                "/odom",
                "nav_msgs/msg/Odometry",
                k,
                &odometry(st, "base_link", &robot),
            );
            bag.write(
                "/mode",
                "std_msgs/msg/String",
                k,
                &bag_writer::text(f[col("robot_mode")]),
            );
            last_t = t.to_string();
        }
        k += 1;
        if f[col("obstacle_id")].is_empty() {
            continue;
        }
        let name = f[col("obstacle_id")];
        let speed: f64 = f[col("obstacle_v")].parse().unwrap_or(0.0);
        let obstacle = Body {
            position: [f[col("obstacle_x")].parse().unwrap(), 0.0],
            orientation: yaw(std::f64::consts::PI),
            velocity: [speed, 0.0],
        };
        bag.write(
            &format!("/obstacles/{name}"),
            "nav_msgs/msg/Odometry",
            k,
            &odometry(st, name, &obstacle),
        );
    }
    bag.finish();
    let csv = monitor(d, &["--certificate", "scene.json", "--json", "fast.csv"]);
    let run = monitor(
        d,
        &[
            "--certificate",
            "scene.json",
            "--json",
            "--ground-truth",
            "fast.mcap",
            "--obstacle-topic",
            "/obstacles/*",
            "--mode-topic",
            "/mode",
        ],
    );
    let (_, c) = json(&csv);
    let (_, b) = json(&run);
    assert_eq!(run.code, csv.code, "{}", run.stderr);
    assert_eq!(
        b["first_violation"]["premise"],
        c["first_violation"]["premise"]
    );
    assert_eq!(b["first_violation"]["t"], c["first_violation"]["t"]);
    assert_eq!(
        b["first_violation"]["obstacle_id"],
        c["first_violation"]["obstacle_id"]
    );
    let seen = |s: &Value| {
        s["scene"]["obstacles"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| (o["name"].clone(), o["seen"].clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        seen(&b),
        seen(&c),
        "every scene obstacle matched by its topic's name"
    );
    assert_eq!(b["scene"]["unmatched"], 0);
}

/// `examples/bags/seed-w0.25.mcap`, the README's bag, is the fixture trace
/// `tests/fixtures/seed-w0.25.run.csv` as [`seed_bag`] writes it (zstd, one odometry topic
/// for the obstacle, the mode on `/mode`). Rewrite it after a deliberate change with
/// `SAFEREACH_BLESS_FIXTURES=1 cargo test --release --test it monitor_bag::`.
#[test]
fn the_shipped_example_bag_is_the_fixture_trace() {
    let dir = tmp();
    let trace = rows(&fs::read_to_string(fixture("seed-w0.25.run.csv")).unwrap());
    let written = dir.path().join("seed.mcap");
    seed_bag(&trace, &written, Layout::default());
    let written = fs::read(written).unwrap();
    let shipped = root().join("examples/bags/seed-w0.25.mcap");
    if std::env::var_os("SAFEREACH_BLESS_FIXTURES").is_some() {
        fs::create_dir_all(shipped.parent().unwrap()).unwrap();
        fs::write(&shipped, &written).unwrap();
    }
    let on_disk = fs::read(&shipped).unwrap_or_default();
    assert!(
        on_disk == written,
        "{} is stale: rewrite it with SAFEREACH_BLESS_FIXTURES=1 cargo test --release --test it monitor_bag::",
        shipped.display()
    );
}

/// `fuzz/corpus/bag/`, the bag fuzz target's seed corpus: small bags without checksums (so
/// mutations reach the decoder) in each layout — odometry per obstacle with a mode topic,
/// tracked objects, a bag with a malformed message. Rewritten like the example bag.
#[test]
fn the_bag_fuzz_corpus_is_what_the_writer_writes() {
    let dir = tmp();
    let trace = rows(&fs::read_to_string(fixture("seed-w0.25.run.csv")).unwrap());
    let corpus = root().join("fuzz/corpus/bag");
    let bless = std::env::var_os("SAFEREACH_BLESS_FIXTURES").is_some();
    let mut written = Vec::new();
    for (name, tracked) in [("odometry.mcap", false), ("tracked.mcap", true)] {
        let path = dir.path().join(name);
        let mut bag = bag_writer::Bag::for_fuzzing(&path);
        for (k, row) in trace.iter().take(6).enumerate() {
            let st = stamp(&row.t);
            let log = k as u64;
            let robot = Body {
                position: [row.robot_x, 0.0],
                orientation: yaw(0.0),
                velocity: [row.robot_v, 0.0],
            };
            let obstacle = Body {
                position: [row.obstacle_x, 0.0],
                orientation: yaw(std::f64::consts::PI),
                velocity: [row.obstacle_v, 0.0],
            };
            bag.write(
                "/odom",
                "nav_msgs/msg/Odometry",
                log,
                &odometry(st, "base_link", &robot),
            );
            bag.write(
                "/mode",
                "std_msgs/msg/String",
                log,
                &bag_writer::text(&row.robot_mode),
            );
            if tracked {
                let data = bag_writer::tracked_objects(st, &[(bag_writer::uuid_of("0"), obstacle)]);
                bag.write(
                    "/obstacles/tracked",
                    "autoware_perception_msgs/msg/TrackedObjects",
                    log,
                    &data,
                );
            } else {
                bag.write(
                    "/obstacles/0",
                    "nav_msgs/msg/Odometry",
                    log,
                    &odometry(st, "0", &obstacle),
                );
            }
        }
        if tracked {
            bag.write("/odom", "nav_msgs/msg/Odometry", 99, &[0, 1, 0, 0, 7]);
        }
        bag.finish();
        written.push((name, fs::read(&path).unwrap()));
    }
    for (name, bytes) in written {
        let shipped = corpus.join(name);
        if bless {
            fs::create_dir_all(&corpus).unwrap();
            fs::write(&shipped, &bytes).unwrap();
        }
        assert!(
            fs::read(&shipped).unwrap_or_default() == bytes,
            "{} is stale: rewrite it with SAFEREACH_BLESS_FIXTURES=1 cargo test --release --test it monitor_bag::",
            shipped.display()
        );
    }
}
