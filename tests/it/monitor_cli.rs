//! `safereach monitor` run as a user runs it: the real binary in a fresh temporary directory,
//! fed files, standard input, and a live pipe read while it is still open.
//!
//! Exit codes: 0 every premise held, 1 a violation, 2 the certificate is unusable or an I/O
//! error.

use std::collections::BTreeSet;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command as Process, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use serde::Deserialize;
use serde_json::Value;

use crate::common::cli::safereach;
use crate::common::paths::{fixture, problem_file, root, seed_file};
use crate::common::tmp;

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

fn run(dir: &Path, args: &[&str], stdin: Option<&str>) -> Run {
    let mut cmd = safereach(dir);
    cmd.args(args);
    if let Some(input) = stdin {
        cmd.write_stdin(input.to_string());
    }
    let out = cmd.output().expect("runs");
    Run {
        code: out.status.code().expect("exited"),
        stdout: String::from_utf8(out.stdout).expect("UTF-8"),
        stderr: String::from_utf8(out.stderr).expect("UTF-8"),
    }
}

/// `<command> seed.toml --set environment.obstacle_speed=W <args>`.
fn on_seed(dir: &Path, command: &str, w: &str, args: &[&str]) -> Run {
    let seed = seed_file();
    let set = format!("environment.obstacle_speed={w}");
    let mut all = vec![command, seed.to_str().unwrap(), "--set", &set];
    all.extend_from_slice(args);
    run(dir, &all, None)
}

/// `certify seed.toml --set environment.obstacle_speed=W --out cert.json`.
fn certify_seed(dir: &Path, w: &str) -> PathBuf {
    let r = on_seed(dir, "certify", w, &["--out", "cert.json"]);
    assert_eq!(r.code, 0, "{}{}", r.stdout, r.stderr);
    dir.join("cert.json")
}

/// `simulate seed.toml --set environment.obstacle_speed=W --trace FILE`.
fn simulate_seed(dir: &Path, w: &str, trace: &str) {
    let r = on_seed(dir, "simulate", w, &["--runs", "200", "--trace", trace]);
    assert!(r.code == 0 || r.code == 1, "{}{}", r.stdout, r.stderr);
}

fn monitor(dir: &Path, args: &[&str], stdin: Option<&str>) -> Run {
    let mut all = vec!["monitor", "--certificate", "cert.json"];
    all.extend_from_slice(args);
    run(dir, &all, stdin)
}

/// A CSV trace's rows as maps from column to text.
fn csv_rows(text: &str) -> Vec<std::collections::HashMap<String, String>> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(h, v)| (h.to_string(), v.to_string()))
                .collect()
        })
        .collect()
}

// ------------------------------------------------------------------------------------------
// The seed's example, end to end
// ------------------------------------------------------------------------------------------

#[test]
fn worked_example_certified_for_w_0_2_flagged_at_0_25() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    simulate_seed(dir.path(), "0.25", "run.csv");
    let trace = std::fs::read_to_string(dir.path().join("run.csv")).unwrap();
    let rows = csv_rows(&trace);
    // The first sample showing a speed above 0.2, read from the file independently.
    let k = rows
        .iter()
        .position(|r| r["obstacle_v"].parse::<f64>().unwrap() > 0.2)
        .expect("some period faster than 0.2");
    let (t, v) = (&rows[k]["t"], &rows[k]["obstacle_v"]);
    let line = k + 2; // the header is line 1

    let r = monitor(dir.path(), &["run.csv"], None);
    assert_eq!(r.code, 1, "{}{}", r.stdout, r.stderr);
    let out: Vec<&str> = r.stdout.lines().collect();
    for (i, row) in rows[..k].iter().enumerate() {
        assert_eq!(out[i], format!("t={} ok", row["t"]));
    }
    // The observed speed is shown without float noise: the file's value to 15 significant
    // digits.
    let head = format!("t={t} VIOLATION obstacle_speed obstacle=0 observed ");
    let tail = format!(" m/s > bound 0.2 m/s -> brake (line {line})");
    let shown = out[k]
        .strip_prefix(&head)
        .and_then(|rest| rest.strip_suffix(&tail))
        .unwrap_or_else(|| panic!("{}", out[k]));
    let (shown, speed) = (shown.parse::<f64>().unwrap(), v.parse::<f64>().unwrap());
    assert!((shown - speed).abs() <= speed * 1e-14, "{shown} vs {speed}");
    assert!(
        format!("{shown:e}").trim_start_matches('-').len() <= 15 + 5,
        "{shown}"
    );
    assert!(
        r.stdout
            .contains(&format!("first violation: t={t} obstacle_speed obstacle=0")),
        "{}",
        r.stdout
    );
    assert!(r.stdout.contains("summary: VIOLATED"));
    assert!(r.stdout.contains("  obstacle_speed           violated"));

    // Without obstacle_v the speed is estimated from positions: the same sample is flagged.
    let stripped: String = trace
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    std::fs::write(dir.path().join("positions.csv"), stripped).unwrap();
    let r = monitor(dir.path(), &["positions.csv", "--json"], None);
    assert_eq!(r.code, 1);
    let first: Value = serde_json::from_str(r.stdout.lines().next().unwrap()).unwrap();
    assert_eq!(first["premise"], "obstacle_speed");
    assert_eq!(first["line"], line as u64);
    assert_eq!(first["t"].as_f64().unwrap(), t.parse::<f64>().unwrap());
    let estimated = first["observed"].as_f64().unwrap();
    assert!(
        (estimated - v.parse::<f64>().unwrap()).abs() < 1e-9,
        "{estimated} vs {v}"
    );
}

