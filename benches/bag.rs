//! Benchmark: reading ROS 2 bags (MCAP) into the monitor. Run with `cargo bench --bench bag`.
//!
//! A bag of the seed's kind is written by the tests' own writer (`tests/it/bag_writer.rs`,
//! hand-encoded CDR, zstd chunks as `ros2 bag record` writes them): the robot's odometry and
//! mode, and four obstacles approaching within the premises of the seed certificate at
//! W = 0.2, in each of the two layouts the reader takes — one `TrackedObjects` message per
//! instant, and one `nav_msgs/Odometry` topic per obstacle. Measured, median of 11 runs:
//!
//! - the floor: the `mcap` crate alone iterating the messages (decompression and framing);
//! - `BagReader` alone: CDR decoding, projection and instant assembly;
//! - `BagReader` feeding `Monitor`: the whole check, in messages per second (target ≥ 1 M);
//! - the CLI on the same file, output to /dev/null.
//!
//! No timing assertions (speed is measured here, never in tests).

use std::hint::black_box;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use safereach::analysis::analyse;
use safereach::core::model::Problem;
use safereach::monitor::Monitor;
use safereach::monitor::bag::{BagItem, BagOptions, BagReader};
use safereach::proof::certificate::Certificate;

#[allow(dead_code)]
#[path = "../tests/it/bag_writer.rs"]
mod bag_writer;

use bag_writer::{Bag, Body, odometry, stamp, text, tracked_objects, yaw};

const OBSTACLES: usize = 4;

/// Writes `instants` control periods of 0.1 s: the robot driving at 0.2 m/s, four obstacles
/// 5 km ahead closing at 0.15 m/s, all stamped at the instant.
fn write(path: &Path, instants: usize, tracked: bool) -> u64 {
    let mut bag = Bag::create(path, Some(mcap::Compression::Zstd));
    let mut messages = 0;
    for k in 0..instants {
        let t = format!("{}.{}", k / 10, k % 10);
        let st = stamp(&t);
        let log = k as u64 * 100_000_000;
        let time = k as f64 / 10.0;
        let robot = Body {
            position: [0.2 * time, 0.0],
            orientation: yaw(0.0),
            velocity: [0.2, 0.0],
        };
        bag.write(
            "/odom",
            "nav_msgs/msg/Odometry",
            log,
            &odometry(st, "base_link", &robot),
        );
        bag.write("/mode", "std_msgs/msg/String", log, &text("drive"));
        messages += 2;
        let obstacle = |i: usize| Body {
            position: [5000.0 + 10.0 * i as f64 - 0.15 * time, 0.0],
            orientation: yaw(std::f64::consts::PI),
            velocity: [0.15, 0.0],
        };
        if tracked {
            let objects: Vec<([u8; 16], Body)> = (0..OBSTACLES)
                .map(|i| ([i as u8; 16], obstacle(i)))
                .collect();
            let data = tracked_objects(st, &objects);
            bag.write(
                "/perception/tracked_objects",
                "autoware_perception_msgs/msg/TrackedObjects",
                log,
                &data,
            );
            messages += 1;
        } else {
            for i in 0..OBSTACLES {
                let name = format!("obstacle_{i}");
                let data = odometry(st, &name, &obstacle(i));
                bag.write(
                    &format!("/obstacles/{i}"),
                    "nav_msgs/msg/Odometry",
                    log,
                    &data,
                );
                messages += 1;
            }
        }
    }
    bag.finish();
    messages
}

fn options() -> BagOptions {
    BagOptions {
        obstacle_topics: vec!["/obstacles/*".into(), "/perception/*".into()],
        mode_topic: Some("/mode".into()),
        ..BagOptions::default()
    }
}

fn median_of(runs: usize, mut f: impl FnMut() -> u64) -> (Duration, u64) {
    let mut times = Vec::new();
    let mut out = 0;
    for _ in 0..runs {
        let start = Instant::now();
        out = black_box(f());
        times.push(start.elapsed());
    }
    times.sort();
    (times[runs / 2], out)
}

fn rate(n: u64, d: Duration) -> String {
    format!(
        "{:.2} M messages/s ({:.0} ns/message)",
        n as f64 / d.as_secs_f64() / 1e6,
        d.as_nanos() as f64 / n as f64
    )
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let problem = Problem::load_with_overrides(
        &root.join("problems/seed.toml"),
        &["environment.obstacle_speed=0.2".to_string()],
    )
    .expect("seed problem loads");
    let cert = Certificate::from_analysis(&analyse(&problem).expect("analyses"));
    let fresh = Monitor::new(&cert).expect("certified");
    let dir = tempfile::tempdir().expect("a temporary directory");
    std::fs::write(
        dir.path().join("cert.json"),
        serde_json::to_string(&cert).unwrap(),
    )
    .unwrap();
    let instants = 100_000;
    for tracked in [true, false] {
        let path = dir.path().join(if tracked {
            "tracked.mcap"
        } else {
            "odometry.mcap"
        });
        let messages = write(&path, instants, tracked);
        let bytes = std::fs::read(&path).unwrap();
        let layout = if tracked {
            "TrackedObjects, 4 objects per message"
        } else {
            "one Odometry topic per obstacle"
        };
        println!(
            "{layout}: {instants} instants, {messages} messages, {:.1} MB zstd",
            bytes.len() as f64 / 1e6
        );
        let (floor, n) = median_of(11, || {
            mcap::MessageStream::new(&bytes)
                .unwrap()
                .map(|m| u64::from(!black_box(m.unwrap().data).is_empty()))
                .sum()
        });
        assert_eq!(n, messages);
        println!("  mcap crate alone (the floor)   {}", rate(messages, floor));
        let (decode, samples) = median_of(11, || {
            let mut reader = BagReader::new(&bytes[..], &options()).unwrap();
            let mut samples = 0;
            while let Some(item) = reader.next_item() {
                samples += u64::from(matches!(item, BagItem::Sample { .. }));
            }
            samples
        });
        assert_eq!(samples, (instants * OBSTACLES) as u64);
        println!(
            "  BagReader (decode, assemble)   {}",
            rate(messages, decode)
        );
        let (whole, events) = median_of(11, || {
            let mut reader = BagReader::new(&bytes[..], &options()).unwrap();
            let mut monitor = fresh.clone();
            let mut events = 0;
            while let Some(item) = reader.next_item() {
                let outcome = monitor.observe_bag_item(reader.ids(), &item);
                events += outcome.events.len() as u64;
            }
            events
        });
        assert_eq!(events, 0, "the generated bag is within the premises");
        println!(
            "  BagReader + Monitor            {} ({:.2}x the floor's time)",
            rate(messages, whole),
            whole.as_secs_f64() / floor.as_secs_f64()
        );
        let exe = root.join("target/release/safereach");
        if exe.exists() {
            let (cli, code) = median_of(3, || {
                let status = Command::new(&exe)
                    .current_dir(dir.path())
                    .args([
                        "monitor",
                        "--certificate",
                        "cert.json",
                        "--events-only",
                        "--mode-topic",
                        "/mode",
                    ])
                    .args([
                        "--obstacle-topic",
                        "/obstacles/*",
                        "--obstacle-topic",
                        "/perception/*",
                    ])
                    .arg(&path)
                    .stdout(Stdio::null())
                    .stderr(Stdio::null())
                    .status()
                    .unwrap();
                status.code().unwrap() as u64
            });
            assert_eq!(code, 0);
            println!("  CLI monitor, file to /dev/null {}", rate(messages, cli));
        }
    }
}
