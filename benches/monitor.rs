//! Benchmark: the runtime monitor's throughput and latency. Run with
//! `cargo bench --bench monitor`.
//!
//! - the library API (`Monitor::observe`) on samples in memory, against the seed's certificate
//!   at W = 0.2 with observation noise on (σ_g = 2 mm, σ_w = 0.01 m/s): samples per second, with
//!   `obstacle_v` given and with speeds estimated from positions; and `Monitor::observe_all`
//!   on the same samples as one block;
//! - the per-sample latency of `observe`, timed one call at a time (the timer's own cost is
//!   measured and shown beside it);
//! - the trace reader alone (`Decoder::decode` on lines in memory);
//! - the CLI over a large generated CSV (written into a temporary directory, in the
//!   simulator's full-precision number format), with its output sent to /dev/null.
//!
//! Plain wall-clock medians; no timing assertions anywhere (speed is measured here, never in
//! tests).

use std::hint::black_box;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use safereach::analysis::analyse;
use safereach::core::model::Problem;
use safereach::core::semantics::Mode;
use safereach::monitor::trace::{Decoded, Decoder, Format};
use safereach::monitor::{Monitor, Sample};
use safereach::proof::certificate::Certificate;

const OBSTACLES: u32 = 4;

/// A trace within the premises of the seed certificate for W = 0.2: the robot drives at
/// 0.2 m/s, four obstacles approach from far away at random speeds ≤ 0.2 m/s, one sample per
/// obstacle per control period of 0.1 s.
fn generate(instants: usize, with_speed: bool) -> Vec<Sample> {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    // Positions in whole 0.1 mm, so that they stay exact over millions of periods.
    let mut x: Vec<i64> = (0..OBSTACLES)
        .map(|i| (1e9 + 1e5 * f64::from(i)) as i64)
        .collect();
    let mut out = Vec::with_capacity(instants * OBSTACLES as usize);
    for k in 0..instants {
        let t = k as f64 * 0.1;
        for (i, xi) in x.iter_mut().enumerate() {
            // Whole mm/s, so that each period's displacement is a whole 0.1 mm and the trace
            // written with 4 decimals states speeds its positions agree with (the monitor
            // compares them: `observation_inconsistent`).
            let mm = if k == 0 {
                0
            } else {
                (200.0 * (1.0 - rng.random::<f64>())).ceil() as i64
            };
            let v = mm as f64 / 1000.0;
            *xi -= mm;
            out.push(Sample {
                t,
                robot_x: 0.2 * t,
                robot_v: 0.2,
                robot_mode: Some(Mode::Drive),
                obstacle_id: i as u32,
                obstacle_x: *xi as f64 / 1e4,
                obstacle_v: with_speed.then_some(v),
                obstacle_t: None,
            });
        }
    }
    out
}

/// The samples as CSV: numbers in Rust's shortest round-trip form (as `simulate --trace`
/// writes them, up to 17 digits), or with `decimals` fixed decimals (as a robot's logger
/// might).
fn csv(samples: &[Sample], decimals: Option<usize>) -> String {
    use std::fmt::Write;
    let mut s = String::from("t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v\n");
    for x in samples {
        let v = x.obstacle_v.unwrap_or(0.0);
        let _ = match decimals {
            None => writeln!(
                s,
                "{},{},{},drive,{},{},{}",
                x.t, x.robot_x, x.robot_v, x.obstacle_id, x.obstacle_x, v
            ),
            Some(d) => writeln!(
                s,
                "{:.1},{:.d$},{:.d$},drive,{},{:.d$},{:.d$}",
                x.t, x.robot_x, x.robot_v, x.obstacle_id, x.obstacle_x, v
            ),
        };
    }
    s
}

/// Median and fastest of repeated timings (the machine is shared: the fastest shows what
/// the code does undisturbed, the median what to expect).
fn median(mut v: Vec<Duration>) -> (Duration, Duration) {
    v.sort();
    (v[v.len() / 2], v[0])
}