#[test]
fn simulations_within_the_premises_pass_in_both_formats() {
    let dir = tmp();
    certify_seed(dir.path(), "0.15");
    simulate_seed(dir.path(), "0.15", "run.csv");
    simulate_seed(dir.path(), "0.15", "run.jsonl");
    let csv = std::fs::read_to_string(dir.path().join("run.csv")).unwrap();
    let jsonl = std::fs::read_to_string(dir.path().join("run.jsonl")).unwrap();
    // Same run, two formats.
    assert_eq!(csv.lines().count(), jsonl.lines().count() + 1);
    for (row, line) in csv_rows(&csv).iter().zip(jsonl.lines()) {
        let v: Value = serde_json::from_str(line).expect("each line is JSON");
        assert_eq!(v["t"].as_f64().unwrap(), row["t"].parse::<f64>().unwrap());
        assert_eq!(v["robot_mode"], row["robot_mode"].as_str());
        assert_eq!(v["obstacle_id"], "0");
    }
    for file in ["run.csv", "run.jsonl"] {
        let r = monitor(dir.path(), &[file], None);
        assert_eq!(r.code, 0, "{file}: {}", r.stdout);
        assert!(r.stdout.lines().all(|l| !l.contains("VIOLATION")));
        assert!(
            r.stdout
                .contains("summary: held: every monitored premise held over")
        );
        let r = monitor(dir.path(), &[file, "--json"], None);
        assert_eq!(r.code, 0);
        let lines: Vec<&str> = r.stdout.lines().collect();
        assert_eq!(lines.len(), 1, "only the summary: {}", r.stdout);
        let s: SummaryLine = serde_json::from_str(lines[0]).unwrap();
        assert_eq!(s.summary.verdict, "held");
        assert_eq!(s.summary.samples as usize, jsonl.lines().count());
        assert_eq!(s.summary.violations, 0);
    }
}

// ------------------------------------------------------------------------------------------
// --json
// ------------------------------------------------------------------------------------------

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct EventLine {
    t: Option<f64>,
    obstacle_id: Option<String>,
    premise: String,
    observed: Option<f64>,
    bound: Option<f64>,
    action: String,
    unit: String,
    line: u64,
    detail: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SummaryLine {
    summary: SummaryBody,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SummaryBody {
    verdict: String,
    samples: u64,
    instants: u64,
    obstacles: u64,
    violations: u64,
    first_violation: Option<EventLine>,
    premises: Vec<PremiseLine>,
    behaviour: Vec<CheckLine>,
    fail_safe: std::collections::BTreeMap<String, u64>,
}

/// The smallest slack of a check, and where.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MarginLine {
    slack: f64,
    t: f64,
    sample: u64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CheckLine {
    check: String,
    status: String,
    bound: Option<f64>,
    unit: String,
    checks: u64,
    violations: u64,
    reason: Option<String>,
    margin: Option<MarginLine>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PremiseLine {
    premise: String,
    status: String,
    bound: f64,
    unit: String,
    checks: u64,
    violations: u64,
    reason: Option<String>,
    margin: Option<MarginLine>,
}

const HEADER: &str = "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v\n";

/// A trace with one of each fail-safe case, each followed by a good line.
fn broken_trace() -> String {
    HEADER.to_string()
        + "0,0,0.2,drive,A,10,0.1\n" // 2
        + "0.1,0.02,0.2,flying,A,9.99,0.1\n" // 3 unknown mode
        + "0.1,0.02,0.2,drive,A,9.99,0.1\n" // 4
        + "0.2,0.04,0.2,drive,A,NaN,0.1\n" // 5 non-finite
        + "0.2,0.04,0.2,drive,A,9.98,0.1\n" // 6
        + "0.15,0.03,0.2,drive,A,9.98,0.1\n" // 7 time backwards
        + "0.2,0.04,0.2,drive,A,9.98,0.1\n" // 8 duplicate
        + "0.3,0.06,0.2,drive,A,9.97\n" // 9 missing column
        + "this is not a sample\n" // 10 malformed
        + "0.3,0.06,0.2,drive,A,9.97,0.1\n" // 11
        + "0.3,0.06,0.2,drive,B,0.5,0.1\n" // 12 inside the reaction radius
        + "0.4,0.08,0.2,drive,A,9.96,0.1\n" // 13
}

#[test]
fn json_events_and_summary_are_typed_lines() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    std::fs::write(dir.path().join("broken.csv"), broken_trace()).unwrap();
    let r = monitor(dir.path(), &["broken.csv", "--json"], None);
    assert_eq!(r.code, 1, "{}", r.stderr);
    let lines: Vec<&str> = r.stdout.lines().collect();
    let (summary, events) = lines.split_last().unwrap();
    let events: Vec<EventLine> = events
        .iter()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect();
    // Every event has exactly the documented keys, in order.
    for l in &lines[..events.len()] {
        let v: serde_json::Map<String, Value> = serde_json::from_str(l).unwrap();
        let keys: Vec<&str> = v.keys().map(String::as_str).collect();
        assert_eq!(
            keys,
            [
                "t",
                "obstacle_id",
                "premise",
                "observed",
                "bound",
                "action",
                "unit",
                "line",
                "detail"
            ]
        );
    }
    let got: Vec<(u64, &str)> = events
        .iter()
        .map(|e| (e.line, e.premise.as_str()))
        .collect();
    assert_eq!(
        got,
        [
            (3, "malformed_sample"),
            (5, "non_finite"),
            (7, "time_backwards"),
            (8, "duplicate_sample"),
            (9, "malformed_sample"),
            (10, "malformed_sample"),
            (12, "first_detection_gap"),
            (13, "controller_reaction"),
        ]
    );
    assert!(events.iter().all(|e| e.action == "brake"));
    let backwards = &events[2];
    assert_eq!(
        (
            backwards.t,
            backwards.observed,
            backwards.bound,
            backwards.unit.as_str()
        ),
        (Some(0.15), Some(0.15), Some(0.2), "s")
    );
    assert_eq!(backwards.obstacle_id.as_deref(), Some("A"));
    assert!(events[0].detail.as_deref().unwrap().contains("robot_mode"));
    assert!(events[1].detail.as_deref().unwrap().contains("obstacle_x"));
    assert!(events[4].detail.as_deref().unwrap().contains("6 fields"));
    let inside = &events[6];
    assert_eq!(inside.obstacle_id.as_deref(), Some("B"));
    assert!((inside.observed.unwrap() - 0.44).abs() < 1e-12);
    assert_eq!(inside.bound, Some(1.4));

    let s: SummaryLine = serde_json::from_str(summary).unwrap();
    let s = s.summary;
    assert_eq!(s.verdict, "violated");
    assert_eq!(
        (s.samples, s.instants, s.obstacles, s.violations),
        (12, 5, 2, 8)
    );
    let first = s.first_violation.unwrap();
    assert_eq!(
        (first.line, first.premise.as_str()),
        (3, "malformed_sample")
    );
    let names: Vec<&str> = s.premises.iter().map(|p| p.premise.as_str()).collect();
    assert_eq!(
        names,
        [
            "obstacle_speed",
            "braking_deceleration",
            "control_period",
            "latency",
            "first_detection_gap",
            "observation_noise"
        ]
    );
    let status = |name: &str| {
        let p = s.premises.iter().find(|p| p.premise == name).unwrap();
        (p.status.as_str(), p.violations)
    };
    assert_eq!(status("first_detection_gap"), ("violated", 1));
    assert_eq!(status("obstacle_speed"), ("held", 0));
    assert_eq!(status("latency").0, "not_monitored");
    assert_eq!(status("observation_noise").0, "not_monitored");
    let latency = s.premises.iter().find(|p| p.premise == "latency").unwrap();
    assert!(latency.reason.as_deref().unwrap().contains("obstacle_t"));
    assert_eq!(
        (latency.bound, latency.unit.as_str(), latency.checks),
        (1.0, "periods", 0)
    );
    let fail_safe: Vec<(&str, u64)> = s.fail_safe.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    assert_eq!(
        fail_safe,
        [
            ("duplicate_sample", 1),
            ("malformed_sample", 3),
            ("non_finite", 1),
            ("time_backwards", 1)
        ]
    );
}

#[test]
fn each_fail_safe_case_is_named_and_the_monitor_reads_on() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    std::fs::write(dir.path().join("broken.csv"), broken_trace()).unwrap();
    let r = monitor(dir.path(), &["broken.csv"], None);
    assert_eq!(r.code, 1);
    let out: Vec<&str> = r.stdout.lines().collect();
    let expected = [
        "t=0 ok",
        "t=0.1 VIOLATION malformed_sample: robot_mode is not one of idle, accelerate, drive, brake, stop -> brake (line 3)",
        "t=0.1 violated",
        "t=0.2 VIOLATION non_finite obstacle=A: obstacle_x is not a finite number -> brake (line 5)",
        "t=0.2 violated",
        "t=0.15 VIOLATION time_backwards obstacle=A observed 0.15 s < bound 0.2 s -> brake (line 7)",
        "t=0.2 VIOLATION duplicate_sample obstacle=A observed 0.2 s -> brake (line 8)",
        "t=0.3 VIOLATION malformed_sample: 6 fields, but the header has 7 columns -> brake (line 9)",
        "t=? VIOLATION malformed_sample: t is not a number -> brake (line 10)",
        "t=0.3 violated",
        "t=0.3 VIOLATION first_detection_gap obstacle=B observed 0.44 m < bound 1.4 m -> brake (line 12)",
        // B at 0.44 m, the robot driving on one period later (latency 1): it ignored danger.
        "t=0.4 VIOLATION controller_reaction obstacle=B observed 0.44 m <= bound 1.4 m: the observed gap (m) was within the danger distance min(rho, d(v)) and the robot was not braking -> brake (line 13)",
    ];
    assert_eq!(&out[..expected.len()], expected, "{}", r.stdout);
    assert!(out[expected.len()].starts_with("summary: VIOLATED: 8 violations in 12 samples"));
    assert!(r.stdout.contains(
        "fail-safe: malformed_sample 3, non_finite 1, time_backwards 1, duplicate_sample 1"
    ));
    // Each case alone is a violation (exit 1), never a crash.
    let good = "0,0,0.2,drive,A,10,0.1\n";
    for bad in [
        "0.1,0.02,0.2,drive,A,9.99,inf\n",
        "-1,0.02,0.2,drive,A,9.99,0.1\n",
        "0,0,0.2,drive,A,10,0.1\n",
        "0.1,0.02,0.2,,A,9.99,\"0.1\n",
        "0.1,0.02,0.2,drive,A,1e999,0.1\n",
        "\u{0}\u{ff}garbage,,,,,,\n",
        "0.5,0.1,0.2,drive,A,9.9,0.1\n",
    ] {
        let r = monitor(dir.path(), &["-"], Some(&format!("{HEADER}{good}{bad}")));
        assert_eq!(r.code, 1, "{bad}: {}{}", r.stdout, r.stderr);
        assert!(r.stdout.contains("VIOLATION"), "{bad}");
    }
}

#[test]
fn a_header_without_a_required_column() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    let text = "t,robot_x,obstacle_id,obstacle_x\n0,0,A,10\n0.1,0.02,A,9.99\n";
    let r = monitor(dir.path(), &["-"], Some(text));
    // Every line is reported, and none could be checked: exit 2, "nothing was checked".
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("nothing was checked"), "{}", r.stderr);
    let out: Vec<&str> = r.stdout.lines().collect();
    assert_eq!(
        out[..3],
        [
            "t=? VIOLATION malformed_sample: the header has no column robot_v (required: t, robot_x, robot_v, obstacle_id, obstacle_x) -> brake (line 1)",
            "t=? VIOLATION malformed_sample: no usable CSV header before this line -> brake (line 2)",
            "t=? VIOLATION malformed_sample: no usable CSV header before this line -> brake (line 3)",
        ]
    );
}