/// The median and best of 21 runs of `run` on a fresh copy of `fresh`; `run` returns the
/// number of events, which must be 0 (the generated trace is within the premises).
fn median_of_runs(
    fresh: &Monitor,
    mut run: impl FnMut(&mut Monitor) -> usize,
) -> (Duration, Duration) {
    let times = (0..21)
        .map(|_| {
            let mut m = fresh.clone();
            let start = Instant::now();
            let events = run(&mut m);
            let d = start.elapsed();
            assert_eq!(events, 0, "the generated trace is within the premises");
            black_box(m.samples());
            d
        })
        .collect();
    median(times)
}

fn rate(n: usize, (median, best): (Duration, Duration)) -> String {
    let r = |d: Duration| n as f64 / d.as_secs_f64() / 1e6;
    format!(
        "{:.1} M samples/s median, {:.1} M samples/s best",
        r(median),
        r(best)
    )
}

fn per(n: usize, (median, _): (Duration, Duration)) -> f64 {
    median.as_nanos() as f64 / n as f64
}

fn percentile(sorted: &[u64], p: f64) -> u64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let problem = Problem::load_with_overrides(
        &root.join("problems/seed.toml"),
        // Noise on (issue 10's benchmark): the consistency checks widen by sigma.
        &[
            "environment.obstacle_speed=0.2".to_string(),
            "sensing.gap_noise=0.002".to_string(),
            "sensing.speed_noise=0.01".to_string(),
        ],
    )
    .expect("seed problem loads");
    let cert = Certificate::from_analysis(&analyse(&problem).expect("analyses"));
    let fresh = Monitor::with_max_obstacles(&cert, OBSTACLES).expect("certified");

    // ---- Library API -------------------------------------------------------------------
    let instants = 250_000;
    for with_speed in [true, false] {
        let samples = generate(instants, with_speed);
        let t = median_of_runs(&fresh, |m| {
            let mut events = 0;
            for s in &samples {
                events += m.observe(black_box(s)).events.len();
            }
            events
        });
        println!(
            "library observe ({}): {} ({:.1} ns/sample median; {} samples, 4 interleaved obstacles)",
            if with_speed {
                "obstacle_v given"
            } else {
                "speed estimated"
            },
            rate(samples.len(), t),
            per(samples.len(), t),
            samples.len()
        );
    }

    // ---- Library API, a block at a time -----------------------------------------------------
    let samples = generate(instants, true);
    let t = median_of_runs(&fresh, |m| {
        let mut events = 0;
        m.observe_all(black_box(&samples), |_, _| events += 1);
        events
    });
    println!(
        "library observe_all (obstacle_v given, the whole trace as one block): {} ({:.1} ns/sample median)",
        rate(samples.len(), t),
        per(samples.len(), t),
    );

    // ---- Per-sample latency --------------------------------------------------------------
    let samples = generate(instants, true);
    let mut m = fresh.clone();
    let mut lat = Vec::with_capacity(samples.len());
    let mut empty = Vec::with_capacity(samples.len());
    for s in &samples {
        let a = Instant::now();
        black_box(m.observe(black_box(s)).events.len());
        lat.push(a.elapsed().as_nanos() as u64);
        let a = Instant::now();
        empty.push(black_box(a).elapsed().as_nanos() as u64);
    }
    lat.sort_unstable();
    empty.sort_unstable();
    println!(
        "library observe latency, one call timed at a time: median {} ns, p99 {} ns, p99.9 {} ns, max {} ns \
         (the timer alone: median {} ns, p99 {} ns)",
        percentile(&lat, 0.5),
        percentile(&lat, 0.99),
        percentile(&lat, 0.999),
        lat[lat.len() - 1],
        percentile(&empty, 0.5),
        percentile(&empty, 0.99),
    );
    // A sample that raises a violation (the cold path: the event is written out).
    let mut m = fresh.clone();
    let mut fast = samples.clone();
    for s in &mut fast {
        s.obstacle_v = Some(0.3);
    }
    let mut lat: Vec<u64> = fast
        .iter()
        .map(|s| {
            let a = Instant::now();
            black_box(m.observe(black_box(s)).events.len());
            a.elapsed().as_nanos() as u64
        })
        .collect();
    lat.sort_unstable();
    println!(
        "library observe latency, every sample a violation: median {} ns, p99 {} ns",
        percentile(&lat, 0.5),
        percentile(&lat, 0.99)
    );

    // ---- The reader alone ----------------------------------------------------------------
    for decimals in [None, Some(4)] {
        let text = csv(&samples, decimals);
        let lines: Vec<&[u8]> = text.as_bytes().split(|&b| b == b'\n').collect();
        let times: Vec<Duration> = (0..11)
            .map(|_| {
                let mut d = Decoder::new(Some(Format::Csv), None, 16);
                let start = Instant::now();
                let mut n = 0;
                for line in &lines {
                    if let Decoded::Sample { sample, .. } = d.decode(black_box(line)) {
                        n += 1;
                        black_box(sample);
                    }
                }
                assert_eq!(n, samples.len());
                start.elapsed()
            })
            .collect();
        let t = median(times);
        println!(
            "reader, CSV lines in memory ({}, {:.0} bytes/line): {} ({:.1} ns/line median)",
            match decimals {
                None => "numbers as simulate writes them, up to 17 digits".to_string(),
                Some(d) => format!("{d} decimals"),
            },
            text.len() as f64 / samples.len() as f64,
            rate(samples.len(), t),
            per(samples.len(), t)
        );
    }

    // ---- The CLI over a large CSV ----------------------------------------------------------
    let dir = tempfile::tempdir().expect("a temporary directory");
    let cert_path = dir.path().join("cert.json");
    std::fs::write(&cert_path, serde_json::to_string(&cert).unwrap()).unwrap();
    let big = generate(1_000_000, true);
    let trace = dir.path().join("big.csv");
    std::fs::write(&trace, csv(&big, None)).unwrap();
    let short = dir.path().join("short.csv");
    std::fs::write(&short, csv(&big, Some(4))).unwrap();
    let exe = env!("CARGO_BIN_EXE_safereach");
    let cli = |trace: &Path, extra: &[&str], stdin_file: bool| -> (Duration, Duration) {
        let times: Vec<Duration> = (0..5)
            .map(|_| {
                let mut cmd = Command::new(exe);
                cmd.args(["monitor", "--certificate"]).arg(&cert_path);
                if stdin_file {
                    cmd.arg("-")
                        .args(["--format", "csv"])
                        .stdin(std::fs::File::open(trace).unwrap());
                } else {
                    cmd.arg(trace);
                }
                cmd.args(extra).stdout(Stdio::null()).stderr(Stdio::null());
                let start = Instant::now();
                let status = cmd.status().expect("runs");
                let d = start.elapsed();
                assert_eq!(
                    status.code(),
                    Some(0),
                    "the big trace is within the premises"
                );
                d
            })
            .collect();
        median(times)
    };
    for (file, what) in [
        (&trace, "numbers as simulate writes them"),
        (&short, "4 decimals"),
    ] {
        let size = std::fs::metadata(file).unwrap().len();
        println!(
            "CLI over a {:.0} MB CSV of {} samples, {what} (output to /dev/null; process start and certificate check included):",
            size as f64 / 1e6,
            big.len()
        );
        for (how, extra, stdin) in [
            ("a verdict line per sample", &[][..], false),
            ("--events-only", &["--events-only"][..], false),
            ("--json", &["--json"][..], false),
            (
                "from standard input, a verdict line per sample",
                &[][..],
                true,
            ),
        ] {
            let t = cli(file, extra, stdin);
            println!(
                "  {how}: {} ({:.0} MB/s median)",
                rate(big.len(), t),
                size as f64 / t.0.as_secs_f64() / 1e6
            );
        }
    }
}