// ------------------------------------------------------------------------------------------
// Exit code 2
// ------------------------------------------------------------------------------------------

#[test]
fn unusable_certificates_and_io_errors_exit_2() {
    let dir = tmp();
    let cert = certify_seed(dir.path(), "0.2");
    std::fs::write(
        dir.path().join("t.csv"),
        format!("{HEADER}0,0,0.2,drive,A,10,0.1\n"),
    )
    .unwrap();
    let text = std::fs::read_to_string(&cert).unwrap();

    // Tampered: the obstacle-speed bound raised from 0.2 to 0.3 in the premises.
    let tampered = text.replacen("\"bound\": 0.2,", "\"bound\": 0.3,", 1);
    assert_ne!(tampered, text);
    std::fs::write(&cert, &tampered).unwrap();
    let r = monitor(dir.path(), &["t.csv"], None);
    assert_eq!(r.code, 2, "{}", r.stdout);
    assert!(r.stdout.is_empty(), "nothing is monitored: {}", r.stdout);
    assert!(
        r.stderr
            .contains("cert.json: certificate unusable: the certificate does not verify"),
        "{}",
        r.stderr
    );

    // Not a certificate; no certificate.
    std::fs::write(&cert, "{\"format\": 1}").unwrap();
    let r = monitor(dir.path(), &["t.csv"], None);
    assert_eq!(r.code, 2);
    assert!(
        r.stderr.contains("not a safereach certificate"),
        "{}",
        r.stderr
    );
    std::fs::remove_file(&cert).unwrap();
    let r = monitor(dir.path(), &["t.csv"], None);
    assert_eq!(r.code, 2);
    assert!(
        r.stderr.contains("cannot read the certificate"),
        "{}",
        r.stderr
    );

    // Valid but refuted: no safety to monitor.
    let fast = problem_file("fast-obstacle.toml");
    let out = run(
        dir.path(),
        &["certify", fast.to_str().unwrap(), "--out", "cert.json"],
        None,
    );
    assert_eq!(out.code, 1, "fast-obstacle is refuted");
    let r = monitor(dir.path(), &["t.csv"], None);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("refuted"), "{}", r.stderr);

    // The trace cannot be opened.
    certify_seed(dir.path(), "0.2");
    let r = monitor(dir.path(), &["missing.csv"], None);
    assert_eq!(r.code, 2);
    assert!(
        r.stderr.contains("missing.csv: cannot open the trace"),
        "{}",
        r.stderr
    );
    // Bad --columns.
    let r = monitor(dir.path(), &["t.csv", "--columns", "t,robot_x"], None);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("no column robot_v"), "{}", r.stderr);
}

// ------------------------------------------------------------------------------------------
// Live on a pipe
// ------------------------------------------------------------------------------------------

#[test]
fn live_on_a_pipe_each_verdict_comes_before_the_input_ends() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    let mut child = Process::new(env!("CARGO_BIN_EXE_safereach"))
        .current_dir(dir.path())
        .args(["monitor", "--certificate", "cert.json", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawns");
    let mut stdin = child.stdin.take().unwrap();
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = mpsc::channel();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            if tx.send(line.expect("UTF-8")).is_err() {
                break;
            }
        }
    });
    // Never hang: a verdict that does not come within the timeout fails the test.
    let next = || {
        rx.recv_timeout(Duration::from_secs(60))
            .expect("a verdict line while the input is still open")
    };
    stdin.write_all(HEADER.as_bytes()).unwrap();
    stdin.write_all(b"0,0,0.2,drive,A,10,0.1\n").unwrap();
    stdin.flush().unwrap();
    assert_eq!(next(), "t=0 ok");
    stdin.write_all(b"0.1,0.02,0.2,drive,A,9.97,0.3\n").unwrap();
    stdin.flush().unwrap();
    assert_eq!(
        next(),
        "t=0.1 VIOLATION obstacle_speed obstacle=A observed 0.3 m/s > bound 0.2 m/s -> brake (line 3)"
    );
    // Half a line is not a sample yet; its verdict comes when the line is complete.
    stdin.write_all(b"0.2,0.04,0.2,dr").unwrap();
    stdin.flush().unwrap();
    assert!(rx.recv_timeout(Duration::from_millis(300)).is_err());
    stdin.write_all(b"ive,A,9.96,0.1\n").unwrap();
    stdin.flush().unwrap();
    assert_eq!(next(), "t=0.2 violated");
    drop(stdin);
    assert!(next().starts_with("summary: VIOLATED: 1 violation in 3 samples"));
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(1));
    reader.join().unwrap();
}

// ------------------------------------------------------------------------------------------
// Formats and options
// ------------------------------------------------------------------------------------------

#[test]
fn format_by_extension_option_or_content() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    let jsonl = "{\"t\":0,\"robot_x\":0,\"robot_v\":0.2,\"obstacle_id\":7,\"obstacle_x\":10}\n\
                 {\"t\":0.1,\"robot_x\":0.02,\"robot_v\":0.2,\"obstacle_id\":\"7\",\"obstacle_x\":9.5}\n";
    std::fs::write(dir.path().join("trace.log"), jsonl).unwrap();
    // By content (stdin and an unknown extension).
    for args in [&["trace.log"][..], &["-"][..]] {
        let stdin = (args[0] == "-").then_some(jsonl);
        let r = monitor(dir.path(), args, stdin);
        assert_eq!(r.code, 1, "{}", r.stdout);
        assert_eq!(
            r.stdout.lines().nth(1).unwrap(),
            "t=0.1 VIOLATION obstacle_speed obstacle=7 observed 5 m/s > bound 0.2 m/s -> brake (line 2)"
        );
    }
    // --format overrides the extension.
    std::fs::write(dir.path().join("trace.csv"), jsonl).unwrap();
    let r = monitor(dir.path(), &["trace.csv", "--format", "jsonl"], None);
    assert_eq!(r.code, 1);
    assert!(r.stdout.contains("observed 5 m/s"));
    let r = monitor(dir.path(), &["trace.csv"], None);
    assert_eq!(r.code, 2, "no line of it is a readable sample");
    let first = r.stdout.lines().next().unwrap();
    assert_eq!(
        first,
        "t=? VIOLATION malformed_sample: not a CSV row: the header looks like JSON Lines \
         (use --format jsonl or a .jsonl name) -> brake (line 1)"
    );
}

#[test]
fn columns_for_a_csv_without_its_header() {
    // `tail -f log.csv` drops the header: --columns names them.
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    let r = monitor(
        dir.path(),
        &[
            "-",
            "--columns",
            "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v",
        ],
        Some("0,0,0.2,drive,A,10,0.1\n0.1,0.02,0.2,drive,A,9.98,0.2\n"),
    );
    assert_eq!(r.code, 0, "{}", r.stdout);
    assert!(r.stdout.starts_with("t=0 ok\nt=0.1 ok\nsummary: held"));
}

#[test]
fn events_only_and_empty_input() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    std::fs::write(dir.path().join("broken.csv"), broken_trace()).unwrap();
    let r = monitor(dir.path(), &["broken.csv", "--events-only"], None);
    assert_eq!(r.code, 1);
    let lines: Vec<&str> = r.stdout.lines().collect();
    let summary = lines
        .iter()
        .position(|l| l.starts_with("summary:"))
        .unwrap();
    assert_eq!(summary, 8);
    assert!(lines[..summary].iter().all(|l| l.contains(" VIOLATION ")));
    // An empty trace checked nothing: that is no "held" (it used to be, exit 0), but exit 2,
    // as is a trace of a header only.
    for text in ["", HEADER] {
        let r = monitor(dir.path(), &["-"], Some(text));
        assert_eq!(r.code, 2, "{text:?}");
        assert!(
            r.stdout
                .starts_with("summary: NOTHING CHECKED: no readable sample"),
            "{}",
            r.stdout
        );
        assert!(
            r.stderr.contains("standard input: nothing was checked"),
            "{}",
            r.stderr
        );
        let r = monitor(dir.path(), &["-", "--json"], Some(text));
        assert_eq!(r.code, 2);
        let s: SummaryLine = serde_json::from_str(r.stdout.trim()).unwrap();
        assert_eq!(s.summary.verdict, "nothing_checked");
    }
}

#[test]
fn many_interleaved_obstacles_by_textual_id() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    let mut text = String::from(HEADER);
    let names = ["person", "cart", "dog"];
    let mut x = [20.0, 21.0, 22.0];
    for k in 0..50 {
        let t = k as f64 * 0.1;
        for (i, name) in names.iter().enumerate() {
            // The cart speeds up past 0.2 m/s from step 30 on; each row states the speed over
            // the period that ends at it, and positions move accordingly.
            let v = match k {
                0 => 0.0,
                _ if *name == "cart" && k >= 30 => 0.25,
                _ => 0.1,
            };
            x[i] -= v * 0.1;
            text += &format!("{t},{},0.2,drive,{name},{},{v}\n", 0.2 * t, x[i]);
        }
    }
    std::fs::write(dir.path().join("many.csv"), &text).unwrap();
    let r = monitor(dir.path(), &["many.csv", "--json"], None);
    assert_eq!(r.code, 1);
    let lines: Vec<&str> = r.stdout.lines().collect();
    let events: Vec<EventLine> = lines[..lines.len() - 1]
        .iter()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(events.len(), 20);
    assert!(
        events
            .iter()
            .all(|e| e.obstacle_id.as_deref() == Some("cart"))
    );
    assert_eq!(events[0].line, 2 + 30 * 3 + 1);
    let s: SummaryLine = serde_json::from_str(lines[lines.len() - 1]).unwrap();
    assert_eq!(
        (s.summary.samples, s.summary.instants, s.summary.obstacles),
        (150, 50, 3)
    );
    let ids: BTreeSet<String> = events.into_iter().filter_map(|e| e.obstacle_id).collect();
    assert_eq!(ids.len(), 1);
}

/// Robot-only rows (empty obstacle cells in CSV, no obstacle keys in JSON Lines) are
/// instants: a trace whose obstacle is out of view for a frame, far outside ρ, holds (it used
/// to be `malformed_sample`); the `--json` summary gives each check's smallest slack and
/// where: `control_period`'s is 0 s (every step exactly dt), `first_detection_gap`'s the
/// first gap less ρ.
#[test]
fn robot_only_rows_and_margins_in_json() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    let csv = format!(
        "{HEADER}0,0,0.2,drive,A,10,0\n0.1,0.02,0.2,drive,,,\n0.2,0.04,0.2,drive,A,9.98,0.1\n"
    );
    let jsonl = "{\"t\":0,\"robot_x\":0,\"robot_v\":0.2,\"robot_mode\":\"drive\",\"obstacle_id\":\"A\",\"obstacle_x\":10,\"obstacle_v\":0}\n\
                 {\"t\":0.1,\"robot_x\":0.02,\"robot_v\":0.2,\"robot_mode\":\"drive\",\"obstacle_id\":null}\n\
                 {\"t\":0.2,\"robot_x\":0.04,\"robot_v\":0.2,\"robot_mode\":\"drive\",\"obstacle_id\":\"A\",\"obstacle_x\":9.98,\"obstacle_v\":0.1}\n";
    for text in [csv.as_str(), jsonl] {
        let r = monitor(dir.path(), &["-", "--json"], Some(text));
        assert_eq!(r.code, 0, "{}{}", r.stdout, r.stderr);
        let s: SummaryLine = serde_json::from_str(r.stdout.trim()).unwrap();
        let s = s.summary;
        assert_eq!((s.verdict.as_str(), s.samples, s.instants), ("held", 3, 3));
        let premise = |name: &str| s.premises.iter().find(|p| p.premise == name).unwrap();
        let period = premise("control_period").margin.as_ref().unwrap();
        assert!(period.slack.abs() < 1e-12 && period.t > 0.0, "{period:?}");
        let first = premise("first_detection_gap").margin.as_ref().unwrap();
        assert_eq!((first.slack, first.t, first.sample), (10.0 - 1.4, 0.0, 0));
        let collision = s.behaviour.iter().find(|c| c.check == "collision").unwrap();
        assert_eq!(
            (collision.status.as_str(), collision.bound),
            ("held", Some(0.0))
        );
        assert_eq!((collision.unit.as_str(), collision.violations), ("m", 0));
        assert!(collision.checks == 2 && collision.reason.is_none());
        assert!(collision.margin.is_some());
    }
}

/// A live monitor stopped by SIGTERM (or Ctrl-C) while waiting for more of its trace prints
/// the summary of what it read, and says it was interrupted.
#[test]
fn sigterm_on_a_live_monitor_prints_the_summary_of_what_was_read() {
    use std::io::{BufRead, BufReader, Write};
    use std::process::{Command, Stdio};
    let trace = std::fs::read_to_string(root().join("examples/traces/noisy.csv")).unwrap();
    let head: String = trace.lines().take(30).map(|l| format!("{l}\n")).collect();
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("safereach"))
        .args(["monitor", "--certificate"])
        .arg(fixture("seed.cert.json"))
        .arg("-")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(head.as_bytes()).unwrap();
    stdin.flush().unwrap();
    // Wait until the monitor has answered the last line written: it is reading, not done.
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut seen = Vec::new();
    while seen.len() < 29 {
        let mut line = String::new();
        assert!(out.read_line(&mut line).unwrap() > 0, "output ended early");
        seen.push(line);
    }
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    drop(stdin);
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut out, &mut rest).unwrap();
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert!(rest.contains("summary"), "no summary after SIGTERM: {rest}");
    assert!(err.contains("interrupted by SIGTERM"), "{err}");
    // The noisy trace violates the exact certificate's premises: the verdict stands.
    assert_eq!(status.code(), Some(1), "{rest}");
}

/// A trace file and the same bytes on standard input give the same output, byte for byte
/// (a guard for any faster path for files, e.g. decoding ahead in batches), on long traces
/// with every kind of line: malformed rows, robot-only rows (dropouts), a line too long, an
/// obstacle first seen late, CRLF line ends, and no line end after the last row.
#[test]
fn a_trace_file_reads_as_standard_input_does() {
    let dir = tmp();
    certify_seed(dir.path(), "0.2");
    let mut csv = HEADER.to_string();
    for k in 0..12_000u32 {
        let t = f64::from(k) * 0.1;
        let (x, id) = (0.02 * t, ["A", "B", "C"][(k % 3) as usize]);
        match k % 997 {
            5 => csv += "this is not a sample\n",
            6 => csv += &format!("{t},{x},0.2,drive,,,\n"),
            7 => csv += &format!("{t},{x},0.2,drive,{id},NaN,0.1\n"),
            8 => csv += "\n",
            _ => csv += &format!("{t},{x},0.2,drive,{id},{},0.1\n", 10_000.0 - 0.01 * t),
        }
        if k == 9_000 {
            csv += &"x".repeat(1 << 20 | 1);
            csv += "\n0,0,0.2,drive,late,0.5,0.1\n";
        }
    }
    let crlf = csv.replace('\n', "\r\n");
    let unended = csv.trim_end().to_string();
    for (name, text) in [
        ("lf.csv", &csv),
        ("crlf.csv", &crlf),
        ("unended.csv", &unended),
    ] {
        std::fs::write(dir.path().join(name), text).unwrap();
        for extra in [&[][..], &["--json"][..], &["--events-only"][..]] {
            let mut args = vec![name, "--format", "csv"];
            args.extend_from_slice(extra);
            let file = monitor(dir.path(), &args, None);
            args[0] = "-";
            let stdin = monitor(dir.path(), &args, Some(text));
            assert_eq!(file.code, 1, "{name} {extra:?}: {}", file.stderr);
            assert!(file.stdout == stdin.stdout, "{name} {extra:?}");
            assert_eq!((file.code, &file.stderr), (stdin.code, &stdin.stderr));
        }
    }
}
